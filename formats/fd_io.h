// Positional reads and writes that finish: pread/pwrite repeated until every byte has moved,
// an interrupted call (EINTR) retried. Each returns 0, or why it stopped: the errno of the
// failing call, ENOSPC for a write that moved nothing, kEndOfFile for a read past the end.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>

namespace hlod {

constexpr int kEndOfFile = -1;

inline int pwriteFully(int fd, const uint8_t* bytes, size_t size, uint64_t offset) {
    for (size_t done = 0; done < size;) {
        const ssize_t n = ::pwrite(fd, bytes + done, size - done, static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return n < 0 ? errno : ENOSPC;
        done += static_cast<size_t>(n);
    }
    return 0;
}

inline int preadFully(int fd, uint8_t* out, size_t size, uint64_t offset) {
    for (size_t done = 0; done < size;) {
        const ssize_t n = ::pread(fd, out + done, size - done, static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return n < 0 ? errno : kEndOfFile;
        done += static_cast<size_t>(n);
    }
    return 0;
}

}  // namespace hlod
