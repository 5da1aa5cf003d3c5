// Source textures read region by region (issue #14: the build's peak RSS stays within
// --memory-limit on scans with tens of 4K atlases). A texture file is decoded once per build,
// a strip of kStripRows scanlines at a time (formats/image_io.h), into an uncompressed
// file in the build's temporary folder; a node then reads only the rows and columns under the
// rectangles its charts use (pread: the page cache holds them, not the process). The thesis's
// downsampling by the node's factor (§3.2: "the original texture data is down-sampled by this
// simplification factor as well") is a box filter computed per rectangle: each scaled texel
// is the area-weighted mean of the source texels it covers, a function of that texel alone, so a
// rectangle's texels equal those of the whole downsampled image (downsampleTexture) and no
// whole atlas, source or downsampled, is held. Without a folder (buildBlock outside runBuild)
// the decoded sources stay in memory, one block's at a time.
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

#include "formats/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>

namespace hlod {

namespace {

constexpr int kStripRows = 64;  // scanlines decoded at once: 4096 x 64 x 3 = 768 KiB

// The texels of one axis an output texel covers: source [first, first + weights.size()).
struct Span {
    uint32_t first = 0;
    std::vector<float> weights;
};

// Output texels [begin, end) of an axis of `out` texels over `in` source texels.
std::vector<Span> spans(uint32_t in, uint32_t out, uint32_t begin, uint32_t end) {
    const double ratio = double(in) / out;
    std::vector<Span> result(end - begin);
    for (uint32_t o = begin; o < end; ++o) {
        const double lo = o * ratio, hi = (o + 1) * ratio;
        Span& s = result[o - begin];
        s.first = static_cast<uint32_t>(std::floor(lo));
        const uint32_t last = std::min(in, static_cast<uint32_t>(std::ceil(hi)));
        for (uint32_t i = s.first; i < last; ++i)
            s.weights.push_back(static_cast<float>((std::min(hi, i + 1.0) - std::max(lo, double(i))) / ratio));
    }
    return result;
}

}  // namespace

uint32_t scaledSide(uint32_t side, double factor) {
    const double scale = factor > 1 ? 1 / std::sqrt(factor) : 1;
    return std::max(1u, static_cast<uint32_t>(std::lround(side * scale)));
}

void TextureSource::rows(uint32_t y0, uint32_t y1, uint32_t x0, uint32_t x1, uint8_t* out) const {
    const size_t rowBytes = size_t(x1 - x0) * channels;
    for (uint32_t y = y0; y < y1; ++y, out += rowBytes) {
        const size_t offset = (size_t(y) * width + x0) * channels;
        if (image) {
            std::memcpy(out, image->pixels.data() + offset, rowBytes);
            continue;
        }
        for (size_t done = 0; done < rowBytes;) {
            const ssize_t n = pread(file, out + done, rowBytes - done, static_cast<off_t>(offset + done));
            if (n <= 0) throw std::runtime_error("texture store: cannot read back a decoded texture (" + std::string(std::strerror(errno)) + ")");
            done += static_cast<size_t>(n);
        }
    }
}

Image scaledRegion(const TextureSource& source, uint32_t scaledWidth, uint32_t scaledHeight, uint32_t x0, uint32_t y0, uint32_t x1,
                   uint32_t y1) {
    const uint32_t nc = source.channels;
    Image out{x1 - x0, y1 - y0, nc, {}};
    out.pixels.resize(size_t(out.width) * out.height * nc);
    if (scaledWidth == source.width && scaledHeight == source.height) {
        source.rows(y0, y1, x0, x1, out.pixels.data());
        return out;
    }
    const std::vector<Span> across = spans(source.width, scaledWidth, x0, x1), down = spans(source.height, scaledHeight, y0, y1);
    const uint32_t sx0 = across.front().first, sx1 = across.back().first + static_cast<uint32_t>(across.back().weights.size());
    std::vector<uint8_t> row(size_t(sx1 - sx0) * nc);
    std::vector<float> filtered(size_t(out.width) * nc), sum(size_t(out.width) * nc);
    for (uint32_t oy = 0; oy < out.height; ++oy) {
        std::fill(sum.begin(), sum.end(), 0.0f);
        const Span& vertical = down[oy];
        for (size_t k = 0; k < vertical.weights.size(); ++k) {
            source.rows(vertical.first + static_cast<uint32_t>(k), vertical.first + static_cast<uint32_t>(k) + 1, sx0, sx1, row.data());
            std::fill(filtered.begin(), filtered.end(), 0.0f);
            for (uint32_t ox = 0; ox < out.width; ++ox) {
                const Span& s = across[ox];
                const uint8_t* texel = &row[size_t(s.first - sx0) * nc];
                for (size_t i = 0; i < s.weights.size(); ++i, texel += nc)
                    for (uint32_t c = 0; c < nc; ++c) filtered[ox * nc + c] += s.weights[i] * texel[c];
            }
            const float w = vertical.weights[k];
            for (size_t i = 0; i < sum.size(); ++i) sum[i] += w * filtered[i];
        }
        for (size_t i = 0; i < sum.size(); ++i)
            out.pixels[size_t(oy) * out.width * nc + i] = static_cast<uint8_t>(std::clamp(std::lround(sum[i]), 0l, 255l));
    }
    return out;
}

Image downsampleTexture(const Image& source, double factor) {
    const uint32_t w = scaledSide(source.width, factor), h = scaledSide(source.height, factor);
    if (w == source.width && h == source.height) return source;
    const TextureSource view{source.width, source.height, source.channels, &source, -1};
    return scaledRegion(view, w, h, 0, 0, w, h);
}

struct TextureStore::Impl {
    std::string dir;
    std::mutex mutex;
    std::map<std::string, std::shared_future<TextureSource>> sources;
    std::vector<int> files;
    std::vector<std::unique_ptr<Image>> images;  // without a folder

