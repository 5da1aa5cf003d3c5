// Writes one block as the pipeline reads it: block_NNN.obj (positions, per-vertex texture
// coordinates, triangles), block_NNN.mtl (map_Kd) and block_NNN.jpg (formats/image_io.h,
// byte for byte as OpenImageIO wrote it). Each file goes to a temporary name and is renamed when
// complete, so an interrupted run never leaves a half-written block; the mesh is freed before
// the texture is painted (bounded memory).
#include "pipeline/synth/synth.h"
#include "formats/temp_files.h"

#include "formats/image_io.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace hlod::synth {

namespace {

namespace fs = std::filesystem;

class TextOut {
public:
    void put(float v, int precision) {
        char buf[48];
        auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, precision);
        text_.append(buf, r.ptr);
    }
    void put(uint64_t v) {
        char buf[24];
        auto r = std::to_chars(buf, buf + sizeof buf, v);
        text_.append(buf, r.ptr);
    }
    void put(const std::string& s) { text_ += s; }
    void put(char c) { text_ += c; }
    std::string& text() { return text_; }

private:
    std::string text_;
};

void writeFileAtomically(const fs::path& path, const std::string& bytes) {
    writeTextFile(path.string(), path.extension() == ".mtl" ? "material library" : "mesh", bytes);
}

std::string objText(const BlockMesh& mesh, const std::string& mtl, const std::string& material,
                    const BlockPlan& b) {
    TextOut o;
    o.text().reserve(mesh.positions.size() * 56 + mesh.triangles.size() * 36 + 256);
    o.put("# hlod synth city: block ");
    o.put(uint64_t(b.index));
    o.put(", one side of city block ");
    o.put(uint64_t(b.cityBlock));
    o.put("; metres, z up\nmtllib ");
    o.put(mtl);
    o.put('\n');
    for (const auto& p : mesh.positions) {
        o.put("v ");
        o.put(p[0], 3);
        o.put(' ');
        o.put(p[1], 3);
        o.put(' ');
        o.put(p[2], 3);
        o.put('\n');
    }
    for (const auto& t : mesh.texcoords) {
        o.put("vt ");
        o.put(t[0], 6);
        o.put(' ');
        o.put(t[1], 6);
        o.put('\n');
    }
    o.put("usemtl ");
    o.put(material);
    o.put('\n');
    for (const auto& tri : mesh.triangles) {
        o.put('f');
        for (uint32_t v : tri) {
            o.put(' ');
            o.put(uint64_t(v) + 1);
            o.put('/');
            o.put(uint64_t(v) + 1);
        }
        o.put('\n');
    }
    return std::move(o.text());
}

void writeJpeg(const fs::path& path, std::vector<uint8_t> pixels, const TextureLayout& t, int quality) {
    writeJpegFile(path.string(), Image{t.width, t.height, 3, std::move(pixels)}, quality);  // through a temporary
}

}  // namespace

BlockRecord writeBlock(const BlockPlan& b, const std::string& dir, int jpegQuality) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "block_%03u", b.index);
    BlockRecord r;
    r.obj = std::string(stem) + ".obj";
    r.mtl = std::string(stem) + ".mtl";
    r.jpg = std::string(stem) + ".jpg";
    TextureLayout t = layoutTexture(b);
    {
        BlockMesh mesh;
        scanFacade(b, t, mesh);
        sampleAerial(b, t, mesh);
        r.triangles = mesh.triangles.size();
        r.vertices = mesh.positions.size();
        r.facadeTriangles = mesh.facadeTriangles;
        r.aerialTriangles = mesh.aerialTriangles;
        r.meanScanSpacing = mesh.meanScanSpacing;
        r.boundsMin = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                       std::numeric_limits<double>::max()};
        r.boundsMax = {-r.boundsMin[0], -r.boundsMin[0], -r.boundsMin[0]};
        for (const auto& p : mesh.positions) {
            for (int k = 0; k < 3; ++k) {
                r.boundsMin[k] = std::min(r.boundsMin[k], double(p[k]));
                r.boundsMax[k] = std::max(r.boundsMax[k], double(p[k]));
            }
        }
        writeFileAtomically(fs::path(dir) / r.obj, objText(mesh, r.mtl, stem, b));
    }
    writeFileAtomically(fs::path(dir) / r.mtl, "newmtl " + std::string(stem) +
                                                   "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd " + r.jpg + "\n");
    writeJpeg(fs::path(dir) / r.jpg, paintTexture(b, t), t, jpegQuality);
    r.width = t.width;
    r.height = t.height;
    r.texels = uint64_t(t.width) * t.height;
    r.targetTriangles = b.targetTriangles;
    r.targetTexels = b.targetTexels;
    r.length = b.length;
    return r;
}

}  // namespace hlod::synth
