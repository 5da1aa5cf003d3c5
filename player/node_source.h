// Where the loading thread gets a node's bytes and how it decodes them: a Database (Draco and
// JPEG/PNG blobs, thesis §3.3 / §4.3). Tests implement NodeSource in memory
// (tests/support/memory_source.h).
#pragma once

#include "formats/db.h"
#include "player/renderer.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace hlod {

// A node whose data could not be read or decoded (truncated, corrupt, undecodable). The loader
// reports it once and never requests it again (thesis §4.3 has no failures; player/STATS.md).
struct LoadFailure {
    uint32_t node = 0;
    std::string what;     // the error, one line naming the file: "FILE (node N, blob B): problem"
    std::string problem;  // the same without the file and the node: "blob B: problem"
};

class NodeSource {
public:
    virtual ~NodeSource() = default;
    virtual const Skeleton& skeleton() const = 0;
    virtual std::string name() const = 0;
    // Size of the node's stored data; chunks are read at offsets relative to its start.
    virtual uint64_t nodeSize(uint32_t id) const = 0;
    virtual void readChunk(uint32_t id, uint64_t offset, std::span<uint8_t> out) const = 0;
    // Verifies and decodes the node's whole data; throws FormatError naming the file.
    virtual DecodedNode decode(uint32_t id, std::span<const uint8_t> data) const = 0;
    // DecodedNode::bytes() the node will have once decoded (memory reservation, §4.3).
    virtual uint64_t expectedBytes(uint32_t id) const = 0;
};

// Reads through `db` (which must outlive the source): one positioned read per chunk, blob
// checksums verified (XXH3-64), geometry decoded with Draco and textures with libjpeg-turbo or libpng (formats/image_io.h).
std::shared_ptr<const NodeSource> databaseSource(const Database& db);

}  // namespace hlod
