// tinygltf's parse of a glTF/GLB input (read_gltf_load.h): the only translation unit that
// compiles tinygltf (and its stb_image).
#define TINYGLTF_IMPLEMENTATION
#include "pipeline/read_gltf_load.h"

#include "formats/image_io.h"
#include "formats/json_text.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

namespace hlod {
namespace {

// tinygltf's file callbacks, confined: an external buffer is looked up as FOLDER/URI (tinygltf
// then also tries ./URI, which is never accepted) and resolved by resolveReference; a refusal
// is kept and thrown once tinygltf returns.
struct BufferFiles {
    const std::string& path;
    const std::string folder;
    const ReadOptions& options;
    std::string refused;
};

std::string expandPath(const std::string& file, void*) { return file; }

// The buffer `file` (FOLDER/URI as tinygltf joins them) resolved, or "" (refusal kept).
std::string bufferPath(const std::string& file, BufferFiles& files) {
    const std::string prefix = files.folder + "/";
    if (file.rfind(prefix, 0) != 0) return "";
    try {
        return resolveReference(files.path, files.folder, file.substr(prefix.size()), "buffer", files.options);
    } catch (const InputError& e) {
        if (files.refused.empty()) files.refused = e.what();
        return "";
    }
}

bool bufferExists(const std::string& file, void* user) {
    const std::string resolved = bufferPath(file, *static_cast<BufferFiles*>(user));
    return !resolved.empty() && std::filesystem::is_regular_file(resolved);
}

bool readBuffer(std::vector<unsigned char>* out, std::string* err, const std::string& file, void* user) {
    std::ifstream in(bufferPath(file, *static_cast<BufferFiles*>(user)), std::ios::binary);
    if (!in) {
        *err = "cannot open";
        return false;
    }
    out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in.bad()) return true;
    *err = "read error";
    return false;
}

// Why an embedded image's header rules it out ("" when nothing does): no image stb_image knows,
// or more texels than kMaxTextureTexels.
std::string headerProblem(const uint8_t* bytes, int size) {
    int w = 0, h = 0, components = 0;
    if (!stbi_info_from_memory(bytes, size, &w, &h, &components)) return std::string("cannot be decoded (") + stbi_failure_reason() + ")";
    if (uint64_t(w) * uint64_t(h) > kMaxTextureTexels)
        return "claims " + std::to_string(w) + "x" + std::to_string(h) + " texels (more than " + std::to_string(kMaxTextureTexels) +
               "): not decoded";
    return "";
}

// Embedded images go through stb_image inside tinygltf; a few hundred bytes of PNG can claim
// 20000 x 16000 texels (a decompression bomb). The header is read first: an image above
// kMaxTextureTexels is not decoded. Such an image, or one stb_image cannot decode, is kept in
// `unusable` instead of failing the whole file, and becomes a TextureProblem of each material
// using it (addMaterials): the one rule for every unusable texture (README "Textures: one rule").
// With a folder (ReadOptions::imageDir), a PNG or JPEG is checked in strips of rows and kept encoded
// (keepEncoded), so no atlas is ever decoded whole; other formats are decoded into memory.
bool loadImageChecked(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int width, int height,
                      const unsigned char* bytes, int size, void* user) {
    auto& images = *static_cast<EmbeddedImages*>(user);
    (void)err;
    if (!images.dir.empty() && keepEncoded(index, bytes, static_cast<size_t>(size), images)) return true;
    if (std::string why = headerProblem(bytes, size); !why.empty()) {
        images.unusable[index] = why;
        return true;
    }
    std::string decodeError;
    if (tinygltf::LoadImageData(image, index, &decodeError, warn, width, height, bytes, size, nullptr)) return true;
    images.unusable[index] = "cannot be decoded (" + decodeError.substr(0, decodeError.find('\n')) + ")";
    *image = tinygltf::Image{};
    return true;
}

}  // namespace

