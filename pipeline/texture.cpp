// Node textures (thesis §3.2: "the original texture data is down-sampled by this
// simplification factor as well"). Per material, the source atlas (formats/image_io.h) is
// downsampled so its texel count drops by the node's factor (sqrt(factor) per side) with a box
// filter: the area-weighted average of the covered texels (texture_store.cpp, which reads only
// the rectangles a node uses; stb_image_resize's box filter, used before issue #14, needed the
// whole atlas decoded and downsampled in memory). A node then keeps only the blocks of that
// downsampled texture (JPEG's: 8 x 8, or a 16 x 16 MCU for a 4:2:0 texture) that its triangles come
// within kReach texels of, so that every texel a bilinear tap inside a triangle reads is kept.
// Charts (connected sets of triangles) that reach a common block form one group, so a block is
// stored once per node; each group keeps its blocks' relative places and is packed whole with the
// baker's horizon packing (pack_charts.cpp, Lévy et al. 2002). UVs move by one translation per
// group, a multiple of the block: exact, and at a leaf (factor <= 1) the atlas's blocks are the
// source's own blocks, which a JPEG source re-codes at its own quality almost losslessly. No
// block mixes two groups, so no colour bleeds between them through the compression; the empty
// blocks take the mean of the nearest stored block (for the player's mip levels). Before stop
// 15 each chart kept its bounding rectangle (shelf-packed, unreached blocks flattened): the leaves
// stored 1.45 x the texels they store now on the generated facade, 1.32 x on the banana and 1.68 x
// on Mars. pipeline/TEXTURE_SIZE.md has the measurements (issue #14).
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

#include "formats/image_io.h"
#include "formats/layout.h"
#include "pipeline/chart.h"
#include "pipeline/texture_charts.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <filesystem>
#include <stdexcept>

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
    if (std::filesystem::is_directory(path, error)) return "is a folder, not an image";  // was "is missing"
    if (!std::filesystem::exists(path, error)) return "is missing";
    if (!std::filesystem::is_regular_file(path, error)) return "is not a regular file";  // a FIFO would block the read
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

TextureHeader textureHeader(const std::string& path) {
    try {
        const std::unique_ptr<ImageRows> input = openImageFile(path);
        if (!absurd(*input).empty()) return {};
        return {static_cast<uint64_t>(input->width) * input->height, input->wholeImageBytes};
    } catch (const ImageError&) {
        return {};
    }
}

TextureHeader usedTextures(const SourceMesh& mesh, const TextureStore* store) {
    std::vector<bool> used(mesh.materials.size());
    for (uint32_t m : mesh.piece.materials) used[m] = true;
    TextureHeader total;
    for (size_t m = 0; m < used.size(); ++m) {
        if (!used[m]) continue;
        const Material& material = mesh.materials[m];
        if (material.image) total.texels += uint64_t(material.image->width) * material.image->height;
        if (material.image || material.texturePath.empty()) continue;
        const TextureHeader header = textureHeader(material.texturePath);
        total.texels += header.texels;
        if (!store || !store->opened(material.texturePath)) total.wholeImageBytes = std::max(total.wholeImageBytes, header.wholeImageBytes);
    }
    return total;
}

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

// Texels beyond a triangle that a block must still hold: a bilinear tap at a point of the
// triangle reads texel centres within 1 texel of it (texels within 1.5), plus half a texel.
constexpr double kReach = 2;

// The block (`block` texels a side) of texel coordinate v among `count` (fmax/fmin: a NaN reads 0).
int blockOf(double v, int block, int count) { return static_cast<int>(std::fmin(std::fmax(std::floor(v / block), 0.0), double(count - 1))); }

// The texel rectangle [lo, hi) of UVs in [uvLo, uvHi] (clamped to [0, 1]) plus one texel of margin.
void texelRange(float uvLo, float uvHi, double size, int& lo, int& hi) {
    lo = std::max(0, static_cast<int>(std::floor(std::clamp(uvLo, 0.0f, 1.0f) * size)) - 1);
    hi = std::min(static_cast<int>(size), static_cast<int>(std::ceil(std::clamp(uvHi, 0.0f, 1.0f) * size)) + 1);
    hi = std::max(hi, lo + 1);
}

