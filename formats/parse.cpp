// Reader side of FORMAT.md: header and skeleton parsing. Nothing read from the file (offset,
// size, count, index) is trusted before it is checked against the file size and the limits of
// layout.h; newer minor versions are read by skipping unknown sections and record tails.
#include "formats/layout.h"

#include <cmath>

namespace hlod {

using namespace layout;

namespace {

std::string str(uint64_t v) { return std::to_string(v); }

// a + b <= limit without overflow.
bool fits(uint64_t a, uint64_t b, uint64_t limit) { return a <= limit && b <= limit - a; }

struct SectionEntry {
    uint32_t tag = 0, recordSize = 0;
    uint64_t offset = 0, size = 0, count = 0;
};

Node getNode(ByteReader& r) {
    Node n;
    n.id = r.get<uint32_t>();
    n.parent = r.get<uint32_t>();
    n.firstChild = r.get<uint32_t>();
    n.nextSibling = r.get<uint32_t>();
    n.level = r.get<uint32_t>();
    n.block = r.get<uint32_t>();
    for (float* f : {&n.bounds.min.x, &n.bounds.min.y, &n.bounds.min.z, &n.bounds.max.x, &n.bounds.max.y,
                     &n.bounds.max.z, &n.cost, &n.staticBenefit, &n.avgNormal.x, &n.avgNormal.y,
                     &n.avgNormal.z, &n.geometricError})
        *f = r.get<float>();
    n.texturedTriangles = r.get<uint32_t>();
    n.untexturedTriangles = r.get<uint32_t>();
    n.vertexCount = r.get<uint32_t>();
    n.firstBlob = r.get<uint32_t>();
    n.blobCount = r.get<uint32_t>();
    r.get<uint32_t>();  // reserved
    n.texelCount = r.get<uint64_t>();
    n.dataOffset = r.get<uint64_t>();
    n.dataSize = r.get<uint64_t>();
    return n;
}

BlobRef getBlob(ByteReader& r) {
    BlobRef b;
    b.kind = BlobKind(r.get<uint8_t>());
    b.codec = Codec(r.get<uint8_t>());
    b.attributes = r.get<uint8_t>();
    b.channels = r.get<uint8_t>();
    b.positionBits = r.get<uint8_t>();
    b.texcoordBits = r.get<uint8_t>();
    b.normalBits = r.get<uint8_t>();
    b.colorBits = r.get<uint8_t>();
    b.node = r.get<uint32_t>();
    b.texture = r.get<uint32_t>();
    b.triangles = r.get<uint32_t>();
    b.vertices = r.get<uint32_t>();
    b.width = r.get<uint32_t>();
    b.height = r.get<uint32_t>();
    b.offset = r.get<uint64_t>();
    b.size = r.get<uint64_t>();
    b.checksum = r.get<uint64_t>();
    return b;
}

std::string getString(ByteReader& r) {
    uint32_t n = r.get<uint32_t>();
    if (n > kMaxMetaString) throw FormatError(r.name + ": metadata string of " + str(n) + " bytes is too long");
    auto s = r.take(n);
    return {s.begin(), s.end()};
}

// Record sections: `known` is this version's record size; a bigger record (newer minor
// version) is read by its known prefix, a smaller one is an error.
template <class T, class Get>
std::vector<T> readRecords(std::span<const uint8_t> skel, const SectionEntry& e, uint32_t known, Get get,
                           const std::string& name, const char* what) {
    if (e.recordSize < known)
        throw FormatError(name + ": " + what + " record size " + str(e.recordSize) + " is smaller than " +
                          str(known));
    if (e.count > e.size / e.recordSize || e.count * e.recordSize != e.size)
        throw FormatError(name + ": " + what + " section size " + str(e.size) + " does not match " + str(e.count) +
                          " records of " + str(e.recordSize) + " bytes");
    std::vector<T> out;
    out.reserve(e.count);
    for (uint64_t i = 0; i < e.count; ++i) {
        ByteReader r{skel.subspan(e.offset + i * e.recordSize, known), name, what};
        out.push_back(get(r));
    }
    return out;
}

std::vector<SectionEntry> readSectionTable(std::span<const uint8_t> skel, const std::string& name) {
    ByteReader r{skel, name, "skeleton section table"};
    uint32_t count = r.get<uint32_t>();
    uint32_t entrySize = r.get<uint32_t>();
    if (count > kMaxSections) throw FormatError(name + ": skeleton claims " + str(count) + " sections");
    if (entrySize < kSectionEntrySize || entrySize > 1024)
        throw FormatError(name + ": bad skeleton section entry size " + str(entrySize));
    std::vector<SectionEntry> out;
    for (uint32_t i = 0; i < count; ++i) {
        ByteReader e{r.take(entrySize), name, "skeleton section entry"};
        SectionEntry s{e.get<uint32_t>(), e.get<uint32_t>(), e.get<uint64_t>(), e.get<uint64_t>(),
                       e.get<uint64_t>()};
        if (!fits(s.offset, s.size, skel.size()))
            throw FormatError(name + ": skeleton section " + str(i) + " lies outside the skeleton");
        out.push_back(s);
    }
    return out;
}

void checkNode(const Skeleton& s, const Node& n, uint32_t i, const HeaderInfo& h, const std::string& name) {
    const std::string at = name + ": node " + str(i) + ": ";
    const auto nodeCount = s.nodes.size();
    if (n.id != i) throw FormatError(at + "id " + str(n.id) + " differs from its index");
    for (uint32_t link : {n.parent, n.firstChild, n.nextSibling})
        if (link != kNone && link >= nodeCount) throw FormatError(at + "link to node " + str(link) + " out of range");
    if (n.block >= s.blockCount) throw FormatError(at + "block " + str(n.block) + " out of range");
    if (n.blobCount > kMaxBlobsPerNode || !fits(n.firstBlob, n.blobCount, s.blobs.size()))
        throw FormatError(at + "blob range out of range");
    if (n.dataOffset < h.headerSize || !fits(n.dataOffset, n.dataSize, h.skeletonOffset))
        throw FormatError(at + "data range lies outside the blob area of the file");
}

void checkBlob(const Skeleton& s, const BlobRef& b, uint32_t i, const std::string& name) {
    const std::string at = name + ": blob " + str(i) + ": ";
    bool geometry = b.kind == BlobKind::Geometry && b.codec == Codec::Draco;
    bool texture = b.kind == BlobKind::Texture && (b.codec == Codec::Jpeg || b.codec == Codec::Png);
    if (!geometry && !texture) throw FormatError(at + "unknown kind/codec");
    if (b.node >= s.nodes.size()) throw FormatError(at + "owner node out of range");
    const Node& n = s.nodes[b.node];
    if (i < n.firstBlob || i - n.firstBlob >= n.blobCount) throw FormatError(at + "not in its owner's blob range");
    if (b.offset < n.dataOffset || !fits(b.offset - n.dataOffset, b.size, n.dataSize))
        throw FormatError(at + "bytes lie outside its node's data range");
    if (b.texture != kNone && (!geometry || b.texture >= s.blobs.size() || s.blobs[b.texture].kind != BlobKind::Texture))
        throw FormatError(at + "texture reference " + str(b.texture) + " is not a texture blob");
    if (b.triangles > kMaxElements || b.vertices > kMaxElements)
        throw FormatError(at + "absurd triangle/vertex count");
    if (b.width > kMaxTextureSide || b.height > kMaxTextureSide || b.channels > 4)
        throw FormatError(at + "absurd texture size " + str(b.width) + "x" + str(b.height) + "x" + str(b.channels));
}

}  // namespace

namespace layout {

HeaderInfo parseHeader(std::span<const uint8_t> header, uint64_t fileSize, const std::string& name) {
    if (header.size() < kMagic.size() || !std::equal(kMagic.begin(), kMagic.end(), header.begin()))
        throw FormatError(name + ": not an HLOD database (bad magic)");
    if (header.size() < kOffHeaderSize + 4) throw FormatError(name + ": truncated header");
    HeaderInfo h;
    h.major = load<uint16_t>(header, kOffMajor);
    h.minor = load<uint16_t>(header, kOffMinor);
    if (h.major != kFormatMajor)
        throw FormatError(name + ": format version " + str(h.major) + "." + str(h.minor) +
                          " is not supported by this hlod (reads " + str(kFormatMajor) + ".x)");
    h.headerSize = load<uint32_t>(header, kOffHeaderSize);
    if (h.headerSize < kHeaderSize || h.headerSize > kMaxHeaderSize)
        throw FormatError(name + ": bad header size " + str(h.headerSize));
    if (header.size() < h.headerSize) throw FormatError(name + ": truncated header");
    if (checksum(header.first(h.headerSize - 8)) != load<uint64_t>(header, h.headerSize - 8))
        throw FormatError(name + ": header checksum mismatch (corrupt header)");
    h.skeletonOffset = load<uint64_t>(header, kOffSkeletonOffset);
    h.skeletonSize = load<uint64_t>(header, kOffSkeletonSize);
    h.skeletonChecksum = load<uint64_t>(header, kOffSkeletonChecksum);
    h.fileSize = load<uint64_t>(header, kOffFileSize);
    if (fileSize < h.fileSize)
        throw FormatError(name + ": truncated: file is " + str(fileSize) + " bytes, header says " + str(h.fileSize));
    if (fileSize > h.fileSize)
        throw FormatError(name + ": file is " + str(fileSize) + " bytes, header says " + str(h.fileSize) +
                          " (trailing data)");
    if (h.skeletonOffset < h.headerSize || h.skeletonSize < 8 || h.skeletonSize > kMaxSkeletonSize ||
        !fits(h.skeletonOffset, h.skeletonSize, fileSize))
        throw FormatError(name + ": skeleton range lies outside the file");
    return h;
}

}  // namespace layout

Skeleton parseDatabase(std::span<const uint8_t> header, std::span<const uint8_t> skel, uint64_t fileSize,
                       const std::string& name) {
    HeaderInfo h = parseHeader(header, fileSize, name);
    if (skel.size() != h.skeletonSize) throw FormatError(name + ": truncated skeleton");
    if (checksum(skel) != h.skeletonChecksum) throw FormatError(name + ": skeleton checksum mismatch (corrupt skeleton)");

    Skeleton s;
    s.major = h.major;
    s.minor = h.minor;
    const SectionEntry* found[4] = {};
    std::vector<SectionEntry> table = readSectionTable(skel, name);
    for (const SectionEntry& e : table) {
        int k = e.tag == kTagInfo ? 0 : e.tag == kTagNode ? 1 : e.tag == kTagBlob ? 2 : e.tag == kTagMeta ? 3 : -1;
        if (k < 0) continue;  // a section of a newer minor version
        if (found[k]) throw FormatError(name + ": duplicate skeleton section");
        found[k] = &e;
    }
    for (const SectionEntry* e : found)
        if (!e) throw FormatError(name + ": skeleton lacks a required section (INFO, NODE, BLOB, META)");

    auto info = readRecords<uint32_t>(skel, *found[0], kInfoRecordSize,
                                      [](ByteReader& r) { return r.get<uint32_t>(); }, name, "INFO");
    if (info.size() != 1) throw FormatError(name + ": INFO section must hold one record");
    s.blockCount = info[0];
    s.nodes = readRecords<Node>(skel, *found[1], kNodeRecordSize, getNode, name, "NODE");
    s.blobs = readRecords<BlobRef>(skel, *found[2], kBlobRecordSize, getBlob, name, "BLOB");
    if (s.nodes.size() >= kNone || s.blobs.size() >= kNone) throw FormatError(name + ": too many records");
    if (s.blockCount > s.nodes.size())  // each block has a root node
        throw FormatError(name + ": INFO block count " + str(s.blockCount) + " exceeds the node count " + str(s.nodes.size()));

    const SectionEntry& m = *found[3];
    if (m.count > m.size / 8) throw FormatError(name + ": META count " + str(m.count) + " exceeds its size");
    ByteReader r{skel.subspan(m.offset, m.size), name, "META section"};
    for (uint64_t i = 0; i < m.count; ++i) {
        std::string key = getString(r);
        s.meta.emplace_back(std::move(key), getString(r));
    }

    for (uint32_t i = 0; i < s.nodes.size(); ++i) checkNode(s, s.nodes[i], i, h, name);
    for (uint32_t i = 0; i < s.blobs.size(); ++i) checkBlob(s, s.blobs[i], i, name);
    return s;
}

}  // namespace hlod
