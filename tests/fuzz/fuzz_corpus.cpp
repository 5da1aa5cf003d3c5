// Writes the seed corpora of the fuzz targets: `fuzz_corpus DIR` creates DIR/skeleton/ (small
// synthetic databases, textured and untextured), DIR/blob/ (each of their blobs, prefixed
// with the selector byte fuzz_blob expects: 0 Draco, 1 JPEG, 2 PNG), and one folder per reader
// target (DIR/ply, obj, mtl, gltf, glb, camera_path, constants, calibration: small files written
// here, and the MTL files, camera paths and heads of the OBJ files of samples/).
#include "formats/codec.h"
#include "tests/support/synthetic.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

void save(const std::filesystem::path& path, uint8_t prefix, const std::vector<uint8_t>& bytes, bool withPrefix) {
    std::ofstream out(path, std::ios::binary);
    if (withPrefix) out.put(char(prefix));
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void text(const std::filesystem::path& path, const std::string& content) { std::ofstream(path, std::ios::binary) << content; }

// The first `lines` lines of a sample file.
std::string head(const std::filesystem::path& file, int lines) {
    std::ifstream in(file);
    std::string out, line;
    for (int i = 0; i < lines && std::getline(in, line); ++i) out += line + "\n";
    return out;
}

// A 3 x 3 vertex grid (8 triangles) with UVs as PLY, in ascii or binary little/big endian; the
// UVs per vertex, or per face (`texcoord` lists and a `texnumber` over two TextureFile lines).
std::string ply(const std::string& format, bool faceUvs = false) {
    std::ostringstream out;
    out << "ply\nformat " << format << " 1.0\ncomment TextureFile t.png\n" << (faceUvs ? "comment TextureFile t.png\n" : "")
        << "element vertex 9\nproperty float x\nproperty float y\nproperty float z\n"
        << (faceUvs ? "" : "property float u\nproperty float v\n") << "property uchar red\n"
        << "property uchar green\nproperty uchar blue\nelement face 8\nproperty list uchar int vertex_indices\n"
        << (faceUvs ? "property list uchar float texcoord\nproperty int texnumber\n" : "") << "end_header\n";
    const auto put = [&](auto value) {
        if (format == "ascii") {
            out << +value << ' ';
            return;
        }
        char b[sizeof value];
        std::memcpy(b, &value, sizeof value);
        if (format == "binary_big_endian") std::reverse(b, b + sizeof value);
        out.write(b, sizeof value);
    };
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) {
            for (float f : {float(x), float(y), float(x * y) * 0.1f}) put(f);
            for (float f : {x / 2.0f, y / 2.0f})
                if (!faceUvs) put(f);
            for (int c = 0; c < 3; ++c) put(uint8_t(40 * (x + y + c)));
            if (format == "ascii") out << '\n';
        }
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (const auto& t : {std::array{0, 1, 4}, std::array{0, 4, 3}}) {
                put(uint8_t(3));
                for (int k = 0; k < 3; ++k) put(int32_t(y * 3 + x + t[k] % 3 + 3 * (t[k] / 3)));
                if (faceUvs) {
                    put(uint8_t(6));
                    for (int k = 0; k < 3; ++k) put((x + t[k] % 3) / 2.0f), put((y + t[k] / 3) / 2.0f);
                    put(int32_t(x));
                }
                if (format == "ascii") out << '\n';
            }
    return out.str();
}

// One textured triangle: its glTF JSON (buffer at `bufferUri`) and its 60-byte buffer.
const char kTriangleBuffer[60] = {};
std::string gltfJson(const std::string& bufferUri) {
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[1,0,0]}],)"
           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],)"
           R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0}],)"
           R"("images":[{"uri":"t.png"}],"buffers":[{)" +
           (bufferUri.empty() ? std::string() : "\"uri\":\"" + bufferUri + "\",") +
           R"("byteLength":60}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
           R"({"buffer":0,"byteOffset":36,"byteLength":24},{"buffer":0,"byteOffset":0,"byteLength":6}],)"
           R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
           R"({"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"},)"
           R"({"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}]})";
}

std::string triangleBuffer() {
    const float v[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    return std::string(reinterpret_cast<const char*>(v), sizeof v);
}

// A GLB container of `json` and `bin` (glTF 2.0 §4.4).
std::string glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    const auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2), u32(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    u32(uint32_t(json.size())), out += "JSON", out += json;
    u32(uint32_t(bin.size())), out += std::string("BIN\0", 4), out += bin;
    return out;
}

