// Bounded line reading for the constants and calibration files (formats/setting_lines.h).
#include "formats/setting_lines.h"

#include "formats/errors.h"

#include <istream>

namespace hlod {

std::string trimBlanks(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

bool nextSettingLine(std::istream& in, std::string& line, const std::string& path, int number) {
    line.clear();
    for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
        if (c == '\n') break;
        if (line.size() == kMaxSettingLine)
            throw InputError(path + ":" + std::to_string(number) + ": line longer than " +
                             std::to_string(kMaxSettingLine) + " characters");
        line.push_back(static_cast<char>(c));
    }
    if (in.bad()) throw InputError(path + ": read error");
    if (line.empty() && in.eof()) return false;
    line = trimBlanks(line.substr(0, line.find('#')));
    return true;
}

}  // namespace hlod
