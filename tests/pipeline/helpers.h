// Test helpers for pipeline/: a generated wavy terrain (UVs an affine function of position, so
// exact interpolation can be checked), PLY/OBJ writers, areas. TempDir and file bytes:
// tests/support/temp_dir.h.
#pragma once

#include "pipeline/pipeline.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace hlod::test {

// n x n quads (2 n^2 triangles) over [0, size]^2 in x/y, height a gentle wave; u = x/size,
// v = y/size; material 0 for x < size/2, 1 otherwise when twoMaterials.
inline Piece terrain(uint32_t n, float size = 100, bool twoMaterials = false) {
    Piece p;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = size * i / n, y = size * j / n;
            p.mesh.positions.insert(p.mesh.positions.end(), {x, y, 2.0f * std::sin(x * 0.11f) * std::cos(y * 0.07f)});
            p.mesh.texcoords.insert(p.mesh.texcoords.end(), {x / size, y / size});
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            p.mesh.indices.insert(p.mesh.indices.end(), {a, b, d, a, d, c});
            const uint32_t m = twoMaterials && 2 * i >= n ? 1 : 0;
            p.materials.insert(p.materials.end(), {m, m});
        }
    return p;
}

// Two fins (triangles standing at z = 3 and -3) on the first edge of every `every`-th triangle:
// edges of three faces, as scans have, which no simplifier collapses (a piece without normals).
inline void addFins(Piece& p, size_t every) {
    const size_t before = p.mesh.triangleCount();
    for (size_t t = 0; t < before; t += every)
        for (float z : {3.0f, -3.0f}) {
            const uint32_t a = p.mesh.indices[3 * t], b = p.mesh.indices[3 * t + 1], fin = static_cast<uint32_t>(p.mesh.vertexCount());
            p.mesh.positions.insert(p.mesh.positions.end(), {p.mesh.positions[3 * a], p.mesh.positions[3 * a + 1], z});
            p.mesh.texcoords.insert(p.mesh.texcoords.end(), {p.mesh.texcoords[2 * a], p.mesh.texcoords[2 * a + 1]});
            p.mesh.indices.insert(p.mesh.indices.end(), {a, b, fin});
            p.materials.push_back(p.materials.front());
        }
}

inline double triangleArea(const MeshData& m, size_t t) {
    const float* a = &m.positions[3 * m.indices[3 * t]];
    const float* b = &m.positions[3 * m.indices[3 * t + 1]];
    const float* c = &m.positions[3 * m.indices[3 * t + 2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

inline double meshArea(const MeshData& m) {
    double sum = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) sum += triangleArea(m, t);
    return sum;
}

// Writes positions (+ u, v when present) as PLY; v is written OBJ-style (flipped back).
inline void writePly(const std::string& path, const MeshData& m, bool binary) {
    std::ofstream out(path, std::ios::binary);
    const bool uv = !m.texcoords.empty();
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\nelement vertex " << m.vertexCount()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << (uv ? "property float u\nproperty float v\n" : "") << "element face " << m.triangleCount()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < m.vertexCount(); ++i) {
        float v[5] = {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2], 0, 0};
        if (uv) v[3] = m.texcoords[2 * i], v[4] = 1.0f - m.texcoords[2 * i + 1];
        const int n = uv ? 5 : 3;
        if (binary) out.write(reinterpret_cast<const char*>(v), n * sizeof(float));
        else {
            for (int k = 0; k < n; ++k) out << v[k] << (k + 1 < n ? " " : "\n");
        }
    }
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        if (binary) {
            const unsigned char three = 3;
            out.write(reinterpret_cast<const char*>(&three), 1);
            out.write(reinterpret_cast<const char*>(&m.indices[3 * t]), 3 * sizeof(uint32_t));
        } else {
            out << "3 " << m.indices[3 * t] << " " << m.indices[3 * t + 1] << " " << m.indices[3 * t + 2] << "\n";
        }
    }
}

// Writes an OBJ (+ MTL naming `texture` for material 1 and 0 when given).
inline void writeObj(const std::string& path, const Piece& p, const std::string& texture) {
    const std::string mtl = std::filesystem::path(path).stem().string() + ".mtl";
    std::ofstream out(path);
    out << "mtllib " << mtl << "\n";
    const MeshData& m = p.mesh;
    for (size_t i = 0; i < m.vertexCount(); ++i)
        out << "v " << m.positions[3 * i] << " " << m.positions[3 * i + 1] << " " << m.positions[3 * i + 2] << "\n";
    for (size_t i = 0; i < m.vertexCount(); ++i) out << "vt " << m.texcoords[2 * i] << " " << 1.0f - m.texcoords[2 * i + 1] << "\n";
    uint32_t current = UINT32_MAX;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        if (p.materials[t] != current) current = p.materials[t], out << "usemtl mat" << current << "\n";
        out << "f";
        for (int k = 0; k < 3; ++k) out << " " << m.indices[3 * t + k] + 1 << "/" << m.indices[3 * t + k] + 1;
        out << "\n";
    }
    std::ofstream mtlOut((std::filesystem::path(path).parent_path() / mtl).string());
    for (int k = 0; k < 2; ++k) mtlOut << "newmtl mat" << k << "\nKd 1 1 1\n" << (texture.empty() ? "" : "map_Kd " + texture + "\n");
}

