// Writer: streams each node's blobs to a temporary file as nodes arrive, then writes the
// skeleton LAST and the header over the placeholder at offset 0, fsyncs, renames into place
// and fsyncs the directory (FORMAT.md §Atomic writing). Links follow thesis §3.3 / Fig. 3.1.
#include "formats/fd_io.h"
#include "formats/interrupt.h"
#include "formats/layout.h"
#include "formats/temp_files.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hlod {

namespace {

std::runtime_error ioError(const std::string& path, const char* what) {
    return std::runtime_error(path + ": " + what + ": " + std::strerror(errno));
}

void writeAll(int fd, uint64_t offset, std::span<const uint8_t> bytes, const std::string& path) {
    if (const int error = pwriteFully(fd, bytes.data(), bytes.size(), offset)) {
        errno = error;
        throw ioError(path, "write failed");
    }
}

std::string directoryOf(const std::string& path) {
    auto slash = path.find_last_of('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

struct Writer::Impl {
    std::string path, tmpPath;
    int fd = -1;
    double cTextured = Constants{}.textured;
    Skeleton skeleton;
    std::vector<uint32_t> lastChild;
    uint32_t lastRoot = kNone;
    uint64_t pos = layout::kHeaderSize;
    bool finished = false;

    void link(uint32_t id, uint32_t parent) {
        uint32_t& last = parent == kNone ? lastRoot : lastChild[parent];
        if (last != kNone) skeleton.nodes[last].nextSibling = id;
        else if (parent != kNone) skeleton.nodes[parent].firstChild = id;
        last = id;
    }
};

Writer::Writer(const std::string& path, double cTextured) : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    impl_->cTextured = cTextured;
    checkReplaceable(path, "database");
    removeStaleTemporaries(path + ".tmp");  // of writers killed before they renamed theirs
    std::string tmpl = temporaryPattern(path + ".tmp");
    impl_->fd = createTemporary(tmpl, false);
    if (impl_->fd < 0) throw ioError(path, "cannot create temporary file");
    impl_->tmpPath = tmpl;
    ::fchmod(impl_->fd, 0644);  // mkstemp's 0600 would hide the database from other readers
    const uint8_t placeholder[layout::kHeaderSize] = {};  // zero magic: never opens as a database
    writeAll(impl_->fd, 0, placeholder, impl_->tmpPath);
}

Writer::Writer(Writer&&) noexcept = default;

Writer::~Writer() {
    if (!impl_ || impl_->finished) return;
    if (impl_->fd >= 0) ::close(impl_->fd);
    ::unlink(impl_->tmpPath.c_str());
    forgetTemporary(impl_->tmpPath);
}

static void checkBlobs(const NodeInput& in) {
    for (const EncodedBlob& b : in.blobs) {
        bool geometry = b.info.kind == BlobKind::Geometry && b.info.codec == Codec::Draco;
        bool texture = b.info.kind == BlobKind::Texture && (b.info.codec == Codec::Jpeg || b.info.codec == Codec::Png);
        if (!geometry && !texture) throw std::invalid_argument("Writer: blob with a bad kind/codec pair");
        if (b.textureSlot == kNone) continue;
        if (!geometry || b.textureSlot >= in.blobs.size() || in.blobs[b.textureSlot].info.kind != BlobKind::Texture)
            throw std::invalid_argument("Writer: textureSlot does not name a texture blob of the same node");
    }
}

uint32_t Writer::addNode(NodeInput in) {
    Impl& w = *impl_;
    if (w.finished) throw std::logic_error("Writer: addNode after finish");
    const auto id = uint32_t(w.skeleton.nodes.size());
    if (in.parent != kNone && in.parent >= id) throw std::invalid_argument("Writer: parent must be added first");
    checkBlobs(in);

    Node n;
    n.id = id;
    n.parent = in.parent;
    n.level = in.level;
    n.block = in.block;
    n.bounds = in.bounds;
    n.staticBenefit = in.staticBenefit;
    n.avgNormal = in.avgNormal;
    n.geometricError = in.geometricError;
    n.firstBlob = uint32_t(w.skeleton.blobs.size());
    n.blobCount = uint32_t(in.blobs.size());
    n.dataOffset = w.pos;
    for (EncodedBlob& b : in.blobs) {
        BlobRef r = b.info;
        r.node = id;
        r.texture = b.textureSlot == kNone ? kNone : n.firstBlob + b.textureSlot;
        r.offset = w.pos;
        r.size = b.bytes.size();
        r.checksum = layout::checksum(b.bytes);
        writeAll(w.fd, w.pos, b.bytes, w.tmpPath);
        w.pos += b.bytes.size();
        if (r.kind == BlobKind::Texture) n.texelCount += uint64_t(r.width) * r.height;
        else (r.texture != kNone ? n.texturedTriangles : n.untexturedTriangles) += r.triangles;
        if (r.kind == BlobKind::Geometry) n.vertexCount += r.vertices;
        w.skeleton.blobs.push_back(r);
    }
    n.dataSize = w.pos - n.dataOffset;
    n.cost = in.cost >= 0 ? in.cost : nodeCost(n.texturedTriangles, n.untexturedTriangles, w.cTextured);
    w.skeleton.nodes.push_back(n);
    w.lastChild.push_back(kNone);
    w.link(id, in.parent);
    w.skeleton.blockCount = std::max(w.skeleton.blockCount, in.block + 1);
    return id;
}

void Writer::setMeta(const std::string& key, const std::string& value) {
    for (auto& kv : impl_->skeleton.meta)
        if (kv.first == key) {
            kv.second = value;
            return;
        }
    impl_->skeleton.meta.emplace_back(key, value);
}

void Writer::finish() {
    Impl& w = *impl_;
    if (w.finished) throw std::logic_error("Writer: finish called twice");
    std::vector<uint8_t> skel = layout::encodeSkeleton(w.skeleton);
    writeAll(w.fd, w.pos, skel, w.tmpPath);
    auto header = layout::encodeHeader(w.pos, skel);
    // The header without its magic first, synced; the magic only just before the rename, so a
    // run killed during the (slow) fsync leaves a temporary that never opens as a database
    // (found by the kill -9 sweep, tests/pipeline/test_kill.cpp).
    std::vector<uint8_t> magic(header.begin(), header.begin() + layout::kMagic.size());
    std::fill(header.begin(), header.begin() + layout::kMagic.size(), uint8_t{0});
    writeAll(w.fd, 0, header, w.tmpPath);
    if (::fsync(w.fd) != 0) throw ioError(w.tmpPath, "fsync failed");
    writeAll(w.fd, 0, magic, w.tmpPath);
    uninterrupted([&] {
        if (::rename(w.tmpPath.c_str(), w.path.c_str()) != 0) throw ioError(w.path, "rename failed");
        forgetTemporary(w.tmpPath);
    });
    w.finished = true;
    const int synced = ::fsync(w.fd), closed = ::close(w.fd);
    w.fd = -1;
    if (synced != 0 || closed != 0) throw ioError(w.path, "fsync failed");
    int dir = ::open(directoryOf(w.path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

}  // namespace hlod
