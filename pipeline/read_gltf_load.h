// read_gltf_load.cpp: a glTF or GLB file parsed by tinygltf for read_gltf.cpp, its external
// buffers confined to the input's folder, its embedded images checked and either decoded into
// memory or written, still encoded, into a folder; and the input file mapped read-only.
#pragma once

#include "pipeline/pipeline.h"
#include "pipeline/tiny_gltf_config.h"

#include <map>
#include <string>

namespace hlod {

// The embedded images, as loadImageChecked left them: decoded into tinygltf's Image (dir empty),
// or written encoded to dir (`written`: image index -> file), or unusable (index -> why).
struct EmbeddedImages {
    std::string dir;
    std::map<int, std::string> written, unusable;
};

tinygltf::Model loadGltfModel(const uint8_t* bytes, size_t size, bool binary, const std::string& path,
                              const ReadOptions& options, EmbeddedImages& images);

// The input file, mapped read-only (tinygltf copies the buffers it parses; the file's own pages
// stay the page cache's). Throws InputError when it cannot be opened or read.
struct MappedFile {
    const uint8_t* data = nullptr;
    size_t size = 0;
    explicit MappedFile(const std::string& path);
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    ~MappedFile();
};

bool isGlb(const std::string& path);  // by extension, any case

}  // namespace hlod
