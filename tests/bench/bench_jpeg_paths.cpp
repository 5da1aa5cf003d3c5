// What each way of reading and writing a JPEG atlas costs on this machine, per source texel
// (issue #14's textured speed goal; pipeline/HUGE_PAGES.md, TEXTURE_SPEED.md round 6): the pixel
// path the build takes today (decode to RGB, the temporary file, encode again) against the
// coefficient-domain paths a redesign would take instead (Wallace 1991, "The JPEG still picture
// compression standard": quantised DCT blocks, entropy-coded; a leaf's blocks copied as quantised
// coefficients, as jpegtran does; libjpeg's scaled inverse DCT, scale_num / 8, for the levels
// above). CPU time of this process, the best of --repeat runs of each path over every file
// given; the heap on 2 MiB pages as in `hlod` (HLOD_HUGE_PAGES=0: 4 KiB pages).
//
//   bench_jpeg_paths [--repeat N] [--tmp DIR] A.jpg [B.jpg ...]
#include "formats/cli/huge_pages.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <jpeglib.h>  // after <cstdio>: it uses size_t and FILE

namespace {

struct Failure {
    jpeg_error_mgr manager;
    std::jmp_buf jump;
};
void onError(j_common_ptr c) {
    char message[JMSG_LENGTH_MAX];
    c->err->format_message(c, message);
    std::fprintf(stderr, "bench_jpeg_paths: %s\n", message);
    std::exit(1);
}

double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Source {
    std::string path;
    std::vector<uint8_t> bytes;
    uint32_t width = 0, height = 0;
    bool chroma420 = false;
};

// A decompressor over `s`'s bytes, its header read.
struct Reader {
    jpeg_decompress_struct cinfo{};
    Failure failure{};
    explicit Reader(const Source& s) {
        cinfo.err = jpeg_std_error(&failure.manager);
        failure.manager.error_exit = onError;
        jpeg_create_decompress(&cinfo);
        jpeg_mem_src(&cinfo, s.bytes.data(), static_cast<unsigned long>(s.bytes.size()));
        jpeg_read_header(&cinfo, TRUE);
    }
    ~Reader() { jpeg_destroy_decompress(&cinfo); }
};

struct Writer {
    jpeg_compress_struct cinfo{};
    Failure failure{};
    unsigned char* out = nullptr;
    unsigned long size = 0;
    Writer() {
        cinfo.err = jpeg_std_error(&failure.manager);
        failure.manager.error_exit = onError;
        jpeg_create_compress(&cinfo);
        jpeg_mem_dest(&cinfo, &out, &size);
    }
    ~Writer() {
        jpeg_destroy_compress(&cinfo);
        std::free(out);
    }
};

// Decodes to RGB at scale num / 8 (8: full size); returns the texels and their bytes in `rgb`.
uint64_t decodeRgb(const Source& s, int num, std::vector<uint8_t>* rgb) {
    Reader r(s);
    r.cinfo.scale_num = static_cast<unsigned>(num), r.cinfo.scale_denom = 8;
    jpeg_start_decompress(&r.cinfo);
    const size_t stride = size_t(r.cinfo.output_width) * r.cinfo.output_components;
    std::vector<uint8_t> row(stride);
    if (rgb) rgb->resize(stride * r.cinfo.output_height);
    while (r.cinfo.output_scanline < r.cinfo.output_height) {
        JSAMPROW p = rgb ? rgb->data() + size_t(r.cinfo.output_scanline) * stride : row.data();
        jpeg_read_scanlines(&r.cinfo, &p, 1);
    }
    const uint64_t texels = uint64_t(r.cinfo.output_width) * r.cinfo.output_height;
    jpeg_finish_decompress(&r.cinfo);
    return texels;
}

// Decodes the Y, Cb, Cr planes as stored (no upsampling, no colour conversion).
void decodeRaw(const Source& s) {
    Reader r(s);
    r.cinfo.raw_data_out = TRUE;
    jpeg_start_decompress(&r.cinfo);
    const int rows = r.cinfo.max_v_samp_factor * DCTSIZE;
    std::vector<std::vector<uint8_t>> planes(size_t(r.cinfo.num_components));
    std::vector<std::vector<JSAMPROW>> pointers(planes.size());
    std::vector<JSAMPARRAY> arrays(planes.size());
    for (size_t c = 0; c < planes.size(); ++c) {
        const jpeg_component_info& ci = r.cinfo.comp_info[c];
        const size_t width = size_t(ci.width_in_blocks) * DCTSIZE, height = size_t(ci.v_samp_factor) * DCTSIZE;
        planes[c].resize(width * height);
        for (size_t y = 0; y < height; ++y) pointers[c].push_back(planes[c].data() + y * width);
        arrays[c] = pointers[c].data();
    }
    while (r.cinfo.output_scanline < r.cinfo.output_height) jpeg_read_raw_data(&r.cinfo, arrays.data(), static_cast<JDIMENSION>(rows));
    jpeg_finish_decompress(&r.cinfo);
}

// Entropy decoding only (the quantised coefficients); with `write`, the same coefficients coded
// again with Huffman tables optimised for them (jpegtran's path), timed separately into *writeCpu.
size_t readCoefficients(const Source& s, bool write, double* writeCpu, uint64_t* nonzero) {
    Reader r(s);
    jvirt_barray_ptr* coefficients = jpeg_read_coefficients(&r.cinfo);
    if (nonzero) {
        for (int c = 0; c < r.cinfo.num_components; ++c) {
            const jpeg_component_info& ci = r.cinfo.comp_info[c];
            for (JDIMENSION y = 0; y < ci.height_in_blocks; ++y) {
                JBLOCKARRAY row = r.cinfo.mem->access_virt_barray(reinterpret_cast<j_common_ptr>(&r.cinfo), coefficients[c], y, 1, FALSE);
                for (JDIMENSION x = 0; x < ci.width_in_blocks; ++x)
                    for (int k = 0; k < DCTSIZE2; ++k) *nonzero += row[0][x][k] != 0;
            }
        }
    }
    size_t bytes = 0;
    if (write) {
        const double t0 = cpuSeconds();
        Writer w;
        jpeg_copy_critical_parameters(&r.cinfo, &w.cinfo);
        w.cinfo.optimize_coding = TRUE;
        jpeg_write_coefficients(&w.cinfo, coefficients);
        jpeg_finish_compress(&w.cinfo);
        bytes = w.size;
        *writeCpu += cpuSeconds() - t0;
    }
    jpeg_finish_decompress(&r.cinfo);
    return bytes;
}

// Encodes RGB texels at `quality` (standard tables scaled, one pass; or optimised, two passes).
size_t encodeRgb(const std::vector<uint8_t>& rgb, uint32_t width, uint32_t height, int quality, bool chroma420, bool optimise) {
    Writer w;
    w.cinfo.image_width = width, w.cinfo.image_height = height, w.cinfo.input_components = 3, w.cinfo.in_color_space = JCS_RGB;
    jpeg_set_defaults(&w.cinfo);
    jpeg_set_quality(&w.cinfo, quality, TRUE);
    w.cinfo.optimize_coding = optimise ? TRUE : FALSE;
    const int h = chroma420 ? 2 : 1;
    w.cinfo.comp_info[0].h_samp_factor = w.cinfo.comp_info[0].v_samp_factor = h;
    jpeg_start_compress(&w.cinfo, TRUE);
    while (w.cinfo.next_scanline < height) {
        JSAMPROW p = const_cast<uint8_t*>(rgb.data() + size_t(w.cinfo.next_scanline) * width * 3);
        jpeg_write_scanlines(&w.cinfo, &p, 1);
    }
    jpeg_finish_compress(&w.cinfo);
    return w.size;
}

// Writes the texels to a new file under dir and reads them back (the build's temporary file).
void tempFile(const std::string& dir, const std::vector<uint8_t>& rgb) {
    const std::string path = dir + "/bench_jpeg_paths.tmp";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
    if (fd < 0) throw std::runtime_error(path + ": cannot create");
    ::unlink(path.c_str());
    constexpr size_t kChunk = size_t(1) << 20;
    for (size_t at = 0; at < rgb.size(); at += kChunk)
        if (::pwrite(fd, rgb.data() + at, std::min(kChunk, rgb.size() - at), off_t(at)) < 0) throw std::runtime_error(path + ": write failed");
    std::vector<uint8_t> back(kChunk);
    for (size_t at = 0; at < rgb.size(); at += kChunk)
        if (::pread(fd, back.data(), std::min(kChunk, rgb.size() - at), off_t(at)) < 0) throw std::runtime_error(path + ": read failed");
    ::close(fd);
}

}  // namespace

