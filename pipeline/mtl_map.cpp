// MTL `map_Kd` statements (mtl_map.h). An option's words are taken by their count in the MTL
// specification's "Options for texture map statements"; -o, -s and -t take one to three numbers
// (the words after the first that read as numbers). The first word that is no option begins the
// file's name, which runs to the line's end, as tinyobjloader reads it.
#include "pipeline/mtl_map.h"

#include <algorithm>
#include <charconv>
#include <vector>

namespace hlod {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    for (size_t i = 0; i < line.size();) {
        while (i < line.size() && blank(line[i])) ++i;
        const size_t start = i;
        while (i < line.size() && !blank(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

bool number(std::string_view word, double& x) {
    const char* begin = word.data() + (!word.empty() && word.front() == '+');
    const auto [end, ec] = std::from_chars(begin, word.data() + word.size(), x);
    return !word.empty() && ec == std::errc() && end == word.data() + word.size();
}

// The number of words option `name` takes, or -1 for the 1-3 numbers of -o/-s/-t, 0: no option.
int optionWords(std::string_view name) {
    static constexpr std::pair<const char*, int> kOptions[] = {
        {"-blendu", 1}, {"-blendv", 1}, {"-bm", 1},   {"-boost", 1}, {"-cc", 1}, {"-clamp", 1}, {"-imfchan", 1},
        {"-texres", 1}, {"-type", 1},   {"-colorspace", 1}, {"-mm", 2},   {"-o", -1},    {"-s", -1}, {"-t", -1}};
    for (const auto& [option, count] : kOptions)
        if (name == option) return count;
    return 0;
}

DiffuseMap parseMap(std::string_view line, std::string_view afterKeyword) {
    DiffuseMap map;
    const std::vector<std::string_view> w = words(afterKeyword);
    size_t i = 0;
    while (i < w.size()) {
        const int count = optionWords(w[i]);
        if (count == 0) break;
        const std::string_view name = w[i++];
        if (count > 0) {
            if (name == "-clamp" && i < w.size()) map.clamp = w[i] == "on";
            i += static_cast<size_t>(count);
            continue;
        }
        double* values = name == "-o" ? map.offset : name == "-s" ? map.scale : nullptr;  // -t: turbulence, unused
        double x = 0;
        for (int k = 0; k < 3 && i < w.size() && number(w[i], x); ++k, ++i)
            if (values) values[k] = x;
    }
    if (i < w.size()) {  // the rest of the line from this word, its trailing blanks cut
        size_t end = line.size();
        while (end > 0 && blank(line[end - 1])) --end;
        map.file = std::string(line.substr(static_cast<size_t>(w[i].data() - line.data()), end - static_cast<size_t>(w[i].data() - line.data())));
    }
    return map;
}

}  // namespace

std::map<std::string, DiffuseMap> diffuseMaps(std::string_view mtl) {
    std::map<std::string, DiffuseMap> maps;
    std::string material;
    for (size_t start = 0; start < mtl.size();) {
        const size_t end = std::min(mtl.find_first_of("\r\n", start), mtl.size());  // CR, LF or CRLF, as tinyobjloader
        const std::string_view line = mtl.substr(start, end - start);
        start = end + 1;
        const std::vector<std::string_view> w = words(line);
        if (w.empty()) continue;
        const std::string_view after = line.substr(static_cast<size_t>(w[0].data() - line.data()) + w[0].size());
        if (w[0] == "newmtl" && w.size() > 1)  // the rest of the line, as tinyobjloader names it
            material = std::string(w[1].data(), static_cast<size_t>(w.back().data() + w.back().size() - w[1].data()));
        else if (w[0] == "map_Kd")
            maps[material] = parseMap(line, after);
    }
    return maps;
}

}  // namespace hlod
