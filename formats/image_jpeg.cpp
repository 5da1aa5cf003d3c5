// JPEG through libjpeg-turbo (formats/image_io.h). Decoding keeps libjpeg's defaults, as
// OpenImageIO's reader did (integer DCT, fancy upsampling, RGB or greyscale output), so the
// texels are the ones it gave; any libjpeg warning (a truncated file's "premature end of data")
// is an error, as OpenImageIO made it one. Encoding: baseline sequential at `quality`; node
// textures fit their Huffman tables to the image (formats/jpeg_tables.cpp, one pass; from
// formats/codec_image.cpp), and writeJpegFile writes what
// OpenImageIO's writer wrote (standard tables, 4:2:0, JFIF plus an empty Exif segment), byte
// for byte (tests/data: Datasets.SampleCityIsExactlyTheGeneratorsOutput).
#include "formats/image_io.h"
#include "formats/jpeg_tables.h"
#include "formats/temp_files.h"

#include <algorithm>
#include <csetjmp>
#include <cstring>
#include <fstream>
#include <new>
#include <type_traits>
#include <vector>

#include <jpeglib.h>
#include <jerror.h>

namespace hlod {

namespace {

struct JpegFailure {
    jpeg_error_mgr manager;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
    char warning[JMSG_LENGTH_MAX];  // the first warning, "" when none
};

void installFailure(JpegFailure& failure) {
    jpeg_std_error(&failure.manager);
    failure.message[0] = failure.warning[0] = 0;
    failure.manager.error_exit = [](j_common_ptr c) {
        JpegFailure* f = reinterpret_cast<JpegFailure*>(c->err);
        f->manager.format_message(c, f->message);
        std::longjmp(f->jump, 1);
    };
    failure.manager.emit_message = [](j_common_ptr c, int level) {
        JpegFailure* f = reinterpret_cast<JpegFailure*>(c->err);
        if (level >= 0) return;  // trace messages
        if (!f->warning[0]) f->manager.format_message(c, f->warning);
        ++f->manager.num_warnings;
    };
}

class JpegRows final : public ImageRows {
public:
    explicit JpegRows(const ImageSource& source) {
        if (!header(source)) throw ImageError(failure_.message);
        if (cinfo_.jpeg_color_space == JCS_CMYK || cinfo_.jpeg_color_space == JCS_YCCK)
            throw ImageNeedsPlugin("a CMYK JPEG");
        if (failure_.warning[0]) throw ImageError(failure_.warning);
        if (cinfo_.num_components != 1 && cinfo_.num_components != 3)
            throw ImageError("JPEG with " + std::to_string(cinfo_.num_components) + " components");
        width = cinfo_.image_width, height = cinfo_.image_height, channels = static_cast<uint32_t>(cinfo_.num_components);
        if (multiScan_) wholeImageBytes = coefficientBytes();
    }
    void read(uint32_t count, uint32_t keep, uint8_t* out) override {
        if (!decode(count, keep, out)) throw ImageError(failure_.message);
        if (failure_.warning[0]) throw ImageError(failure_.warning);
    }

private:
    // The whole-image coefficient arrays libjpeg's coefficient controller requests for a
    // multi-scan file (jdcoefct.c: each component's blocks rounded up to its sampling factors).
    uint64_t coefficientBytes() const {
        const auto roundUp = [](uint64_t n, uint64_t m) { return (n + m - 1) / m * m; };
        uint64_t blocks = 0;
        for (int c = 0; c < cinfo_.num_components; ++c) {
            const jpeg_component_info& component = cinfo_.comp_info[c];
            blocks += roundUp(component.width_in_blocks, uint64_t(component.h_samp_factor)) *
                      roundUp(component.height_in_blocks, uint64_t(component.v_samp_factor));
        }
        return blocks * sizeof(JBLOCK);
    }
    bool header(const ImageSource& source) {
        if (setjmp(failure_.jump)) return false;
        if (source.file) jpeg_stdio_src(&cinfo_, source.file);
        else jpeg_mem_src(&cinfo_, source.bytes.data(), static_cast<unsigned long>(source.bytes.size()));
        jpeg_read_header(&cinfo_, TRUE);
        multiScan_ = jpeg_has_multiple_scans(&cinfo_);
        return true;
    }
    bool decode(uint32_t count, uint32_t keep, uint8_t* out) {
        if (setjmp(failure_.jump)) return false;
        if (!started_) {
            jpeg_start_decompress(&cinfo_);
            started_ = true;
            row_.resize(size_t(width) * channels);
        }
        for (uint32_t r = 0; r < count; ++r) {
            uint8_t* texels = out + size_t(r) * width * keep;
            JSAMPROW row = keep == channels ? texels : row_.data();
            if (cinfo_.output_scanline >= cinfo_.output_height || jpeg_read_scanlines(&cinfo_, &row, 1) != 1) {
                std::strcpy(failure_.message, "fewer rows than the header says");
                return false;
            }
            if (keep != channels)
                for (uint32_t x = 0; x < width; ++x) std::memcpy(texels + size_t(x) * keep, &row_[size_t(x) * channels], keep);
        }
        return true;
    }

