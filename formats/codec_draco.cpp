// Geometry blobs: one Draco-compressed mesh per sub-mesh (FORMAT.md §Geometry blobs).
// Positions on one power-of-two lattice (explicit Draco quantization, exact: see Lattice),
// texture coordinates, normals and colours with per-attribute quantization. The record's
// counts are those the decoder will produce, which can differ from the input's (Draco splits
// non-manifold vertices and drops unused vertices and faces with a repeated index): the
// encoder's own counts of encoded points and faces (SetTrackEncodedProperties; without it
// Draco 1.5 reports 0), equal to a decode's (Codec.CountsAreThoseOfTheDecodedMesh) without
// decoding the blob again.
#include "formats/codec.h"
#include "formats/draco_attribute.h"
#include "formats/layout.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>

namespace hlod {

namespace {

// Above 2^23 steps Draco's quantizer, floor(n + 0.5f) in float, is no longer exact.
constexpr int kMaxLatticeBits = 23;

double powerOfTwoAtMost(double v) {
    int exponent = 0;
    std::frexp(v, &exponent);
    return std::ldexp(1.0, exponent - 1);
}

// A blob's positions rounded to multiples of `step` (a power of two), the origin (the smallest
// multiple per axis) and the fewest bits covering them. Draco quantizes q = floor((x - origin) *
// (M / range) + 0.5f) and decodes q * (range / M) + origin, M = 2^bits - 1, in float: with
// range = step * M both factors are exactly step and 1 / step, x - origin is an exact multiple
// of step below 2^23 steps, so every snapped x decodes to itself, in every blob, bit for bit.
struct Lattice {
    std::vector<float> positions;
    float origin[3] = {0, 0, 0};
    float range = 1;
    int bits = 1;
};

Lattice snapToLattice(const std::vector<float>& positions, double step) {
    Lattice l;
    l.positions.resize(positions.size());
    float top[3] = {0, 0, 0};
    for (size_t i = 0; i < positions.size(); ++i) {
        // + 0.0: a coordinate rounding to 0 from below is +0, not -0, which Draco's deduplication
        // would keep apart from the +0 of the same vertex in another chart
        const float x = static_cast<float>(std::round(double(positions[i]) / step) * step + 0.0);
        const size_t c = i % 3;
        l.positions[i] = x;
        if (i < 3 || x < l.origin[c]) l.origin[c] = x;
        if (i < 3 || x > top[c]) top[c] = x;
    }
    double span = 0;  // in steps; compared as a double: a step too fine for the positions overflows any integer
    for (int c = 0; c < 3; ++c) span = std::max(span, (double(top[c]) - l.origin[c]) / step);
    if (!(span < std::ldexp(1.0, kMaxLatticeBits)))
        throw std::runtime_error("encodeGeometry: positions span " + std::to_string(span) + " steps of 2^" +
                                 std::to_string(std::ilogb(step)) + ", more than 2^23 (position lattice too fine)");
    l.bits = std::max(1, static_cast<int>(std::bit_width(static_cast<uint64_t>(span))));
    l.range = static_cast<float>(step * double((uint64_t(1) << l.bits) - 1));
    return l;
}

// Draco keeps option values as text written with std::to_string (6 decimals), which moves a
// small origin or range off the lattice; hexadecimal floats read back exactly.
std::string exactFloat(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%a", double(v));
    return text;
}

void setExactQuantization(draco::Encoder& encoder, const Lattice& l) {
    using GA = draco::GeometryAttribute;
    encoder.SetAttributeExplicitQuantization(GA::POSITION, l.bits, 3, l.origin, l.range);
    draco::Options options = *encoder.options().FindAttributeOptions(GA::POSITION);
    options.SetString("quantization_origin",
                      exactFloat(l.origin[0]) + " " + exactFloat(l.origin[1]) + " " + exactFloat(l.origin[2]));
    options.SetString("quantization_range", exactFloat(l.range));
    encoder.options().SetAttributeOptions(GA::POSITION, options);
}

Box3f boundsOf(const std::vector<float>& positions) {
    Box3f b{{positions[0], positions[1], positions[2]}, {positions[0], positions[1], positions[2]}};
    for (size_t i = 3; i + 2 < positions.size(); i += 3) {
        b.min = {std::min(b.min.x, positions[i]), std::min(b.min.y, positions[i + 1]), std::min(b.min.z, positions[i + 2])};
        b.max = {std::max(b.max.x, positions[i]), std::max(b.max.y, positions[i + 1]), std::max(b.max.z, positions[i + 2])};
    }
    return b;
}

template <class T>
void addAttribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, int components, draco::DataType dataType,
                  bool normalized, const std::vector<T>& values) {
    const size_t count = mesh.num_points();
    auto att = std::make_unique<draco::PointAttribute>();
    att->Init(type, int8_t(components), dataType, normalized, count);
    for (size_t i = 0; i < count; ++i)
        att->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), values.data() + i * components);
    mesh.AddAttribute(std::move(att));
}

