// Node textures (thesis §3.2: "the original texture data is down-sampled by this
// simplification factor as well"). Per material, the source atlas (formats/image_io.h) is
// downsampled so its texel count drops by the node's factor (sqrt(factor) per side) with a box
// filter: the area-weighted average of the covered texels (texture_store.cpp, which reads only
// the rectangles a node uses; stb_image_resize's box filter, used before issue #14, needed the
// whole atlas decoded and downsampled in memory). A node
// then keeps only the charts its triangles use: each connected set of triangles gets the
// bounding rectangle of its texels plus one texel of margin (so bilinear filtering at a chart
// border reads the source's own neighbours, never another chart), and the rectangles are
// shelf-packed into one atlas. UVs move by one affine map per chart: exact. JPEG codes 8 x 8
// blocks (chroma too at 4:4:4, formats/codec_image.cpp), so each chart is placed on a multiple
// of 8 (at a leaf of a JPEG source re-coded at its own quality, its rectangle widened to the
// source's 8 x 8 grid: the atlas's blocks are then the source's own) and padded to one with
// copies of its edge texels: no block mixes two charts, and no chart's colour bleeds into another through the
// compression. Blocks no triangle reaches are flattened to their mean (flattenUnusedBlocks).
// pipeline/TEXTURE_SIZE.md has the measurements (issue #14).
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

#include "formats/image_io.h"
#include "formats/layout.h"
#include "pipeline/chart.h"
#include "pipeline/texture_charts.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace hlod {

namespace {

// The side limit of a stored texture (FORMAT.md "Limits"): a larger source could not be kept
// at its leaves, and its header is refused before its pixels are allocated.
constexpr uint32_t kMaxSourceSide = layout::kMaxTextureSide;

std::string absurd(const ImageRows& image) {
    if (image.width > 0 && image.height > 0 && image.width <= kMaxSourceSide && image.height <= kMaxSourceSide && image.channels > 0)
        return "";
    return "has absurd size " + std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
           std::to_string(image.channels) + " (at most " + std::to_string(kMaxSourceSide) + " per side)";
}

}  // namespace

std::string textureProblem(const std::string& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) return "is missing";
    if (std::filesystem::file_size(path, error) == 0) return "is empty (0 bytes)";
    try {
        return absurd(*openImageFile(path));
    } catch (const ImageError& e) {
        return "is not a readable image (" + firstLine(e.what()) + ")";
    }
}

std::unique_ptr<ImageRows> openTexture(const std::string& path) {
    std::unique_ptr<ImageRows> image;
    try {
        image = openImageFile(path);
    } catch (const ImageError& e) {
        throw InputError(path + ": cannot read texture (" + firstLine(e.what()) + ")");
    }
    if (const std::string problem = absurd(*image); !problem.empty()) throw InputError(path + ": texture " + problem);
    return image;
}

void readTextureRows(ImageRows& image, const std::string& path, uint32_t rows, uint32_t channels, uint8_t* out) {
    try {
        image.read(rows, channels, out);  // a truncated JPEG's libjpeg warning included
    } catch (const ImageError& e) {
        throw InputError(path + ": corrupt texture (" + firstLine(e.what()) + ")");
    }
}

Image loadTexture(const std::string& path) {
    const std::unique_ptr<ImageRows> input = openTexture(path);
    Image image;
    image.width = input->width;
    image.height = input->height;
    image.channels = input->channels >= 3 ? 3 : 1;
    image.pixels.resize(static_cast<size_t>(image.width) * image.height * image.channels);
    readTextureRows(*input, path, image.height, image.channels, image.pixels.data());
    return image;
}

uint64_t textureTexels(const std::string& path) {
    try {
        const std::unique_ptr<ImageRows> input = openImageFile(path);
        return absurd(*input).empty() ? static_cast<uint64_t>(input->width) * input->height : 0;
    } catch (const ImageError&) {
        return 0;
    }
}

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

constexpr int kBlock = 8;  // JPEG block side

int padded(int size) { return (size + kBlock - 1) / kBlock * kBlock; }

struct Chart {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // texel rectangle in the scaled source, margin included
    int ox = 0, oy = 0;                  // its place in the atlas (multiples of kBlock)
    int width() const { return padded(x1 - x0); }
    int height() const { return padded(y1 - y0); }
};