// Calls reach(i, j, c, test) for each candidate block (i, j) of each triangle (chart c), where
// test() says whether the triangle, as given, comes within kReach of the block inside the
// texture, or, wholly outside, its image clamped to the border does; columns x rows blocks.
template <class Reach>
void candidateBlocks(const MeshData& mesh, const std::vector<uint32_t>& chart, uint32_t width, uint32_t height, int block, Reach reach) {
    const int columns = static_cast<int>((width + block - 1) / block), rows = static_cast<int>((height + block - 1) / block);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        double x[3], y[3], cx[3], cy[3];  // texel coordinates, as given and clamped to the texture
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.indices[3 * t + k];
            x[k] = double(mesh.texcoords[2 * v]) * width, y[k] = double(mesh.texcoords[2 * v + 1]) * height;
            cx[k] = std::clamp(x[k], 0.0, double(width)), cy[k] = std::clamp(y[k], 0.0, double(height));
        }
        const bool clamped = x[0] != cx[0] || x[1] != cx[1] || x[2] != cx[2] || y[0] != cy[0] || y[1] != cy[1] || y[2] != cy[2];
        const int i0 = blockOf(std::min({cx[0], cx[1], cx[2]}) - kReach, block, columns), i1 = blockOf(std::max({cx[0], cx[1], cx[2]}) + kReach, block, columns);
        const int j0 = blockOf(std::min({cy[0], cy[1], cy[2]}) - kReach, block, rows), j1 = blockOf(std::max({cy[0], cy[1], cy[2]}) + kReach, block, rows);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
                reach(i, j, chart[mesh.indices[3 * t]], [&] {
                    const double bx0 = i * block - kReach, by0 = j * block - kReach, bx1 = (i + 1) * block + kReach, by1 = (j + 1) * block + kReach;
                    return triangleMeetsBox(x, y, bx0, by0, bx1, by1) || (clamped && triangleMeetsBox(cx, cy, bx0, by0, bx1, by1));
                });
    }
}

}  // namespace

