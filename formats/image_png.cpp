// PNG through libpng (formats/image_io.h), a row at a time. An interlaced PNG's rows are complete
// only after its seven passes, i.e. after the whole file: it is decoded in bands of at most
// `interlacedBandBytes` of decoded rows, the file read once per band (one pass when it fits). The transformations are OpenImageIO's reader's: a palette expanded
// to RGB, greys of 1, 2 or 4 bits to 8, a transparent colour (tRNS) to an alpha channel; 16-bit
// samples are rounded to 8 bits as OpenImageIO's conversion rounds them, v * 255 / 65535 to the
// nearest (tests/pipeline/test_image_io.cpp checks every value against OpenImageIO).
#include "formats/image_io.h"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdlib>
#include <cstring>

namespace hlod {

namespace {

// libpng allocates an ancillary chunk (text, ICC profile, ...) at its declared length, up to
// 2 GiB, before reading it (fuzz_blob: a 417-byte PNG's tEXt chunk declared 1.8 GB). Its own buffers are a
// few rows at most (8 bytes per texel), so larger requests are refused and the image fails with an
// error ("out of memory"), as fuzz_blob's finding now does (tests/fuzz/README.md).
constexpr png_alloc_size_t kMaxLibpngAllocation = png_alloc_size_t(64) << 20;

png_voidp boundedMalloc(png_structp, png_alloc_size_t size) { return size > kMaxLibpngAllocation ? nullptr : std::malloc(size); }
void freeMemory(png_structp, png_voidp memory) { std::free(memory); }

class PngRows final : public ImageRows {
public:
    PngRows(const ImageSource& source, bool refuseAlpha, size_t interlacedBandBytes)
        : source_(source), start_(source.file ? std::ftell(source.file) : 0), bandBytes_(interlacedBandBytes) {
        bool alpha = false;
        if (!open(alpha)) throw ImageError(message_);
        if (refuseAlpha && alpha) throw ImageNeedsPlugin("a PNG with alpha");
    }

    // After an error libpng's state is undefined: every later read fails with the same message.
    void read(uint32_t count, uint32_t keep, uint8_t* out) override {
        if (failed_ || !decode(count, keep, out)) failed_ = true, throw ImageError(message_);
    }

private:
    struct Read {
        png_structp png = nullptr;
        png_infop info = nullptr;
        Read() = default;
        Read(const Read&) = delete;
        Read& operator=(const Read&) = delete;
        ~Read() { reset(); }
        void reset() {
            if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
            png = nullptr, info = nullptr;
        }
    };

    [[noreturn]] static void onError(png_structp png, png_const_charp message) {
        PngRows* self = static_cast<PngRows*>(png_get_error_ptr(png));
        self->message_ = message;
        png_longjmp(png, 1);
    }
    static void onWarning(png_structp, png_const_charp) {}  // ancillary-chunk problems: the texels are fine
    static void readMemory(png_structp png, png_bytep out, size_t bytes) {
        PngRows* self = static_cast<PngRows*>(png_get_io_ptr(png));
        if (bytes > self->source_.bytes.size() - self->offset_) png_error(png, "truncated PNG data");
        std::memcpy(out, self->source_.bytes.data() + self->offset_, bytes);
        self->offset_ += bytes;
    }

    bool open(bool& alpha) {
        read_.reset();
        read_.png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, this, onError, onWarning, nullptr, boundedMalloc, freeMemory);
        if (read_.png) read_.info = png_create_info_struct(read_.png);
        if (!read_.info) return message_ = "out of memory", false;
        return header(alpha);
    }

    bool header(bool& alpha) {
        png_structp png = read_.png;
        png_infop info = read_.info;
        if (setjmp(png_jmpbuf(png))) return false;
        if (source_.file) png_init_io(png, source_.file);
        else png_set_read_fn(png, this, readMemory);
        png_read_info(png, info);
        const int type = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
        const bool transparent = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
        alpha = (type & PNG_COLOR_MASK_ALPHA) || transparent;
        if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
        if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
        if (transparent) png_set_tRNS_to_alpha(png);
        sixteen_ = depth == 16;
        if (sixteen_) png_set_swap(png);  // host (little-endian) order
        interlaced_ = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
        if (interlaced_) passes_ = png_set_interlace_handling(png);
        png_read_update_info(png, info);
        width = png_get_image_width(png, info), height = png_get_image_height(png, info);
        channels = png_get_channels(png, info);
        return true;
    }

    size_t rowBytes() const { return size_t(width) * channels * (sixteen_ ? 2 : 1); }

