// Benchmark of `hlod build`'s memory bound (issue #14) on a textured scan like real
// photogrammetry deliveries (41-80 x 4K JPEG atlases, ~1 M triangles): writes a chunked scan
// (tests/support/chunked_scan.h: a generated facade, one material and one JPEG atlas per chunk,
// fragmented charts) into DIR once, then builds it in a child process per --memory-limit and
// prints the child's peak RSS (ru_maxrss) against the limit, the memory gate's largest
// estimate (BuildSummary::gatePeak), CPU time, source texels per CPU-second and input triangles
// per CPU-second. Figures in pipeline/MEMORY.md.
//   bench_memory [--dir DIR] [--chunks 40] [--texture 4096] [--facade 1000] [--charts 4]
//                [--limits 256M,512M,1G,default] [-j N] [--input FILE] [--glb 1] [--chroma 4:2:0]
// --chroma 4:2:0 writes the atlases 4:2:0 (most cameras' and photogrammetry tools' JPEGs), into
// a folder of its own (NAME_420).
// --input builds FILE (any input hlod builds) instead of the generated scan. --glb 1 converts the
// input once into NAME.glb beside it, every texture embedded as a buffer view (the form
// photogrammetry tools export), and builds that: the glTF path of issue #14.
#include "formats/cli/huge_pages.h"
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"
#include "tests/support/child_usage.h"
#include "tests/support/chunked_scan.h"
#include "tests/support/gltf_model.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>

namespace fs = std::filesystem;
using namespace hlod;

namespace {

uint64_t parseBytes(const std::string& s) {
    if (s == "default") return 0;
    const double v = std::strtod(s.c_str(), nullptr);
    const char unit = s.empty() ? 0 : s.back();
    const double scale = unit == 'G' ? 1 << 30 : unit == 'M' ? 1 << 20 : unit == 'K' ? 1 << 10 : 1;
    return static_cast<uint64_t>(v * scale);
}

// Texels of the input's textures (their headers), the figure texels per CPU-second divides.
uint64_t sourceTexels(const std::string& input) {
    uint64_t texels = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(input).parent_path())) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".jpg" || ext == ".png") texels += textureHeader(entry.path().string()).texels;
    }
    return texels;
}

