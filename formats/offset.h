// What `hlod build --offset X,Y,Z` subtracted from every input position before storing it as a
// 32-bit float (FORMAT.md, META key "offset"): database coordinates + offset = input coordinates.
// A model far from the origin (a scan in UTM metres) keeps its detail that way; `hlod inspect`
// prints the key with the other provenance, `hlod export tiles` records it in the tileset.
#pragma once

#include "formats/db.h"

#include <array>
#include <optional>
#include <string>

namespace hlod {

using Offset = std::array<double, 3>;
// "X,Y,Z", each the shortest decimal that reads back as the same double.
std::string offsetText(const Offset& offset);
// Three numbers within +-1e15 separated by commas; anything else throws std::invalid_argument
// naming `option` (--offset).
Offset parseOffset(const std::string& text, const std::string& option);
// The database's offset, or none (nothing was subtracted); a malformed value throws FormatError "NAME: ...".
std::optional<Offset> offsetOf(const Skeleton& skeleton, const std::string& name);

}  // namespace hlod
