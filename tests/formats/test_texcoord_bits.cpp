// Texture coordinate bits chosen per blob from its texture's size (texcoordBitsForTexture,
// formats/codec.h): a quarter-texel step whatever the size, so a decoded UV is within an eighth of
// a texel of the one given; a fixed 12 bits, the default before, misses that at 4096².
#include "helpers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

namespace hlod::test {
namespace {

// Largest distance, in texels along `side`, between a decoded UV and the UV given for the same
// vertex (matched by position: every vertex of gridMesh has its own).
double largestUvError(const MeshData& in, int bits, uint32_t side) {
    DracoOptions o;
    o.texcoordBits = bits;
    const MeshData out = decodeGeometry(encodeGeometry(in, o).bytes, "blob");
    std::map<std::pair<float, float>, std::pair<float, float>> uvAt;
    for (size_t v = 0; v < in.vertexCount(); ++v)
        uvAt[{in.positions[3 * v], in.positions[3 * v + 1]}] = {in.texcoords[2 * v], in.texcoords[2 * v + 1]};
    double largest = 0;
    for (size_t v = 0; v < out.vertexCount(); ++v) {
        const auto& [u, w] = uvAt.at({out.positions[3 * v], out.positions[3 * v + 1]});
        largest = std::max({largest, std::abs(double(out.texcoords[2 * v]) - u) * side, std::abs(double(out.texcoords[2 * v + 1]) - w) * side});
    }
    return largest;
}

TEST(TexcoordBits, AQuarterTexelOfTheLongerSide) {
    const std::vector<float> whole = {0, 0, 1, 0, 1, 1};  // UVs over the whole texture
    EXPECT_EQ(texcoordBitsForTexture(whole, 256, 256), 10);
    EXPECT_EQ(texcoordBitsForTexture(whole, 1024, 1024), 12);
    EXPECT_EQ(texcoordBitsForTexture(whole, 4096, 4096), 14);
    EXPECT_EQ(texcoordBitsForTexture(whole, 256, 4096), 14);
    EXPECT_EQ(texcoordBitsForTexture(whole, 1000, 600), 12);  // 4,000 quarters: 2^12 = 4,096
    EXPECT_EQ(texcoordBitsForTexture({0.25f, 0.5f, 0.75f, 0.5f}, 1024, 1024), 11);  // half the texture wide
    EXPECT_EQ(texcoordBitsForTexture({0.5f, 0.5f, 0.5f, 0.5f}, 1024, 1024), 1);     // one UV
    EXPECT_EQ(texcoordBitsForTexture(whole, 1u << 20, 1u << 20), 22);               // 2^22 quarters
    EXPECT_EQ(texcoordBitsForTexture({0, 0, 1e9f, 1}, 64, 64), kMaxTexcoordBits);    // a stray UV: capped
}

TEST(TexcoordBits, DecodedUvsStayWithinAnEighthTexel) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> uv(0, 1);
    MeshData mesh = gridMesh(24);
    for (size_t v = 0; v < mesh.vertexCount(); ++v)  // integer positions: on the lattice, each vertex its own
        std::copy_n(std::array<float, 3>{float(v % 25), float(v / 25), 0}.data(), 3, &mesh.positions[3 * v]);
    for (float& t : mesh.texcoords) t = uv(random);
    for (uint32_t side : {256u, 1024u, 4096u, 16384u}) {
        const int bits = texcoordBitsForTexture(mesh.texcoords, side, side);
        EXPECT_LE(largestUvError(mesh, bits, side), 0.125 * (1 + 1e-3)) << side;
    }
    EXPECT_GT(largestUvError(mesh, 12, 4096), 0.25);  // the fixed 12 bits: up to half a texel
}

TEST(TexcoordBits, EncodeRefusesBitsOutsideDracosRange) {
    DracoOptions o;
    o.texcoordBits = 0;
    EXPECT_THROW(encodeGeometry(gridMesh(2), o), std::runtime_error);
    o.texcoordBits = kMaxTexcoordBits + 1;  // 23: Draco would take 31, at up to 4 B per possible symbol
    EXPECT_THROW(encodeGeometry(gridMesh(2), o), std::runtime_error);
    MeshData untextured = gridMesh(2);
    untextured.texcoords.clear();
    o.texcoordBits = 0;  // no texture coordinates: the bits do not matter
    EXPECT_NO_THROW(encodeGeometry(untextured, o));
}

}  // namespace
}  // namespace hlod::test
