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

// Image `index` kept encoded: a PNG or JPEG is checked (header, texel count against
// kMaxTextureTexels, one full decode, freed) and written as it is to images.dir/image_N.png|jpg,
// or its problem kept in images.unusable; false (nothing done) for any other format.
bool keepEncoded(int index, const uint8_t* bytes, size_t size, EmbeddedImages& images);

// tinygltf hands an image's buffer view to the image loader without checking it against its
// buffer: a view past the buffer's declared byteLength would be read past the end of tinygltf's
// copy (found by fuzz_glb). Checked here first, on glTF JSON or a GLB's JSON chunk; throws
// InputError naming the image (read_glb_images.cpp). Anything else malformed is left to tinygltf.
void checkImageViews(const uint8_t* bytes, size_t size, bool binary, const std::string& path);

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
    void release(size_t offset, size_t length) const;  // done with these bytes: their pages leave the process
};

bool isGlb(const std::string& path);  // by extension, any case

// read_glb_images.cpp: a GLB whose PNG/JPEG images lie in its BIN chunk, rebuilt for tinygltf
// without them, so the atlases are never copied into memory: each such image is kept encoded
// (keepEncoded) straight from `glb`, its bufferView emptied and its reference replaced by a
// placeholder URI, and the other buffer views moved into a compacted BIN chunk. Empty when there
// is nothing to take out or the container is not as expected (tinygltf then reads `glb` itself
// and reports what is wrong).
std::vector<uint8_t> glbWithoutImages(const MappedFile& glb, EmbeddedImages& images);

}  // namespace hlod
