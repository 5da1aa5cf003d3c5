// Images read and written without OpenImageIO (issue #14: OpenImageIO's libraries alone were
// ~122 MiB of the process's baseline). JPEG through libjpeg-turbo (image_jpeg.cpp) and PNG through
// libpng (image_png.cpp), row by row; every other format through OpenImageIO in a plugin loaded
// with dlopen() the first time such a file is met (image_plugin.cpp, plugin/hlod_oiio.cpp).
// Decoded texels are those OpenImageIO gave before (tests/pipeline/test_image_io.cpp compares them).
#pragma once

#include "formats/codec.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace hlod {

// What went wrong, without the file's name (the caller adds it).
struct ImageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// A library's message up to its first line break (one-line errors).
inline std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

// Whether `head` starts with the JPEG (FF D8 FF) or the PNG signature.
inline bool hasJpegSignature(std::span<const uint8_t> head) {
    return head.size() >= 3 && head[0] == 0xFF && head[1] == 0xD8 && head[2] == 0xFF;
}
inline bool hasPngSignature(std::span<const uint8_t> head) {
    static constexpr uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    return head.size() >= sizeof kPng && std::equal(kPng, kPng + sizeof kPng, head.begin());
}

// A JPEG or PNG this code does not decode as OpenImageIO did: a CMYK JPEG (OpenImageIO converts
// it to RGB) or, read as a texture file, a PNG with alpha (OpenImageIO associates its colour with
// alpha). openImageFile gives such a file to the OpenImageIO plugin.
struct ImageNeedsPlugin : ImageError {
    using ImageError::ImageError;
};

// An image being decoded, its rows in order, 8 bits per channel.
class ImageRows {
public:
    virtual ~ImageRows() = default;
    // Decodes the next `count` rows into `out`: the first `keep` (1..channels) channels of each
    // texel. Throws ImageError on corrupt or truncated data (a libjpeg warning included).
    virtual void read(uint32_t count, uint32_t keep, uint8_t* out) = 0;
    uint32_t width = 0, height = 0, channels = 0;  // channels: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
    // Bytes the decoder holds for the whole image until its last row is read, beside the rows: a
    // progressive or multi-scan JPEG's coefficients (libjpeg keeps every block's, 128 bytes a block,
    // ~6 bytes a texel at 4:4:4, ~3 at 4:2:0); 0 for an image decoded row by row.
    uint64_t wholeImageBytes = 0;
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file{nullptr, &std::fclose};  // the file read, closed last
};

// Where the encoded bytes are: an open file, or memory.
struct ImageSource {
    std::FILE* file = nullptr;
    std::span<const uint8_t> bytes;
};

// Throw ImageError when the header cannot be read, ImageNeedsPlugin for a CMYK JPEG and, with
// `refuseAlpha`, a PNG with an alpha channel or a transparent colour. Alpha is kept as stored.
std::unique_ptr<ImageRows> openJpeg(const ImageSource& source);
// An interlaced PNG is decoded in bands of at most `interlacedBandBytes` of decoded rows (at least
// one row), the file read once per band: the memory stays bounded whatever the image's size.
constexpr size_t kInterlacedBandBytes = size_t(32) << 20;
std::unique_ptr<ImageRows> openPng(const ImageSource& source, bool refuseAlpha, size_t interlacedBandBytes = kInterlacedBandBytes);

// A texture file as OpenImageIO opened it by default: JPEG and PNG (by their signature) here,
// with associated alpha; any other format, and CMYK JPEG, through the OpenImageIO plugin. Throws
// ImageError (no file name in it) when it cannot be opened, the plugin's absence included.
std::unique_ptr<ImageRows> openImageFile(const std::string& path);

// The OpenImageIO plugin: HLOD_OIIO_PLUGIN when set, else hlod_oiio.so beside the executable
// ("" when the executable's folder cannot be read).
std::string oiioPluginPath();

// JPEG bytes of a 1- or 3-channel image: chroma halved per axis (4:2:0) or not (4:4:4), Huffman
// tables fitted to the image (formats/jpeg_tables.h) or libjpeg's standard ones, with OpenImageIO's empty Exif
// segment or without; throws std::runtime_error "encodeTexture: ...".
std::vector<uint8_t> encodeJpeg(const Image& image, int quality, bool chroma420, bool fittedTables, bool emptyExif);
// PNG of the image as given (alpha not premultiplied), zlib's default level; throws
// std::runtime_error.
std::vector<uint8_t> encodePng(const Image& image);
// A JPEG as OpenImageIO's writer made it (standard Huffman tables, 4:2:0, `quality`), written
// to `path`; throws std::runtime_error "PATH: ...".
void writeJpegFile(const std::string& path, const Image& image, int quality);
// A PNG written to `path`; throws std::runtime_error "PATH: ...".
void writePngFile(const std::string& path, const Image& image);
// `bytes` written to `path` (a FORMAT file); throws std::runtime_error "PATH: cannot write FORMAT".
void writeImageBytes(const std::string& path, const std::vector<uint8_t>& bytes, const char* format);

}  // namespace hlod