int main(int argc, char** argv) {
    hlod::cli::reexecWithHugePages(argv);  // the heap `hlod` has (HLOD_HUGE_PAGES=0: 4 KiB pages)
    int repeat = 3;
    std::string tmp = "/tmp";
    std::vector<Source> sources;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--tmp" && i + 1 < argc) tmp = argv[++i];
        else {
            std::ifstream in(a, std::ios::binary);
            if (!in) return std::fprintf(stderr, "bench_jpeg_paths: %s: cannot read\n", a.c_str()), 1;
            Source s{a, {std::istreambuf_iterator<char>(in), {}}};
            Reader r(s);
            s.width = r.cinfo.image_width, s.height = r.cinfo.image_height;
            s.chroma420 = r.cinfo.num_components == 3 && r.cinfo.comp_info[0].h_samp_factor == 2 && r.cinfo.comp_info[0].v_samp_factor == 2;
            sources.push_back(std::move(s));
        }
    }
    if (sources.empty()) return std::fprintf(stderr, "usage: bench_jpeg_paths [--repeat N] [--tmp DIR] A.jpg [B.jpg ...]\n"), 2;
    uint64_t texels = 0, jpegBytes = 0;
    for (const Source& s : sources) texels += uint64_t(s.width) * s.height, jpegBytes += s.bytes.size();
    std::printf("%zu files, %.1f Mtexel, %.1f MB of JPEG, %s; best of %d, CPU time\n", sources.size(), texels / 1e6, jpegBytes / 1e6,
                sources[0].chroma420 ? "4:2:0" : "4:4:4 or grey", repeat);
    const auto best = [&](const char* what, const std::function<void()>& run) {
        double t = 1e300;
        for (int k = 0; k < repeat; ++k) {
            const double t0 = cpuSeconds();
            run();
            t = std::min(t, cpuSeconds() - t0);
        }
        std::printf("  %-58s %7.3f s  %7.1f M source texel/s\n", what, t, texels / 1e6 / t);
        return t;
    };
    best("decode to RGB (the build's path; fancy upsampling)", [&] {
        for (const Source& s : sources) decodeRgb(s, 8, nullptr);
    });
    best("decode Y, Cb, Cr planes as stored (raw_data_out)", [&] {
        for (const Source& s : sources) decodeRaw(s);
    });
    uint64_t nonzero = 0;
    best("entropy decoding only (jpeg_read_coefficients)", [&] {
        nonzero = 0;
        for (const Source& s : sources) readCoefficients(s, false, nullptr, &nonzero);
    });
    for (const int num : {6, 4, 2}) {
        const std::string what = "decode to RGB at " + std::to_string(num) + "/8 per side (scaled inverse DCT)";
        best(what.c_str(), [&] {
            for (const Source& s : sources) decodeRgb(s, num, nullptr);
        });
    }
    double writeCpu = 0;
    size_t transcoded = 0;
    best("coefficients coded again, optimised tables (jpegtran)", [&] {
        writeCpu = 0, transcoded = 0;
        for (const Source& s : sources) transcoded += readCoefficients(s, true, &writeCpu, nullptr);
    });
    std::printf("    of which the coding: %.3f s (%.1f M source texel/s), %.1f MB\n", writeCpu, texels / 1e6 / writeCpu, transcoded / 1e6);
    std::vector<std::vector<uint8_t>> rgb(sources.size());
    for (size_t i = 0; i < sources.size(); ++i) decodeRgb(sources[i], 8, &rgb[i]);
    for (const bool optimise : {false, true}) {
        size_t bytes = 0;
        const std::string what = std::string("RGB encoded at q90, ") + (sources[0].chroma420 ? "4:2:0" : "4:4:4") +
                                 (optimise ? ", optimised tables" : ", standard tables");
        best(what.c_str(), [&] {
            bytes = 0;
            for (size_t i = 0; i < sources.size(); ++i) bytes += encodeRgb(rgb[i], sources[i].width, sources[i].height, 90, sources[i].chroma420, optimise);
        });
        std::printf("    %.1f MB\n", bytes / 1e6);
    }
    best("RGB written to a temporary file and read back", [&] {
        for (const auto& r : rgb) tempFile(tmp, r);
    });
    std::printf("  non-zero quantised coefficients: %.3f per source texel (%.1f M)\n", double(nonzero) / texels, nonzero / 1e6);
    return 0;
}