    // Destroyed also when the constructor throws.
    struct Decompress {
        Decompress(JpegFailure& failure) {
            cinfo.err = &failure.manager;
            installFailure(failure);
            if (setjmp(failure.jump)) throw ImageError(failure.message);  // out of memory in the create
            jpeg_create_decompress(&cinfo);
        }
        ~Decompress() { jpeg_destroy_decompress(&cinfo); }
        jpeg_decompress_struct cinfo{};
    };
    JpegFailure failure_{};
    Decompress decompress_{failure_};
    jpeg_decompress_struct& cinfo_ = decompress_.cinfo;
    bool started_ = false, multiScan_ = false;
    std::vector<uint8_t> row_;
};

// The APP1 segment OpenImageIO's writer adds: "Exif", then a little-endian TIFF header whose
// first IFD has no entries.
constexpr uint8_t kEmptyExif[] = {'E', 'x', 'i', 'f', 0, 0, 'I', 'I', '*', 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0};

// A destination appending to a vector (jpeg_mem_dest frees its first buffer when it grows but
// hands the caller the new one only at the end, so an error in between cannot free it safely).
struct VectorDestination {
    jpeg_destination_mgr manager{};
    std::vector<uint8_t> bytes;

    VectorDestination() {
        manager.init_destination = [](j_compress_ptr c) {
            VectorDestination& d = self(c);
            d.bytes.resize(size_t{1} << 16);
            d.manager.next_output_byte = d.bytes.data(), d.manager.free_in_buffer = d.bytes.size();
        };
        manager.empty_output_buffer = [](j_compress_ptr c) -> boolean {
            VectorDestination& d = self(c);
            const size_t used = d.bytes.size();  // called when the whole buffer is full
            try {
                d.bytes.resize(2 * used);
            } catch (const std::bad_alloc&) {
                ERREXIT(c, JERR_OUT_OF_MEMORY);
            }
            d.manager.next_output_byte = d.bytes.data() + used, d.manager.free_in_buffer = d.bytes.size() - used;
            return TRUE;
        };
        manager.term_destination = [](j_compress_ptr c) {
            VectorDestination& d = self(c);
            d.bytes.resize(d.bytes.size() - d.manager.free_in_buffer);
        };
    }
    static VectorDestination& self(j_compress_ptr c) { return *reinterpret_cast<VectorDestination*>(c->dest); }
};
static_assert(std::is_standard_layout_v<VectorDestination>);  // `manager` first: self() casts its address

// Huffman tables fitted to the image. A small one (at most kSampledMcus MCUs) takes libjpeg's
// exact optimisation: its two passes and whole-image coefficient arrays cost little there, and
// its tables omit the symbols the image does not use. A larger one gets tables fitted to a sample
// of its blocks (formats/jpeg_tables.cpp) in place of the standard ones jpeg_set_defaults gave,
// and libjpeg codes it in one pass.
void installFittedTables(jpeg_compress_struct& cinfo, const Image& image, bool chroma420) {
    if (jpegMcuCount(image, chroma420) <= kSampledMcus) {
        cinfo.optimize_coding = TRUE;
        return;
    }
    const JpegHuffmanTables tables = sampledHuffmanTables(image, cinfo.quant_tbl_ptrs[0]->quantval, cinfo.quant_tbl_ptrs[1]->quantval, chroma420);
    const auto install = [](JHUFF_TBL* target, const HuffmanTable& table) {
        std::copy(table.bits.begin(), table.bits.end(), target->bits);
        std::copy(table.values.begin(), table.values.end(), target->huffval);
        target->sent_table = FALSE;
    };
    for (int t = 0; t < 2; ++t) {
        install(cinfo.dc_huff_tbl_ptrs[t], tables.dc[t]);
        install(cinfo.ac_huff_tbl_ptrs[t], tables.ac[t]);
    }
}

}  // namespace

std::unique_ptr<ImageRows> openJpeg(const ImageSource& source) { return std::make_unique<JpegRows>(source); }

std::vector<uint8_t> encodeJpeg(const Image& image, int quality, bool chroma420, bool fittedTables, bool emptyExif) {
    jpeg_compress_struct cinfo{};
    JpegFailure failure{};
    cinfo.err = &failure.manager;
    installFailure(failure);
    VectorDestination destination;  // before the setjmp: a longjmp must not skip their destructors
    if (setjmp(failure.jump)) {
        jpeg_destroy_compress(&cinfo);
        throw std::runtime_error(std::string("encodeTexture: ") + failure.message);
    }
    jpeg_create_compress(&cinfo);
    cinfo.dest = &destination.manager;
    cinfo.image_width = image.width;
    cinfo.image_height = image.height;
    cinfo.input_components = static_cast<int>(image.channels);
    cinfo.in_color_space = image.channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, quality, TRUE);
    if (image.channels == 3) {
        // 4:4:4: 8 x 8 chroma blocks, the blocks node atlases are made of
        cinfo.comp_info[0].h_samp_factor = cinfo.comp_info[0].v_samp_factor = chroma420 ? 2 : 1;
        for (int c = 1; c < 3; ++c) cinfo.comp_info[c].h_samp_factor = cinfo.comp_info[c].v_samp_factor = 1;
    }
    if (fittedTables) try {
            installFittedTables(cinfo, image, chroma420);
        } catch (const std::bad_alloc&) {  // no libjpeg frame to cross, but cinfo to free
            jpeg_destroy_compress(&cinfo);
            throw std::runtime_error("encodeTexture: out of memory");
        }
    jpeg_start_compress(&cinfo, TRUE);
    if (emptyExif) jpeg_write_marker(&cinfo, JPEG_APP0 + 1, kEmptyExif, sizeof kEmptyExif);
    const size_t rowBytes = size_t(image.width) * image.channels;
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW row = const_cast<JSAMPROW>(image.pixels.data() + cinfo.next_scanline * rowBytes);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    return std::move(destination.bytes);
}

void writeJpegFile(const std::string& path, const Image& image, int quality) {
    if ((image.channels != 1 && image.channels != 3) || image.width == 0 || image.height == 0 ||
        image.pixels.size() != size_t(image.width) * image.height * image.channels)
        throw std::runtime_error(path + ": cannot write JPEG: bad image dimensions or channels");
    std::vector<uint8_t> bytes;
    try {
        bytes = encodeJpeg(image, quality, true, false, true);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(path + ": cannot write JPEG: " + e.what());
    }
    writeImageBytes(path, bytes, "JPEG");
}

void writeImageBytes(const std::string& path, const std::vector<uint8_t>& bytes, const char* format) {
    TextFileWriter file(path, format);  // a temporary beside PATH, renamed: a failed write leaves nothing
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

}  // namespace hlod
