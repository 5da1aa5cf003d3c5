// The errors every hlod library throws. Each what() is one line naming the file and the problem.
// The command line maps them to exit statuses (formats/cli/command.h, README "Exit status"):
//   InputError, UnreadableDatabase, std::invalid_argument (usage) -> 2
//   FormatError (a database that opens but whose data is invalid), any other failure -> 1
#pragma once

#include <stdexcept>

namespace hlod {

// An input file (mesh, texture, camera path, constants or calibration file) that is missing or
// cannot be read or parsed.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

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