// `input` (read by hlod's own reader) as one GLB: one primitive per material, its texture file's
// bytes embedded as a buffer view.
void writeGlb(const std::string& input, const std::string& glb) {
    const SourceMesh s = readMesh(input);
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    const auto view = [&](const void* data, size_t bytes) { return test::addView(model, data, bytes); };
    const auto accessor = [&](int v, int componentType, int type, size_t count) { return test::addAccessor(model, v, componentType, type, count); };
    const MeshData& m = s.piece.mesh;
    const int position = accessor(view(m.positions.data(), 4 * m.positions.size()), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, m.vertexCount());
    const int uv = m.texcoords.empty() ? -1 : accessor(view(m.texcoords.data(), 4 * m.texcoords.size()), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, m.vertexCount());
    model.meshes.resize(1);
    for (size_t k = 0; k < s.materials.size(); ++k) {
        std::vector<uint32_t> indices;
        for (size_t t = 0; t < s.piece.materials.size(); ++t)
            if (s.piece.materials[t] == k) indices.insert(indices.end(), &m.indices[3 * t], &m.indices[3 * t] + 3);
        if (indices.empty()) continue;
        tinygltf::Material material;
        material.name = s.materials[k].name;
        if (!s.materials[k].texturePath.empty()) {
            std::ifstream in(s.materials[k].texturePath, std::ios::binary);
            const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            tinygltf::Image image;
            image.bufferView = view(bytes.data(), bytes.size());
            image.mimeType = fs::path(s.materials[k].texturePath).extension() == ".png" ? "image/png" : "image/jpeg";
            model.images.push_back(image);
            tinygltf::Texture texture;
            texture.source = static_cast<int>(model.images.size()) - 1;
            model.textures.push_back(texture);
            material.pbrMetallicRoughness.baseColorTexture.index = static_cast<int>(model.textures.size()) - 1;
        }
        model.materials.push_back(material);
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.attributes["POSITION"] = position;
        if (uv >= 0) prim.attributes["TEXCOORD_0"] = uv;
        prim.indices = accessor(view(indices.data(), 4 * indices.size()), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
        prim.material = static_cast<int>(model.materials.size()) - 1;
        model.meshes[0].primitives.push_back(prim);
    }
    test::singleNodeScene(model);
    if (!tinygltf::TinyGLTF().WriteGltfSceneToFile(&model, glb, false, true, false, true)) throw std::runtime_error(glb + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
    hlod::cli::reexecWithHugePages(argv);  // as `hlod` does: its builds run in this process's children
    std::string dir = (fs::temp_directory_path() / "hlod-bench-memory").string(), limits = "256M,512M,1G,default", input;
    ChunkedScanOptions scan;
    scan.chunks = 40, scan.textureSize = 4096, scan.chartCells = 4, scan.jpeg = true;
    uint32_t facade = 1000;
    int jobs = 0;
    bool glb = false;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--dir") dir = v;
        else if (a == "--chunks") scan.chunks = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--texture") scan.textureSize = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--facade") facade = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--charts") scan.chartCells = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--limits") limits = v;
        else if (a == "-j") jobs = std::atoi(v.c_str());
        else if (a == "--input") input = v;
        else if (a == "--glb") glb = v == "1";
        else if (a == "--chroma") scan.jpegChroma420 = v == "4:2:0";
    }
    if (input.empty()) {
        const std::string name = "facade_" + std::to_string(scan.chunks) + "x" + std::to_string(scan.textureSize) + "_" +
                                 std::to_string(facade) + "_" + std::to_string(scan.chartCells) + (scan.jpegChroma420 ? "_420" : "");
        const fs::path folder = fs::path(dir) / name;
        input = (folder / (name + ".obj")).string();
        if (!fs::exists(input)) {
            fs::create_directories(folder);
            const test::ChildUsage g = test::runInChild([&] { writeChunkedScan(folder.string(), name, facadeMesh(facade), scan); });
            if (!g.ok) return 1;
            std::printf("wrote %s in %.1f s\n", input.c_str(), g.wall);
        }
    }
    if (glb) {
        const std::string converted = fs::path(input).replace_extension(".glb").string();
        if (!fs::exists(converted)) {
            const test::ChildUsage g = test::runInChild([&] { writeGlb(input, converted); });
            if (!g.ok) return 1;
            std::printf("wrote %s in %.1f s\n", converted.c_str(), g.wall);
        }
        input = converted;
    }
    const uint64_t texels = sourceTexels(input);
    std::printf("input %s: %.1f Mtexel of source textures\n", input.c_str(), texels / 1e6);
    std::printf("%-9s %10s %10s %9s %12s %8s %8s %14s %12s %10s\n", "limit", "peak RSS", "over", "gate peak", "model/RSS",
                "wall s", "CPU s", "texel/CPU-s", "tri/CPU-s", "db MB");
    std::stringstream list(limits);
    for (std::string item; std::getline(list, item, ',');) {
        const uint64_t limit = parseBytes(item);
        const std::string output = dir + "/out.hlod", figures = dir + "/out.figures";
        const test::ChildUsage c = test::runInChild([&] {
            std::ostringstream log;
            Progress progress(log, false);
            BuildRequest r;
            r.input = input, r.output = output;
            r.options.jobs = jobs;
            if (limit) r.options.memoryLimit = limit;
            const BuildSummary s = runBuild(r, progress);
            std::ofstream(figures) << s.inputTriangles << " " << s.gatePeak << " " << r.options.memoryLimit;
        });
        if (!c.ok) return 1;
        uint64_t triangles = 0, gatePeak = 0, used = 0;
        std::ifstream(figures) >> triangles >> gatePeak >> used;
        const double over = double(c.peakRss) - double(used);
        std::printf("%-9s %7.0f MB %7.0f MB %6.0f MB %12.2f %8.1f %8.1f %14.0f %12.0f %10.1f\n", item.c_str(), c.peakRss / 1e6,
                    over / 1e6, gatePeak / 1e6, c.peakRss ? double(gatePeak) / c.peakRss : 0.0, c.wall, c.cpu,
                    c.cpu > 0 ? texels / c.cpu : 0.0, c.cpu > 0 ? triangles / c.cpu : 0.0, fs::file_size(output) / 1e6);
        std::fflush(stdout);
    }
    return 0;
}
