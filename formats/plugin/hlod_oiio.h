// The C interface of the OpenImageIO plugin (hlod_oiio.cpp), which formats/image_plugin.cpp loads
// with dlopen() the first time a texture file is neither JPEG nor PNG (issue #14: linking
// OpenImageIO cost every hlod process ~122 MiB of libraries). C, so that the plugin and the
// tool need not agree on a C++ ABI; `version` changes with any change to this struct.
#pragma once

#include <stddef.h>

extern "C" {

struct HlodOiioApi {
    int version;  // kHlodOiioVersion
    // Opens `path` as OpenImageIO::ImageInput::open does by default (any format it reads;
    // colour associated with alpha). nullptr, and OpenImageIO's message in `error`, when it cannot.
    void* (*open)(const char* path, int* width, int* height, int* channels, char* error, size_t errorSize);
    // Rows [y0, y1), their channels [0, keep), as 8-bit texels into `out`; 0, and the message
    // in `error`, on failure (a decode warning OpenImageIO records included).
    int (*read)(void* image, int y0, int y1, int keep, unsigned char* out, char* error, size_t errorSize);
    void (*close)(void* image);
};

// The plugin's one exported symbol.
const HlodOiioApi* hlod_oiio_api(void);
}

inline constexpr int kHlodOiioVersion = 1;
inline constexpr const char* kHlodOiioSymbol = "hlod_oiio_api";
