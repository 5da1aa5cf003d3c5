// Stale temporaries of killed runs (formats/temp_files.h).
#include "formats/temp_files.h"

#include "formats/interrupt.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <xxhash.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string_view>
#include <stdexcept>
#include <utility>

namespace hlod {

namespace {

// This machine and PID namespace, as 8 hex digits (XXH3-64 of the host name and the namespace's
// inode): a PID means a process only where it was taken. Runs on other hosts sharing a folder (NFS,
// Slurm) or in other containers sharing a volume deleted each other's live temporaries until stop 47.
const std::string& processSpace() {
    static const std::string space = [] {
        char host[256] = {};
        ::gethostname(host, sizeof host - 1);
        struct stat ns {};
        const std::string key = std::string(host) + "/" + (::stat("/proc/self/ns/pid", &ns) == 0 ? std::to_string(ns.st_ino) : "");
        char hex[9];
        std::snprintf(hex, sizeof hex, "%08llx", static_cast<unsigned long long>(XXH3_64bits(key.data(), key.size()) & 0xffffffffu));
        return std::string(hex);
    }();
    return space;
}

bool mkstempLetters(std::string_view text) {
    return text.size() == 6 && std::all_of(text.begin(), text.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); });
}

}  // namespace

std::string temporaryPattern(const std::string& prefix, long pid) {
    return prefix + "-hlod" + processSpace() + "-" + std::to_string(pid) + "-XXXXXX";
}

void removeStaleTemporaries(const std::string& prefix) {
    namespace fs = std::filesystem;
    const fs::path p(prefix);
    const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string start = p.filename().string() + "-hlod" + processSpace() + "-";
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= start.size() + 7 || name.compare(0, start.size(), start) != 0) continue;
        const char* first = name.data() + start.size();
        const char* last = name.data() + name.size() - 7;  // "-XXXXXX" made by mkstemp / mkdtemp
        long pid = 0;
        const auto [ptr, error] = std::from_chars(first, last, pid);
        if (error != std::errc() || ptr != last || *last != '-' || pid <= 0 || !mkstempLetters({last + 1, 6})) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // running (or not ours to ask)
        struct stat st {};
        if (::lstat(it->path().c_str(), &st) != 0 || st.st_uid != ::geteuid()) continue;  // another user's
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
    }
}

void checkReplaceable(const std::string& path, const std::string& what) {
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);  // follows a symbolic link
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
        throw std::runtime_error(path + ": cannot write " + what + " (exists and is not a regular file)");
}

void refuseOutputOverInputs(const std::string& output, std::initializer_list<std::string> inputs) {
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (!output.empty() && !input.empty() && std::filesystem::equivalent(output, input, ec))
            throw std::invalid_argument(output + ": is also an input (" + input + "); write the output elsewhere");
    }
}

namespace {

// Whether PATH lies strictly below FOLDER (after symbolic links); nullopt when either cannot be resolved.
std::optional<bool> below(const std::string& path, const std::string& folder) {
    std::error_code pathError, dirError;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path), pathError);
    const std::filesystem::path dir = std::filesystem::weakly_canonical(std::filesystem::absolute(folder), dirError);
    if (pathError || dirError) return std::nullopt;
    const auto [d, o] = std::mismatch(dir.begin(), dir.end(), p.begin(), p.end());
    return d == dir.end() && o != p.end() && !o->empty();
}

}  // namespace

void refuseOutputInsideFolder(const std::string& output, const std::string& folder) {
    if (below(output, folder).value_or(false))  // unresolvable: the writer of OUTPUT, the reader of FOLDER say why
        throw std::invalid_argument(output + ": is inside an input folder (" + folder + "); write the output elsewhere");
}

bool sameOutput(const std::string& a, const std::string& b) {
    std::error_code ea, eb;
    const auto p = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ea), ea);
    const auto q = std::filesystem::weakly_canonical(std::filesystem::absolute(b, eb), eb);
    return ea || eb ? a == b : p == q;
}

bool isInsideFolder(const std::string& path, const std::string& folder) { return below(path, folder).value_or(false); }

