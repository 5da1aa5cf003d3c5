// Constants of thesis Table 6.1 (plus the build constants of §3.2), defaults in ONE place: no
// other file spells their values. Every run prints the ones it uses (printConstants) so results
// can be reproduced; each can be overridden from the command line (--set name=value) or a
// constants file (name = value lines) of a subcommand that uses it.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace hlod {

struct Constants {
    // §3.2 HLOD generation
    double desiredTris = 900;     // c_desiredTris: desired triangles per HLOD node
    double levelFactor = 4;       // c_levelFactor: triangle/texture ratio between levels, = children per node
    // §3.3 cost model
    double textured = 0.127;      // c_textured: weight of textured vs untextured triangles (eq. 3.1)
    // §4.2 selection
    double vis = 1.275;           // c_vis: importance of visibility in the priority
    double fore = 0.45;           // c_fore: importance of foreshortening in the priority
    double targetTimeMs = 30;     // c_targetTime: target frame time, milliseconds
    double hystSwitch = 1500;     // c_hystSwitch: hysteresis threshold for switching a node
    double hystLimit = 4510;      // c_hystLimit: range of the hysteresis counter
    // §4.3 memory
    double memory = 935;          // c_memory: bytes per unit of cost
};

// Which stage reads a constant: the build (thesis §3: `hlod build`) or the player (§4: `hlod
// play`, `hlod view`, `hlod compare`). A bit mask, so a set of uses can be asked for.
enum ConstantUse : uint8_t { kUsedByBuild = 1, kUsedByPlayer = 2, kUsedByAny = kUsedByBuild | kUsedByPlayer };

struct ConstantInfo {
    const char* name;        // as written in the thesis, e.g. "c_targetTime"
    double Constants::*field;  // the meaning of each: the comments of Constants above
    ConstantUse use;
};

// All constants with their thesis names, in Table 6.1 order.
const std::vector<ConstantInfo>& constantTable();

// Sets one constant by thesis name ("c_vis") from text; throws std::invalid_argument with a
// one-line message for an unknown name or a value that is not a finite number.
void setConstant(Constants& c, const std::string& name, const std::string& value);

// Parses "name=value".
void setConstantAssignment(Constants& c, const std::string& assignment);

// Reads a constants file of "name = value" lines ('#' starts a comment) into the constants
// `use` reads; returns the names it holds of constants `use` does not read (left unchanged), so
// one file can serve a whole experiment. Throws InputError "FILE:LINE: problem" on a bad line or
// an unreadable file.
std::vector<std::string> loadConstantsFile(Constants& c, const std::string& path, ConstantUse use = kUsedByAny);

// Checks the constants `use` reads against the ranges they make sense in (README "Reliability"):
// 1 <= c_desiredTris <= kMaxDesiredTris; 2 <= c_levelFactor <= 64 (children per node); 0 < c_textured <= 1;
// c_vis, c_fore >= 0; 0 < c_targetTime <= 10 s (kMaxFrameMs); 0 < c_hystSwitch <= c_hystLimit; c_memory > 0.
// Throws std::invalid_argument "c_NAME = VALUE: must be ..." (one line) for the first violation.
void validateConstants(const Constants& c, ConstantUse use);
// A node's triangle count is 32-bit (formats/FORMAT.md); 1e300 was accepted until stop 49.
inline constexpr double kMaxDesiredTris = 4294967295.0;
// The table entry of a constant, or nullptr for an unknown name.
const ConstantInfo* findConstant(const std::string& name);

// "name=value" pairs of the constants `use` reads, in table order, exactly round-trippable
// through setConstant.
std::vector<std::pair<std::string, std::string>> constantsAsPairs(const Constants& c, ConstantUse use = kUsedByAny);

// A constant's value as constantsAsPairs and printConstants write it (round-trippable).
std::string formatConstant(double value);

// One line: "constants: c_desiredTris=900 c_levelFactor=4 ..." (the constants `use` reads).
void printConstants(std::ostream& os, const Constants& c, ConstantUse use);

}  // namespace hlod
