// The constants of thesis Table 6.1 (and §3.2 build constants): names, parsing from
// "name=value" and config files, and printing, so every run can be reproduced.
#include "formats/constants.h"

#include "formats/calibration.h"
#include "formats/errors.h"
#include "formats/setting_lines.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace hlod {

std::string formatConstant(double v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trippable form
    return {buf, r.ptr};
}

const std::vector<ConstantInfo>& constantTable() {
    static const std::vector<ConstantInfo> table = {
        {"c_desiredTris", &Constants::desiredTris, kUsedByBuild},
        {"c_levelFactor", &Constants::levelFactor, kUsedByBuild},
        {"c_textured", &Constants::textured, kUsedByBuild},
        {"c_vis", &Constants::vis, kUsedByPlayer},
        {"c_fore", &Constants::fore, kUsedByPlayer},
        {"c_targetTime", &Constants::targetTimeMs, kUsedByPlayer},
        {"c_hystSwitch", &Constants::hystSwitch, kUsedByPlayer},
        {"c_hystLimit", &Constants::hystLimit, kUsedByPlayer},
        {"c_memory", &Constants::memory, kUsedByPlayer},
    };
    return table;
}

const ConstantInfo* findConstant(const std::string& name) {
    for (const ConstantInfo& info : constantTable())
        if (name == info.name) return &info;
    return nullptr;
}

void setConstant(Constants& c, const std::string& name, const std::string& value) {
    if (const ConstantInfo* info = findConstant(name)) {
        const std::string v = trimBlanks(value);
        double parsed = 0;
        auto r = std::from_chars(v.data(), v.data() + v.size(), parsed);
        if (v.empty() || r.ec != std::errc() || r.ptr != v.data() + v.size() || !std::isfinite(parsed))
            throw std::invalid_argument("constant " + name + ": '" + shownBytes(value) + "' is not a finite number");
        c.*info->field = parsed;
        return;
    }
    std::string known;
    for (const ConstantInfo& info : constantTable()) known += std::string(known.empty() ? "" : ", ") + info.name;
    throw std::invalid_argument("unknown constant '" + name + "' (known: " + known + ")");
}

void validateConstants(const Constants& c, ConstantUse use) {
    const auto check = [&](ConstantUse by, const char* name, double value, bool ok, const std::string& rule) {
        if ((by & use) && !ok) throw std::invalid_argument(std::string(name) + " = " + formatConstant(value) + ": must be " + rule);
    };
    check(kUsedByBuild, "c_desiredTris", c.desiredTris, c.desiredTris >= 1 && c.desiredTris <= kMaxDesiredTris,
          "in [1, " + formatConstant(kMaxDesiredTris) + "] (triangles per node)");
    check(kUsedByBuild, "c_levelFactor", c.levelFactor, c.levelFactor >= 2 && c.levelFactor <= 64 && c.levelFactor == std::floor(c.levelFactor),
          "a whole number in [2, 64] (children per node)");
    check(kUsedByBuild, "c_textured", c.textured, c.textured > 0 && c.textured <= 1, "in (0, 1]");
    check(kUsedByPlayer, "c_vis", c.vis, c.vis >= 0, ">= 0");
    check(kUsedByPlayer, "c_fore", c.fore, c.fore >= 0, ">= 0");
    check(kUsedByPlayer, "c_targetTime", c.targetTimeMs, c.targetTimeMs > 0 && c.targetTimeMs <= kMaxFrameMs,
          "> 0 and at most 10000 (milliseconds: a frame of at most 10 s)");
    check(kUsedByPlayer, "c_hystSwitch", c.hystSwitch, c.hystSwitch > 0, "> 0");
    check(kUsedByPlayer, "c_hystSwitch", c.hystSwitch, c.hystSwitch <= c.hystLimit,
          "<= c_hystLimit = " + formatConstant(c.hystLimit) + " (the counter could never reach it)");
    check(kUsedByPlayer, "c_memory", c.memory, c.memory > 0, "> 0 (bytes per unit of cost)");
}

void setConstantAssignment(Constants& c, const std::string& assignment) {
    auto eq = assignment.find('=');
    if (eq == std::string::npos)
        throw std::invalid_argument("'" + assignment + "' is not of the form name=value");
    setConstant(c, trimBlanks(assignment.substr(0, eq)), assignment.substr(eq + 1));
}

std::vector<std::string> loadConstantsFile(Constants& c, const std::string& path, ConstantUse use) {
    std::ifstream in = openTextInput(path, "constants file");
    std::vector<std::string> skipped;
    std::string line;
    for (int number = 1; nextSettingLine(in, line, path, number); ++number) {
        if (line.empty()) continue;
        try {
            const size_t eq = line.find('=');
            const ConstantInfo* info = eq == std::string::npos ? nullptr : findConstant(trimBlanks(line.substr(0, eq)));
            if (info && !(info->use & use)) {
                skipped.push_back(info->name);
                continue;
            }
            setConstantAssignment(c, line);
        } catch (const std::invalid_argument& e) {
            throw InputError(path + ":" + std::to_string(number) + ": " + e.what());
        }
    }
    return skipped;
}

std::vector<std::pair<std::string, std::string>> constantsAsPairs(const Constants& c, ConstantUse use) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const ConstantInfo& info : constantTable())
        if (info.use & use) out.emplace_back(info.name, formatConstant(c.*info.field));
    return out;
}

void printConstants(std::ostream& os, const Constants& c, ConstantUse use) {
    os << "constants:";
    for (const auto& [name, value] : constantsAsPairs(c, use)) os << ' ' << name << '=' << value;
    os << '\n';
}

}  // namespace hlod