// On a grid over the box of blocks the triangles span (4 bytes a block) when it is at most
// gridBlocks blocks or costs no more than a list of the candidates (16 bytes each), else on a
// sorted list of the (block, chart) pairs reached: memory follows the blocks the triangles meet,
// not the box they span (a node's UVs may be scattered over a 32k² atlas: a grid over its 4096²
// blocks would take 64 MiB). The same groups either way.
std::vector<BlockGroup> reachedBlocks(const MeshData& mesh, const std::vector<uint32_t>& chart, uint32_t charts, uint32_t width,
                                      uint32_t height, std::vector<uint32_t>& groupOfChart, size_t gridBlocks, int block) {
    const int columns = static_cast<int>((width + block - 1) / block);
    int gx0 = INT_MAX, gy0 = INT_MAX, gx1 = -1, gy1 = -1;  // the candidates' box
    size_t candidates = 0;
    candidateBlocks(mesh, chart, width, height, block, [&](int i, int j, uint32_t, auto) {
        gx0 = std::min(gx0, i), gy0 = std::min(gy0, j), gx1 = std::max(gx1, i), gy1 = std::max(gy1, j), ++candidates;
    });
    groupOfChart.assign(charts, kNone);
    if (gx1 < 0) return {};
    std::vector<uint32_t> parent(charts);
    for (uint32_t c = 0; c < charts; ++c) parent[c] = c;
    const auto unite = [&](uint32_t a, uint32_t b) {
        a = findRoot(parent, a), b = findRoot(parent, b);
        parent[std::max(a, b)] = std::min(a, b);
    };
    std::vector<BlockGroup> groups;  // numbered in block order: deterministic
    const auto addBlock = [&](uint64_t key, uint32_t c) {  // in key order
        uint32_t& g = groupOfChart[findRoot(parent, c)];
        if (g == kNone) g = static_cast<uint32_t>(groups.size()), groups.emplace_back();
        BlockGroup& group = groups[g];
        const int bx = static_cast<int>(key % columns), by = static_cast<int>(key / columns);
        group.blocks.push_back(key);
        group.bx0 = std::min(group.bx0, bx), group.by0 = std::min(group.by0, by), group.bx1 = std::max(group.bx1, bx), group.by1 = std::max(group.by1, by);
    };
    const size_t gw = size_t(gx1 - gx0 + 1), gh = size_t(gy1 - gy0 + 1);
    if (gw * gh <= std::max(gridBlocks, 4 * candidates)) {
        std::vector<uint32_t> owner(gw * gh, kNone);  // a chart reaching the block
        candidateBlocks(mesh, chart, width, height, block, [&](int i, int j, uint32_t c, auto test) {
            uint32_t& o = owner[size_t(j - gy0) * gw + size_t(i - gx0)];
            if (o != kNone && findRoot(parent, o) == findRoot(parent, c)) return;  // reached by the group already
            if (!test()) return;
            if (o == kNone) o = c;
            else unite(o, c);
        });
        for (size_t k = 0; k < owner.size(); ++k)
            if (owner[k] != kNone) addBlock(uint64_t(gy0 + k / gw) * columns + uint64_t(gx0) + k % gw, owner[k]);
    } else {
        std::vector<std::pair<uint64_t, uint32_t>> reached;  // (by * columns + bx, chart)
        candidateBlocks(mesh, chart, width, height, block, [&](int i, int j, uint32_t c, auto test) {
            if (test()) reached.emplace_back(uint64_t(j) * columns + i, c);
        });
        std::sort(reached.begin(), reached.end());
        reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
        for (size_t k = 1; k < reached.size(); ++k)
            if (reached[k].first == reached[k - 1].first) unite(reached[k].second, reached[k - 1].second);
        for (size_t k = 0; k < reached.size(); ++k)
            if (k == 0 || reached[k].first != reached[k - 1].first) addBlock(reached[k].first, reached[k].second);
    }
    for (uint32_t c = 0; c < charts; ++c) groupOfChart[c] = groupOfChart[findRoot(parent, c)];
    return groups;
}