void checkMesh(const MeshData& m) {
    const size_t n = m.vertexCount();
    if (m.positions.size() != n * 3 || n == 0 || m.indices.empty() || m.indices.size() % 3 != 0)
        throw std::runtime_error("encodeGeometry: mesh needs positions (3 per vertex) and triangles");
    if (n > layout::kMaxElements || m.triangleCount() > layout::kMaxElements)
        throw std::runtime_error("encodeGeometry: mesh too large for one blob");
    if ((!m.texcoords.empty() && m.texcoords.size() != n * 2) || (!m.normals.empty() && m.normals.size() != n * 3) ||
        (!m.colors.empty() && m.colors.size() != n * 4))
        throw std::runtime_error("encodeGeometry: attribute array sizes do not match the vertex count");
    for (uint32_t i : m.indices)
        if (i >= n) throw std::runtime_error("encodeGeometry: index out of range");
    for (float x : m.positions)
        if (!std::isfinite(x)) throw std::runtime_error("encodeGeometry: NaN/Inf position");
}

template <class T, int N>
std::vector<T> extract(const draco::Mesh& mesh, const draco::PointAttribute* att) {
    std::vector<T> out(size_t(mesh.num_points()) * N);
    T value[N];
    for (uint32_t p = 0; p < mesh.num_points(); ++p) {
        std::fill(value, value + N, T(N == 4 && std::is_same_v<T, uint8_t> ? 255 : 0));
        att->ConvertValue(att->mapped_index(draco::PointIndex(p)), int8_t(std::min<int>(N, att->num_components())),
                          value);
        std::copy(value, value + N, out.begin() + size_t(p) * N);
    }
    return out;
}

// The Draco mesh of `m` with its positions snapped; with `deduplicate`, equal attribute values and
// then equal points merged (DeduplicateAttributeValues, DeduplicatePointIds).
std::unique_ptr<draco::Mesh> dracoMesh(const MeshData& m, const std::vector<float>& positions, bool deduplicate) {
    auto mesh = std::make_unique<draco::Mesh>();
    mesh->set_num_points(uint32_t(m.vertexCount()));
    using GA = draco::GeometryAttribute;
    addAttribute(*mesh, GA::POSITION, 3, draco::DT_FLOAT32, false, positions);
    if (!m.texcoords.empty()) addAttribute(*mesh, GA::TEX_COORD, 2, draco::DT_FLOAT32, false, m.texcoords);
    if (!m.normals.empty()) addAttribute(*mesh, GA::NORMAL, 3, draco::DT_FLOAT32, false, m.normals);
    if (!m.colors.empty()) addAttribute(*mesh, GA::COLOR, 4, draco::DT_UINT8, true, m.colors);
    for (size_t t = 0; t < m.triangleCount(); ++t)
        mesh->AddFace({draco::PointIndex(m.indices[3 * t]), draco::PointIndex(m.indices[3 * t + 1]), draco::PointIndex(m.indices[3 * t + 2])});
    if (deduplicate) {
        mesh->DeduplicateAttributeValues();
        mesh->DeduplicatePointIds();
    }
    return mesh;
}

