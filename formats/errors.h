// The errors every hlod library throws. Each what() is one line naming the file and the problem.
// The command line maps them to exit statuses (formats/cli/command.h, README "Exit status"):
//   InputError, UnreadableDatabase, std::invalid_argument (usage) -> 2
//   FormatError (a database that opens but whose data is invalid), any other failure -> 1
#pragma once

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

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

// A value from a file as a message quotes it: control bytes (C0, DEL, C1) and bytes that do not
// form a UTF-8 sequence (by lead and continuation bytes; C0, C1, F5-FF never lead) as \xNN (a NUL
// ended the message, what() being a C string, and 0xFF reached the terminal raw), at most `most`
// bytes, then "...".
inline std::string shownBytes(std::string_view text, size_t most = 40) {
    std::string out;
    const auto hex = [&](unsigned char c) {
        const char digits[] = "0123456789ABCDEF";
        out += {'\\', 'x', digits[c >> 4], digits[c & 15]};
    };
    const std::string_view t = text.substr(0, most);
    for (size_t i = 0; i < t.size();) {
        const auto c = static_cast<unsigned char>(t[i]);
        const size_t n = c < 0x80 ? 1 : c < 0xC2 ? 0 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : c < 0xF5 ? 4 : 0;  // C0, C1, F5+: never
        bool utf8 = n > 1 && i + n <= t.size();
        for (size_t k = 1; utf8 && k < n; ++k) utf8 = (static_cast<unsigned char>(t[i + k]) >> 6) == 2;
        if (utf8) {  // the second byte's range (Unicode Table 3-7): no C1 control, overlong form, surrogate or > U+10FFFF
            const auto b = static_cast<unsigned char>(t[i + 1]);
            const unsigned char low = c == 0xC2 ? 0xA0 : c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
            const unsigned char high = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
            utf8 = b >= low && b <= high;
        }
        if (n == 1 && c >= 0x20 && c != 0x7f) out += t[i++];
        else if (utf8) out += t.substr(i, n), i += n;
        else hex(c), ++i;
    }
    return text.size() > most ? out + "..." : out;
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

// A text input (a camera path, a calibration or constants file) opened for reading, or InputError
// "PATH: a folder, not a WHAT", "PATH: cannot read WHAT (REASON)", or refuseSpecialFile's (until
// stop 49 a folder read as "read error" and a missing file gave no reason).
inline std::ifstream openTextInput(const std::string& path, const std::string& what) {
    refuseSpecialFile(path);
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) throw InputError(path + ": a folder, not a " + what);
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot read " + what + " (" + std::strerror(errno ? errno : EACCES) + ")");
    return in;
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
