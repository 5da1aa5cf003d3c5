// Geometry blobs: one Draco-compressed mesh per sub-mesh (FORMAT.md §Geometry blobs).
// Positions, texture coordinates, normals and colours with per-attribute quantization; the
// record's counts come from decoding the encoded bytes, so they match what a reader gets.
#include "formats/codec.h"
#include "formats/layout.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

namespace hlod {

namespace {

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
}

// Only the attribute layouts hlod writes are accepted (a corrupt stream may declare others,
// e.g. bool attributes whose bytes are not valid bools).
const draco::PointAttribute* attribute(const draco::Mesh& mesh, draco::GeometryAttribute::Type type,
                                       draco::DataType dataType, int minComponents, int maxComponents,
                                       const std::string& name) {
    const draco::PointAttribute* a = mesh.GetNamedAttribute(type);
    if (a && (a->data_type() != dataType || a->num_components() < minComponents || a->num_components() > maxComponents))
        throw FormatError(name + ": Draco geometry has an attribute of unexpected type or size");
    return a;
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

}  // namespace

EncodedBlob encodeGeometry(const MeshData& m, const DracoOptions& o) {
    checkMesh(m);
    draco::Mesh mesh;
    mesh.set_num_points(uint32_t(m.vertexCount()));
    using GA = draco::GeometryAttribute;
    addAttribute(mesh, GA::POSITION, 3, draco::DT_FLOAT32, false, m.positions);
    if (!m.texcoords.empty()) addAttribute(mesh, GA::TEX_COORD, 2, draco::DT_FLOAT32, false, m.texcoords);
    if (!m.normals.empty()) addAttribute(mesh, GA::NORMAL, 3, draco::DT_FLOAT32, false, m.normals);
    if (!m.colors.empty()) addAttribute(mesh, GA::COLOR, 4, draco::DT_UINT8, true, m.colors);
    for (size_t t = 0; t < m.triangleCount(); ++t)
        mesh.AddFace({draco::PointIndex(m.indices[3 * t]), draco::PointIndex(m.indices[3 * t + 1]),
                      draco::PointIndex(m.indices[3 * t + 2])});

    draco::Encoder encoder;
    encoder.SetAttributeQuantization(GA::POSITION, o.positionBits);
    encoder.SetAttributeQuantization(GA::TEX_COORD, o.texcoordBits);
    encoder.SetAttributeQuantization(GA::NORMAL, o.normalBits);
    encoder.SetSpeedOptions(10 - o.compressionLevel, 10 - o.compressionLevel);
    draco::EncoderBuffer buffer;
    draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
    if (!status.ok()) throw std::runtime_error("encodeGeometry: Draco: " + status.error_msg_string());

    EncodedBlob blob;
    blob.bytes.assign(buffer.data(), buffer.data() + buffer.size());
    MeshData decoded = decodeGeometry(blob.bytes, "encodeGeometry");
    BlobRef& r = blob.info;
    r.kind = BlobKind::Geometry;
    r.codec = Codec::Draco;
    r.triangles = uint32_t(decoded.triangleCount());
    r.vertices = uint32_t(decoded.vertexCount());
    r.attributes = kAttrPosition | (m.texcoords.empty() ? 0 : kAttrTexcoord) | (m.normals.empty() ? 0 : kAttrNormal) |
                   (m.colors.empty() ? 0 : kAttrColor);
    r.positionBits = uint8_t(o.positionBits);
    r.texcoordBits = m.texcoords.empty() ? 0 : uint8_t(o.texcoordBits);
    r.normalBits = m.normals.empty() ? 0 : uint8_t(o.normalBits);
    r.colorBits = m.colors.empty() ? 0 : 8;
    return blob;
}

MeshData decodeGeometry(std::span<const uint8_t> bytes, const std::string& name) {
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    draco::Decoder decoder;
    auto result = decoder.DecodeMeshFromBuffer(&buffer);
    if (!result.ok()) throw FormatError(name + ": bad Draco geometry: " + result.status().error_msg_string());
    const draco::Mesh& mesh = *result.value();
    using GA = draco::GeometryAttribute;
    const draco::PointAttribute* pos = attribute(mesh, GA::POSITION, draco::DT_FLOAT32, 3, 3, name);
    if (!pos) throw FormatError(name + ": Draco geometry has no positions");
    if (mesh.num_points() > layout::kMaxElements || mesh.num_faces() > layout::kMaxElements)
        throw FormatError(name + ": Draco geometry is absurdly large");

    MeshData m;
    m.positions = extract<float, 3>(mesh, pos);
    if (auto* a = attribute(mesh, GA::TEX_COORD, draco::DT_FLOAT32, 2, 2, name)) m.texcoords = extract<float, 2>(mesh, a);
    if (auto* a = attribute(mesh, GA::NORMAL, draco::DT_FLOAT32, 3, 3, name)) m.normals = extract<float, 3>(mesh, a);
    if (auto* a = attribute(mesh, GA::COLOR, draco::DT_UINT8, 3, 4, name)) m.colors = extract<uint8_t, 4>(mesh, a);
    m.indices.reserve(size_t(mesh.num_faces()) * 3);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = mesh.face(draco::FaceIndex(f))[k].value();
            if (v >= mesh.num_points()) throw FormatError(name + ": Draco geometry has an index out of range");
            m.indices.push_back(v);
        }
    return m;
}

}  // namespace hlod
