// `hlod validate`: every invariant of formats/FORMAT.md §Invariants, reported one per line.
#pragma once

#include "formats/db.h"

#include <string>
#include <vector>

namespace hlod {

struct ValidateOptions {
    bool quick = false;                 // skip reading and decoding blobs
    double boundsTolerance = 1e-4;      // relative to the parent's diagonal
    double cTextured = -1;              // < 0: from the database's c_textured meta (default: Constants{}.textured)
};

struct Violation {
    uint32_t node = kNone;  // kNone for file-level problems
    std::string message;    // one line
};

std::vector<Violation> validate(const Database& db, const ValidateOptions& options);

}  // namespace hlod
