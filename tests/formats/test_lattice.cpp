// Geometry blobs quantize positions on one power-of-two lattice (FORMAT.md §Geometry blobs):
// a vertex shared by two blobs of different extents and origins decodes to the same float in
// both, bit for bit, including small coordinates (which Draco's text options would round);
// small blobs use fewer bits; the record's counts are those of the decoded mesh.
#include "helpers.h"

#include <array>
#include <cmath>
#include <random>
#include <set>

namespace hlod::test {
namespace {

using Point = std::array<float, 3>;

std::set<Point> decodedPoints(const EncodedBlob& blob) {
    const MeshData m = decodeGeometry(blob.bytes, "blob");
    std::set<Point> points;
    for (size_t v = 0; v < m.vertexCount(); ++v)
        points.insert({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
    return points;
}

// A strip of 2 n triangles between the shared column `border` and a column offset by `dx`.
MeshData strip(const std::vector<Point>& border, float dx) {
    MeshData m;
    for (const Point& p : border) m.positions.insert(m.positions.end(), {p[0], p[1], p[2]});
    for (const Point& p : border) m.positions.insert(m.positions.end(), {p[0] + dx, p[1], p[2] + 0.5f * dx});
    const uint32_t n = static_cast<uint32_t>(border.size());
    for (uint32_t i = 0; i + 1 < n; ++i)
        m.indices.insert(m.indices.end(), {i, i + 1, n + i + 1, i, n + i + 1, n + i});
    return m;
}

// Two neighbouring blobs, one 90 times wider than the other, share `border` (random floats, not
// on the lattice): with the same step, every shared vertex decodes to round(x / step) * step in
// both. Scales cover small coordinates (origin and range below Draco's 6 printed decimals) and
// large ones.
TEST(Codec, SharedVerticesDecodeIdenticallyOnOneLattice) {
    std::mt19937 rng(7);
    for (float scale : {0.003f, 1.0f, 700.0f}) {
        std::uniform_real_distribution<float> along(0.40f * scale, 0.41f * scale), height(-0.002f * scale, 0.002f * scale);
        std::vector<Point> border;
        for (int i = 0; i < 64; ++i) border.push_back({0.37f * scale, along(rng), height(rng)});
        std::sort(border.begin(), border.end(), [](const Point& a, const Point& b) { return a[1] < b[1]; });
        DracoOptions o;
        o.positionStep = positionLatticeStep({{0, 0, 0}, {scale, scale, scale}}, o.positionBits);
        const EncodedBlob narrow = encodeGeometry(strip(border, -0.01f * scale), o);
        const EncodedBlob wide = encodeGeometry(strip(border, 0.9f * scale), o);
        EXPECT_LT(narrow.info.positionBits, wide.info.positionBits) << scale;
        EXPECT_LE(wide.info.positionBits, o.positionBits + 1) << scale;
        const std::set<Point> a = decodedPoints(narrow), b = decodedPoints(wide);
        for (const Point& p : border) {
            Point snapped;
            for (int c = 0; c < 3; ++c)
                snapped[c] = static_cast<float>(std::round(double(p[c]) / o.positionStep) * o.positionStep);
            EXPECT_TRUE(a.count(snapped)) << "scale " << scale << ": narrow blob moved " << p[1];
            EXPECT_TRUE(b.count(snapped)) << "scale " << scale << ": wide blob moved " << p[1];
        }
    }
}

TEST(Codec, LatticeStepIsAPowerOfTwoKeepingTheConfiguredBits) {
    const double step = positionLatticeStep({{0, 0, 0}, {100, 3, 1}}, 14);
    EXPECT_EQ(step, std::ldexp(1.0, -8));  // 100 / 16383 = 0.0061 -> 2^-8 = 0.0039
    DracoOptions o;
    o.positionStep = 0.005;  // rounded down to 2^-8
    const EncodedBlob blob = encodeGeometry(gridMesh(4, 0, 100), o);
    EXPECT_EQ(blob.info.positionBits, 15);  // 100 / 2^-8 = 25600 steps
    o.positionStep = 0;  // the blob's own bounds: the same step
    EXPECT_EQ(encodeGeometry(gridMesh(4, 0, 100), o).bytes, blob.bytes);
}

TEST(Codec, RejectsLatticesBeyondExactFloatQuantization) {
    DracoOptions o;
    o.positionStep = std::ldexp(1.0, -20);  // a side of 100 m is 100 * 2^20 > 2^23 steps
    try {
        encodeGeometry(gridMesh(2, 0, 100), o);
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("more than 2^23"), std::string::npos) << e.what();
    }
    o.positionStep = 0;
    o.positionBits = kMaxPositionBits + 1;
    EXPECT_THROW(encodeGeometry(gridMesh(2), o), std::runtime_error);
    MeshData nan = gridMesh(2);
    nan.positions[4] = std::nanf("");
    EXPECT_THROW(encodeGeometry(nan, {}), std::runtime_error);
}

// The record's counts are the encoder's (not a decode of the blob): they must be the decoded
// mesh's in every case where Draco's output differs from its input. A bowtie (a vertex shared by
// two fans) is split into two vertices; an unused vertex and a face with a repeated index are
// dropped; a texture seam (one position, two texture coordinates) and per-vertex normals and
// colours; every compression level (0 is Draco's sequential coder, the others edgebreaker).
TEST(Codec, CountsAreThoseOfTheDecodedMesh) {
    MeshData bowtie;
    bowtie.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
    bowtie.indices = {0, 1, 2, 0, 3, 4};
    MeshData unused = gridMesh(3);
    unused.positions.insert(unused.positions.end(), {5, 5, 5});
    unused.texcoords.insert(unused.texcoords.end(), {0.5f, 0.5f});
    MeshData degenerate = gridMesh(3);
    degenerate.indices.insert(degenerate.indices.end(), {0, 0, 5, 1, 2, 1});
    MeshData seam = gridMesh(4);
    seam.texcoords.clear();
    for (size_t v = 0; v < seam.vertexCount(); ++v) {
        seam.texcoords.insert(seam.texcoords.end(), {seam.positions[3 * v] * 0.25f, seam.positions[3 * v + 1] * 0.25f});
        seam.normals.insert(seam.normals.end(), {0, 0, 1});
        seam.colors.insert(seam.colors.end(), {uint8_t(v * 9), 100, 200, 255});
    }
    const uint32_t n = uint32_t(seam.vertexCount());  // vertex 0's position again, other attributes
    seam.positions.insert(seam.positions.end(), seam.positions.begin(), seam.positions.begin() + 3);
    seam.texcoords.insert(seam.texcoords.end(), {0.9f, 0.9f});
    seam.normals.insert(seam.normals.end(), {0, 1, 0});
    seam.colors.insert(seam.colors.end(), {1, 2, 3, 255});
    for (uint32_t& i : seam.indices)
        if (i == 0) i = n;
    seam.indices.insert(seam.indices.end(), {0, 1, 6});
    const std::vector<std::pair<const char*, const MeshData*>> meshes = {
        {"bowtie", &bowtie}, {"unused", &unused}, {"degenerate", &degenerate}, {"seam", &seam}};
    for (int level : {0, 1, 7, 10})
        for (const auto& [name, mesh] : meshes) {
            DracoOptions o;
            o.compressionLevel = level;
            const EncodedBlob blob = encodeGeometry(*mesh, o);
            const MeshData decoded = decodeGeometry(blob.bytes, name);
            EXPECT_EQ(blob.info.vertices, decoded.vertexCount()) << name << " level " << level;
            EXPECT_EQ(blob.info.triangles, decoded.triangleCount()) << name << " level " << level;
            if (level != 7) continue;
            if (mesh == &bowtie) {
                EXPECT_EQ(decoded.vertexCount(), 6u);
            } else if (mesh == &unused) {
                EXPECT_EQ(decoded.vertexCount(), mesh->vertexCount() - 1);
            } else if (mesh == &degenerate) {
                EXPECT_EQ(decoded.triangleCount(), mesh->triangleCount() - 2);
            }
        }
}

}  // namespace
}  // namespace hlod::test