// The triangle as gltfpack writes it (EXT_meshopt_compression): its three views coded by
// meshoptimizer into the BIN chunk, each pointing at a fallback buffer that has no data.
std::string glbMeshopt() {
    const std::string triangle = triangleBuffer();  // 3 positions, then 3 UVs
    const unsigned int corners[3] = {0, 1, 2};
    std::string bin, views;
    const auto add = [&](std::vector<unsigned char> code, size_t size, size_t count, size_t stride, const char* mode) {
        code.resize(size);
        while (bin.size() % 4) bin += '\0';
        views += std::string(views.empty() ? "" : ",") + R"({"buffer":1,"byteLength":)" + std::to_string(count * stride) +
                 (std::string(mode) == "ATTRIBUTES" ? R"(,"byteStride":)" + std::to_string(stride) : "") +
                 R"(,"extensions":{"EXT_meshopt_compression":{"buffer":0,"byteOffset":)" + std::to_string(bin.size()) +
                 R"(,"byteLength":)" + std::to_string(size) + R"(,"byteStride":)" + std::to_string(stride) + R"(,"count":)" +
                 std::to_string(count) + R"(,"mode":")" + mode + R"("}}})";
        bin.append(code.begin(), code.end());
    };
    std::vector<unsigned char> code(meshopt_encodeVertexBufferBound(3, 12) + meshopt_encodeIndexBufferBound(3, 3));
    add(code, meshopt_encodeVertexBuffer(code.data(), code.size(), triangle.data(), 3, 12), 3, 12, "ATTRIBUTES");
    add(code, meshopt_encodeVertexBuffer(code.data(), code.size(), triangle.data() + 36, 3, 8), 3, 8, "ATTRIBUTES");
    add(code, meshopt_encodeIndexBuffer(code.data(), code.size(), corners, 3), 3, 2, "TRIANGLES");
    std::string json = gltfJson("");
    const size_t from = json.find(R"("buffers")"), to = json.find(R"("accessors")");
    json.replace(from, to - from, R"("extensionsUsed":["EXT_meshopt_compression"],"extensionsRequired":["EXT_meshopt_compression"],)"
                                  R"("buffers":[{"byteLength":)" + std::to_string(bin.size()) +
                                      R"(},{"byteLength":60,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}],)"
                                      R"("bufferViews":[)" + views + "],");
    return glb(json, bin);
}

// The triangle with its texture, a 4 x 4 PNG, in the BIN chunk as buffer view 3 (what
// glbWithoutImages takes out).
std::string glbWithImage() {
    hlod::Image image;
    image.width = image.height = 4, image.channels = 3;
    for (int i = 0; i < 48; ++i) image.pixels.push_back(uint8_t(i * 5));
    const std::vector<uint8_t> png = hlod::encodeTexture(image, hlod::Codec::Png).bytes;
    std::string json = gltfJson("");
    const auto replace = [&](const std::string& from, const std::string& to) { json.replace(json.find(from), from.size(), to); };
    const std::string length = std::to_string(png.size());
    replace(R"("images":[{"uri":"t.png"}])", R"("images":[{"bufferView":3,"mimeType":"image/png"}])");
    replace(R"("byteLength":60}])", R"("byteLength":)" + std::to_string(60 + png.size()) + "}]");
    replace(R"({"buffer":0,"byteOffset":0,"byteLength":6}])",
            R"({"buffer":0,"byteOffset":0,"byteLength":6},{"buffer":0,"byteOffset":60,"byteLength":)" + length + "}]");
    return glb(json, triangleBuffer() + std::string(png.begin(), png.end()));
}