// A smooth RGB test image written with OpenImageIO-readable PNG via the formats codec.
inline Image testImage(uint32_t w, uint32_t h) {
    Image img{w, h, 3, {}};
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            img.pixels.insert(img.pixels.end(), {static_cast<uint8_t>(x * 255 / w), static_cast<uint8_t>(y * 255 / h), 128});
    return img;
}

// A gradient with texel noise: each texel distinct, and JPEG cannot code it exactly.
inline Image noisyImage(uint32_t side) {
    Image img = testImage(side, side);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<uint8_t>(img.pixels[i] / 2 + (i * 2654435761u >> 13) % 96);
    return img;
}

// Two UV charts (one of two triangles) over a 256 x 256 texture; the first reaches from texel 10.8.
inline MeshData chartsOver256() {
    MeshData m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 5, 5, 0, 6, 5, 0, 5, 6, 0};
    m.texcoords = {0.05f, 0.05f, 0.40f, 0.07f, 0.06f, 0.35f, 0.42f, 0.38f, 0.60f, 0.55f, 0.95f, 0.60f, 0.65f, 0.90f};
    m.indices = {0, 1, 2, 1, 3, 2, 4, 5, 6};
    return m;
}

// Base64 (RFC 4648, padded), for data URIs.
inline std::string base64(const std::vector<uint8_t>& in) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        const uint32_t n = (in[i] << 16) | ((i + 1 < in.size() ? in[i + 1] : 0) << 8) | (i + 2 < in.size() ? in[i + 2] : 0);
        out += table[(n >> 18) & 63], out += table[(n >> 12) & 63];
        out += i + 1 < in.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? table[n & 63] : '=';
    }
    return out;
}

// A glTF of one textured triangle (positions and UVs in a data URI, image 0 a 32 x 32 PNG):
// `materials` and `textures` are the contents of those arrays, `extra` further members.
inline std::string texturedTriangleGltf(const std::string& materials, const std::string& textures, const std::string& extra = "") {
    const float values[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    const auto* p = reinterpret_cast<const uint8_t*>(values);
    const std::string image = base64(encodeTexture(testImage(32, 32), Codec::Png).bytes);
    return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
  "materials": [)" + materials + R"(],
  "buffers": [{"uri": "data:application/octet-stream;base64,)" + base64({p, p + sizeof values}) + R"(", "byteLength": 60}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}],)" + extra + R"(
  "textures": [)" + textures + R"(], "images": [{"uri": "data:image/png;base64,)" + image + R"("}]})";
}

// One triangle as glTF 2.0 JSON with one material, "skin": its 36-byte POSITION buffer at
// `bufferUri`, and when `imageUri` is given a base-colour texture (with TEXCOORD_0 from the same
// buffer's second half).
inline std::string triangleGltf(const std::string& bufferUri, const std::string& imageUri = "") {
    const std::string textured = imageUri.empty() ? "" : R"(, "TEXCOORD_0": 1)";
    std::string json = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0)" + textured + R"(}, "material": 0}]}],
  "materials": [{"name": "skin", "pbrMetallicRoughness": {)" + (imageUri.empty() ? "" : R"("baseColorTexture": {"index": 0})") + R"(}}],
  "buffers": [{"uri": ")" + bufferUri + R"(", "byteLength": 60}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}])";
    if (!imageUri.empty()) json += R"(, "textures": [{"source": 0}], "images": [{"uri": ")" + imageUri + R"("}])";
    return json + "}\n";
}

inline std::vector<uint8_t> triangleBuffer() {
    const float values[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    const auto* p = reinterpret_cast<const uint8_t*>(values);
    return {p, p + sizeof values};
}

// triangleBuffer() as a data: URI.
inline std::string triangleBufferDataUri() { return "data:application/octet-stream;base64," + base64(triangleBuffer()); }

// The InputError message `f` throws, or "" when it throws none.
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

inline std::string sharedDir() {
#ifdef HLOD_SHARED_DIR
    return HLOD_SHARED_DIR;
#else
    return "";
#endif
}

}  // namespace hlod::test
