// Blob codecs: Draco for geometry, JPEG/PNG (OpenImageIO) for textures.
#pragma once

#include "formats/db.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hlod {

// An indexed triangle mesh with optional per-vertex attributes (empty vector = absent).
struct MeshData {
    std::vector<float> positions;   // 3 per vertex
    std::vector<float> texcoords;   // 2 per vertex
    std::vector<float> normals;     // 3 per vertex
    std::vector<uint8_t> colors;    // 4 per vertex (RGBA)
    std::vector<uint32_t> indices;  // 3 per triangle

    size_t vertexCount() const { return positions.size() / 3; }
    size_t triangleCount() const { return indices.size() / 3; }
};

struct DracoOptions {
    int positionBits = 14;   // see README "Draco defaults" for the measurements behind them
    int texcoordBits = 12;
    int normalBits = 8;
    int colorBits = 8;
    int compressionLevel = 7;  // 0..10 (Draco's speed = 10 - level)
};

// 8-bit pixels, row-major, `channels` interleaved (1 grey, 3 RGB, 4 RGBA).
struct Image {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
};

// Encode; the returned blob has kind, codec and counts filled in. Throw std::runtime_error.
EncodedBlob encodeGeometry(const MeshData& mesh, const DracoOptions& options);
EncodedBlob encodeTexture(const Image& image, Codec codec, int jpegQuality = 90);

// Decode; throw FormatError("NAME: problem") on malformed input. `name` names the source.
MeshData decodeGeometry(std::span<const uint8_t> bytes, const std::string& name);
Image decodeTexture(std::span<const uint8_t> bytes, Codec codec, const std::string& name);

}  // namespace hlod