// Shelf packing of the padded rectangles, tallest first (ties by chart order, so
// deterministic); returns the atlas size, a multiple of kBlock.
std::pair<int, int> packCharts(std::vector<Chart>& charts) {
    std::vector<uint32_t> order(charts.size());
    double area = 0;
    int widest = kBlock;
    for (uint32_t i = 0; i < order.size(); ++i) {
        order[i] = i;
        area += double(charts[i].width()) * charts[i].height();
        widest = std::max(widest, charts[i].width());
    }
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return charts[a].height() > charts[b].height(); });
    const int width = std::max(widest, padded(static_cast<int>(std::ceil(std::sqrt(area) * 1.1))));
    int x = 0, y = 0, shelf = 0;
    for (uint32_t i : order) {
        Chart& c = charts[i];
        if (x + c.width() > width) x = 0, y += shelf, shelf = 0;
        c.ox = x, c.oy = y;
        x += c.width();
        shelf = std::max(shelf, c.height());
    }
    return {width, std::max(kBlock, y + shelf)};
}

// Copies the chart's rectangle (`texels`, cut from the scaled source) to its place and fills the
// padding with its edge texels.
void copyChart(const Image& texels, const Chart& c, Image& atlas) {
    const size_t nc = texels.channels;
    for (int y = 0; y < c.height(); ++y) {
        const int sy = std::min(y, c.y1 - c.y0 - 1);
        uint8_t* row = &atlas.pixels[(static_cast<size_t>(c.oy + y) * atlas.width + c.ox) * nc];
        std::copy_n(&texels.pixels[static_cast<size_t>(sy) * texels.width * nc], static_cast<size_t>(c.x1 - c.x0) * nc, row);
        for (int x = c.x1 - c.x0; x < c.width(); ++x) std::copy_n(row + (c.x1 - c.x0 - 1) * nc, nc, row + x * nc);
    }
}

// Texels beyond a triangle that a block must still hold: a bilinear tap at a point of the
// triangle reads texel centres within 1 texel of it (texels within 1.5), plus half a texel.
constexpr double kReach = 2;

// Sets every kBlock x kBlock block of `atlas` that no triangle of `mesh` (atlas UVs) comes within
// kReach texels of to the block's mean colour: texels no triangle shows cost JPEG one DC
// coefficient per channel (a few bits) instead of their detail, and the mean keeps the block's
// mip level (issue #14: "charts store only what triangles use"; pipeline/TEXTURE_SIZE.md).
void flattenUnusedBlocks(const MeshData& mesh, Image& atlas) {
    const int wb = static_cast<int>(atlas.width) / kBlock, hb = static_cast<int>(atlas.height) / kBlock;
    std::vector<uint8_t> used(size_t(wb) * hb, 0);
    const auto blockOf = [](double v, int count) { return std::clamp(static_cast<int>(std::floor(v / kBlock)), 0, count - 1); };
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        double x[3], y[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.indices[3 * t + k];
            x[k] = double(mesh.texcoords[2 * v]) * atlas.width, y[k] = double(mesh.texcoords[2 * v + 1]) * atlas.height;
        }
        const int i0 = blockOf(std::min({x[0], x[1], x[2]}) - kReach, wb), i1 = blockOf(std::max({x[0], x[1], x[2]}) + kReach, wb);
        const int j0 = blockOf(std::min({y[0], y[1], y[2]}) - kReach, hb), j1 = blockOf(std::max({y[0], y[1], y[2]}) + kReach, hb);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
                if (!used[size_t(j) * wb + i])
                    used[size_t(j) * wb + i] = triangleMeetsBox(x, y, i * kBlock - kReach, j * kBlock - kReach, (i + 1) * kBlock + kReach,
                                                                (j + 1) * kBlock + kReach);
    }
    const size_t nc = atlas.channels;
    for (int j = 0; j < hb; ++j)
        for (int i = 0; i < wb; ++i) {
            if (used[size_t(j) * wb + i]) continue;
            uint32_t sum[4] = {0, 0, 0, 0};
            const auto at = [&](int x, int y) { return &atlas.pixels[(size_t(j * kBlock + y) * atlas.width + i * kBlock + x) * nc]; };
            for (int y = 0; y < kBlock; ++y)
                for (int x = 0; x < kBlock; ++x)
                    for (size_t c = 0; c < nc; ++c) sum[c] += at(x, y)[c];
            for (int y = 0; y < kBlock; ++y)
                for (int x = 0; x < kBlock; ++x)
                    for (size_t c = 0; c < nc; ++c) at(x, y)[c] = static_cast<uint8_t>((sum[c] + kBlock * kBlock / 2) / (kBlock * kBlock));
        }
}

