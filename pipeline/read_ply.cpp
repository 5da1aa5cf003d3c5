// PLY input (ascii, binary little/big endian): positions, per-vertex normals, texture
// coordinates (u/v, s/t, texture_u/texture_v, or per face: a `texcoord` list, as MeshLab and
// Agisoft Metashape write them) and colours when present; `comment TextureFile` names the
// texture, several of them one each, chosen per face by `texnumber`; polygons are cut into
// triangles by their shape (polygon.h). Read in one buffered pass into a RawMesh (in memory, or spilled to disk for a large
// single input); every short read is reported as a truncated file.
#include "pipeline/pipeline.h"
#include "pipeline/polygon.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
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
            std::string f2, version;
            in >> f2 >> version;
            haveFormat = true;
            if (f2 == "ascii") h.format = PlyFormat::Ascii;
            else if (f2 == "binary_little_endian") h.format = PlyFormat::BinaryLE;
            else if (f2 == "binary_big_endian") h.format = PlyFormat::BinaryBE;
            else throw InputError(name + ": unsupported PLY format '" + f2 + "'");
            if (version != "1.0" && version != "1")  // the only version there is (Turk 1994)
                throw InputError(name + ": unsupported PLY format version '" + version + "' (1.0 is read)");
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
            for (const PlyProperty& q : h.elements.back().properties)  // which one would the reader take?
                if (q.name == p.name)
                    throw InputError(name + ": corrupt PLY header (property '" + p.name + "' twice in element '" +
                                     h.elements.back().name + "')");
            h.elements.back().properties.push_back(p);
        } else if (word == "comment") {
            std::string tag, file;
            in >> tag;
            std::getline(in, file);  // the rest of the line: a file name may hold spaces
            const size_t first = file.find_first_not_of(" \t\r\n"), last = file.find_last_not_of(" \t\r\n");
            if (tag == "TextureFile" && first != std::string::npos) h.textures.push_back(file.substr(first, last - first + 1));
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

int findList(const PlyElement& e, std::initializer_list<const char*> names) {
    for (size_t i = 0; i < e.properties.size(); ++i)
        for (const char* n : names)
            if (e.properties[i].name == n && e.properties[i].isList) return static_cast<int>(i);
    return -1;
}

// One face's polygon, cut into triangles (polygon.h): its vertices, its texture coordinates (2 per vertex,
// or none) and its material.
struct PlyFace {
    std::vector<uint32_t> vertices, texcoords;  // texcoords: indices into raw.texcoords (the vertices' without face UVs)
    std::vector<float> uvs;
    std::vector<std::array<double, 3>> points;          // the polygon's positions (reused)
    std::vector<std::array<uint32_t, 3>> triangles;     // its triangles, as corner indices
    uint32_t material = 0;
};

// With face UVs (MeshLab's and Agisoft Metashape's textured PLY: a `texcoord` list of 2 n floats
// for an n-gon) each corner gets a texture coordinate of its own, held in the arrays that spill
// (24 bytes a triangle) rather than in a table of the vertices' UVs that no budget bounds; the
// corners of one vertex with the same (u, v) become one vertex when welded by value (toSourceMesh
// here, weld.cpp after the split), so a chart stays one connected surface for the simplifier.
void addFace(RawMesh& raw, PlyFace& face, bool faceUvs, uint64_t number, const std::string& name) {
    std::vector<uint32_t>& texcoords = face.texcoords;
    texcoords = face.vertices;
    if (faceUvs) {
        const std::string which = name + ": face " + std::to_string(number);
        if (face.uvs.size() != 2 * face.vertices.size())
            throw InputError(name + ": corrupt PLY (face " + std::to_string(number) + " has " + std::to_string(face.vertices.size()) +
                             " vertices but " + std::to_string(face.uvs.size()) + " texture coordinate values)");
        for (size_t k = 0; k < face.vertices.size(); ++k) {
            if (face.vertices[k] >= raw.positionCount())
                throw InputError(which + " uses vertex " + std::to_string(face.vertices[k]) + " but there are only " +
                                 std::to_string(raw.positionCount()));
            if (!std::isfinite(face.uvs[2 * k]) || !std::isfinite(face.uvs[2 * k + 1]))
                throw InputError(which + " has a NaN/Inf texture coordinate");
            if (raw.texcoords.size() / 2 >= UINT32_MAX)  // a corner's index would wrap
                throw InputError(which + ": more than 4,294,967,294 face texture coordinates (not supported)");
            texcoords[k] = static_cast<uint32_t>(raw.texcoords.size() / 2);
            raw.addTexcoord(face.uvs[2 * k] + 0.0f, 1.0f - face.uvs[2 * k + 1] + 0.0f, name);  // + 0: -0 welds with +0
        }
    }
    // A polygon is cut by its shape (polygon.h); its vertices precede it (a face index beyond them
    // fails later, in toSourceMesh, and is fanned here).
    face.triangles.clear();
    bool known = face.vertices.size() > 3;
    for (uint32_t v : face.vertices) known = known && v < raw.positionCount();
    if (known) {
        face.points.resize(face.vertices.size());
        for (size_t i = 0; i < face.vertices.size(); ++i) {
            float xyz[3];
            raw.positions.read(3 * size_t(face.vertices[i]), 3, xyz);
            face.points[i] = {xyz[0], xyz[1], xyz[2]};
        }
        triangulatePolygon(face.points, face.triangles);
    } else {
        for (uint32_t k = 2; k < face.vertices.size(); ++k) face.triangles.push_back({0, k - 1, k});
    }
    for (const std::array<uint32_t, 3>& corners : face.triangles) {
        RawTriangle t{};
        t.material = face.material;
        for (int c = 0; c < 3; ++c) {
            t.position[c] = t.normal[c] = face.vertices[corners[c]];
            t.texcoord[c] = texcoords[corners[c]];
        }
        raw.addTriangle(t);
    }
}

// A face's `texnumber`: which of the header's `comment TextureFile` lines its texture is (read
// only when there are several).
uint32_t textureNumber(double value, size_t textures, uint64_t number, const std::string& name) {
    if (!(value >= 0 && value < static_cast<double>(textures)) || value != std::floor(value))
        throw InputError(name + ": face " + std::to_string(number) + " uses texture " + formatConstant(value) + " but the header names " +
                         std::to_string(textures) + " (comment TextureFile)");
    return static_cast<uint32_t>(value);
}

// Reads the face element; returns whether its faces carry their own texture coordinates.
bool readFaces(PlyReader& r, const PlyElement& e, RawMesh& raw, const std::string& name, size_t textures) {
    const int list = findList(e, {"vertex_indices", "vertex_index"}), uvList = findList(e, {"texcoord"});
    const int texnumber = textures > 1 ? findProperty(e, {"texnumber"}) : -1;
    if (list < 0) throw InputError(name + ": unsupported PLY (face element without vertex_indices)");
    const bool faceUvs = uvList >= 0;
    if (faceUvs) {
        if (raw.positionCount() == 0) throw InputError(name + ": unsupported PLY (face texture coordinates without vertices before them)");
        raw.hasTexcoords = true;
    }
    PlyFace face;
    for (uint64_t i = 0; i < e.count; ++i) {
        face.vertices.clear(), face.uvs.clear(), face.material = 0;
        for (size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            if (!prop.isList) {
                const double v = r.value(prop.type);
                if (static_cast<int>(p) == texnumber) face.material = textureNumber(v, textures, i, name);
                continue;
            }
            const double n = r.value(prop.countType);
            const bool corners = static_cast<int>(p) == list;
            if (!(n >= 0 && n <= (corners ? 1024 : 2048))) {
                const bool whole = n >= 0 && n < 1e18 && n == std::floor(n);
                throw InputError(name + ": corrupt PLY (face with " + (whole ? std::to_string(static_cast<uint64_t>(n)) : formatConstant(n)) +
                                 " " + (corners ? "vertices" : prop.name + " values") + ")");
            }
            for (int k = 0; k < static_cast<int>(n); ++k) {
                const double value = r.value(prop.type);
                if (static_cast<int>(p) == uvList) face.uvs.push_back(static_cast<float>(value));
                if (static_cast<int>(p) != list) continue;
                if (!(value >= 0 && value < 4294967295.0))  // NaN fails too
                    throw InputError(name + ": vertex index " + formatConstant(value) + " out of range");
                if (value != std::floor(value))  // a float list: 1.5 was read as 1
                    throw InputError(name + ": vertex index " + formatConstant(value) + " is not a whole number");
                face.vertices.push_back(static_cast<uint32_t>(value));
            }
        }
        addFace(raw, face, faceUvs, i, name);
    }
    return faceUvs;
}

}  // namespace