    // Rows [bandStart_, bandStart_ + band_.size() / rowBytes()) of an interlaced image: every pass
    // of the file decoded, only the band's rows kept (libpng merges each pass's texels into the
    // row it is given; a null row skips them). The file is read again from its start for every
    // band after the first.
    bool decodeBand(uint32_t first) {
        if (first > 0) {
            bool alpha = false;
            if (source_.file && (start_ < 0 || std::fseek(source_.file, start_, SEEK_SET) != 0))
                return message_ = "cannot seek back to re-read an interlaced PNG", false;
            offset_ = 0;
            if (!open(alpha)) return false;
        }
        if (setjmp(png_jmpbuf(read_.png))) return false;
        const size_t rows = std::clamp<size_t>(bandBytes_ / rowBytes(), 1, height - first);
        band_.assign(rows * rowBytes(), 0);
        bandStart_ = first;
        for (int pass = 0; pass < passes_; ++pass)
            for (uint32_t y = 0; y < height; ++y)
                png_read_row(read_.png, y >= first && y - first < rows ? &band_[(y - first) * rowBytes()] : nullptr, nullptr);
        return true;
    }

    bool decode(uint32_t count, uint32_t keep, uint8_t* out) {
        if (!interlaced_) row_.resize(rowBytes());
        for (uint32_t r = 0; r < count; ++r, ++next_) {
            if (next_ >= height) return message_ = "fewer rows than the header says", false;
            if (interlaced_ && (band_.empty() || next_ - bandStart_ >= band_.size() / rowBytes()) && !decodeBand(next_)) return false;
            const uint8_t* row = interlaced_ ? &band_[rowBytes() * (next_ - bandStart_)] : row_.data();
            if (!interlaced_ && !readRow()) return false;
            uint8_t* texels = out + size_t(r) * width * keep;
            for (uint32_t x = 0; x < width; ++x)
                for (uint32_t c = 0; c < keep; ++c) {
                    const size_t i = size_t(x) * channels + c;
                    texels[size_t(x) * keep + c] = sixteen_ ? static_cast<uint8_t>((uint32_t(row[2 * i] | row[2 * i + 1] << 8) + 128) / 257) : row[i];
                }
        }
        return true;
    }

    bool readRow() {
        if (setjmp(png_jmpbuf(read_.png))) return false;
        png_read_row(read_.png, row_.data(), nullptr);
        return true;
    }

    Read read_;
    ImageSource source_;
    long start_;
    size_t bandBytes_;
    size_t offset_ = 0;
    std::string message_;
    bool sixteen_ = false, interlaced_ = false, failed_ = false;
    int passes_ = 1;
    uint32_t next_ = 0, bandStart_ = 0;
    std::vector<uint8_t> row_, band_;
};

struct Write {
    png_structp png = nullptr;
    png_infop info = nullptr;
    std::vector<uint8_t>* bytes = nullptr;
    std::string message;
    ~Write() {
        if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
    }
};

bool writePng(Write& w, const Image& image) {
    if (setjmp(png_jmpbuf(w.png))) return false;
    png_set_write_fn(
        w.png, &w,
        [](png_structp png, png_bytep data, size_t size) {
            Write* self = static_cast<Write*>(png_get_io_ptr(png));
            self->bytes->insert(self->bytes->end(), data, data + size);
        },
        nullptr);
    static constexpr int kTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(w.png, w.info, image.width, image.height, 8, kTypes[image.channels - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(w.png, w.info);
    const size_t rowBytes = size_t(image.width) * image.channels;
    for (uint32_t y = 0; y < image.height; ++y) png_write_row(w.png, image.pixels.data() + rowBytes * y);
    png_write_end(w.png, nullptr);
    return true;
}

}  // namespace

std::unique_ptr<ImageRows> openPng(const ImageSource& source, bool refuseAlpha, size_t interlacedBandBytes) {
    return std::make_unique<PngRows>(source, refuseAlpha, interlacedBandBytes);
}

std::vector<uint8_t> encodePng(const Image& image) {
    if (image.channels < 1 || image.channels > 4 || image.width == 0 || image.height == 0 ||
        image.pixels.size() != size_t(image.width) * image.height * image.channels)
        throw std::runtime_error("encodeTexture: bad image dimensions, channels or pixel count");
    std::vector<uint8_t> bytes;
    Write w;
    w.bytes = &bytes;
    w.png = png_create_write_struct(
        PNG_LIBPNG_VER_STRING, &w,
        [](png_structp png, png_const_charp message) {
            static_cast<Write*>(png_get_error_ptr(png))->message = message;
            png_longjmp(png, 1);
        },
        nullptr);
    if (w.png) w.info = png_create_info_struct(w.png);
    if (!w.info) throw std::runtime_error("encodeTexture: out of memory");
    if (!writePng(w, image)) throw std::runtime_error("encodeTexture: " + w.message);
    return bytes;
}

void writePngFile(const std::string& path, const Image& image) {
    std::vector<uint8_t> bytes;
    try {
        bytes = encodePng(image);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(path + ": cannot write PNG: " + e.what());
    }
    writeImageBytes(path, bytes, "PNG");
}

}  // namespace hlod
