// A bottom-up block's nodes finish depth-first but are emitted breadth-first once the whole block
// is done (build_tree.cpp): their encoded blobs wait here, in an unnamed temporary file, instead of
// in memory (issue #14: the textured facade's one block held its ~360 MiB of records until the end,
// 745 MiB peak RSS under --memory-limit 256M; pipeline/MEMORY.md). Written and read with
// pwrite/pread, so the page cache holds them, not the process; thread-safe.
#pragma once

#include "formats/db.h"

#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hlod {

class BlobSpill {
public:
    // An unnamed file in `dir` (created and unlinked at once; the system's temporary folder when
    // empty). Throws std::runtime_error naming the file.
    explicit BlobSpill(const std::string& dir);
    ~BlobSpill();
    BlobSpill(const BlobSpill&) = delete;
    BlobSpill& operator=(const BlobSpill&) = delete;

    // Writes the blobs' bytes out and frees them; `parked` (per blob: offset, size) brings them back.
    void park(std::vector<EncodedBlob>& blobs, std::vector<std::pair<uint64_t, uint64_t>>& parked);
    void restore(std::vector<EncodedBlob>& blobs, const std::vector<std::pair<uint64_t, uint64_t>>& parked) const;

private:
    std::string name_;
    int fd_ = -1;
    std::atomic<uint64_t> end_{0};
};

}  // namespace hlod
