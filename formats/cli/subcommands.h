// The subcommands of formats/ (registered by the table in hlod.cpp).
#pragma once

#include "formats/cli/command.h"

namespace hlod::cli {

// `hlod inspect DB`: the per-level summary, the node tree or one node in full.
void addInspect(CLI::App& app, int& status);
// `hlod validate DB`: every violated invariant of formats/FORMAT.md, one line each.
void addValidate(CLI::App& app, int& status);
// `hlod export tiles DB -o DIR`: a 3D Tiles 1.1 tileset (formats/export_tiles.h).
void addExport(CLI::App& app, int& status);

}  // namespace hlod::cli
