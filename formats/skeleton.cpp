// Skeleton serialisation (FORMAT.md §Skeleton, §Header) and the skeleton's tree queries.
// Node links follow thesis §3.3 (first child / next sibling lists); cost is eq. 3.1. The META
// keys readers interpret (up, offset).
#include "formats/errors.h"
#include "formats/layout.h"
#include "formats/offset.h"
#include "formats/up_axis.h"

#include <xxhash.h>

#include <charconv>
#include <cmath>

namespace hlod {

namespace layout {

uint64_t checksum(std::span<const uint8_t> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

namespace {

void putNode(ByteWriter& w, const Node& n) {
    for (uint32_t v : {n.id, n.parent, n.firstChild, n.nextSibling, n.level, n.block}) w.put(v);
    for (float v : {n.bounds.min.x, n.bounds.min.y, n.bounds.min.z, n.bounds.max.x, n.bounds.max.y,
                    n.bounds.max.z, n.cost, n.staticBenefit, n.avgNormal.x, n.avgNormal.y, n.avgNormal.z,
                    n.geometricError})
        w.put(v);
    for (uint32_t v : {n.texturedTriangles, n.untexturedTriangles, n.vertexCount, n.firstBlob, n.blobCount, 0u})
        w.put(v);
    for (uint64_t v : {n.texelCount, n.dataOffset, n.dataSize}) w.put(v);
}

void putBlob(ByteWriter& w, const BlobRef& b) {
    for (uint8_t v : {uint8_t(b.kind), uint8_t(b.codec), b.attributes, b.channels, b.positionBits,
                      b.texcoordBits, b.normalBits, b.colorBits})
        w.put(v);
    for (uint32_t v : {b.node, b.texture, b.triangles, b.vertices, b.width, b.height}) w.put(v);
    for (uint64_t v : {b.offset, b.size, b.checksum}) w.put(v);
}

void putString(ByteWriter& w, const std::string& s) {
    w.put(uint32_t(s.size()));
    w.bytes({reinterpret_cast<const uint8_t*>(s.data()), s.size()});
}

struct Section {
    uint32_t tag, recordSize;
    uint64_t count;
    std::vector<uint8_t> bytes;
};

}  // namespace

std::vector<uint8_t> encodeSkeleton(const Skeleton& s) {
    std::vector<Section> sections(4);
    sections[0] = {kTagInfo, kInfoRecordSize, 1, {}};
    ByteWriter info{sections[0].bytes};
    info.put(s.blockCount);
    info.put(uint32_t(0));
    sections[1] = {kTagNode, kNodeRecordSize, s.nodes.size(), {}};
    ByteWriter nodes{sections[1].bytes};
    for (const Node& n : s.nodes) putNode(nodes, n);
    sections[2] = {kTagBlob, kBlobRecordSize, s.blobs.size(), {}};
    ByteWriter blobs{sections[2].bytes};
    for (const BlobRef& b : s.blobs) putBlob(blobs, b);
    sections[3] = {kTagMeta, 0, s.meta.size(), {}};
    ByteWriter meta{sections[3].bytes};
    for (const auto& [key, value] : s.meta) {
        putString(meta, key);
        putString(meta, value);
    }

    std::vector<uint8_t> out;
    ByteWriter w{out};
    w.put(uint32_t(sections.size()));
    w.put(kSectionEntrySize);
    uint64_t offset = 8 + sections.size() * kSectionEntrySize;
    for (const Section& sec : sections) {
        w.put(sec.tag);
        w.put(sec.recordSize);
        w.put(offset);
        w.put(uint64_t(sec.bytes.size()));
        w.put(sec.count);
        offset += sec.bytes.size();
    }
    for (const Section& sec : sections) w.bytes(sec.bytes);
    return out;
}

std::array<uint8_t, kHeaderSize> encodeHeader(uint64_t skeletonOffset, std::span<const uint8_t> skeleton) {
    std::array<uint8_t, kHeaderSize> h{};
    std::copy(kMagic.begin(), kMagic.end(), h.begin());
    store(std::span(h), kOffMajor, kFormatMajor);
    store(std::span(h), kOffMinor, kFormatMinor);
    store(std::span(h), kOffHeaderSize, kHeaderSize);
    store(std::span(h), kOffSkeletonOffset, skeletonOffset);
    store(std::span(h), kOffSkeletonSize, uint64_t(skeleton.size()));
    store(std::span(h), kOffSkeletonChecksum, checksum(skeleton));
    store(std::span(h), kOffFileSize, skeletonOffset + skeleton.size());
    store(std::span(h), kOffFlags, uint64_t(0));
    store(std::span(h), kHeaderSize - 8, checksum(std::span(h).first(kHeaderSize - 8)));
    return h;
}

}  // namespace layout

const std::string* Skeleton::findMeta(const std::string& key) const {
    for (const auto& kv : meta)
        if (kv.first == key) return &kv.second;
    return nullptr;
}

UpAxis upAxisOf(const Skeleton& skeleton, const std::string& name) {
    const std::string* up = skeleton.findMeta("up");
    if (!up) return {};
    if (*up != "y" && *up != "z") throw FormatError(name + ": META up '" + shownBytes(*up) + "' is neither y nor z");
    return {*up == "y" ? 1 : 2, true};
}

std::string offsetText(const Offset& offset) {
    std::string text;
    for (size_t k = 0; k < 3; ++k) {
        char digits[32];
        const auto [end, ec] = std::to_chars(digits, digits + sizeof digits, offset[k]);
        if (k) text += ',';
        text.append(digits, ec == std::errc() ? end : digits);
    }
    return text;
}

Offset parseOffset(const std::string& text, const std::string& option) {
    Offset offset{};
    const char* p = text.data();
    const char* const end = text.data() + text.size();
    for (size_t k = 0; k < 3; ++k) {
        const auto [next, ec] = std::from_chars(p, end, offset[k]);
        const bool separated = k < 2 ? next < end && *next == ',' : next == end;
        // Within the coordinates' own limit (1e15, pipeline.h kMaxCoordinate): a larger offset moves
        // every position past what a float holds, which the readers would blame on the input.
        if (ec != std::errc() || !(std::abs(offset[k]) <= 1e15) || !separated)
            throw std::invalid_argument(option + " '" + shownBytes(text) + "': expected X,Y,Z (three numbers within +-1e15)");
        p = next + 1;
    }
    return offset;
}

std::optional<Offset> offsetOf(const Skeleton& skeleton, const std::string& name) {
    const std::string* text = skeleton.findMeta("offset");
    if (!text) return std::nullopt;
    try {
        return parseOffset(*text, "META offset");
    } catch (const std::invalid_argument& e) {
        throw FormatError(name + ": " + e.what());
    }
}

int parseUpAxis(const std::string& text, const std::string& option) {
    if (text == "y") return 1;
    if (text == "z") return 2;
    throw std::invalid_argument(option + " '" + shownBytes(text) + "': y or z");
}

std::vector<uint32_t> Skeleton::roots() const {
    std::vector<uint32_t> out;
    for (const Node& n : nodes)
        if (n.parent == kNone) out.push_back(n.id);
    return out;
}

// Follows the sibling list from the first child; bounded by the node count so that a
// corrupt cycle cannot hang the caller.
std::vector<uint32_t> Skeleton::children(uint32_t id) const {
    std::vector<uint32_t> out;
    if (id >= nodes.size()) return out;
    for (uint32_t c = nodes[id].firstChild; c < nodes.size() && out.size() < nodes.size();
         c = nodes[c].nextSibling)
        out.push_back(c);
    return out;
}

float nodeCost(uint32_t texturedTriangles, uint32_t untexturedTriangles, double cTextured) {
    return float(texturedTriangles * cTextured + untexturedTriangles * (1 - cTextured));
}

}  // namespace hlod
