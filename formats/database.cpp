// Database: opens a file, checks header and skeleton (parse.cpp), keeps the skeleton in memory
// and reads each blob with one positioned read (pread), verified by its XXH3-64 checksum.
#include "formats/constants.h"
#include "formats/fd_io.h"
#include "formats/layout.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hlod {

struct Database::Impl {
    std::string path;
    int fd = -1;
    uint64_t fileSize = 0;
    Skeleton skeleton;
    ~Impl() {
        if (fd >= 0) ::close(fd);
    }
};

namespace {

void preadAll(int fd, uint64_t offset, std::span<uint8_t> out, const std::string& path) {
    const int error = preadFully(fd, out.data(), out.size(), offset);
    if (error == kEndOfFile) throw FormatError(path + ": unexpected end of file (was it truncated while open?)");
    if (error) throw FormatError(path + ": read error: " + std::strerror(error));
}

}  // namespace

Database::Database() : impl_(std::make_unique<Impl>()) {}
Database::Database(Database&&) noexcept = default;
Database& Database::operator=(Database&&) noexcept = default;
Database::~Database() = default;

// Every failure to open is UnreadableDatabase: the file is not a database this reader can use.
Database Database::open(const std::string& path, bool checkNodeTree) try {
    Database db;
    Impl& d = *db.impl_;
    d.path = path;
    d.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block us
    if (d.fd < 0) {
        if (errno == ENOENT) throw FormatError(path + ": no such file");
        throw FormatError(path + ": cannot open: " + std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(d.fd, &st) != 0) throw FormatError(path + ": cannot stat: " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw FormatError(path + ": is a directory, not an HLOD database");
    if (!S_ISREG(st.st_mode)) throw FormatError(path + ": not a regular file");
    d.fileSize = uint64_t(st.st_size);
    if (d.fileSize == 0) throw FormatError(path + ": empty file, not an HLOD database");

    std::vector<uint8_t> header(std::min<uint64_t>(d.fileSize, layout::kMaxHeaderSize));
    preadAll(d.fd, 0, header, path);
    layout::HeaderInfo h = layout::parseHeader(header, d.fileSize, path);
    std::vector<uint8_t> skel(h.skeletonSize);
    preadAll(d.fd, h.skeletonOffset, skel, path);
    d.skeleton = parseDatabase(header, skel, d.fileSize, path);
    if (checkNodeTree) {
        const auto refuse = [&](uint32_t node, const std::string& message) {
            throw FormatError(path + ": " + (node == kNone ? "" : "node " + std::to_string(node) + ": ") + message +
                              " (`hlod validate` lists every violation)");
        };
        checkTree(d.skeleton, refuse);
        // Every reader sums costs (budgets, memory estimates): a NaN played on as `nan` until stop 49.
        for (const Node& n : d.skeleton.nodes)  // eq. 3.1 weighs each triangle at most 1
            if (!(n.cost >= 0 && n.cost <= 1.0001 * (double(n.texturedTriangles) + n.untexturedTriangles) + 1))
                refuse(n.id, "cost " + formatConstant(n.cost) + " is not within [0, its " +
                                 std::to_string(uint64_t(n.texturedTriangles) + n.untexturedTriangles) + " triangles]");
    }
    return db;
} catch (const FormatError& e) {
    throw UnreadableDatabase(e.what());
}

const std::string& Database::path() const { return impl_->path; }
const Skeleton& Database::skeleton() const { return impl_->skeleton; }
uint64_t Database::fileSize() const { return impl_->fileSize; }

void Database::readRange(uint64_t offset, std::span<uint8_t> out) const {
    if (offset > impl_->fileSize || out.size() > impl_->fileSize - offset)
        throw FormatError(impl_->path + ": read of " + std::to_string(out.size()) + " bytes at " +
                          std::to_string(offset) + " lies outside the file");
    preadAll(impl_->fd, offset, out, impl_->path);
}

std::vector<uint8_t> Database::readBlob(uint32_t index) const {
    const Skeleton& s = impl_->skeleton;
    if (index >= s.blobs.size())
        throw FormatError(impl_->path + ": blob " + std::to_string(index) + " does not exist");
    const BlobRef& b = s.blobs[index];
    std::vector<uint8_t> bytes(b.size);
    readRange(b.offset, bytes);
    if (layout::checksum(bytes) != b.checksum)
        throw FormatError(impl_->path + ": blob " + std::to_string(index) + " (node " + std::to_string(b.node) +
                          ") checksum mismatch (corrupt data)");
    return bytes;
}

}  // namespace hlod
