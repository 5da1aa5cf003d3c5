// The line-oriented files users write by hand (the constants file of `--config`, the calibration
// file of `--calibration`): `name = value` lines, `#` comments. Lines are read one at a time and
// bounded, so a file without newlines (or a 1 GiB line) is refused at once rather than held whole.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

namespace hlod {

inline constexpr size_t kMaxSettingLine = 4096;  // characters per line, comment included

// The next line of `in` (numbered `number`, 1-based, in `path`), without its comment and
// surrounding blanks. False at the end of the file; throws InputError
// "PATH:N: line longer than 4096 characters" and "PATH: read error".
bool nextSettingLine(std::istream& in, std::string& line, const std::string& path, int number);

std::string trimBlanks(const std::string& s);  // without leading/trailing spaces, tabs and CRs

}  // namespace hlod