// The texel rectangle [lo, hi) of UVs in [uvLo, uvHi] (clamped to [0, 1]) plus one texel of margin.
void texelRange(float uvLo, float uvHi, double size, int& lo, int& hi) {
    lo = std::max(0, static_cast<int>(std::floor(std::clamp(uvLo, 0.0f, 1.0f) * size)) - 1);
    hi = std::min(static_cast<int>(size), static_cast<int>(std::ceil(std::clamp(uvHi, 0.0f, 1.0f) * size)) + 1);
    hi = std::max(hi, lo + 1);
}

// [lo, hi) widened to the source's kBlock grid (hi clamped to the source): at a leaf, whose
// texels are the source's, the atlas's JPEG blocks are then the source's own blocks.
void alignToBlocks(int& lo, int& hi, uint32_t size) {
    lo = lo / kBlock * kBlock;
    hi = std::min(static_cast<int>(size), padded(hi));
}

}  // namespace

std::vector<uint32_t> uvCharts(const MeshData& mesh, uint32_t& count) {
    std::vector<uint32_t> parent(mesh.vertexCount());
    for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
        for (int k = 1; k < 3; ++k) {
            const uint32_t a = findRoot(parent, mesh.indices[3 * t]), b = findRoot(parent, mesh.indices[3 * t + k]);
            parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<uint32_t> chart(parent.size(), kNone), id(parent.size(), kNone);
    count = 0;
    for (uint32_t i = 0; i < parent.size(); ++i) {
        const uint32_t r = findRoot(parent, i);
        if (id[r] == kNone) id[r] = count++;
        chart[i] = id[r];
    }
    return chart;
}

Image atlasTexture(const TextureSource& source, double factor, MeshData& mesh, bool onSourceGrid) {
    uint32_t count = 0;
    const std::vector<uint32_t> chart = uvCharts(mesh, count);
    const uint32_t scaledWidth = scaledSide(source.width, factor), scaledHeight = scaledSide(source.height, factor);
    const double size[2] = {static_cast<double>(scaledWidth), static_cast<double>(scaledHeight)};
    std::vector<float> lo(2 * count, 1), hi(2 * count, 0);
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) {
            const float c = std::clamp(mesh.texcoords[2 * v + a], 0.0f, 1.0f);
            lo[2 * chart[v] + a] = std::min(lo[2 * chart[v] + a], c), hi[2 * chart[v] + a] = std::max(hi[2 * chart[v] + a], c);
        }
    std::vector<Chart> charts(count);
    for (uint32_t c = 0; c < count; ++c) {
        texelRange(lo[2 * c], hi[2 * c], size[0], charts[c].x0, charts[c].x1);
        texelRange(lo[2 * c + 1], hi[2 * c + 1], size[1], charts[c].y0, charts[c].y1);
        if (!onSourceGrid || factor > 1) continue;
        alignToBlocks(charts[c].x0, charts[c].x1, scaledWidth);
        alignToBlocks(charts[c].y0, charts[c].y1, scaledHeight);
    }
    const auto [width, height] = packCharts(charts);
    const uint32_t nc = source.channels;
    Image atlas{static_cast<uint32_t>(width), static_cast<uint32_t>(height), nc, {}};
    atlas.pixels.assign(static_cast<size_t>(width) * height * nc, 0);
    for (const Chart& c : charts)
        copyChart(scaledRegion(source, scaledWidth, scaledHeight, static_cast<uint32_t>(c.x0), static_cast<uint32_t>(c.y0),
                               static_cast<uint32_t>(c.x1), static_cast<uint32_t>(c.y1)),
                  c, atlas);
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
        const Chart& c = charts[chart[v]];
        mesh.texcoords[2 * v] = static_cast<float>((mesh.texcoords[2 * v] * size[0] - c.x0 + c.ox) / width);
        mesh.texcoords[2 * v + 1] = static_cast<float>((mesh.texcoords[2 * v + 1] * size[1] - c.y0 + c.oy) / height);
    }
    flattenUnusedBlocks(mesh, atlas);
    return atlas;
}