void parsePly(const std::string& path, RawMesh& raw, const ReadOptions& options) {
    refuseSpecialFile(path);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
    const PlyHeader header = readHeader(f.get(), path);
    raw.offset = options.offset;
    PlyReader reader(f.get(), header.format, path, raw.progress);
    bool haveVertices = false, haveFaces = false, faceTexcoords = false;
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex") {
            if (findProperty(e, {"x"}) < 0 || findProperty(e, {"y"}) < 0 || findProperty(e, {"z"}) < 0)
                throw InputError(path + ": unsupported PLY (vertex element without x, y, z)");
            readVertices(reader, e, raw, path);
            haveVertices = true;
        } else if (e.name == "face") {
            if (haveFaces) throw InputError(path + ": unsupported PLY (two face elements)");
            faceTexcoords = readFaces(reader, e, raw, path, header.textures.size());
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
    raw.sharedIndices = !faceTexcoords;
    raw.texcoordsPerCorner = faceTexcoords;
    // One material per `comment TextureFile` (faces choose by `texnumber`), or one untextured.
    for (size_t m = 0; m < std::max<size_t>(header.textures.size(), 1); ++m) {
        const bool textured = m < header.textures.size() && raw.hasTexcoords;
        raw.materials.push_back({header.textures.size() > 1 ? header.textures[m] : "ply",
                                 textured ? resolveReference(path, folderOf(path), header.textures[m], "texture", options) : "", nullptr});
    }
    raw.seal();
}

SourceMesh readPly(const std::string& path, const ReadOptions& options) {
    RawMesh raw;
    parsePly(path, raw, options);
    return toSourceMesh(raw, path);
}

}  // namespace hlod
