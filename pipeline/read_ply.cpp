// PLY input (ascii, binary little/big endian): positions, per-vertex normals, texture
// coordinates (u/v, s/t, texture_u/texture_v) and colours when present; polygons are fanned into
// triangles. Read in one buffered pass into a RawMesh (in memory, or spilled to disk for a large
// single input); every short read is reported as a truncated file.
#include "pipeline/pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

namespace hlod {
namespace {

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::F32;
    bool isList = false;
    PlyType countType = PlyType::U8;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

size_t typeSize(PlyType t) {
    static constexpr size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[static_cast<int>(t)];
}

bool parseType(const std::string& s, PlyType& t) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::I8},    {"int8", PlyType::I8},     {"uchar", PlyType::U8},   {"uint8", PlyType::U8},
        {"short", PlyType::I16},  {"int16", PlyType::I16},   {"ushort", PlyType::U16}, {"uint16", PlyType::U16},
        {"int", PlyType::I32},    {"int32", PlyType::I32},   {"uint", PlyType::U32},   {"uint32", PlyType::U32},
        {"float", PlyType::F32},  {"float32", PlyType::F32}, {"double", PlyType::F64}, {"float64", PlyType::F64}};
    for (const auto& [name, type] : names)
        if (s == name) {
            t = type;
            return true;
        }
    return false;
}

// Buffered reader of PLY values in any of the three encodings.
class PlyReader {
public:
    PlyReader(std::FILE* f, PlyFormat format, std::string name, Progress* progress)
        : f_(f), format_(format), name_(std::move(name)), progress_(progress) {}

    double value(PlyType t) {
        if (format_ == PlyFormat::Ascii) return asciiValue();
        unsigned char b[8];
        bytes(b, typeSize(t));
        if (format_ == PlyFormat::BinaryBE) std::reverse(b, b + typeSize(t));
        return decode(b, t);
    }

private:
    static double decode(const unsigned char* b, PlyType t) {
        switch (t) {
        case PlyType::I8: return static_cast<int8_t>(b[0]);
        case PlyType::U8: return b[0];
        case PlyType::I16: return load<int16_t>(b);
        case PlyType::U16: return load<uint16_t>(b);
        case PlyType::I32: return load<int32_t>(b);
        case PlyType::U32: return load<uint32_t>(b);
        case PlyType::F32: return load<float>(b);
        case PlyType::F64: return load<double>(b);
        }
        return 0;
    }
    template <class T>
    static T load(const unsigned char* b) {
        T v;
        std::memcpy(&v, b, sizeof v);
        return v;
    }
    bool fill() {
        size_ = std::fread(buffer_.data(), 1, buffer_.size(), f_);
        pos_ = 0;
        if (progress_) progress_->advance(size_);
        return size_ > 0;
    }
    void bytes(unsigned char* out, size_t n) {
        for (size_t i = 0; i < n; ++i) {
            if (pos_ == size_ && !fill()) throw InputError(name_ + ": truncated PLY (data ends early)");
            out[i] = static_cast<unsigned char>(buffer_[pos_++]);
        }
    }
    int nextChar() {
        if (pos_ == size_ && !fill()) return EOF;
        return static_cast<unsigned char>(buffer_[pos_++]);
    }
    double asciiValue() {
        char token[64];
        size_t n = 0;
        int c = nextChar();
        while (c == ' ' || c == '\n' || c == '\r' || c == '\t') c = nextChar();
        while (c != EOF && c != ' ' && c != '\n' && c != '\r' && c != '\t') {
            if (n + 1 >= sizeof token) throw InputError(name_ + ": corrupt PLY (overlong number)");
            token[n++] = static_cast<char>(c);
            c = nextChar();
        }
        if (n == 0) throw InputError(name_ + ": truncated PLY (data ends early)");
        token[n] = 0;
        char* end = nullptr;
        double v = std::strtod(token, &end);
        if (end != token + n) throw InputError(name_ + ": corrupt PLY (bad number '" + token + "')");
        return v;
    }

