// BlobSpill (blob_spill.h): encoded blobs parked in an unnamed temporary file.
#include "pipeline/blob_spill.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace hlod {

BlobSpill::BlobSpill(const std::string& dir) {
    const std::filesystem::path folder = dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(dir);
    path_ = (folder / "hlod-blobs-XXXXXX").string();
    fd_ = mkstemp(path_.data());
    if (fd_ < 0) throw std::runtime_error(path_ + ": cannot create temporary file (" + std::strerror(errno) + ")");
    unlink(path_.c_str());  // removed by the system when closed, or when the process dies
}

BlobSpill::~BlobSpill() { close(fd_); }

void BlobSpill::park(std::vector<EncodedBlob>& blobs, std::vector<std::pair<uint64_t, uint64_t>>& parked) {
    uint64_t total = 0;
    for (const EncodedBlob& b : blobs) total += b.bytes.size();
    uint64_t at = end_.fetch_add(total);
    parked.clear();
    for (EncodedBlob& b : blobs) {
        parked.push_back({at, b.bytes.size()});
        for (size_t done = 0; done < b.bytes.size();) {
            const ssize_t n = pwrite(fd_, b.bytes.data() + done, b.bytes.size() - done, static_cast<off_t>(at + done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw std::runtime_error(path_ + ": write failed (" + std::strerror(n < 0 ? errno : ENOSPC) + ")");
            done += static_cast<size_t>(n);
        }
        at += b.bytes.size();
        std::vector<uint8_t>().swap(b.bytes);
    }
}

void BlobSpill::restore(std::vector<EncodedBlob>& blobs, const std::vector<std::pair<uint64_t, uint64_t>>& parked) const {
    if (parked.size() != blobs.size()) throw std::logic_error(path_ + ": parked blobs do not match the record");
    for (size_t i = 0; i < blobs.size(); ++i) {
        const auto [at, size] = parked[i];
        blobs[i].bytes.resize(size);
        for (size_t done = 0; done < size;) {
            const ssize_t n = pread(fd_, blobs[i].bytes.data() + done, size - done, static_cast<off_t>(at + done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw std::runtime_error(path_ + ": read failed (" + (n < 0 ? std::strerror(errno) : "short file") + ")");
            done += static_cast<size_t>(n);
        }
    }
}

}  // namespace hlod
