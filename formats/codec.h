// Blob codecs: Draco for geometry, JPEG/PNG (libjpeg-turbo, libpng: formats/image_io.h) for textures.
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

// Positions are quantized on one lattice (FORMAT.md §Geometry blobs): every coordinate is
// rounded to the nearest multiple of `positionStep` (a power of two, absolute coordinates), so an
// input float gives the same decoded float in every blob encoded with the same step, whatever the
// blob's extent: neighbouring nodes keep their shared borders exactly. Each blob then uses the
// fewest bits that cover its own extent on that lattice (recorded as its positionBits).
inline constexpr int kMaxPositionBits = 22;  // the coarsest node needs one more, 23 = exact limit
// The coarsest lattice: 2^8 steps across a block (a step of 1 on a model 0.2 across collapsed it
// to one empty node, exit 0, until stop 45).
inline constexpr int kMinPositionBits = 8;
// Draco quantizes up to 30 bits, but its entropy coder sizes a histogram by the largest symbol
// (4 B each): 30 bits took 4 GiB on a node whose UVs span 10^9 (a stray UV), 22 bits is 16 MiB.
inline constexpr int kMaxTexcoordBits = 22;
inline constexpr int kMaxDecodablePositionBits = 23;  // a blob record's positionBits (FORMAT.md), checked by validate

struct DracoOptions {
    int positionBits = 14;     // 1..kMaxPositionBits; see README "Draco and JPEG defaults" for the measurements
    double positionStep = 0;   // lattice step, rounded down to a power of two; 0 = positionLatticeStep
                               // of the blob's own bounds (a blob encoded on its own)
    int texcoordBits = 12;     // 1..kMaxTexcoordBits (a build picks them per blob: texcoordBitsForTexture)
    int normalBits = 8;
    int colorBits = 8;
    int compressionLevel = 7;  // 0..10 (Draco's speed = 10 - level)
};

// Texture coordinate bits for a blob textured by a width x height image: the fewest with 2^bits
// >= 4 x the UVs' extent in texels along the image's longer side (Draco quantizes both components
// over their largest extent), i.e. a step of a quarter texel (within 2^-bits of it) whatever the
// image's size; 1..kMaxTexcoordBits (coarser on a span beyond 2^20 texels). A fixed 12 is a
// quarter texel at 1024², a whole texel at 4096², a sixteenth at 256² (README "Draco and JPEG defaults").
int texcoordBitsForTexture(const std::vector<float>& texcoords, uint32_t width, uint32_t height);

// 8-bit pixels, row-major, `channels` interleaved (1 grey, 3 RGB, 4 RGBA).
struct Image {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
};

// The lattice step that gives geometry within `bounds` at least `positionBits` bits over its
// largest side: the largest power of two <= that side / (2^positionBits - 1).
double positionLatticeStep(const Box3f& bounds, int positionBits);

// Encode; the returned blob has kind, codec and counts filled in. Throw std::runtime_error.
EncodedBlob encodeGeometry(const MeshData& mesh, const DracoOptions& options);
// JPEG chroma at full resolution (4:4:4, 8 x 8 blocks in every channel) or, with chroma420, halved
// per axis (4:2:0, 16 x 16 blocks of colour).
EncodedBlob encodeTexture(const Image& image, Codec codec, int jpegQuality = 90, bool chroma420 = false);

// Decode; throw FormatError("NAME: problem") on malformed input. `name` names the source.
MeshData decodeGeometry(std::span<const uint8_t> bytes, const std::string& name);
Image decodeTexture(std::span<const uint8_t> bytes, Codec codec, const std::string& name);

}  // namespace hlod
