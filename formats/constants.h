// Constants of thesis Table 6.1 (plus the build constants of §3.2), defaults in ONE place.
// Every run prints them (printConstants) so results can be reproduced; every value can be
// overridden from the command line (--set name=value) or a config file (name = value lines).
#pragma once

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

struct ConstantInfo {
    const char* name;        // as written in the thesis, e.g. "c_targetTime"
    double Constants::*field;
    const char* meaning;
};

// All constants with their thesis names, in Table 6.1 order.
const std::vector<ConstantInfo>& constantTable();

// Sets one constant by thesis name ("c_vis") from text; throws std::invalid_argument with a
// one-line message for an unknown name or a value that is not a finite number.
void setConstant(Constants& c, const std::string& name, const std::string& value);

// Parses "name=value".
void setConstantAssignment(Constants& c, const std::string& assignment);

// Reads a config file of "name = value" lines ('#' starts a comment); throws
// std::runtime_error "FILE:LINE: problem" on a bad line or unreadable file.
void loadConstantsFile(Constants& c, const std::string& path);

// "name=value" pairs, in table order, exactly round-trippable through setConstant.
std::vector<std::pair<std::string, std::string>> constantsAsPairs(const Constants& c);

// One line: "constants: c_desiredTris=900 c_levelFactor=4 ...".
void printConstants(std::ostream& os, const Constants& c);

}  // namespace hlod
