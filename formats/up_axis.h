// The model's up axis as the database records it (FORMAT.md, META key "up"): `hlod build`
// writes "y" for glTF and "z" for OBJ/PLY unless --up says otherwise; `hlod path`, `hlod view`
// and `hlod export tiles` read it (their --up overrides it).
#pragma once

#include "formats/db.h"

#include <string>

namespace hlod {

// What the database records, or z for a database written before the key existed (what every
// reader assumed then); `recorded` tells which. Throws FormatError "NAME: ..." for any other value.
struct UpAxis {
    int axis = 2;  // 1: y up, 2: z up
    bool recorded = false;
};
UpAxis upAxisOf(const Skeleton& skeleton, const std::string& name);
// "y" -> 1, "z" -> 2; anything else throws std::invalid_argument naming `option` (--up).
int parseUpAxis(const std::string& text, const std::string& option);

}  // namespace hlod