    TextureSource decode(const std::string& path, size_t index) {
        if (dir.empty()) {
            auto image = std::make_unique<Image>(loadTexture(path));
            const std::lock_guard lock(mutex);
            images.push_back(std::move(image));
            const Image* held = images.back().get();
            return {held->width, held->height, held->channels, held, -1};
        }
        const std::unique_ptr<ImageRows> input = openTexture(path);
        TextureSource source{input->width, input->height, input->channels >= 3 ? 3u : 1u, nullptr, -1};
        const std::string file = (std::filesystem::path(dir) / ("texture_" + std::to_string(index) + ".raw")).string();
        source.file = ::open(file.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        if (source.file < 0) throw std::runtime_error(file + ": cannot create temporary file (" + std::strerror(errno) + ")");
        {
            const std::lock_guard lock(mutex);
            files.push_back(source.file);
        }
        const size_t rowBytes = size_t(source.width) * source.channels;
        std::vector<uint8_t> strip(rowBytes * kStripRows);
        for (uint32_t y = 0; y < source.height; y += kStripRows) {
            const uint32_t end = std::min<uint32_t>(source.height, y + kStripRows);
            readTextureRows(*input, path, end - y, source.channels, strip.data());
            const size_t bytes = rowBytes * (end - y);
            if (pwrite(source.file, strip.data(), bytes, static_cast<off_t>(rowBytes * y)) != static_cast<ssize_t>(bytes))
                throw std::runtime_error(file + ": cannot write a decoded texture (" + std::strerror(errno) + ")");
        }
        std::filesystem::remove(file);  // the open descriptor keeps it until the store closes it
        return source;
    }
};

TextureStore::TextureStore(const std::string& dir) : impl_(std::make_unique<Impl>()) {
    impl_->dir = dir;
    if (!dir.empty()) std::filesystem::create_directories(dir);
}

TextureStore::~TextureStore() {
    for (int f : impl_->files) ::close(f);
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
            TextureSource source = impl_->decode(path, index);
            source.jpegQuality = jpegFileQuality(path);
            if (progress) progress->textureLoaded(uint64_t{source.width} * source.height);
            promise.set_value(source);
        } catch (...) {
            promise.set_exception(std::current_exception());
        }
    }
    return future.get();  // a failed decode throws its InputError in every block that uses it
}

}  // namespace hlod
