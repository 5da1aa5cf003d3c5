// read_gltf_load.cpp: a glTF or GLB file parsed by tinygltf for read_gltf.cpp, its external
// buffers confined to the input's folder, its embedded images checked and either decoded into
// memory or written, still encoded, into a folder; and the input file mapped read-only.
#pragma once

#include "pipeline/pipeline.h"
#include "pipeline/tiny_gltf_config.h"

#include <array>
#include <map>
#include <span>
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

// A GLB container (glTF 2.0 §4.4: a 12-byte header, a JSON chunk, an optional BIN chunk, each
// 4-byte aligned): splitGlb finds the chunks within the header's length, as tinygltf does (bin
// empty when there is none; false for what tinygltf refuses: a length beyond the file, a JSON
// chunk that does not fit, a second chunk that is not a BIN chunk of 4 n bytes; and for a BIN
// chunk longer than the bytes after its header, which checkGltfJson refuses since tinygltf would
// read past them), assembleGlb writes one (padding both chunks).
struct GlbChunks {
    std::span<const uint8_t> json, bin;
};
bool splitGlb(const uint8_t* bytes, size_t size, GlbChunks& out);
std::vector<uint8_t> assembleGlb(std::string json, std::span<const uint8_t> bin);

// tinygltf hands an image's buffer view to the image loader without checking it against its
// buffer: a view past the buffer's declared byteLength would be read past the end of tinygltf's
// copy (found by fuzz_glb). Checked here first, on glTF JSON or a GLB's JSON chunk; throws
// InputError naming the image (read_glb_images.cpp), or the first required extension that is
// not in kReadExtensions, or a GLB's BIN chunk claiming more bytes than follow its header (tinygltf
// would read past the file). Anything else malformed is left to tinygltf.
void checkGltfJson(const uint8_t* bytes, size_t size, bool binary, const std::string& path);

// The glTF extensions a file may list in extensionsRequired: tinygltf decodes Draco primitives,
// read_gltf_meshopt.cpp meshoptimizer-coded buffer views, readFloats reads quantized attributes,
// read_gltf_materials.cpp applies texture transforms and reads a specular-glossiness material's
// diffuse texture, and an unlit material's base colour is what hlod reads of every material. Any
// other required extension is refused (InputError, checkGltfJson): the glTF 2.0 specification
// ("Specifying Extensions") forbids a loader to go on without it, and it would drop textures
// (KHR_texture_basisu) or instances (EXT_mesh_gpu_instancing) without a word.
inline constexpr std::array<const char*, 6> kReadExtensions = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                                               "KHR_mesh_quantization",      "KHR_texture_transform",
                                                               "KHR_materials_unlit",        "KHR_materials_pbrSpecularGlossiness"};

// read_gltf_meshopt.cpp (EXT_meshopt_compression). meshoptPlan: every compressed view's numbers
// from the file's JSON, checked (InputError naming the view: a mode, stride or filter that do not
// fit, more decoded bytes claimed than 64 per byte of data, an image or Draco primitive on a
// fallback buffer), and the file with each fallback buffer given three bytes (`bytes`, empty when
// none needs it). decodeMeshoptViews: on the model tinygltf loaded, each view decoded into a
// buffer of its own and pointed at it (InputError when it does not decode).
struct MeshoptView {
    size_t index = 0;  // of the buffer view
    uint64_t buffer = 0, offset = 0, length = 0, stride = 0, count = 0;
    std::string mode, filter;
};
struct MeshoptFile {
    std::vector<uint8_t> bytes;
    std::vector<MeshoptView> views;
    size_t fileBuffers = 0;  // the file's own buffers (decoded ones are appended after them)
};
MeshoptFile meshoptPlan(const uint8_t* bytes, size_t size, bool binary, const std::string& path);
void decodeMeshoptViews(tinygltf::Model& model, const MeshoptFile& file, const std::string& path);

// How a material's base-colour texture reads its primitive's texture coordinates
// (read_gltf_materials.cpp): TEXCOORD_<set>, then u' = a0 u + a2 v + a4, v' = a1 u + a3 v + a5
// (KHR_texture_transform's offset, rotation and scale; the identity without it).
struct UvMapping {
    int set = 0;
    std::array<double, 6> affine{1, 0, 0, 1, 0, 0};
    bool identity() const { return affine == std::array<double, 6>{1, 0, 0, 1, 0, 0}; }
};
struct GltfMaterials {
    std::vector<uint32_t> materialOfGltf;  // glTF material -> index in raw.materials
    std::vector<UvMapping> uvOfGltf;       // glTF material -> its texture's UV mapping
};
// Appends one Material per glTF material, then the default one, to raw.materials; an unusable
// embedded image becomes a TextureProblem of its materials (README "Textures: one rule").
GltfMaterials addGltfMaterials(const tinygltf::Model& model, const EmbeddedImages& images, const std::string& path,
                               const ReadOptions& options, RawMesh& raw);

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