void checkOutputFile(const std::string& output, const std::string& what, std::initializer_list<std::string> inputs) {
    if (output.empty()) return;
    if (output.back() == '/')  // f.hlod/ failed at the end with "cannot create a temporary folder (Not a directory)"
        throw std::invalid_argument(output + ": names a folder (ends in '/'); the " + what + " is a file");
    // The temporary beside it is named longer (temporaryPattern): a name the folder takes but not its
    // temporary's failed only after the whole build (until stop 47).
    const std::string name = std::filesystem::path(output).filename().string();
    const std::filesystem::path parent = std::filesystem::path(output).parent_path();
    const long limit = ::pathconf(parent.empty() ? "." : parent.c_str(), _PC_NAME_MAX);
    const size_t longest = name.size() + temporaryPattern(".tmp", 9999999999L).size();
    if (limit > 0 && longest > static_cast<size_t>(limit))
        throw std::invalid_argument(output + ": its name of " + std::to_string(name.size()) + " bytes leaves no room for its temporary's (" +
                                    std::to_string(longest) + " bytes; the folder takes " + std::to_string(limit) + ")");
    refuseOutputOverInputs(output, inputs);
    checkReplaceable(output, what);
}

TextFileWriter::TextFileWriter(std::string path, std::string what) : path_(std::move(path)), what_(std::move(what)) {
    checkReplaceable(path_, what_);
    removeStaleTemporaries(path_ + ".tmp");
    std::string name = temporaryPattern(path_ + ".tmp");
    const int fd = createTemporary(name, false);
    if (fd < 0) fail(std::strerror(errno));
    ::fchmod(fd, 0644);  // mkstemp's 0600 would hide the output from other readers
    ::close(fd);
    temporary_ = name;
    out_.open(temporary_, std::ios::trunc);
    if (!out_) fail("cannot open a temporary file beside it");
}

TextFileWriter::~TextFileWriter() {
    if (!committed_ && !temporary_.empty()) std::remove(temporary_.c_str());
    forgetTemporary(temporary_);
}

void TextFileWriter::fail(const std::string& reason) {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
    forgetTemporary(temporary_);
    temporary_.clear();
    throw std::runtime_error(path_ + ": cannot write " + what_ + " (" + reason + ")");
}

std::optional<std::string> foreignEntry(const std::string& folder,
                                        const std::function<bool(const std::string& relative, bool isFolder)>& ours) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::recursive_directory_iterator it(folder, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const fs::file_status st = it->symlink_status(ec);
        const std::string relative = fs::path(it->path()).lexically_relative(folder).generic_string();
        if (ec || !(fs::is_regular_file(st) || fs::is_directory(st)) || !ours(relative, fs::is_directory(st)))
            return relative;
    }
    if (ec) return std::string(".");  // unreadable: not known to be ours
    return std::nullopt;
}

void createOutputFolder(const std::string& folder, const std::string& what) {
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) throw std::runtime_error(folder + ": cannot create the folder for " + what + " (" + error.message() + ")");
}

void TextFileWriter::commit() {
    const int earlier = out_ ? 0 : errno;  // a write that failed already (its buffer flushed) set errno then
    errno = 0;
    out_.close();
    const int error = earlier ? earlier : errno;
    if (!out_) fail(error ? std::string("write failed: ") + std::strerror(error) : "write failed");
    uninterrupted([&] {
        if (std::rename(temporary_.c_str(), path_.c_str()) != 0) fail(std::strerror(errno));
        forgetTemporary(temporary_);
    });
    committed_ = true;
}

void writeTextFile(const std::string& path, const std::string& what, const std::string& text) {
    TextFileWriter file(path, what);
    file.stream() << text;
    file.commit();
}

StagingFolder::StagingFolder(const std::string& target) {
    const std::string prefix = target + ".tmp";
    removeStaleTemporaries(prefix);  // of runs killed before they removed theirs
    std::string pattern = temporaryPattern(prefix);
    if (createTemporary(pattern, true) < 0) {
        const int error = errno;
        throw std::runtime_error(target + ": cannot create a temporary folder next to it (" + std::strerror(error) + ")");
    }
    ::chmod(pattern.c_str(), 0755);  // mkdtemp's 0700 would hide the output from other readers (a web server)
    path = pattern;
}

void StagingFolder::publish(const std::function<void()>& renames) {
    uninterrupted([&] {
        renames();
        forgetTemporary(path);
    });
    kept = true;
}

StagingFolder::~StagingFolder() {
    std::error_code ignored;
    if (!kept) std::filesystem::remove_all(path, ignored);
    forgetTemporary(path);
}

}  // namespace hlod