namespace {

// Copies a group's blocks from the scaled texture to the atlas at block (ax, ay), kBandBlocks rows
// of blocks at a time (at a leaf, the texture store's 64-row tiles; scaledRegion's texels do not
// depend on the rectangle asked for); blocks that run past the texture's edge repeat its edge
// texels.
constexpr uint32_t kBandBlocks = 8;
void copyBlocks(const TextureSource& source, uint32_t width, uint32_t height, const BlockGroup& g, int ax, int ay, uint32_t block,
                Image& atlas) {
    const uint32_t columns = (width + block - 1) / block;
    const size_t nc = atlas.channels;
    for (size_t first = 0; first < g.blocks.size();) {  // sorted: one band at a time
        const uint64_t band = g.blocks[first] / columns / kBandBlocks;
        size_t last = first;
        uint32_t bx0 = UINT32_MAX, bx1 = 0;
        for (; last < g.blocks.size() && g.blocks[last] / columns / kBandBlocks == band; ++last)
            bx0 = std::min(bx0, uint32_t(g.blocks[last] % columns)), bx1 = std::max(bx1, uint32_t(g.blocks[last] % columns));
        const uint32_t x0 = bx0 * block, y0 = static_cast<uint32_t>(g.blocks[first] / columns) * block;
        const uint32_t x1 = std::min(width, (bx1 + 1) * block);
        const uint32_t y1 = std::min(height, static_cast<uint32_t>(g.blocks[last - 1] / columns + 1) * block);
        const Image texels = scaledRegion(source, width, height, x0, y0, x1, y1);
        for (size_t b = first; b < last; ++b) {
            const uint32_t bx = static_cast<uint32_t>(g.blocks[b] % columns), by = static_cast<uint32_t>(g.blocks[b] / columns);
            const uint32_t sx0 = bx * block - x0, inside = std::min<uint32_t>(block, texels.width - sx0);  // texels before the edge
            for (uint32_t y = 0; y < block; ++y) {
                const uint32_t sy = std::min(by * block + y - y0, texels.height - 1);
                const uint8_t* from = &texels.pixels[(size_t(sy) * texels.width + sx0) * nc];
                uint8_t* row = &atlas.pixels[(size_t(ay + int(by) - g.by0) * block + y) * atlas.width * nc + size_t(ax + int(bx) - g.bx0) * block * nc];
                std::copy_n(from, inside * nc, row);
                for (uint32_t x = inside; x < block; ++x) std::copy_n(from + (inside - 1) * nc, nc, row + x * nc);
            }
        }
        first = last;
    }
}

// Every block no group owns takes the mean colour of the nearest owned block (breadth first over
// the 8 neighbours, in a fixed order, from all owned blocks at once): the player samples
// trilinearly (player/gl/gl_mesh.cpp), and from mip level 3 (one texel per block) on, a level's
// texels mix neighbouring blocks, which are then a group's own colours, not black. A flat block
// costs JPEG one DC coefficient per channel.
void fillUnownedBlocks(const std::vector<uint8_t>& owned, int block, Image& atlas) {
    const int columns = static_cast<int>(atlas.width) / block, rows = static_cast<int>(atlas.height) / block;
    const size_t nc = atlas.channels;
    const auto texel = [&](int b, int x, int y) {
        return &atlas.pixels[(size_t((b / columns) * block + y) * atlas.width + size_t((b % columns) * block + x)) * nc];
    };
    std::vector<int> from(owned.size(), -1), queue;  // the owned block whose mean a block takes
    for (int b = 0; b < int(owned.size()); ++b)
        if (owned[b]) from[b] = b, queue.push_back(b);
    for (size_t next = 0; next < queue.size(); ++next) {
        const int b = queue[next], bx = b % columns, by = b / columns;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = bx + dx, ny = by + dy;
                if (nx < 0 || ny < 0 || nx >= columns || ny >= rows || from[size_t(ny) * columns + nx] >= 0) continue;
                from[size_t(ny) * columns + nx] = from[b], queue.push_back(ny * columns + nx);
            }
    }
    // The means of only the owned blocks whose colour some unowned block takes (summing every
    // owned block's texels was 4 % of a textured build's CPU, pipeline/TEXTURE_SPEED.md round 8).
    std::vector<uint8_t> mean(owned.size() * nc), meant(owned.size(), 0);
    for (int b = 0; b < int(owned.size()); ++b)
        if (!owned[b] && from[b] >= 0) meant[size_t(from[b])] = 1;
    for (int b = 0; b < int(owned.size()); ++b) {
        if (!meant[b]) continue;
        uint32_t sum[4] = {0, 0, 0, 0};
        for (int y = 0; y < block; ++y) {
            const uint8_t* row = texel(b, 0, y);
            for (size_t i = 0; i < size_t(block) * nc; ++i) sum[i % nc] += row[i];
        }
        for (size_t c = 0; c < nc; ++c) mean[size_t(b) * nc + c] = static_cast<uint8_t>((sum[c] + block * block / 2) / (block * block));
    }
    for (int b = 0; b < int(owned.size()); ++b) {
        if (owned[b] || from[b] < 0) continue;
        for (int y = 0; y < block; ++y)
            for (int x = 0; x < block; ++x) std::copy_n(&mean[size_t(from[b]) * nc], nc, texel(b, x, y));
    }
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

Image atlasTexture(const TextureSource& source, double factor, MeshData& mesh, int block) {
    if (block != kJpegBlock && block != 2 * kJpegBlock) throw std::invalid_argument("atlasTexture: block " + std::to_string(block) + " is not 8 or 16");
    uint32_t count = 0;
    const std::vector<uint32_t> chart = uvCharts(mesh, count);
    const uint32_t width = scaledSide(source.width, factor), height = scaledSide(source.height, factor);
    std::vector<uint32_t> groupOfChart;
    const std::vector<BlockGroup> groups = reachedBlocks(mesh, chart, count, width, height, groupOfChart, kGridBlocks, block);
    std::vector<BlockMask> masks(groups.size());
    const uint64_t columns = (width + block - 1) / block;
    for (size_t g = 0; g < groups.size(); ++g) {
        BlockMask& m = masks[g];
        m.wb = groups[g].bx1 - groups[g].bx0 + 1, m.hb = groups[g].by1 - groups[g].by0 + 1;
        m.blocks.assign(size_t(m.wb) * m.hb, 0);
        for (const uint64_t key : groups[g].blocks)
            m.blocks[size_t(int(key / columns) - groups[g].by0) * m.wb + size_t(int(key % columns) - groups[g].bx0)] = 1;
        finishMask(m);
    }
    BlockPacking packing = packMasks(masks, layout::kMaxTextureSide / block);
    if (packing.rows * block > int(layout::kMaxTextureSide)) {  // packed taller than the format allows: the blocks where they are
        int gx0 = INT_MAX, gy0 = INT_MAX, gx1 = 0, gy1 = 0;
        for (const BlockGroup& g : groups) gx0 = std::min(gx0, g.bx0), gy0 = std::min(gy0, g.by0), gx1 = std::max(gx1, g.bx1), gy1 = std::max(gy1, g.by1);
        packing.columns = gx1 - gx0 + 1, packing.rows = gy1 - gy0 + 1;
        for (size_t g = 0; g < groups.size(); ++g) packing.at[g] = {groups[g].bx0 - gx0, groups[g].by0 - gy0};
    }
    const uint32_t nc = source.channels;
    Image atlas{static_cast<uint32_t>(std::max(1, packing.columns) * block), static_cast<uint32_t>(std::max(1, packing.rows) * block), nc, {}};
    atlas.pixels.assign(size_t(atlas.width) * atlas.height * nc, 0);
    std::vector<uint8_t> owned(size_t(atlas.width / block) * (atlas.height / block), 0);
    for (size_t g = 0; g < groups.size(); ++g) {
        copyBlocks(source, width, height, groups[g], packing.at[g].first, packing.at[g].second, block, atlas);
        for (int j = 0; j < masks[g].hb; ++j)
            for (int i = 0; i < masks[g].wb; ++i)
                if (masks[g].blocks[size_t(j) * masks[g].wb + i])
                    owned[size_t(packing.at[g].second + j) * (atlas.width / block) + size_t(packing.at[g].first + i)] = 1;
    }
    fillUnownedBlocks(owned, block, atlas);
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
        const uint32_t g = groupOfChart[chart[v]];
        if (g == kNone) continue;  // a vertex of no triangle
        const double dx = (packing.at[g].first - groups[g].bx0) * block, dy = (packing.at[g].second - groups[g].by0) * block;
        mesh.texcoords[2 * v] = static_cast<float>((mesh.texcoords[2 * v] * double(width) + dx) / atlas.width);
        mesh.texcoords[2 * v + 1] = static_cast<float>((mesh.texcoords[2 * v + 1] * double(height) + dy) / atlas.height);
    }
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
        if (m.image) {
            source = textureView(*m.image, mips_[material] = mipLevels(*m.image));
            source->jpegQuality = m.jpegQuality, source->chroma420 = m.jpegChroma420;
        }
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

bool BlockTextures::chroma420(uint32_t material, JpegChroma chroma) {
    const TextureSource* s = source(material);
    if (!s || s->channels != 3) return false;  // untextured, or grey: no chroma to subsample
    return chroma == JpegChroma::Source ? s->chroma420 : chroma == JpegChroma::Half;
}

Image BlockTextures::atlas(uint32_t material, double factor, MeshData& mesh, bool chroma420) {
    const TextureSource* s = source(material);
    return s ? atlasTexture(*s, factor, mesh, chroma420 ? 2 * kJpegBlock : kJpegBlock) : Image{};
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