tinygltf::Model loadGltfModel(const uint8_t* bytes, size_t size, bool binary, const std::string& path,
                              const ReadOptions& options, EmbeddedImages& images) {
    if (size >= UINT32_MAX) throw InputError(path + ": glTF larger than 4 GiB (not supported)");
    checkGltfJson(bytes, size, binary, path);
    const MeshoptFile meshopt = meshoptPlan(bytes, size, binary, path);
    if (!meshopt.bytes.empty()) bytes = meshopt.bytes.data(), size = meshopt.bytes.size();
    if (size >= UINT32_MAX) throw InputError(path + ": glTF larger than 4 GiB (not supported)");
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    BufferFiles files{path, folderOf(path), options, {}};
    loader.SetFsCallbacks({bufferExists, expandPath, readBuffer, nullptr, &files});
    loader.SetImageLoader(loadImageChecked, &images);
    const unsigned int length = static_cast<unsigned int>(size);
    const uint8_t empty = 0;
    const uint8_t* data = size ? bytes : &empty;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, length, files.folder)
                           : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data), length, files.folder);
    if (!files.refused.empty()) throw InputError(files.refused);
    if (!ok) {
        std::string why = err.substr(0, err.find('\n'));
        if (why.find("[json.exception.parse_error.") != std::string::npos) why = "not JSON: " + why;
        why = jsonProblem(why);  // nlohmann's tag, not a sentence
        throw InputError(path + ": corrupt glTF (" + why + ")");
    }
    decodeMeshoptViews(model, meshopt, path);
    return model;
}

MappedFile::MappedFile(const std::string& path) {
    refuseSpecialFile(path);
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    const bool ok = fstat(fd, &st) == 0;
    size = ok ? static_cast<size_t>(st.st_size) : 0;
    void* p = ok && size ? mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0) : nullptr;
    ::close(fd);
    if (!ok || p == MAP_FAILED) throw InputError(path + ": read error");
    data = static_cast<const uint8_t*>(p);
}

MappedFile::~MappedFile() {
    if (data) munmap(const_cast<uint8_t*>(data), size);
}

void MappedFile::release(size_t offset, size_t length) const {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE)), from = (offset + page - 1) / page * page;
    const size_t to = std::min(offset + length, size) / page * page;
    if (data && to > from) madvise(const_cast<uint8_t*>(data) + from, to - from, MADV_DONTNEED);
}

namespace {
// Whether an embedded image's body decodes, read in strips of rows (formats/image_io.h): a corrupt
// one is an unusable image at the read (the textures rule), not a failed build. stb_image decoded it
// whole until stop 47: 1 GiB for a 16k RGBA PNG, a 3 GiB peak for a 1 KB glTF claiming a 16k
// progressive JPEG. A CMYK JPEG is left to the texture store's OpenImageIO plugin, as a file's.
std::string bodyProblem(const uint8_t* bytes, size_t size, bool png) {
    constexpr uint32_t kRows = 16;
    try {
        const ImageSource source{nullptr, {bytes, size}};
        const std::unique_ptr<ImageRows> rows = png ? openPng(source, false) : openJpeg(source);
        std::vector<uint8_t> strip(size_t(rows->width) * rows->channels * kRows);
        for (uint32_t y = 0; y < rows->height; y += kRows) rows->read(std::min(kRows, rows->height - y), rows->channels, strip.data());
        return "";
    } catch (const ImageNeedsPlugin&) {
        return "";
    } catch (const ImageError& e) {
        return std::string("cannot be decoded (") + e.what() + ")";
    }
}
}  // namespace

bool keepEncoded(int index, const uint8_t* bytes, size_t size, EmbeddedImages& images) {
    const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
    const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
    if (!png && !jpeg) return false;
    const int length = static_cast<int>(std::min<size_t>(size, INT32_MAX));
    if (std::string why = headerProblem(bytes, length); !why.empty()) {
        images.unusable[index] = why;
    } else if (why = bodyProblem(bytes, size, png); !why.empty()) {
        images.unusable[index] = why;
    } else {
        const std::string file = (std::filesystem::path(images.dir) / ("image_" + std::to_string(index) + (png ? ".png" : ".jpg"))).string();
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        if (!out.write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(size)).flush())
            throw std::runtime_error(file + ": cannot write the embedded image (" + std::strerror(errno) + ")");
        images.written[index] = file;
    }
    return true;
}

bool isGlb(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".glb";
}

}  // namespace hlod
