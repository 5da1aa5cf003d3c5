// The HLOD database: plain data structs, the reader and the writer.
// Byte layout and rules: formats/FORMAT.md. Node attributes follow thesis §3.3.
#pragma once

#include "formats/constants.h"
#include "formats/errors.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hlod {

inline constexpr uint16_t kFormatMajor = 1;
inline constexpr uint16_t kFormatMinor = 0;
inline constexpr uint32_t kNone = 0xFFFFFFFFu;  // "no node" / "no blob"

struct Vec3f {
    float x = 0, y = 0, z = 0;
};

struct Box3f {
    Vec3f min{}, max{};
};

enum class BlobKind : uint8_t { Geometry = 1, Texture = 2 };
enum class Codec : uint8_t { Draco = 1, Jpeg = 2, Png = 3 };

// One stored blob (a node's sub-mesh geometry or one of its textures).
struct BlobRef {
    BlobKind kind = BlobKind::Geometry;
    Codec codec = Codec::Draco;
    uint32_t node = kNone;       // owning node
    uint32_t texture = kNone;    // Geometry: global index of the texture blob it samples, or kNone
    uint64_t offset = 0;         // absolute file offset
    uint64_t size = 0;           // bytes
    uint64_t checksum = 0;       // XXH3-64 of the bytes
    // Geometry
    uint32_t triangles = 0;
    uint32_t vertices = 0;
    uint8_t positionBits = 0;    // Draco quantization, 0 = lossless / absent
    uint8_t texcoordBits = 0;
    uint8_t normalBits = 0;
    uint8_t colorBits = 0;
    uint8_t attributes = 0;      // AttributeMask bits present in the blob
    // Texture
    uint32_t width = 0;
    uint32_t height = 0;
    uint8_t channels = 0;
};

enum AttributeMask : uint8_t { kAttrPosition = 1, kAttrTexcoord = 2, kAttrNormal = 4, kAttrColor = 8 };

// One HLOD node (thesis §3.3 attributes + what validation and the player need).
struct Node {
    uint32_t id = kNone;           // unique ID == index in Skeleton::nodes
    uint32_t parent = kNone;       // kNone for hlod0 (block roots)
    uint32_t firstChild = kNone;
    uint32_t nextSibling = kNone;  // hlod0 nodes are siblings of each other (thesis Fig. 3.1)
    uint32_t level = 0;            // 0 = hlod0
    uint32_t block = 0;
    Box3f bounds{};
    float cost = 0;                // eq. 3.1
    float staticBenefit = 0;       // §3.3: sqrt(numTriangles * sum of areas)
    Vec3f avgNormal{};             // §3.3: area-weighted, normalised
    float geometricError = 0;      // object-space distance simplified -> original, metres
    uint32_t texturedTriangles = 0;
    uint32_t untexturedTriangles = 0;
    uint32_t vertexCount = 0;
    uint64_t texelCount = 0;
    uint32_t firstBlob = 0;        // this node's blobs are blobs[firstBlob, firstBlob + blobCount)
    uint32_t blobCount = 0;
    uint64_t dataOffset = 0;       // all of the node's blobs lie in [dataOffset, dataOffset + dataSize)
    uint64_t dataSize = 0;

    uint32_t triangles() const { return texturedTriangles + untexturedTriangles; }
};

// The skeleton: header facts, all node and blob records, metadata. Small, loaded once.
struct Skeleton {
    uint16_t major = kFormatMajor;
    uint16_t minor = kFormatMinor;
    uint32_t blockCount = 0;
    std::vector<Node> nodes;
    std::vector<BlobRef> blobs;
    // Build provenance and constants, in insertion order ("tool", "input", "c_levelFactor", ...).
    std::vector<std::pair<std::string, std::string>> meta;

    const std::string* findMeta(const std::string& key) const;
    std::vector<uint32_t> roots() const;        // hlod0 node ids, block order
    std::vector<uint32_t> children(uint32_t id) const;
};

// Cost of eq. 3.1: textured * c_textured + untextured * (1 - c_textured).
float nodeCost(uint32_t texturedTriangles, uint32_t untexturedTriangles, double cTextured);

// FORMAT.md §Invariants 1–2 (formats/tree_check.cpp): links form one tree per block without
// cycles or sharing, roots at level 0, level = parent's + 1, block = parent's. Calls `report` for
// each violation (node kNone: of no one node).
void checkTree(const Skeleton& s, const std::function<void(uint32_t node, const std::string& message)>& report);

// Read side. Opening checks the header and skeleton (bounds, counts, checksum) and, with
// checkNodeTree (the default), the node tree (checkTree: no reader walks a cycle); `hlod validate`
// opens without it to list every violation. Blobs are read on demand with one positioned read
// each and checked against their checksum.
class Database {
public:
    static Database open(const std::string& path, bool checkNodeTree = true);  // throws UnreadableDatabase
    Database(Database&&) noexcept;
    Database& operator=(Database&&) noexcept;
    ~Database();

    const std::string& path() const;
    const Skeleton& skeleton() const;
    uint64_t fileSize() const;

    // Reads and verifies blob `index`; throws FormatError on I/O error or checksum mismatch.
    std::vector<uint8_t> readBlob(uint32_t index) const;
    // Raw positioned read inside the file (for chunked/preemptible loading); no verification.
    void readRange(uint64_t offset, std::span<uint8_t> out) const;

private:
    Database();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Parses a skeleton from the whole file image (used by the reader and the fuzzer); `name` is
// used in error messages. Throws FormatError.
Skeleton parseDatabase(std::span<const uint8_t> header, std::span<const uint8_t> skeletonBytes,
                       uint64_t fileSize, const std::string& name);

// A blob ready to store: already encoded (see codec.h), with the facts its record claims.
struct EncodedBlob {
    BlobRef info;                // kind, codec, counts, quantization; offsets are filled by the writer
    std::vector<uint8_t> bytes;
    uint32_t textureSlot = kNone;  // Geometry: index into NodeInput::blobs of its texture, or kNone
};

// What the writer needs for one node. Links (firstChild, nextSibling), id, blob ranges,
// triangle/vertex/texel counts are filled by the writer from `blobs`.
struct NodeInput {
    uint32_t parent = kNone;
    uint32_t level = 0;
    uint32_t block = 0;
    Box3f bounds{};
    float cost = -1;              // < 0: computed by eq. 3.1 from the blobs and c_textured
    float staticBenefit = 0;
    Vec3f avgNormal{};
    float geometricError = 0;
    std::vector<EncodedBlob> blobs;
};

// Write side. Writes to "PATH.tmp-hlodSPACE-PID-XXXXXX" in the same directory (an existing PATH that is not a
// regular file is refused, checkReplaceable), then fsync + rename in
// finish(). Destroying an unfinished writer removes the temporary file, so a killed or
// failed writer never leaves a file that opens as a database at PATH.
class Writer {
public:
    explicit Writer(const std::string& path, double cTextured = Constants{}.textured);  // throws std::runtime_error
    Writer(Writer&&) noexcept;
    ~Writer();

    // Appends a node; returns its id (ids are given in call order). The parent must already
    // be added. Children are linked in call order. Throws std::invalid_argument on bad links.
    uint32_t addNode(NodeInput node);
    void setMeta(const std::string& key, const std::string& value);
    void finish();  // writes skeleton and header, fsync, rename; throws std::runtime_error

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hlod
