// Block record files, shards and the final merge. Blocks finish in any order on any number of
// threads or machines; each writes its encoded nodes to its own record file, and the merge
// writes the database in one fixed order: every hlod0 in block order (thesis Fig. 3.1: the
// hlod0 nodes are siblings), then each block's remaining nodes breadth-first. A one-machine
// build is a single shard merged, so shard + merge gives the same bytes as one build.
#include "pipeline/pipeline.h"

#include "formats/json_text.h"
#include "formats/layout.h"
#include "formats/temp_files.h"

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <type_traits>

namespace hlod {
namespace {

constexpr uint32_t kRecordTag = 0x45444F4E;  // "NODE"
constexpr uint32_t kEndTag = 0x20444E45;     // "END "
constexpr const char* kShardFormat = "hlod-shard-2";  // 2: XXH3-64 of each blob and record (stop 36)

template <class T>
void write(std::FILE* f, const T& value, const std::string& file) {
    if (std::fwrite(&value, sizeof value, 1, f) != 1) throw std::runtime_error(file + ": write failed (" + std::strerror(errno) + ")");
}

template <class T>
T read(std::FILE* f, const std::string& file) {
    T value{};
    if (std::fread(&value, sizeof value, 1, f) != 1) throw InputError(file + ": truncated block record file");
    return value;
}

// The bytes of a record's fields, in the order written, for its checksum.
template <class T>
void append(std::vector<uint8_t>& hashed, const T& value) {
    const auto* p = reinterpret_cast<const uint8_t*>(&value);
    hashed.insert(hashed.end(), p, p + sizeof value);
}

[[noreturn]] void corrupt(const std::string& file, const std::string& what) {
    throw InputError(file + ": corrupt block record file (" + what + ")");
}

}  // namespace

struct BlockRecordWriter::Impl {
    std::string file;
    std::FILE* f = nullptr;
    uint64_t count = 0;
    std::vector<long> errorOffsets;  // file offset of each record's geometricError
};

BlockRecordWriter::BlockRecordWriter(const std::string& file) : impl_(new Impl{file, std::fopen(file.c_str(), "wb"), 0, {}}) {
    if (!impl_->f) {
        const std::string problem = std::strerror(errno);
        delete impl_;
        throw std::runtime_error(file + ": cannot write (" + problem + ")");
    }
}

BlockRecordWriter::~BlockRecordWriter() {
    if (impl_->f) std::fclose(impl_->f);
    delete impl_;
}

void BlockRecordWriter::add(const NodeRecord& record) {
    std::FILE* f = impl_->f;
    const std::string& file = impl_->file;
    const NodeInput& n = record.node;
    std::vector<uint8_t> hashed;  // every field but geometricError (rewritten by setGeometricErrors)
    const auto put = [&](const auto& value) { write(f, value, file), append(hashed, value); };
    write(f, kRecordTag, file), put(record.parentLocal), put(n.level), put(n.block);
    put(n.bounds), put(n.cost), put(n.staticBenefit), put(n.avgNormal);
    impl_->errorOffsets.push_back(std::ftell(f));
    write(f, n.geometricError, file), put(static_cast<uint32_t>(n.blobs.size()));
    for (const EncodedBlob& blob : n.blobs) {
        BlobRef info = blob.info;
        info.checksum = layout::checksum(blob.bytes);  // checked by the merge (the Writer computes its own)
        put(info), put(blob.textureSlot), put(static_cast<uint64_t>(blob.bytes.size()));
        if (!blob.bytes.empty() && std::fwrite(blob.bytes.data(), 1, blob.bytes.size(), f) != blob.bytes.size())
            throw std::runtime_error(file + ": write failed (" + std::strerror(errno) + ")");
    }
    write(f, layout::checksum(hashed), file);  // the record's fields; each blob's bytes by its own
    ++impl_->count;
}

void BlockRecordWriter::setGeometricErrors(const std::vector<float>& errors) {
    if (errors.size() != impl_->errorOffsets.size()) throw std::logic_error(impl_->file + ": error count differs from nodes");
    const long end = std::ftell(impl_->f);
    for (size_t i = 0; i < errors.size(); ++i) {
        if (std::fseek(impl_->f, impl_->errorOffsets[i], SEEK_SET) != 0) throw std::runtime_error(impl_->file + ": seek failed");
        write(impl_->f, errors[i], impl_->file);
    }
    if (std::fseek(impl_->f, end, SEEK_SET) != 0) throw std::runtime_error(impl_->file + ": seek failed");
}

void BlockRecordWriter::finish() {
    write(impl_->f, kEndTag, impl_->file), write(impl_->f, impl_->count, impl_->file);
    const bool ok = std::fclose(impl_->f) == 0;
    impl_->f = nullptr;
    const int error = errno;
    if (!ok) throw std::runtime_error(impl_->file + ": write failed (" + std::strerror(error) + ")");
}

namespace {

// Reads up to maxRecords records of a block record file in order, handing each to `each` (so a
// merge holds one node's blobs at a time, not a block's: issue #14, a 418 MB block's records
// were the build's peak RSS).
void readRecords(const std::string& file, size_t maxRecords, const std::function<void(NodeRecord&&)>& each) {
    refuseSpecialFile(file);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> holder(std::fopen(file.c_str(), "rb"), &std::fclose);
    std::FILE* f = holder.get();
    if (!f) throw InputError(file + ": cannot read block record file (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(::fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) throw InputError(file + ": not a block record file");
    const uint64_t fileSize = uint64_t(st.st_size);
    size_t count = 0;
    while (count < maxRecords) {
        const uint32_t tag = read<uint32_t>(f, file);
        if (tag == kEndTag) {
            if (read<uint64_t>(f, file) != count) corrupt(file, "count");
            break;
        }
        if (tag != kRecordTag) corrupt(file, "record tag");
        NodeRecord r;
        NodeInput& n = r.node;
        std::vector<uint8_t> hashed;
        const auto get = [&](auto& value) {
            value = read<std::remove_reference_t<decltype(value)>>(f, file);
            append(hashed, value);
        };
        get(r.parentLocal), get(n.level), get(n.block), get(n.bounds), get(n.cost), get(n.staticBenefit), get(n.avgNormal);
        n.geometricError = read<float>(f, file);
        uint32_t blobs = 0;
        get(blobs);
        if (blobs > layout::kMaxBlobsPerNode) corrupt(file, std::to_string(blobs) + " blobs in one node");
        n.blobs.resize(blobs);
        for (EncodedBlob& blob : n.blobs) {
            uint64_t size = 0;
            get(blob.info), get(blob.textureSlot), get(size);
            const uint64_t at = uint64_t(std::ftell(f));
            if (size > fileSize - std::min(at, fileSize)) throw InputError(file + ": truncated block record file");
            blob.bytes.resize(size);
            if (!blob.bytes.empty() && std::fread(blob.bytes.data(), 1, blob.bytes.size(), f) != blob.bytes.size())
                throw InputError(file + ": truncated block record file");
            if (layout::checksum(blob.bytes) != blob.info.checksum) corrupt(file, "blob checksum mismatch");
        }
        if (read<uint64_t>(f, file) != layout::checksum(hashed)) corrupt(file, "record checksum mismatch");
        ++count;
        each(std::move(r));
    }
}

}  // namespace

std::vector<NodeRecord> readBlockRecords(const std::string& file, size_t maxRecords) {
    std::vector<NodeRecord> records;
    readRecords(file, maxRecords, [&](NodeRecord&& r) { records.push_back(std::move(r)); });
    return records;
}

std::string blockRecordPath(const std::string& dir, uint32_t block) {
    char name[32];
    std::snprintf(name, sizeof name, "block_%06u.nodes", block);
    return (std::filesystem::path(dir) / name).string();
}

void writeShardInfo(const std::string& dir, const ShardInfo& info) {
    nlohmann::json j;
    j["format"] = kShardFormat;
    j["blockCount"] = info.blockCount;
    j["blocks"] = info.blocks;
    j["meta"] = info.meta;
    std::ofstream out(std::filesystem::path(dir) / "shard.json");
    out << jsonText(j, 1) << "\n";
    if (!out.flush()) {
        const int error = errno;
        throw std::runtime_error(dir + "/shard.json: write failed (" + std::strerror(error) + ")");
    }
}

ShardInfo readShardInfo(const std::string& dir) {
    const std::string file = (std::filesystem::path(dir) / "shard.json").string();
    refuseSpecialFile(file);
    std::ifstream in(file);
    if (!in) throw InputError(file + ": cannot read (not a shard folder?)");
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        if (j.at("format") == "hlod-shard-1")  // before stop 36: records without checksums
            throw InputError(file + ": a shard of an older hlod (hlod-shard-1): build it again");
        if (j.at("format") != kShardFormat) throw std::runtime_error("unknown format");
        ShardInfo info;
        info.blockCount = j.at("blockCount").get<uint32_t>();
        info.blocks = j.at("blocks").get<std::vector<uint32_t>>();
        info.meta = j.at("meta").get<std::vector<std::pair<std::string, std::string>>>();
        return info;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(file + ": corrupt shard description (" + jsonProblem(e.what()) + ")");
    }
}

void mergeShards(const std::vector<std::string>& shardDirs, const std::string& output, double cTextured) {
    if (shardDirs.empty()) throw InputError("merge: no shards given");
    for (const std::string& dir : shardDirs) {
        refuseOutputOverInputs(output, {dir});  // -o S0 of shard S0: "exists and is not a regular file", status 1, until stop 47
        refuseOutputInsideFolder(output, dir);
    }
    const ShardInfo first = readShardInfo(shardDirs[0]);
    if (first.blockCount == 0) throw InputError(shardDirs[0] + "/shard.json: corrupt shard description (0 blocks)");
    // Each listed block with its shard, sorted: the block count (unchecksummed) sizes nothing until
    // the shards are seen to list every block (2^32 ended in std::bad_alloc until stop 44).
    std::vector<std::pair<uint32_t, std::string>> listed;
    for (const std::string& dir : shardDirs) {
        const ShardInfo info = readShardInfo(dir);
        if (info.meta != first.meta || info.blockCount != first.blockCount)
            throw InputError(dir + ": shard built from a different input or options than " + shardDirs[0]);
        for (uint32_t b : info.blocks) {
            if (b >= first.blockCount) throw InputError(dir + ": block " + std::to_string(b) + " out of range");
            listed.emplace_back(b, dir);
        }
    }
    std::stable_sort(listed.begin(), listed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<std::string> owner;
    for (const auto& [b, dir] : listed) {
        if (b < owner.size()) throw InputError(dir + ": block " + std::to_string(b) + " also in " + owner[b]);
        if (b > owner.size()) break;  // block owner.size() is missing
        owner.push_back(dir);
    }
    if (owner.size() < first.blockCount)
        throw InputError(shardDirs.front() + ": block " + std::to_string(owner.size()) + " of " + std::to_string(first.blockCount) +
                         " is in none of the " + std::to_string(shardDirs.size()) + " shard(s) given");
    // A record file holds its own block's nodes: one copied over another's merged into a database of
    // two roots for one block and none for the other, exit 0 (until stop 45).
    auto checkBlock = [&](const NodeRecord& r, uint32_t b) {
        if (r.node.block != b)
            throw InputError(blockRecordPath(owner[b], b) + ": holds block " + std::to_string(r.node.block) + "'s nodes (corrupt shard)");
    };
    Writer writer(output, cTextured);
    std::vector<uint32_t> roots(owner.size());
    for (uint32_t b = 0; b < owner.size(); ++b) {
        auto records = readBlockRecords(blockRecordPath(owner[b], b), 1);
        if (records.empty()) throw InputError(blockRecordPath(owner[b], b) + ": block has no nodes");
        checkBlock(records[0], b);
        roots[b] = writer.addNode(std::move(records[0].node));
    }
    for (uint32_t b = 0; b < owner.size(); ++b) {
        std::vector<uint32_t> ids;  // database id of each record of the block
        readRecords(blockRecordPath(owner[b], b), SIZE_MAX, [&](NodeRecord&& r) {
            const size_t i = ids.size();
            if (i == 0) return ids.push_back(roots[b]);  // hlod0, written above
            if (r.parentLocal >= i) corrupt(blockRecordPath(owner[b], b), "parent link");
            checkBlock(r, b);
            r.node.parent = ids[r.parentLocal];
            ids.push_back(writer.addNode(std::move(r.node)));
        });
    }
    for (const auto& [key, value] : first.meta) writer.setMeta(key, value);
    writer.finish();
}

}  // namespace hlod
