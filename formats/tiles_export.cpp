// `hlod export tiles` as a function (formats/export_tiles.h): every node's GLB, then tileset.json,
// into OUT.tmp-hlodSPACE-PID-XXXXXX next to OUT, renamed onto OUT at the end (swapped with an earlier export
// in one renameat2(RENAME_EXCHANGE)), like the database writer's atomic rename (FORMAT.md §Atomic
// writing): a failed or killed export never leaves at OUT a tileset that looks complete, and the
// next export to OUT removes a killed one's temporary (formats/temp_files.h).
#include "formats/interrupt.h"
#include "formats/json_text.h"
#include "formats/temp_files.h"
#include "formats/tiles_detail.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hlod {

namespace {

namespace fs = std::filesystem;

void writeFile(const fs::path& path, const void* data, size_t size) {
    errno = 0;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(data), std::streamsize(size));
    const int failed = out ? 0 : errno;  // the write's reason, before close can change errno
    out.close();
    if (!out) throw std::runtime_error(tiles::writeFailure(path.string(), failed ? failed : errno));
}

// Refuses an OUT that an export must not replace: anything but an earlier export.
void checkTarget(const fs::path& out, bool archive) {
    std::error_code ec;
    const fs::file_status st = fs::status(out, ec);
    const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    // a failed write (status 1), as for every other output (status 2 until stop 46)
    if (!fs::is_directory(parent)) throw std::runtime_error(out.string() + ": its folder does not exist");
    if (!fs::exists(st)) return;
    if (archive) {
        if (!fs::is_regular_file(st)) throw InputError(out.string() + ": exists and is not a file");
    } else if (!fs::is_directory(st) || (!fs::is_empty(out) && !fs::exists(out / "tileset.json"))) {
        throw InputError(out.string() + ": exists and is not a tileset folder (no tileset.json); not replaced");
    } else if (const auto other = foreignEntry(out.string(), [](const std::string& entry, bool isFolder) {
                   static const std::regex tile(R"(tiles/[0-9]+\.glb)");
                   return isFolder ? entry == "tiles" : entry == "tileset.json" || std::regex_match(entry, tile);
               })) {
        throw InputError(out.string() + ": holds " + *other + ", which hlod export does not write; not replaced");
    }
}

// A temporary file next to `out` (the archive), removed on destruction.
struct Temporary {
    fs::path path;
    explicit Temporary(fs::path p) : path(std::move(p)) {}
    ~Temporary() {
        std::error_code ec;
        if (!path.empty()) fs::remove_all(path, ec);
        forgetTemporary(path.string());
    }
};

// Moves `from` onto `to`; an existing `to` ends up at `from` (removed by its Temporary).
void renameOnto(const fs::path& from, const fs::path& to) {
    if (fs::exists(to)) {
        if (renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) != 0)
            throw std::runtime_error(to.string() + ": cannot replace the earlier export");
    } else if (std::rename(from.c_str(), to.c_str()) != 0) {
        throw std::runtime_error(to.string() + ": cannot rename the finished export onto it");
    }
}

uint64_t folderBytes(const fs::path& folder) {
    uint64_t bytes = 0;
    for (const auto& e : fs::recursive_directory_iterator(folder))
        if (e.is_regular_file()) bytes += e.file_size();
    return bytes;
}

}  // namespace

TilesReport exportTiles(const Database& db, const std::string& outPath, const TilesOptions& options) {
    fs::path out = fs::path(outPath).lexically_normal();
    if (out.filename().empty() && !options.archive) out = out.parent_path();  // DIR/ names the folder DIR
    if (out.filename().empty() || out.filename() == "." || out.filename() == "..")
        throw InputError(outPath + ": not a file or folder name");
    checkTarget(out, options.archive);
    refuseOutputOverInputs(out.string(), {db.path()});
    const Skeleton& s = db.skeleton();
    const StagingFolder staging(out.string());  // OUT.tmp-hlodSPACE-PID-XXXXXX, 0755; removed at the end (after an exchange: the old OUT)
    const fs::path folder = staging.path;
    fs::create_directory(folder / "tiles");

    TilesReport report;
    std::vector<std::optional<Box3f>> content(s.nodes.size());
    for (uint32_t n = 0; n < s.nodes.size(); ++n) {
        std::optional<tiles::Glb> glb = tiles::nodeGlb(db, n);
        if (!glb) continue;
        writeFile(folder / tiles::contentUri(n), glb->bytes.data(), glb->bytes.size());
        content[n] = glb->bounds;
        report.contentTiles += 1;
        report.triangles += glb->triangles;
        report.contentBytes += glb->bytes.size();
    }
    const std::string json = jsonText(tiles::tilesetJson(s, content, options, db.path()));
    writeFile(folder / "tileset.json", json.data(), json.size());  // last: the folder is complete
    report.tiles = s.nodes.size() + 1;
    report.tilesetBytes = json.size();

    if (options.archive) {
        std::string name = temporaryPattern(out.string() + ".tmp");  // OUT.tmp-hlodSPACE-PID-XXXXXX: swept like the folder
        const int fd = createTemporary(name, false);
        if (fd < 0) throw std::runtime_error(out.string() + ": cannot create a temporary file beside it");
        ::fchmod(fd, 0644);  // mkstemp's 0600 would hide the archive from other readers
        ::close(fd);
        Temporary archive(name);
        tiles::write3tz(folder.string(), archive.path.string());
        report.outputBytes = fs::file_size(archive.path);
        uninterrupted([&] { renameOnto(archive.path, out); });  // afterwards it holds the earlier archive, if any
    } else {
        report.outputBytes = folderBytes(folder);
        uninterrupted([&] { renameOnto(folder, out); });  // afterwards it holds the earlier export, if any
    }
    return report;
}

}  // namespace hlod
