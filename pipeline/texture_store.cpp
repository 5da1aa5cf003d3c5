// Source textures read region by region (issue #14: the build's peak RSS stays within
// --memory-limit on scans with tens of 4K atlases). A texture file is decoded once per build,
// a strip of kStripRows scanlines at a time (formats/image_io.h), into an uncompressed
// file in the build's temporary folder, followed by its mip pyramid (each level the box-filtered
// halving of the one before, computed by strips from it read back: 1/3 more bytes); a node then
// reads only the rows and columns under the bands of blocks its triangles reach (pread: the page cache
// holds them, not the process). Each level lies in the file as 64 x 64-texel tiles (`Tiles`),
// so a rectangle's rows within one band of 64 are one pread of the band's tiles it crosses, into
// a buffer each thread keeps (at most a band of the widest level: as a decoded strip, 768 KiB for
// 4K), where a file of whole rows took a pread per row (6.26 M calls on the facade of
// TEXTURE_SPEED.md, 135 k tiled; its round 3). The thesis's downsampling by the node's factor
// (§3.2: "the original texture data is down-sampled by this simplification factor as well") is
// a box filter computed per rectangle from the pyramid level just finer than the node's size (a
// remaining factor below 2 per side): each scaled texel is the area-weighted mean of the level's
// texels it covers, a function of that texel alone, so a rectangle's texels equal those of the
// whole downsampled image (downsampleTexture) and no whole atlas, source or downsampled, is held.
// Reading the level instead of the source makes a node's filter cost proportional to its own
// texels, not the source texels under them (pipeline/TEXTURE_SPEED.md).
// Without a folder (buildBlock outside runBuild) the decoded sources and pyramids stay in
// memory, one block's at a time.
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

#include "formats/fd_io.h"
#include "formats/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>