// Whether some face's corners are three distinct position values (what Draco's connectivity sees).
bool hasFaceOfThreePositions(const draco::Mesh& mesh) {
    const draco::PointAttribute* position = mesh.GetNamedAttribute(draco::GeometryAttribute::POSITION);
    for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
        const auto& face = mesh.face(f);
        const auto a = position->mapped_index(face[0]), b = position->mapped_index(face[1]), c = position->mapped_index(face[2]);
        if (a != b && b != c && a != c) return true;
    }
    return false;
}

}  // namespace

double positionLatticeStep(const Box3f& b, int positionBits) {
    const double side = std::max({double(b.max.x) - b.min.x, double(b.max.y) - b.min.y, double(b.max.z) - b.min.z});
    return powerOfTwoAtMost((side > 0 ? side : 1.0) / double((uint64_t(1) << positionBits) - 1));
}

int texcoordBitsForTexture(const std::vector<float>& texcoords, uint32_t width, uint32_t height) {
    float lo[2] = {0, 0}, hi[2] = {0, 0};
    for (size_t i = 0; i < texcoords.size(); ++i) {
        const size_t c = i % 2;
        if (i < 2 || texcoords[i] < lo[c]) lo[c] = texcoords[i];
        if (i < 2 || texcoords[i] > hi[c]) hi[c] = texcoords[i];
    }
    const double quarters = 4.0 * std::max(double(hi[0]) - lo[0], double(hi[1]) - lo[1]) * std::max(width, height);
    int bits = 1;
    while (bits < kMaxTexcoordBits && std::ldexp(1.0, bits) < quarters) ++bits;
    return bits;
}

EncodedBlob encodeGeometry(const MeshData& m, const DracoOptions& o) {
    checkMesh(m);
    if (!m.texcoords.empty() && (o.texcoordBits < 1 || o.texcoordBits > kMaxTexcoordBits))
        throw std::runtime_error("encodeGeometry: texcoordBits must be 1.." + std::to_string(kMaxTexcoordBits));
    if (o.positionBits < 1 || o.positionBits > kMaxPositionBits || !(o.positionStep >= 0) || !std::isfinite(o.positionStep))
        throw std::runtime_error("encodeGeometry: positionBits must be 1.." + std::to_string(kMaxPositionBits) +
                                 " and positionStep finite and >= 0");
    const double step = o.positionStep > 0 ? powerOfTwoAtMost(o.positionStep) : positionLatticeStep(boundsOf(m.positions), o.positionBits);
    const Lattice lattice = snapToLattice(m.positions, step);
    // A vertex split only by another attribute (a UV chart's seam) keeps one position: Draco then
    // codes the surface's connectivity and positions once, with attribute seams, instead of each
    // chart as a piece of its own whose border positions are coded again (FORMAT.md §Geometry
    // blobs). Its connectivity is that of the positions, so a face two of whose corners share a
    // lattice position (zero area as decoded) goes, as Draco drops a face with a repeated index;
    // when every face would, they are kept as they were. Positions alone have no seams (and the
    // build welds them): nothing to gain, time to lose.
    const bool seams = !m.texcoords.empty() || !m.normals.empty() || !m.colors.empty();
    std::unique_ptr<draco::Mesh> mesh = dracoMesh(m, lattice.positions, seams);
    if (seams && !hasFaceOfThreePositions(*mesh)) mesh = dracoMesh(m, lattice.positions, false);

    draco::Encoder encoder;
    setExactQuantization(encoder, lattice);
    using GA = draco::GeometryAttribute;
    encoder.SetAttributeQuantization(GA::TEX_COORD, o.texcoordBits);
    encoder.SetAttributeQuantization(GA::NORMAL, o.normalBits);
    encoder.SetSpeedOptions(10 - o.compressionLevel, 10 - o.compressionLevel);
    encoder.SetTrackEncodedProperties(true);
    draco::EncoderBuffer buffer;
    draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
    if (!status.ok()) throw std::runtime_error("encodeGeometry: Draco: " + status.error_msg_string());

    EncodedBlob blob;
    blob.bytes.assign(buffer.data(), buffer.data() + buffer.size());
    BlobRef& r = blob.info;
    r.kind = BlobKind::Geometry;
    r.codec = Codec::Draco;
    r.triangles = uint32_t(encoder.num_encoded_faces());
    r.vertices = uint32_t(encoder.num_encoded_points());
    r.attributes = kAttrPosition | (m.texcoords.empty() ? 0 : kAttrTexcoord) | (m.normals.empty() ? 0 : kAttrNormal) |
                   (m.colors.empty() ? 0 : kAttrColor);
    r.positionBits = uint8_t(lattice.bits);
    r.texcoordBits = m.texcoords.empty() ? 0 : uint8_t(o.texcoordBits);
    r.normalBits = m.normals.empty() ? 0 : uint8_t(o.normalBits);
    r.colorBits = m.colors.empty() ? 0 : 8;
    return blob;
}

