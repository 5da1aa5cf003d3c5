// The diffuse texture statements of an MTL file (`map_Kd [options] FILE`), read as the MTL
// specification writes them (Wavefront, "Material Library File (.mtl)", "Texture map
// statements"): -o, -s and -t take u and optionally v and w; tinyobjloader, which still reads the
// materials, takes three numbers and so swallowed the file of `map_Kd -o 0 0.25 a.png` (mtl_map.cpp).
#pragma once

#include <map>
#include <string>
#include <string_view>

namespace hlod {

struct DiffuseMap {
    std::string file;                // the rest of the line after the options (may hold spaces); empty: none named
    double scale[3] = {1, 1, 1};     // -s u v w
    double offset[3] = {0, 0, 0};    // -o u v w
    bool clamp = false;              // -clamp on
};

// Each material's last `map_Kd` statement, by the material's name as its `newmtl` line gives it
// (blanks around it trimmed), as tinyobjloader reads the lines (ended by CR, LF or CRLF; no `\`
// continuation).
std::map<std::string, DiffuseMap> diffuseMaps(std::string_view mtl);

}  // namespace hlod