namespace hlod {

namespace {

constexpr int kStripRows = 64;  // scanlines decoded at once: 4096 x 64 x 3 = 768 KiB
constexpr uint32_t kTile = 64;   // texels per side of the temporary file's tiles
static_assert(kStripRows == int(kTile), "a decoded strip is one band of tiles");

// A level's layout in the file: its bands of kTile rows one after the other, each band its tiles
// of kTile columns left to right (the last ones narrower or shorter), each tile row by row. The
// level takes width x height x channels bytes, as row by row.
struct Tiles {
    uint32_t width = 0, height = 0, channels = 0;
    uint32_t bandRows(uint32_t band) const { return std::min(kTile, height - band * kTile); }
    uint32_t tileWidth(uint32_t tx) const { return std::min(kTile, width - tx * kTile); }
    uint64_t tile(uint32_t tx, uint32_t band) const {  // its first byte in the level
        return (uint64_t(band) * kTile * width + uint64_t(tx) * kTile * bandRows(band)) * channels;
    }
    // Band `band`'s rows, row by row in `rows`, as tiles in `out` (bandRows x width x channels bytes).
    void tile(uint32_t band, const uint8_t* rows, uint8_t* out) const {
        const uint32_t n = bandRows(band);
        for (uint32_t tx = 0; tx * kTile < width; ++tx)
            for (uint32_t r = 0; r < n; ++r)
                out = std::copy_n(rows + (size_t(r) * width + tx * kTile) * channels, size_t(tileWidth(tx)) * channels, out);
    }
};

// The texels of one axis an output texel covers: source [first, first + count), their weights
// at [weight, weight + count) of Spans::weights.
struct Span {
    uint32_t first = 0, count = 0, weight = 0;
};
struct Spans {
    std::vector<Span> spans;
    std::vector<float> weights;
};

// Output texels [begin, end) of an axis of `out` texels over `in` source texels.
Spans spans(uint32_t in, uint32_t out, uint32_t begin, uint32_t end) {
    const double ratio = double(in) / out;
    Spans result;
    result.spans.resize(end - begin);
    for (uint32_t o = begin; o < end; ++o) {
        const double lo = o * ratio, hi = (o + 1) * ratio;
        Span& s = result.spans[o - begin];
        s.first = static_cast<uint32_t>(std::floor(lo));
        s.weight = static_cast<uint32_t>(result.weights.size());
        const uint32_t last = std::min(in, static_cast<uint32_t>(std::ceil(hi)));
        for (uint32_t i = s.first; i < last; ++i)
            result.weights.push_back(static_cast<float>((std::min(hi, i + 1.0) - std::max(lo, double(i))) / ratio));
        s.count = last - s.first;
    }
    return result;
}

// A halving by 2 x 2 means: `pairs` rows of `rowBytes` (two input rows per output row, 2 x
// `width` texels each) into `pairs` rows of `width` texels. The float box filter's exact sum,
// rounded half up as its lround.
void halveRows(const uint8_t* in, size_t rowBytes, uint32_t width, uint32_t pairs, uint32_t nc, uint8_t* out) {
    for (uint32_t y = 0; y < pairs; ++y, in += 2 * rowBytes)
        for (size_t x = 0; x < width; ++x)
            for (uint32_t c = 0; c < nc; ++c, ++out) {
                const uint8_t* t = in + 2 * x * nc + c;
                *out = static_cast<uint8_t>((t[0] + t[nc] + t[rowBytes] + t[rowBytes + nc] + 2) >> 2);
            }
}

// The horizontal box filter of one row of source texels (from column sx0) into `filtered`.
template <uint32_t NC>
void filterRow(const uint8_t* row, const Spans& across, uint32_t sx0, float* filtered) {
    for (const Span& s : across.spans) {
        const uint8_t* texel = row + size_t(s.first - sx0) * NC;
        const float* weight = &across.weights[s.weight];
        float f[NC] = {};
        for (uint32_t i = 0; i < s.count; ++i, texel += NC)
            for (uint32_t c = 0; c < NC; ++c) f[c] += weight[i] * texel[c];
        for (uint32_t c = 0; c < NC; ++c) filtered[c] = f[c];
        filtered += NC;
    }
}

// An axis's spans as kTaps taps each (its texels, then zero weights: adding 0 x texel leaves a
// non-negative float sum as it is), when none is longer: the ratio of a level to the output is
// below 2, so spans are 2 or 3 texels long, alternating unpredictably.
constexpr uint32_t kTaps = 3;
struct Taps {
    std::vector<uint32_t> first;  // per output texel, its span's first texel from sx0
    std::vector<float> weights;   // kTaps per output texel
};
bool tapsFit(const Spans& across) {
    return std::all_of(across.spans.begin(), across.spans.end(), [](const Span& s) { return s.count <= kTaps; });
}
Taps taps(const Spans& across, uint32_t sx0) {
    Taps t;
    t.first.reserve(across.spans.size()), t.weights.assign(across.spans.size() * kTaps, 0.0f);
    for (size_t o = 0; o < across.spans.size(); ++o) {
        t.first.push_back(across.spans[o].first - sx0);
        std::copy_n(&across.weights[across.spans[o].weight], across.spans[o].count, &t.weights[o * kTaps]);
    }
    return t;
}
// filterRow<3> over taps from a row of RGB texels as floats: a texel's three channels (and the
// next texel's first) in one vector of GCC's vector extensions, each lane summed in filterRow's
// order (the same floats). `row` has kTaps texels and a float past its end, `filtered` a float.
void filterRgb(const float* row, const Taps& taps, float* filtered) {
    using Floats = float __attribute__((vector_size(16)));
    for (size_t o = 0; o < taps.first.size(); ++o, filtered += 3) {
        const float* texel = row + size_t(taps.first[o]) * 3;
        const float* weight = &taps.weights[o * kTaps];
        Floats f = {0, 0, 0, 0};
        for (uint32_t i = 0; i < kTaps; ++i) {
            Floats t;
            std::memcpy(&t, texel + 3 * i, sizeof t);
            f += weight[i] * t;
        }
        std::memcpy(filtered, &f, sizeof f);
    }
}

}  // namespace

uint32_t scaledSide(uint32_t side, double factor) {
    const double scale = factor > 1 ? 1 / std::sqrt(factor) : 1;
    return std::max(1u, static_cast<uint32_t>(std::lround(side * scale)));
}

uint32_t mipSide(uint32_t side) { return (side + 1) / 2; }

namespace {

// A level's columns [x0, x1) of rows [y0, y1) (in memory, or a band of tiles at a time from the
// file, in one pread from the first tile's first row wanted to the last tile's last: the tiles
// between them are contiguous), copied row by row.
class LevelRows {
public:
    LevelRows(const TextureSource& source, size_t level, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1)
        : source_(source), level_(source.levels.at(level)), tiles_{level_.width, level_.height, source.channels}, x0_(x0), x1_(x1), y0_(y0),
          y1_(y1) {}
    void copy(uint32_t y, uint8_t* out) {
        const uint32_t nc = source_.channels;
        if (x1_ == x0_) return;
        if (level_.pixels) {
            std::memcpy(out, level_.pixels + (size_t(y) * level_.width + x0_) * nc, size_t(x1_ - x0_) * nc);
            return;
        }
        const uint32_t band = y / kTile, row = y % kTile;
        if (band != band_ || owner_ != this) read(band);
        for (uint32_t tx = x0_ / kTile; tx * kTile < x1_; ++tx) {
            const uint32_t c0 = std::max(x0_, tx * kTile), c1 = std::min(x1_, tx * kTile + kTile), width = tiles_.tileWidth(tx);
            const uint8_t* from = buffer_.data() + (tiles_.tile(tx, band) + (uint64_t(row) * width + c0 - tx * kTile) * nc - start_);
            out = std::copy_n(from, size_t(c1 - c0) * nc, out);
        }
    }

private:
    void read(uint32_t band) {
        const uint32_t nc = source_.channels, first = x0_ / kTile, last = (x1_ - 1) / kTile;
        const uint32_t r0 = std::max(y0_, band * kTile) - band * kTile, r1 = std::min(y1_, band * kTile + tiles_.bandRows(band)) - band * kTile;
        start_ = tiles_.tile(first, band) + uint64_t(r0) * tiles_.tileWidth(first) * nc;
        const uint64_t end = tiles_.tile(last, band) + uint64_t(r1) * tiles_.tileWidth(last) * nc;
        if (buffer_.size() < end - start_) buffer_.resize(end - start_);
        if (const int error = preadFully(source_.file, buffer_.data(), end - start_, level_.offset + start_))
            throw std::runtime_error("texture store: cannot read back a decoded texture (" +
                                     std::string(error == kEndOfFile ? "unexpected end of the temporary file" : std::strerror(error)) + ")");
        band_ = band, owner_ = this;
    }
    // One band's bytes per thread, kept from rectangle to rectangle (no fresh pages per read).
    static thread_local std::vector<uint8_t> buffer_;
    static thread_local const LevelRows* owner_;  // whose band buffer_ holds
    const TextureSource& source_;
    const TextureLevel& level_;
    const Tiles tiles_;
    const uint32_t x0_, x1_, y0_, y1_;
    uint32_t band_ = UINT32_MAX;
    uint64_t start_ = 0;  // buffer_'s first byte in the level
};
thread_local std::vector<uint8_t> LevelRows::buffer_;
thread_local const LevelRows* LevelRows::owner_ = nullptr;

}  // namespace

void TextureSource::rows(uint32_t y0, uint32_t y1, uint32_t x0, uint32_t x1, uint8_t* out, size_t level) const {
    LevelRows reader(*this, level, x0, x1, y0, y1);
    for (uint32_t y = y0; y < y1; ++y, out += size_t(x1 - x0) * channels) reader.copy(y, out);
}

TextureSource textureView(const Image& image, const std::vector<Image>& mips) {
    TextureSource view{image.width, image.height, image.channels, -1, 0, {{image.width, image.height, image.pixels.data(), 0}}};
    for (const Image& m : mips) view.levels.push_back({m.width, m.height, m.pixels.data(), 0});
    return view;
}

Image scaledRegion(const TextureSource& source, uint32_t scaledWidth, uint32_t scaledHeight, uint32_t x0, uint32_t y0, uint32_t x1,
                   uint32_t y1) {
    const uint32_t nc = source.channels;
    Image out{x1 - x0, y1 - y0, nc, {}};
    out.pixels.resize(size_t(out.width) * out.height * nc);
    size_t level = 0;  // the coarsest level that still has scaledWidth x scaledHeight texels
    while (level + 1 < source.levels.size() && source.levels[level + 1].width >= scaledWidth && source.levels[level + 1].height >= scaledHeight)
        ++level;
    const TextureLevel& from = source.levels[level];
    if (scaledWidth == from.width && scaledHeight == from.height) {
        source.rows(y0, y1, x0, x1, out.pixels.data(), level);
        return out;
    }
    if (from.width == 2 * scaledWidth && from.height == 2 * scaledHeight) {  // a halving (the pyramid's)
        std::vector<uint8_t> pair(size_t(x1 - x0) * 2 * nc * 2);
        LevelRows rows(source, level, 2 * x0, 2 * x1, 2 * y0, 2 * y1);
        for (uint32_t oy = 0; oy < out.height; ++oy) {
            rows.copy(2 * (y0 + oy), pair.data()), rows.copy(2 * (y0 + oy) + 1, pair.data() + pair.size() / 2);
            halveRows(pair.data(), pair.size() / 2, out.width, 1, nc, &out.pixels[size_t(oy) * out.width * nc]);
        }
        return out;
    }
    const Spans across = spans(from.width, scaledWidth, x0, x1), down = spans(from.height, scaledHeight, y0, y1);
    const uint32_t sx0 = across.spans.front().first, sx1 = across.spans.back().first + across.spans.back().count;
    // The last kCachedRows source rows read, filtered horizontally (by row modulo kCachedRows):
    // consecutive output rows share rows, which are then read and filtered once.
    constexpr uint32_t kCachedRows = 4;
    const size_t filteredSize = size_t(out.width) * nc;
    std::vector<uint8_t> row(size_t(sx1 - sx0) * nc);
    const bool rgb = nc == 3 && tapsFit(across);  // RGB rows converted to floats once, then filtered by taps
    const Taps tapsAcross = rgb ? taps(across, sx0) : Taps{};
    std::vector<float> rowFloats(rgb ? row.size() + kTaps * 3 + 1 : 0, 0.0f);
    LevelRows rows(source, level, sx0, sx1, down.spans.front().first, down.spans.back().first + down.spans.back().count);
    std::vector<float> cache((filteredSize + 1) * kCachedRows);  // a float past each row: filterRgb's spare lane
    uint32_t cachedY[kCachedRows];
    std::fill_n(cachedY, kCachedRows, UINT32_MAX);
    const auto filteredRow = [&](uint32_t y) {
        float* slot = &cache[(y % kCachedRows) * (filteredSize + 1)];
        if (cachedY[y % kCachedRows] == y) return slot;
        rows.copy(y, row.data()), cachedY[y % kCachedRows] = y;
        if (rgb) {
            std::copy(row.begin(), row.end(), rowFloats.begin());
            filterRgb(rowFloats.data(), tapsAcross, slot);
        } else if (nc == 3) filterRow<3>(row.data(), across, sx0, slot);
        else if (nc == 1) filterRow<1>(row.data(), across, sx0, slot);
        else if (nc == 2) filterRow<2>(row.data(), across, sx0, slot);
        else filterRow<4>(row.data(), across, sx0, slot);  // Image: 1 to 4 channels
        return slot;
    };
    std::vector<float> sum(filteredSize);
    for (uint32_t oy = 0; oy < out.height; ++oy) {
        std::fill(sum.begin(), sum.end(), 0.0f);
        const Span& vertical = down.spans[oy];
        for (uint32_t k = 0; k < vertical.count; ++k) {
            const float* filtered = filteredRow(vertical.first + k);
            const float w = down.weights[vertical.weight + k];
            for (size_t i = 0; i < filteredSize; ++i) sum[i] += w * filtered[i];
        }
        uint8_t* o = &out.pixels[size_t(oy) * out.width * nc];
        // Half up, clamped to [0, 255] after the rounding, in integers: float comparisons may trap
        // (-ftrapping-math), so GCC left a clamp of the float a branchy scalar loop; rounding first
        // gives the same bytes (a sum below 0 or above 255 gives 0 or 255 either way).
        for (size_t i = 0; i < sum.size(); ++i) {
            const int v = static_cast<int>(sum[i] + 0.5f);
            o[i] = static_cast<uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    }
    return out;
}

std::vector<Image> mipLevels(const Image& image) {
    std::vector<Image> mips;
    for (const Image* last = &image; last->width > 1 || last->height > 1; last = &mips.back()) {
        const uint32_t w = mipSide(last->width), h = mipSide(last->height);
        Image next = scaledRegion(textureView(*last), w, h, 0, 0, w, h);
        mips.push_back(std::move(next));  // `last` is re-pointed after the move
    }
    return mips;
}

Image downsampleTexture(const Image& source, double factor) {
    const uint32_t w = scaledSide(source.width, factor), h = scaledSide(source.height, factor);
    if (w == source.width && h == source.height) return source;
    const std::vector<Image> mips = mipLevels(source);
    return scaledRegion(textureView(source, mips), w, h, 0, 0, w, h);
}

namespace {

// A JPEG whose decoder holds all its coefficients (formats/image_io.h) above the memory limit.
std::string wholeImageWarning(const std::string& path, const ImageRows& image, uint64_t limit) {
    return "warning: " + path + ": a progressive (multi-scan) JPEG of " + std::to_string(image.width) + " x " +
           std::to_string(image.height) + ": libjpeg holds all its coefficients while decoding it (" + formatBytes(image.wholeImageBytes) +
           "), more than --memory-limit (" + formatBytes(limit) + "); `jpegtran -outfile BASELINE.jpg " + shellWord(path) +
           "` (libjpeg-turbo-progs) writes the same texels as a baseline JPEG, decoded by strips";
}

}  // namespace

struct TextureStore::Impl {
    struct Held {
        Image image;
        std::vector<Image> mips;
    };
    std::string dir;
    uint64_t memoryLimit = 0;
    std::mutex mutex;
    std::map<std::string, std::shared_future<TextureSource>> sources;
    std::vector<int> files;
    std::vector<std::unique_ptr<Held>> images;  // without a folder

    TextureSource decode(const std::string& path, size_t index, Progress* progress) {
        if (dir.empty()) {
            auto held = std::make_unique<Held>();
            held->image = loadTexture(path);
            held->mips = mipLevels(held->image);
            const TextureSource source = textureView(held->image, held->mips);
            const std::lock_guard lock(mutex);
            images.push_back(std::move(held));
            return source;
        }
        const std::unique_ptr<ImageRows> input = openTexture(path);
        if (memoryLimit && input->wholeImageBytes > memoryLimit && progress) progress->message(wholeImageWarning(path, *input, memoryLimit));
        TextureSource source{input->width, input->height, input->channels >= 3 ? 3u : 1u, -1, 0, {{input->width, input->height, nullptr, 0}}};
        const std::string file = (std::filesystem::path(dir) / ("texture_" + std::to_string(index) + ".raw")).string();
        source.file = ::open(file.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        if (source.file < 0) throw std::runtime_error(file + ": cannot create temporary file (" + std::strerror(errno) + ")");
        {
            const std::lock_guard lock(mutex);
            files.push_back(source.file);
        }
        const auto write = [&](const uint8_t* bytes, size_t size, uint64_t offset) {
            if (const int error = pwriteFully(source.file, bytes, size, offset))
                throw std::runtime_error(file + ": cannot write a decoded texture (" + std::strerror(error) + ")");
        };
        // A band of a level's rows (row by row in `rows`) written as its tiles, in one call.
        std::vector<uint8_t> tiled;
        const auto writeBand = [&](const TextureLevel& level, uint32_t band, const uint8_t* rows) {
            const Tiles tiles{level.width, level.height, source.channels};
            tiled.resize(size_t(tiles.bandRows(band)) * level.width * source.channels);
            tiles.tile(band, rows, tiled.data());
            write(tiled.data(), tiled.size(), level.offset + tiles.tile(0, band));
        };
        const size_t rowBytes = size_t(source.width) * source.channels;
        std::vector<uint8_t> strip(rowBytes * kStripRows);
        // Even sides: level 1 from the decoded strips (kStripRows is even), not read back; its
        // band of kTile rows gathered from two strips.
        const bool even = source.width % 2 == 0 && source.height % 2 == 0;
        const TextureLevel half{source.width / 2, source.height / 2, nullptr, uint64_t(rowBytes) * source.height};
        std::vector<uint8_t> halved(even ? rowBytes / 2 * kTile : 0);
        for (uint32_t y = 0; y < source.height; y += kStripRows) {
            const uint32_t end = std::min<uint32_t>(source.height, y + kStripRows);
            readTextureRows(*input, path, end - y, source.channels, strip.data());
            writeBand(source.levels[0], y / kTile, strip.data());
            if (!even) continue;
            const uint32_t first = y / 2, pairs = (end - y) / 2;
            halveRows(strip.data(), rowBytes, half.width, pairs, source.channels, &halved[rowBytes / 2 * (first % kTile)]);
            if ((first + pairs) % kTile == 0 || first + pairs == half.height) writeBand(half, first / kTile, halved.data());
        }
        if (even) source.levels.push_back(half);
        // The rest of the pyramid, each level filtered by bands from the one before, read back.
        for (TextureLevel last = source.levels.back(); last.width > 1 || last.height > 1; last = source.levels.back()) {
            const TextureLevel next{mipSide(last.width), mipSide(last.height), nullptr,
                                    last.offset + uint64_t(last.width) * last.height * source.channels};
            TextureSource previous = source;
            previous.levels = {last};
            for (uint32_t y = 0; y < next.height; y += kTile) {
                const Image rows = scaledRegion(previous, next.width, next.height, 0, y, next.width, std::min<uint32_t>(next.height, y + kTile));
                writeBand(next, y / kTile, rows.pixels.data());
            }
            source.levels.push_back(next);
        }
        std::filesystem::remove(file);  // the open descriptor keeps it until the store closes it
        return source;
    }
};

TextureStore::TextureStore(const std::string& dir, uint64_t memoryLimit) : impl_(std::make_unique<Impl>()) {
    impl_->dir = dir, impl_->memoryLimit = memoryLimit;
    if (!dir.empty()) std::filesystem::create_directories(dir);
}

TextureStore::~TextureStore() {
    for (int f : impl_->files) ::close(f);
}

bool TextureStore::opened(const std::string& path) const {
    const std::lock_guard lock(impl_->mutex);
    return impl_->sources.count(path) != 0;
}

TextureSource TextureStore::open(const std::string& path, Progress* progress) {
    std::promise<TextureSource> promise;
    std::shared_future<TextureSource> future;
    bool first = false;
    size_t index = 0;
    {
        const std::lock_guard lock(impl_->mutex);
        auto it = impl_->sources.find(path);
        if (it == impl_->sources.end()) {
            index = impl_->sources.size();
            it = impl_->sources.emplace(path, promise.get_future().share()).first;
            first = true;
        }
        future = it->second;
    }
    if (first) {
        try {
            TextureSource source = impl_->decode(path, index, progress);
            const std::vector<uint8_t> head = jpegFileHead(path);
            source.jpegQuality = jpegQuality(head), source.chroma420 = jpegChroma420(head);
            if (progress) progress->textureLoaded(uint64_t{source.width} * source.height);
            promise.set_value(source);
        } catch (...) {
            promise.set_exception(std::current_exception());
        }
    }
    return future.get();  // a failed decode throws its InputError in every block that uses it
}

}  // namespace hlod