BlockTextures::BlockTextures(const std::vector<Material>& materials, TextureStore* store, bool strict,
                             std::vector<TextureProblem>& problems, Progress* progress)
    : materials_(materials),
      own_(store ? nullptr : std::make_unique<TextureStore>()),
      store_(store ? store : own_.get()),
      strict_(strict),
      problems_(problems),
      progress_(progress) {}

const TextureSource* BlockTextures::source(uint32_t material) {
    if (material >= materials_.size()) return nullptr;
    const Material& m = materials_[material];
    if (!m.image && m.texturePath.empty()) return nullptr;
    const std::lock_guard lock(mutex_);  // held while a first use decodes: its nodes wait for it anyway
    auto it = sources_.find(material);
    if (it == sources_.end()) {
        std::optional<TextureSource> source;
        if (m.image) source = textureView(*m.image, mips_[material] = mipLevels(*m.image)), source->jpegQuality = m.jpegQuality;
        else try {
                source = store_->open(m.texturePath, progress_);
            } catch (const InputError& e) {
                if (strict_) throw InputError(std::string(e.what()) + " (--strict)");
                problems_.push_back({e.what(), m.name});
            }
        it = sources_.emplace(material, source).first;
    }
    return it->second ? &*it->second : nullptr;
}

int BlockTextures::jpegQuality(uint32_t material, int quality) {
    const TextureSource* s = source(material);
    return s && s->jpegQuality > 0 ? std::min(quality, s->jpegQuality) : quality;
}

Image BlockTextures::atlas(uint32_t material, double factor, MeshData& mesh, int quality) {
    const TextureSource* s = source(material);
    return s ? atlasTexture(*s, factor, mesh, s->jpegQuality > 0 && s->jpegQuality <= quality) : Image{};
}

Image BlockTextures::region(uint32_t material, double factor, MeshData& mesh) {
    const TextureSource* s = source(material);
    if (!s || mesh.vertexCount() == 0) return {};
    const uint32_t width = scaledSide(s->width, factor), height = scaledSide(s->height, factor);
    float lo[2] = {1, 1}, hi[2] = {0, 0};
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], mesh.texcoords[2 * v + a]), hi[a] = std::max(hi[a], mesh.texcoords[2 * v + a]);
    int x0, x1, y0, y1;
    texelRange(lo[0], hi[0], width, x0, x1);
    texelRange(lo[1], hi[1], height, y0, y1);
    Image texels = scaledRegion(*s, width, height, static_cast<uint32_t>(x0), static_cast<uint32_t>(y0), static_cast<uint32_t>(x1),
                                static_cast<uint32_t>(y1));
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
        mesh.texcoords[2 * v] = static_cast<float>((double(mesh.texcoords[2 * v]) * width - x0) / texels.width);
        mesh.texcoords[2 * v + 1] = static_cast<float>((double(mesh.texcoords[2 * v + 1]) * height - y0) / texels.height);
    }
    return texels;
}

std::vector<TexturedChart> textureCharts(BlockTextures& textures, uint32_t material, double factor, const MeshData& mesh) {
    if (!textures.source(material) || mesh.vertexCount() == 0) return {};
    uint32_t count = 0;
    const std::vector<uint32_t> chart = uvCharts(mesh, count);
    std::vector<TexturedChart> out(count);
    std::vector<uint32_t> local(mesh.vertexCount(), kNone);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        MeshData& m = out[chart[mesh.indices[3 * t]]].mesh;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.indices[3 * t + k];
            if (local[v] == kNone) {
                local[v] = static_cast<uint32_t>(m.vertexCount());
                m.positions.insert(m.positions.end(), &mesh.positions[3 * v], &mesh.positions[3 * v] + 3);
                m.texcoords.insert(m.texcoords.end(), &mesh.texcoords[2 * v], &mesh.texcoords[2 * v] + 2);
                if (!mesh.normals.empty()) m.normals.insert(m.normals.end(), &mesh.normals[3 * v], &mesh.normals[3 * v] + 3);
                if (!mesh.colors.empty()) m.colors.insert(m.colors.end(), &mesh.colors[4 * v], &mesh.colors[4 * v] + 4);
            }
            m.indices.push_back(local[v]);
        }
    }
    for (TexturedChart& c : out) c.texels = textures.region(material, factor, c.mesh);
    return out;
}

}  // namespace hlod
