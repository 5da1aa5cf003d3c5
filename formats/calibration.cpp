// Reader and writer of the calibration file (formats/calibration.h).
#include "formats/calibration.h"

#include "formats/constants.h"
#include "formats/errors.h"
#include "formats/setting_lines.h"
#include "formats/temp_files.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>

namespace hlod {

namespace {

// The numeric figures of the file, by name, as members of Calibration.
const std::map<std::string, double Calibration::*>& numericFields() {
    static const std::map<std::string, double Calibration::*> fields = {
        {"c_textured", &Calibration::cTextured}, {"ms_per_cost", &Calibration::msPerCost},
        {"fixed_overhead_ms", &Calibration::fixedOverheadMs}};
    return fields;
}

double* fitField(Calibration& c, const std::string& name) {
    if (name == "textured_ms_per_tri") return &c.textured.slope;
    if (name == "untextured_ms_per_tri") return &c.untextured.slope;
    if (name == "textured_intercept_ms") return &c.textured.intercept;
    if (name == "untextured_intercept_ms") return &c.untextured.intercept;
    if (name == "ms_per_pixel") return &c.msPerPixel;  // optional: files before it read as 0
    return nullptr;
}

}  // namespace

void writeCalibration(const Calibration& c, std::ostream& out) {
    out << std::setprecision(8);
    out << "# hlod calibrate: render-time model (formats/calibration.h)\n"
        << "# time_ms = overhead + perTri * triangles; c_textured = perTexturedTri / (perTexturedTri + perUntexturedTri)\n"
        << "renderer = " << c.renderer << "\n"
        << "c_textured = " << c.cTextured << "\n"
        << "ms_per_cost = " << c.msPerCost << "\n"
        << "fixed_overhead_ms = " << c.fixedOverheadMs << "\n"
        << "textured_ms_per_tri = " << c.textured.slope << "\n"
        << "untextured_ms_per_tri = " << c.untextured.slope << "\n"
        << "textured_intercept_ms = " << c.textured.intercept << "\n"
        << "untextured_intercept_ms = " << c.untextured.intercept << "\n"
        << "ms_per_pixel = " << c.msPerPixel << "\n";
    for (const CalibrationSample& s : c.samples)
        out << "# sample " << (s.textured ? "textured" : "untextured") << " triangles=" << s.triangles
            << " ms=" << s.ms << "\n";
    for (const auto& [pixels, ms] : c.pixelSamples) out << "# sample pixels=" << pixels << " ms=" << ms << "\n";
}

void writeCalibration(const Calibration& c, const std::string& path) {
    TextFileWriter file(path, "calibration");
    writeCalibration(c, file.stream());
    file.commit();
}

Calibration readCalibration(const std::string& path) {
    std::ifstream in = openTextInput(path, "calibration file");
    Calibration c;
    std::set<std::string> seen;  // each once: three lines of one name were a complete file (until stop 49)
    std::string line;
    for (int number = 1; nextSettingLine(in, line, path, number); ++number) {
        if (line.empty()) continue;
        const std::string at = path + ":" + std::to_string(number) + ": ";
        const size_t eq = line.find('=');
        if (eq == std::string::npos) throw InputError(at + "expected 'name = value'");
        const std::string name = trimBlanks(line.substr(0, eq)), text = trimBlanks(line.substr(eq + 1));
        if (!seen.insert(name).second) throw InputError(at + "'" + shownBytes(name) + "' given twice");
        if (name == "renderer") {
            c.renderer = text;
            continue;
        }
        auto field = numericFields().find(name);
        double* target = field != numericFields().end() ? &(c.*field->second) : fitField(c, name);
        if (!target) throw InputError(at + "unknown name '" + shownBytes(name) + "'");
        double value = 0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
        const bool intercept = name.ends_with("_intercept_ms");  // a fitted line's, of either sign
        if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value) ||
            (value < 0 && !intercept))
            throw InputError(at + name + " '" + text + "' is not a finite " + (intercept ? "" : "non-negative ") + "number");
        *target = value;
    }
    if (std::ranges::any_of(numericFields(), [&](const auto& f) { return !seen.contains(f.first); }))
        throw InputError(path + ": not a calibration file (needs c_textured, ms_per_cost and fixed_overhead_ms)");
    if (!(c.cTextured > 0 && c.cTextured <= 1)) throw InputError(path + ": c_textured must lie in (0, 1]");
    for (const auto& [name, value] : {std::pair{"ms_per_cost", c.msPerCost}, {"fixed_overhead_ms", c.fixedOverheadMs}})
        if (value > kMaxFrameMs)
            throw InputError(path + ": " + name + " = " + formatConstant(value) + " is absurd (a frame of more than " +
                             std::to_string(int(kMaxFrameMs / 1000)) + " s)");
    return c;
}

}  // namespace hlod