MeshData decodeGeometry(std::span<const uint8_t> bytes, const std::string& name) {
    const std::unique_ptr<draco::Mesh> decoded = decodeDracoMesh(bytes, name);
    const draco::Mesh& mesh = *decoded;
    using GA = draco::GeometryAttribute;
    const draco::PointAttribute* pos = checkedDracoAttribute(mesh, GA::POSITION, draco::DT_FLOAT32, 3, 3, name);
    if (!pos) throw FormatError(name + ": Draco geometry has no positions");
    if (mesh.num_points() > layout::kMaxElements || mesh.num_faces() > layout::kMaxElements)
        throw FormatError(name + ": Draco geometry is absurdly large");

    MeshData m;
    m.positions = extract<float, 3>(mesh, pos);
    if (auto* a = checkedDracoAttribute(mesh, GA::TEX_COORD, draco::DT_FLOAT32, 2, 2, name))
        m.texcoords = extract<float, 2>(mesh, a);
    if (auto* a = checkedDracoAttribute(mesh, GA::NORMAL, draco::DT_FLOAT32, 3, 3, name))
        m.normals = extract<float, 3>(mesh, a);
    if (auto* a = checkedDracoAttribute(mesh, GA::COLOR, draco::DT_UINT8, 3, 4, name))
        m.colors = extract<uint8_t, 4>(mesh, a);
    m.indices.reserve(size_t(mesh.num_faces()) * 3);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = mesh.face(draco::FaceIndex(f))[k].value();
            if (v >= mesh.num_points()) throw FormatError(name + ": Draco geometry has an index out of range");
            m.indices.push_back(v);
        }
    return m;
}

const draco::PointAttribute* checkedDracoAttribute(const draco::Mesh& mesh, draco::GeometryAttribute::Type type,
                                                   draco::DataType dataType, int minComponents, int maxComponents,
                                                   const std::string& name) {
    const draco::PointAttribute* a = mesh.GetNamedAttribute(type);
    if (a && (a->data_type() != dataType || a->num_components() < minComponents || a->num_components() > maxComponents))
        throw FormatError(name + ": Draco geometry has an attribute of unexpected type or size");
    return a;
}

// FORMAT.md's geometry blob is a Draco 1.5 mesh: bitstream 2.2 ("DRACO", major 2, minor 2,
// encoder type 1 = mesh), its connectivity edgebreaker (method 1) or, at --draco-level 0,
// sequential (method 0). Other headers are refused before Draco sees them: its decoders for older
// bitstreams reserve what a header claims before reading it (the blob fuzzer's 100-byte 1.253
// header asked for 4.5 GB and took 5 s to fail).
std::unique_ptr<draco::Mesh> decodeDracoMesh(std::span<const uint8_t> bytes, const std::string& name) {
    constexpr uint8_t kHeader[8] = {'D', 'R', 'A', 'C', 'O', 2, 2, 1};
    if (bytes.size() <= sizeof kHeader || !std::equal(kHeader, kHeader + sizeof kHeader, bytes.begin()) || bytes[8] > 1)
        throw FormatError(name + ": bad Draco geometry: not a Draco 2.2 mesh (FORMAT.md)");
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    draco::Decoder decoder;
    auto result = decoder.DecodeMeshFromBuffer(&buffer);
    if (!result.ok()) throw FormatError(name + ": bad Draco geometry: " + result.status().error_msg_string());
    return std::move(result).value();
}

}  // namespace hlod
