// BlobSpill (blob_spill.h): encoded blobs parked in an unnamed temporary file.
#include "pipeline/blob_spill.h"

#include "formats/fd_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace hlod {

BlobSpill::BlobSpill(const std::string& dir) {
    const std::filesystem::path folder = dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(dir);
    name_ = (folder / "hlod-blobs-XXXXXX").string();
    fd_ = mkostemp(name_.data(), O_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error(folder.string() + ": cannot create a temporary file (" + std::strerror(errno) + "; --temp-dir)");
    unlink(name_.c_str());  // removed by the system when closed, or when the process dies
    name_ = folder.string() + ": the unnamed temporary file of a block's finished nodes";  // what its messages name
}

BlobSpill::~BlobSpill() { close(fd_); }

void BlobSpill::park(std::vector<EncodedBlob>& blobs, std::vector<std::pair<uint64_t, uint64_t>>& parked) {
    uint64_t total = 0;
    for (const EncodedBlob& b : blobs) total += b.bytes.size();
    uint64_t at = end_.fetch_add(total);
    parked.clear();
    for (EncodedBlob& b : blobs) {
        parked.push_back({at, b.bytes.size()});
        if (const int error = pwriteFully(fd_, b.bytes.data(), b.bytes.size(), at))
            throw std::runtime_error(name_ + ": write failed (" + std::strerror(error) + "; --temp-dir)");
        at += b.bytes.size();
        std::vector<uint8_t>().swap(b.bytes);
    }
}

void BlobSpill::restore(std::vector<EncodedBlob>& blobs, const std::vector<std::pair<uint64_t, uint64_t>>& parked) const {
    if (parked.size() != blobs.size()) throw std::logic_error(name_ + ": parked blobs do not match the record");
    for (size_t i = 0; i < blobs.size(); ++i) {
        const auto [at, size] = parked[i];
        blobs[i].bytes.resize(size);
        if (const int error = preadFully(fd_, blobs[i].bytes.data(), size, at))
            throw std::runtime_error(name_ + ": read failed (" + (error == kEndOfFile ? "short file" : std::strerror(error)) + ")");
    }
}

}  // namespace hlod