    std::FILE* f_;
    PlyFormat format_;
    std::string name_;
    Progress* progress_;
    std::vector<char> buffer_ = std::vector<char>(readBufferBytes(f_));
    size_t size_ = 0, pos_ = 0;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    std::vector<std::string> textures;  // "comment TextureFile NAME"
};

PlyHeader readHeader(std::FILE* f, const std::string& name) {
    PlyHeader h;
    char line[4096];
    if (!std::fgets(line, sizeof line, f) || std::strncmp(line, "ply", 3) != 0)
        throw InputError(name + ": not a PLY file (no 'ply' magic)");
    bool haveFormat = false;
    while (std::fgets(line, sizeof line, f)) {
        std::istringstream in(line);
        std::string word;
        in >> word;
        if (word == "end_header") {
            if (!haveFormat) throw InputError(name + ": corrupt PLY header (no format line)");
            return h;
        }
        if (word == "format") {
            std::string f2;
            in >> f2;
            haveFormat = true;
            if (f2 == "ascii") h.format = PlyFormat::Ascii;
            else if (f2 == "binary_little_endian") h.format = PlyFormat::BinaryLE;
            else if (f2 == "binary_big_endian") h.format = PlyFormat::BinaryBE;
            else throw InputError(name + ": unsupported PLY format '" + f2 + "'");
        } else if (word == "element") {
            PlyElement e;
            long long count = -1;
            in >> e.name >> count;
            if (!in || count < 0) throw InputError(name + ": corrupt PLY header (bad element line)");
            e.count = static_cast<uint64_t>(count);
            h.elements.push_back(e);
        } else if (word == "property") {
            if (h.elements.empty()) throw InputError(name + ": corrupt PLY header (property before element)");
            PlyProperty p;
            std::string t;
            in >> t;
            if (t == "list") {
                std::string ct, vt;
                in >> ct >> vt;
                p.isList = true;
                if (!parseType(ct, p.countType) || !parseType(vt, p.type))
                    throw InputError(name + ": corrupt PLY header (bad list type)");
            } else if (!parseType(t, p.type)) {
                throw InputError(name + ": corrupt PLY header (unknown type '" + t + "')");
            }
            in >> p.name;
            h.elements.back().properties.push_back(p);
        } else if (word == "comment") {
            std::string tag, file;
            in >> tag;
            if (tag == "TextureFile" && in >> file) h.textures.push_back(file);
        }
    }
    throw InputError(name + ": truncated PLY header (no end_header)");
}

int findProperty(const PlyElement& e, std::initializer_list<const char*> names) {
    for (size_t i = 0; i < e.properties.size(); ++i)
        for (const char* n : names)
            if (e.properties[i].name == n && !e.properties[i].isList) return static_cast<int>(i);
    return -1;
}

void readVertices(PlyReader& r, const PlyElement& e, RawMesh& raw, const std::string& name) {
    const int pos[3] = {findProperty(e, {"x"}), findProperty(e, {"y"}), findProperty(e, {"z"})};
    const int nrm[3] = {findProperty(e, {"nx"}), findProperty(e, {"ny"}), findProperty(e, {"nz"})};
    const int uv[2] = {findProperty(e, {"u", "s", "texture_u"}), findProperty(e, {"v", "t", "texture_v"})};
    const int col[4] = {findProperty(e, {"red", "r"}), findProperty(e, {"green", "g"}),
                        findProperty(e, {"blue", "b"}), findProperty(e, {"alpha", "a"})};
    raw.hasNormals = nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0;
    raw.hasTexcoords = uv[0] >= 0 && uv[1] >= 0;
    const bool hasC = col[0] >= 0 && col[1] >= 0 && col[2] >= 0;
    const bool floatColor = hasC && e.properties[col[0]].type >= PlyType::F32;
    std::vector<double> values(e.properties.size());
    for (uint64_t i = 0; i < e.count; ++i) {
        for (size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            if (!prop.isList) {
                values[p] = r.value(prop.type);
                continue;
            }
            const double n = r.value(prop.countType);
            for (double k = 0; k < n; ++k) r.value(prop.type);
        }
        const double position[3] = {values[pos[0]], values[pos[1]], values[pos[2]]};
        raw.addPosition(position, name);
        if (raw.hasNormals) {
            const float normal[3] = {static_cast<float>(values[nrm[0]]), static_cast<float>(values[nrm[1]]),
                                     static_cast<float>(values[nrm[2]])};
            raw.addNormal(normal, name);
        }
        if (raw.hasTexcoords) raw.addTexcoord(static_cast<float>(values[uv[0]]), 1.0f - static_cast<float>(values[uv[1]]), name);
        if (hasC) {
            uint8_t rgba[4];
            for (int a = 0; a < 4; ++a) {
                const double v = col[a] < 0 ? (floatColor ? 1.0 : 255.0) : values[col[a]];
                if (std::isnan(v)) throw InputError(name + ": corrupt PLY (a vertex colour is not a number)");
                rgba[a] = static_cast<uint8_t>(std::clamp(floatColor ? v * 255.0 : v, 0.0, 255.0));
            }
            raw.colors.push(rgba, 4);
        }
    }
}