void readerSeeds(const std::filesystem::path& dir) {
    namespace fs = std::filesystem;
    const fs::path samples = fs::path(HLOD_SOURCE_DIR) / "samples";
    for (const char* d : {"ply", "obj", "mtl", "gltf", "glb", "camera_path", "constants", "calibration"})
        fs::create_directories(dir / d);
    for (const char* f : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        text(dir / "ply" / f, ply(f));
        text(dir / "ply" / (std::string(f) + "_face_uvs"), ply(f, true));
    }
    text(dir / "obj" / "quad.obj",
         "mtllib q.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nusemtl a\n"
         "f 1/1/1 2/2/1 3/3/1 4/1/1\nf -1//1 -2//1 -3//1\nf 1 3 4\n");
    text(dir / "obj" / "continued.obj", "v 0 0 \\\n0\nv 1 0 0\nv 1 1 0\n# C:\\scans\\\nf 1 \\ \r\n2 \\\n3\nf 1 3 \\");
    text(dir / "obj" / "city-head.obj", head(samples / "city" / "block_000.obj", 120));
    text(dir / "obj" / "banana-head.obj", head(samples / "banana" / "textured_simple_reoriented.obj", 120));
    text(dir / "mtl" / "synthetic.mtl", "newmtl material0\nKd 1 0.5 0.25\nmap_Kd -s 1 1 1 t.png\nnewmtl a\nmap_Kd sub/t.jpg\n");
    fs::copy_file(samples / "city" / "block_000.mtl", dir / "mtl" / "city.mtl", fs::copy_options::overwrite_existing);
    fs::copy_file(samples / "banana" / "textured_simple_reoriented.mtl", dir / "mtl" / "banana.mtl",
                  fs::copy_options::overwrite_existing);
    const std::string buffer = triangleBuffer() + std::string(kTriangleBuffer, 60 - triangleBuffer().size());
    std::string base64;  // the buffer as a data: URI
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < buffer.size(); i += 3) {
        const uint32_t n = (uint8_t(buffer[i]) << 16) | (uint8_t(buffer[i + 1]) << 8) | uint8_t(buffer[i + 2]);
        for (int k = 18; k >= 0; k -= 6) base64 += table[(n >> k) & 63];
    }
    text(dir / "gltf" / "data-uri.gltf", gltfJson("data:application/octet-stream;base64," + base64));
    text(dir / "gltf" / "external.gltf", gltfJson("in.bin"));
    text(dir / "glb" / "triangle.glb", glb(gltfJson(""), triangleBuffer()));
    text(dir / "glb" / "textured.glb", glbWithImage());
    text(dir / "glb" / "meshopt.glb", glbMeshopt());
    std::string overrun = glb(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":8}]})", "\1\2\3\4");
    overrun[overrun.size() - 12] = 8;  // the BIN chunk claims 8 bytes, 4 follow (tinygltf read past them)
    text(dir / "glb" / "bin-overrun.glb", overrun);
    for (const char* p : {"walk.path", "drive.path"})
        text(dir / "camera_path" / p, head(samples / "banana" / p, 12));
    text(dir / "camera_path" / "cut.path", "hlod-camera-path 1\n0 0 0 1.7 0 0 0 1 60\n0.001 5 0 1.7 0 1 0 0 60 # cut\n\n2 5 5 1.7 0 0.7071 0 0.7071 90\n");
    text(dir / "constants" / "all.conf",
         "# every constant\nc_desiredTris = 900\nc_levelFactor = 4\nc_textured = 0.127\nc_vis = 1.275\nc_fore = 0.45\n"
         "c_targetTime = 30\nc_hystSwitch = 1500\nc_hystLimit = 4510\nc_memory = 935\n");
    text(dir / "calibration" / "calibration.txt",
         "renderer = cost-model\nc_textured = 0.127\nms_per_cost = 0.0001\nfixed_overhead_ms = 0.5\n"
         "textured_ms_per_tri = 1e-05\nuntextured_ms_per_tri = 6e-05\ntextured_intercept_ms = 0.1\n"
         "untextured_intercept_ms = 0.2\n# sample textured triangles=1000 ms=0.11\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: fuzz_corpus DIR\n";
        return 2;
    }
    namespace fs = std::filesystem;
    const fs::path dir = argv[1];
    fs::create_directories(dir / "skeleton");
    fs::create_directories(dir / "blob");
    try {
        for (uint32_t textureSize : {8u, 0u}) {
            hlod::SyntheticOptions o;
            o.blocksX = 1;
            o.blocksY = 1;
            o.levels = 2;
            o.levelFactor = 2;
            o.trianglesPerNode = 8;
            o.textureSize = textureSize;
            const fs::path db = dir / "skeleton" / ("synthetic-" + std::to_string(textureSize) + ".hlod");
            hlod::writeSyntheticDatabase(db.string(), o);
            hlod::Database d = hlod::Database::open(db.string());
            for (uint32_t i = 0; i < d.skeleton().blobs.size(); ++i) {
                const hlod::BlobRef& b = d.skeleton().blobs[i];
                uint8_t selector = b.codec == hlod::Codec::Draco ? 0 : b.codec == hlod::Codec::Jpeg ? 1 : 2;
                save(dir / "blob" / ("t" + std::to_string(textureSize) + "-" + std::to_string(i)), selector,
                     d.readBlob(i), true);
            }
        }
        readerSeeds(dir);
        hlod::Image img{4, 4, 4, std::vector<uint8_t>(64, 200)};
        save(dir / "blob" / "png-rgba", 2, hlod::encodeTexture(img, hlod::Codec::Png).bytes, true);
    } catch (const std::exception& e) {
        std::cerr << "fuzz_corpus: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
