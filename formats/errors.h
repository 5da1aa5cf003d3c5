// The errors every hlod library throws. Each what() is one line naming the file and the problem.
// The command line maps them to exit statuses (formats/cli/command.h, README "Exit status"):
//   InputError, UnreadableDatabase, std::invalid_argument (usage) -> 2
//   FormatError (a database that opens but whose data is invalid), any other failure -> 1
#pragma once

#include <sys/stat.h>

#include <stdexcept>
#include <string>

namespace hlod {

// An input file (mesh, texture, camera path, constants or calibration file) that is missing or
// cannot be read or parsed.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `text` with every control character shown as '?': one printable line whatever bytes a file name
// or a bad file holds (error messages; the `# key: value` lines of CSV outputs and inspect's text,
// where a newline in a database's name broke the CSV until stop 45).
inline std::string printableLine(std::string text) {
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return text;
}

// An input that is neither a regular file nor a folder (a FIFO, a device, a socket) is refused
// before it is opened: opening a FIFO blocks until a writer comes, and a device's data may never
// end. Throws InputError "PATH: not a regular file"; a path that does not exist passes (the
// open that follows says why it fails), as does a folder (its reader says what it expected).
inline void refuseSpecialFile(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
        throw InputError(path + ": not a regular file");
}

// Invalid data in a database file: a checksum mismatch, a blob that does not decode, a broken
// invariant.
struct FormatError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A file that cannot be opened as a database at all (missing, not a database, bad header or
// skeleton): thrown by Database::open.
struct UnreadableDatabase : FormatError {
    using FormatError::FormatError;
};

}  // namespace hlod