void readFaces(PlyReader& r, const PlyElement& e, RawMesh& raw, const std::string& name) {
    int list = -1;
    for (size_t i = 0; i < e.properties.size(); ++i)
        if (e.properties[i].isList && (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index"))
            list = static_cast<int>(i);
    if (list < 0) throw InputError(name + ": unsupported PLY (face element without vertex_indices)");
    std::vector<uint32_t> polygon;
    for (uint64_t i = 0; i < e.count; ++i) {
        for (size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            if (!prop.isList) {
                r.value(prop.type);
                continue;
            }
            const double n = r.value(prop.countType);
            if (!(n >= 0 && n <= 1024)) throw InputError(name + ": corrupt PLY (face with " + std::to_string(n) + " vertices)");
            polygon.clear();
            for (int k = 0; k < static_cast<int>(n); ++k) {
                const double index = r.value(prop.type);
                if (static_cast<int>(p) == list) {
                    if (!(index >= 0 && index < 4294967295.0))  // NaN fails too
                        throw InputError(name + ": vertex index " + std::to_string(index) + " out of range");
                    polygon.push_back(static_cast<uint32_t>(index));
                }
            }
            for (size_t k = 2; static_cast<int>(p) == list && k < polygon.size(); ++k) {
                RawTriangle t{};
                t.material = 0;
                const uint32_t corners[3] = {polygon[0], polygon[k - 1], polygon[k]};
                for (int c = 0; c < 3; ++c) t.position[c] = t.texcoord[c] = t.normal[c] = corners[c];
                raw.addTriangle(t);
            }
        }
    }
}

}  // namespace

void parsePly(const std::string& path, RawMesh& raw, const ReadOptions& options) {
    refuseSpecialFile(path);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
    const PlyHeader header = readHeader(f.get(), path);
    raw.offset = options.offset;
    PlyReader reader(f.get(), header.format, path, raw.progress);
    bool haveVertices = false, haveFaces = false;
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex") {
            if (findProperty(e, {"x"}) < 0 || findProperty(e, {"y"}) < 0 || findProperty(e, {"z"}) < 0)
                throw InputError(path + ": unsupported PLY (vertex element without x, y, z)");
            readVertices(reader, e, raw, path);
            haveVertices = true;
        } else if (e.name == "face") {
            readFaces(reader, e, raw, path);
            haveFaces = true;
        } else {
            for (uint64_t i = 0; i < e.count; ++i)
                for (const PlyProperty& p : e.properties) {
                    const double n = p.isList ? reader.value(p.countType) : 1;
                    for (double k = 0; k < n; ++k) reader.value(p.type);
                }
        }
    }
    if (!haveVertices || !haveFaces) throw InputError(path + ": PLY has no " + (haveVertices ? "faces" : "vertices"));
    raw.sharedIndices = true;
    raw.materials.push_back({"ply", "", nullptr});
    if (!header.textures.empty() && raw.hasTexcoords)
        raw.materials[0].texturePath = resolveReference(path, folderOf(path), header.textures[0], "texture", options);
    raw.seal();
}

SourceMesh readPly(const std::string& path, const ReadOptions& options) {
    RawMesh raw;
    parsePly(path, raw, options);
    return toSourceMesh(raw, path);
}

}  // namespace hlod
