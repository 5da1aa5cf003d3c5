// An append-only array that lives in memory, or, given a file, on disk (for inputs larger than
// memory): appends are buffered and written out a chunk at a time; seal() then
// maps the file read-only, so random reads are served by the page cache and the kernel may drop
// pages under pressure instead of the process holding the whole array.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace hlod {

template <class T>
class SpillArray {
public:
    SpillArray() = default;
    SpillArray(const SpillArray&) = delete;
    SpillArray& operator=(const SpillArray&) = delete;
    ~SpillArray() {
        if (map_) munmap(map_, mapBytes_);
        if (file_) std::fclose(file_);
    }

    // Spill to `path` (created, truncated) instead of memory, before the first push or midway:
    // what memory holds so far is written out first and its memory returned.
    void spillTo(const std::string& path) {
        path_ = path;
        file_ = std::fopen(path.c_str(), "w+b");
        if (!file_) throw std::runtime_error(path + ": cannot create temporary file (" + std::strerror(errno) + ")");
        if (!buffer_.empty()) flush();
        std::vector<T>().swap(buffer_);
    }
    bool spilled() const { return file_ != nullptr; }
    size_t heldBytes() const { return buffer_.capacity() * sizeof(T); }  // in memory, reserved included

    void push(const T* values, size_t n) {
        buffer_.insert(buffer_.end(), values, values + n);
        size_ += n;
        if (file_ && buffer_.size() >= kChunk) flush();
    }

    // Ends appending; data() is valid from here on.
    void seal() {
        if (!file_) return;
        flush();
        buffer_.shrink_to_fit();
        mapBytes_ = size_ * sizeof(T);
        if (mapBytes_ == 0) return;
        void* p = mmap(nullptr, mapBytes_, PROT_READ, MAP_PRIVATE, fileno(file_), 0);
        if (p == MAP_FAILED) throw std::runtime_error(path_ + ": cannot map temporary file (" + std::strerror(errno) + ")");
        map_ = p;
    }

    // Done with elements [begin, end): their pages leave the process (read again from the
    // file if touched later). A no-op in memory.
    void release(size_t begin, size_t end) const {
        if (!map_) return;
        const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE)), from = (begin * sizeof(T) + page - 1) / page * page, to = end * sizeof(T) / page * page;
        if (to > from) madvise(static_cast<char*>(map_) + from, to - from, MADV_DONTNEED);
    }

    // Elements [first, first + n) into `out`, while appending too (a reader looking back at what it
    // read: a polygon's corners): from memory, the map, or the spilled file and the unwritten chunk.
    void read(size_t first, size_t n, T* out) const {
        if (!file_ || map_) return static_cast<void>(std::memcpy(out, data() + first, n * sizeof(T)));
        const size_t written = size_ - buffer_.size();
        for (size_t i = first; i < first + n; ++i) {
            if (i >= written) {
                out[i - first] = buffer_[i - written];
            } else if (pread(fileno(file_), &out[i - first], sizeof(T), static_cast<off_t>(i * sizeof(T))) != sizeof(T)) {
                throw std::runtime_error(path_ + ": read failed (" + std::strerror(errno) + ")");
            }
        }
    }

    size_t size() const { return size_; }
    const T* data() const { return file_ ? static_cast<const T*>(map_) : buffer_.data(); }
    const T& operator[](size_t i) const { return data()[i]; }

private:
    static constexpr size_t kChunk = (1u << 20) / sizeof(T);

    void flush() {
        if (!buffer_.empty() && std::fwrite(buffer_.data(), sizeof(T), buffer_.size(), file_) != buffer_.size())
            throw std::runtime_error(path_ + ": write failed (" + std::strerror(errno) + ")");
        buffer_.clear();
        if (std::fflush(file_) != 0) throw std::runtime_error(path_ + ": write failed (" + std::strerror(errno) + ")");
    }

    std::vector<T> buffer_;
    size_t size_ = 0;
    std::string path_;
    std::FILE* file_ = nullptr;
    void* map_ = nullptr;
    size_t mapBytes_ = 0;
};

}  // namespace hlod
