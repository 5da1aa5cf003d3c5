// Texture files without OpenImageIO in the hlod process (formats/image_io.h, issue #14): JPEG and
// PNG decode to the texels OpenImageIO gave (its reader, linked into this test, is the reference),
// the city generator's JPEG is OpenImageIO's byte for byte, other formats go through the
// OpenImageIO plugin, and a missing plugin is a one-line error naming the texture file.
#include "helpers.h"

#include "formats/image_io.h"
#include "formats/jpeg_tables.h"
#include "pipeline/texture_store.h"
#include "tests/support/run_hlod.h"

#include <jpeglib.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <png.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace hlod::test {
namespace {

// The built plugin, for this test process (the hlod executable finds it beside itself).
class PluginEnvironment {
public:
    explicit PluginEnvironment(const std::string& path) { setenv("HLOD_OIIO_PLUGIN", path.c_str(), 1); }
    ~PluginEnvironment() { unsetenv("HLOD_OIIO_PLUGIN"); }
};

// File names without GCC 12's false -Wrestrict on "literal" + std::string.
std::string joined(std::initializer_list<std::string> parts) {
    std::string out;
    for (const std::string& part : parts) out += part;
    return out;
}

// A texture file as the build read it before issue #14: OpenImageIO's defaults, 1 or 3 channels.
Image readWithOpenImageIO(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    Image image{uint32_t(spec.width), uint32_t(spec.height), spec.nchannels >= 3 ? 3u : 1u, {}};
    image.pixels.resize(size_t(image.width) * image.height * image.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, int(image.channels), OIIO::TypeDesc::UINT8, image.pixels.data())) << in->geterror();
    return image;
}

void writeWithOpenImageIO(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(spec.format, pixels) && out->close()) << path;
}

// Texels with detail in every channel (edges, gradients, noise), so subsampling and DCT differ.
std::vector<uint8_t> busyTexels(uint32_t w, uint32_t h, uint32_t channels) {
    std::vector<uint8_t> p(size_t(w) * h * channels);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < channels; ++c)
                p[(size_t(y) * w + x) * channels + c] = uint8_t((x * (c + 3) + y * (7 - c) + ((x ^ y) & 8) * 13 + (x * y) % 29) & 0xFF);
    return p;
}

// A PNG written by libpng: `type` (PNG_COLOR_TYPE_*), `depth` bits, interlaced or not, with a
// transparent palette entry when it has a palette.
void writePngVariant(const std::string& path, uint32_t w, uint32_t h, int type, int depth, bool interlaced) {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_TRUE(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, depth, type, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (type == PNG_COLOR_TYPE_PALETTE) {
        std::vector<png_color> palette(size_t(1) << depth);
        for (size_t i = 0; i < palette.size(); ++i) palette[i] = {uint8_t(i * 37), uint8_t(255 - i * 11), uint8_t(i * 5)};
        png_set_PLTE(png, info, palette.data(), int(palette.size()));
        const png_byte alpha[] = {0, 128};
        png_set_tRNS(png, info, alpha, 2, nullptr);
    }
    png_write_info(png, info);
    const int samples = type == PNG_COLOR_TYPE_RGB ? 3 : type == PNG_COLOR_TYPE_RGB_ALPHA ? 4 : type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : 1;
    const size_t rowBytes = (size_t(w) * samples * depth + 7) / 8;
    std::vector<uint8_t> rows(rowBytes * h);
    for (size_t i = 0; i < rows.size(); ++i) rows[i] = uint8_t((i * 2654435761u) >> 13);
    std::vector<png_bytep> pointers(h);
    for (uint32_t y = 0; y < h; ++y) pointers[y] = &rows[rowBytes * y];
    png_write_image(png, pointers.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
}

// A CMYK JPEG (as Photoshop writes one: Adobe marker, inverted CMYK), written by libjpeg.
void writeCmykJpeg(const std::string& path, uint32_t w, uint32_t h) {
    jpeg_compress_struct cinfo{};
    jpeg_error_mgr error{};
    cinfo.err = jpeg_std_error(&error);
    jpeg_create_compress(&cinfo);
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_TRUE(f);
    jpeg_stdio_dest(&cinfo, f);
    cinfo.image_width = w, cinfo.image_height = h, cinfo.input_components = 4, cinfo.in_color_space = JCS_CMYK;
    jpeg_set_defaults(&cinfo);
    jpeg_start_compress(&cinfo, TRUE);
    const std::vector<uint8_t> texels = busyTexels(w, h, 4);
    while (cinfo.next_scanline < h) {
        JSAMPROW row = const_cast<JSAMPROW>(&texels[size_t(cinfo.next_scanline) * w * 4]);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    std::fclose(f);
}

TEST(ImageIo, JpegAndPngFilesDecodeToWhatOpenImageIOGave) {
    TempDir dir;
    const PluginEnvironment plugin(HLOD_OIIO_PLUGIN_PATH);  // PNG with alpha, CMYK JPEG
    std::vector<std::string> files;
    const uint32_t w = 77, h = 45;  // not multiples of the 16 x 16 MCU
    for (const uint32_t channels : {1u, 3u}) {
        const std::vector<uint8_t> texels = busyTexels(w, h, channels);
        for (const char* subsampling : {"4:2:0", "4:2:2", "4:4:4"}) {
            for (const int progressive : {0, 1}) {
                OIIO::ImageSpec spec(int(w), int(h), int(channels), OIIO::TypeDesc::UINT8);
                spec.attribute("Compression", "jpeg:83");
                spec.attribute("jpeg:subsampling", subsampling);
                spec.attribute("jpeg:progressive", progressive);
                files.push_back(dir.file(joined({"j", std::to_string(channels), subsampling, std::to_string(progressive), ".jpg"})));
                writeWithOpenImageIO(files.back(), spec, texels.data());
            }
        }
        for (const int16_t bits : {8, 16}) {
            OIIO::ImageSpec spec(int(w), int(h), int(channels), bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
            std::vector<uint16_t> wide(texels.size());
            for (size_t i = 0; i < wide.size(); ++i) wide[i] = uint16_t(texels[i] * 251 + i % 251);
            files.push_back(dir.file(joined({"p", std::to_string(channels), "_", std::to_string(bits), ".png"})));
            writeWithOpenImageIO(files.back(), spec, bits == 8 ? static_cast<const void*>(texels.data()) : wide.data());
        }
    }
    // Through the plugin: alpha (OpenImageIO associates colour with it), a transparent palette
    // entry, CMYK JPEG (OpenImageIO converts it to RGB).
    for (const int type : {PNG_COLOR_TYPE_RGB_ALPHA, PNG_COLOR_TYPE_GRAY_ALPHA}) {
        files.push_back(dir.file(joined({"a", std::to_string(type), ".png"})));
        writePngVariant(files.back(), w, h, type, 8, false);
    }
    files.push_back(dir.file("cmyk.jpg"));
    writeCmykJpeg(files.back(), w, h);
    files.push_back(dir.file("palette.png"));
    writePngVariant(files.back(), w, h, PNG_COLOR_TYPE_PALETTE, 4, false);
    // Here: 2-bit grey, interlaced RGB and 16-bit grey, a palette without transparency.
    files.push_back(dir.file("grey2.png"));
    writePngVariant(files.back(), w, h, PNG_COLOR_TYPE_GRAY, 2, false);
    files.push_back(dir.file("interlaced.png"));
    writePngVariant(files.back(), w, h, PNG_COLOR_TYPE_RGB, 8, true);
    files.push_back(dir.file("interlaced16.png"));
    writePngVariant(files.back(), w, h, PNG_COLOR_TYPE_GRAY, 16, true);
    // Every 16-bit value, rounded to 8 bits.
    std::vector<uint16_t> every(65536);
    for (size_t i = 0; i < every.size(); ++i) every[i] = uint16_t(i);
    files.push_back(dir.file("every16.png"));
    writeWithOpenImageIO(files.back(), OIIO::ImageSpec(256, 256, 1, OIIO::TypeDesc::UINT16), every.data());
    for (const std::string& file : files) {
        SCOPED_TRACE(file);
        const Image expected = readWithOpenImageIO(file), got = loadTexture(file);
        EXPECT_EQ(got.width, expected.width);
        EXPECT_EQ(got.height, expected.height);
        EXPECT_EQ(got.channels, expected.channels);
        EXPECT_TRUE(got.pixels == expected.pixels);
        EXPECT_EQ(textureHeader(file).texels, uint64_t(expected.width) * expected.height);
    }
}

// Node textures: a PNG with alpha decodes as stored (not associated), a JPEG as OpenImageIO's
// reader decoded it from memory.
TEST(ImageIo, NodeTexturesDecodeToWhatOpenImageIOGave) {
    for (const uint32_t channels : {1u, 2u, 3u, 4u}) {
        const Image image{61, 35, channels, busyTexels(61, 35, channels)};
        for (const Codec codec : {Codec::Png, Codec::Jpeg}) {
            if (codec == Codec::Jpeg && (channels == 2 || channels == 4)) continue;
            SCOPED_TRACE(std::to_string(channels) + (codec == Codec::Png ? " PNG" : " JPEG"));
            std::vector<uint8_t> bytes = encodeTexture(image, codec, 75).bytes;
            OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
            OIIO::ImageSpec spec, config;
            config.attribute("oiio:UnassociatedAlpha", 1);
            auto in = OIIO::ImageInput::create(codec == Codec::Png ? "t.png" : "t.jpg", false, nullptr, &proxy);
            ASSERT_TRUE(in && in->set_ioproxy(&proxy) && in->open(codec == Codec::Png ? "t.png" : "t.jpg", spec, config)) << OIIO::geterror();
            std::vector<uint8_t> expected(size_t(spec.width) * spec.height * spec.nchannels);
            ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, expected.data()));
            const Image got = decodeTexture(bytes, codec, "blob");
            EXPECT_EQ(got.channels, uint32_t(spec.nchannels));
            EXPECT_TRUE(got.pixels == expected);
            if (codec == Codec::Png) {
                EXPECT_TRUE(got.pixels == image.pixels) << "lossless";
            }
        }
    }
}

// The city generator's JPEG (pipeline/synth, samples/city) is OpenImageIO's writer's, byte for byte.
// libjpeg's exact optimisation of the Huffman tables (two passes), as encodeJpeg sets up the rest.
std::vector<uint8_t> libjpegOptimised(const Image& image, int quality, bool chroma420) {
    jpeg_compress_struct cinfo{};
    jpeg_error_mgr error{};
    cinfo.err = jpeg_std_error(&error);
    jpeg_create_compress(&cinfo);
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&cinfo, &buffer, &size);
    cinfo.image_width = image.width, cinfo.image_height = image.height;
    cinfo.input_components = int(image.channels);
    cinfo.in_color_space = image.channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, quality, TRUE);
    cinfo.optimize_coding = TRUE;
    if (image.channels == 3) {
        cinfo.comp_info[0].h_samp_factor = cinfo.comp_info[0].v_samp_factor = chroma420 ? 2 : 1;
        for (int c = 1; c < 3; ++c) cinfo.comp_info[c].h_samp_factor = cinfo.comp_info[c].v_samp_factor = 1;
    }
    jpeg_start_compress(&cinfo, TRUE);
    while (cinfo.next_scanline < image.height) {
        JSAMPROW row = const_cast<JSAMPROW>(&image.pixels[size_t(cinfo.next_scanline) * image.width * image.channels]);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    std::vector<uint8_t> bytes(buffer, buffer + size);
    std::free(buffer);
    return bytes;
}

// Node textures' Huffman tables are fitted to the image (image_jpeg.cpp, formats/jpeg_tables.cpp):
// the coefficients are the standard-table encoder's, so the two files decode to the same texels,
// for grey, 4:4:4 and 4:2:0, odd sides, small and large. A small image (at most kSampledMcus MCUs)
// is libjpeg's exact optimisation byte for byte; a larger one's tables come from 512 of its MCUs
// (2100 x 1500: 1 in ~97 at 4:4:4, 1 in ~24 at 4:2:0), so its file differs from the exact
// optimisation's, by at most 1 % more bytes; both are smaller than the standard tables' file.
TEST(ImageIo, FittedTablesKeepTheCoefficients) {
    for (const auto& [w, h] : {std::pair{17u, 9u}, std::pair{61u, 35u}, std::pair{1031u, 777u}, std::pair{2100u, 1500u}})
        for (const uint32_t channels : {1u, 3u})
            for (const bool chroma420 : {false, true}) {
                SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(channels) + (chroma420 ? " 4:2:0" : ""));
                const Image image{w, h, channels, busyTexels(w, h, channels)};
                const std::vector<uint8_t> fitted = encodeJpeg(image, 85, chroma420, true, false);
                const std::vector<uint8_t> standard = encodeJpeg(image, 85, chroma420, false, false);
                const std::vector<uint8_t> exact = libjpegOptimised(image, 85, chroma420);
                EXPECT_LT(fitted.size(), standard.size());
                EXPECT_TRUE(decodeTexture(fitted, Codec::Jpeg, "f").pixels == decodeTexture(standard, Codec::Jpeg, "s").pixels);
                if (jpegMcuCount(image, chroma420) <= kSampledMcus) {
                    EXPECT_TRUE(fitted == exact);
                } else {
                    EXPECT_FALSE(fitted == exact);  // the sampled path was taken
                    EXPECT_LE(double(fitted.size()), 1.01 * double(exact.size())) << fitted.size() << " vs " << exact.size();
                }
            }
}

TEST(ImageIo, GeneratorJpegIsOpenImageIOsByteForByte) {
    TempDir dir;
    for (const uint32_t channels : {1u, 3u}) {
        const Image image{100, 50, channels, busyTexels(100, 50, channels)};
        OIIO::ImageSpec spec(100, 50, int(channels), OIIO::TypeDesc::UINT8);
        spec.attribute("Compression", "jpeg:90");
        writeWithOpenImageIO(dir.file("oiio.jpg"), spec, image.pixels.data());
        writeJpegFile(dir.file("ours.jpg"), image, 90);
        EXPECT_TRUE(readFile(dir.file("ours.jpg")) == readFile(dir.file("oiio.jpg"))) << channels << " channels";
    }
}

// Other formats, here TGA and TIFF, go through the plugin: the same texels as OpenImageIO gave,
// through the texture store's strips too.
TEST(ImageIo, OtherFormatsGoThroughThePlugin) {
    TempDir dir;
    const PluginEnvironment plugin(HLOD_OIIO_PLUGIN_PATH);
    const std::vector<uint8_t> texels = busyTexels(90, 130, 3);
    for (const char* name : {"t.tga", "t.tif"}) {
        SCOPED_TRACE(name);
        writeWithOpenImageIO(dir.file(name), OIIO::ImageSpec(90, 130, 3, OIIO::TypeDesc::UINT8), texels.data());
        EXPECT_EQ(textureProblem(dir.file(name)), "");
        EXPECT_EQ(textureHeader(dir.file(name)).texels, 90u * 130u);
        const Image image = loadTexture(dir.file(name));
        EXPECT_TRUE(image.pixels == readWithOpenImageIO(dir.file(name)).pixels);
        EXPECT_TRUE(image.pixels == texels) << "lossless";
        TextureStore store(dir.file("store"));
        const TextureSource source = store.open(dir.file(name), nullptr);
        std::vector<uint8_t> rows(texels.size());
        source.rows(0, 130, 0, 90, rows.data());
        EXPECT_TRUE(rows == texels);
    }
}

// An interlaced PNG larger than the band is decoded in bands, the file read again for each: the
// same texels as OpenImageIO's whole decode, from a file and from memory, for bands of one row, a
// few rows and a band that does not divide the height, read in uneven batches.
TEST(ImageIo, InterlacedPngDecodesInBands) {
    TempDir dir;
    const uint32_t w = 37, h = 23;
    for (const auto& [type, depth] : {std::pair{PNG_COLOR_TYPE_RGB, 8}, std::pair{PNG_COLOR_TYPE_GRAY, 16}, std::pair{PNG_COLOR_TYPE_GRAY, 2}}) {
        const std::string file = dir.file("i" + std::to_string(type) + "_" + std::to_string(depth) + ".png");
        writePngVariant(file, w, h, type, depth, true);
        const Image expected = readWithOpenImageIO(file);
        const std::vector<uint8_t> bytes = readFile(file);
        const size_t rowBytes = size_t(w) * expected.channels * (depth == 16 ? 2 : 1);  // decoded rows
        for (const size_t band : {size_t(1), 3 * rowBytes, 5 * rowBytes + 1, 100 * rowBytes}) {
            SCOPED_TRACE(file + ", band " + std::to_string(band));
            const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.c_str(), "rb"), &std::fclose);
            ASSERT_TRUE(f);
            for (const ImageSource source : {ImageSource{f.get(), {}}, ImageSource{nullptr, bytes}}) {
                const std::unique_ptr<ImageRows> rows = openPng(source, false, band);
                std::vector<uint8_t> got(expected.pixels.size());
                for (uint32_t y = 0, batch = 1; y < h; y += batch, batch = batch % 4 + 1)
                    rows->read(std::min(batch, h - y), expected.channels, &got[size_t(y) * w * expected.channels]);
                EXPECT_TRUE(got == expected.pixels);
                EXPECT_THROW(rows->read(1, expected.channels, got.data()), ImageError) << "past the last row";
            }
        }
    }
}

// An interlaced PNG cut in half: libpng's error longjmps out of a band's decode: a one-line
// error naming the file (and, under ASan, nothing leaked on the way), whole or in bands.
TEST(ImageIo, TruncatedInterlacedPngIsAnError) {
    TempDir dir;
    writePngVariant(dir.file("whole.png"), 64, 64, PNG_COLOR_TYPE_RGB, 8, true);
    const std::vector<uint8_t> bytes = readFile(dir.file("whole.png"));
    writeFile(dir.file("half.png"), std::vector<uint8_t>(bytes.begin(), bytes.begin() + bytes.size() / 2));
    EXPECT_EQ(loadTexture(dir.file("whole.png")).width, 64u);
    try {
        loadTexture(dir.file("half.png"));
        ADD_FAILURE() << "a truncated interlaced PNG decoded";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(dir.file("half.png") + ": ", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    const std::vector<uint8_t> half(bytes.begin(), bytes.begin() + bytes.size() / 2);
    const std::unique_ptr<ImageRows> rows = openPng({nullptr, half}, false, 8 * 64 * 3);
    std::vector<uint8_t> texels(64 * 64 * 3);
    EXPECT_THROW(rows->read(64, 3, texels.data()), ImageError) << "in bands of 8 rows";
    EXPECT_THROW(rows->read(1, 3, texels.data()), ImageError) << "and every read after the error";
}

// Without the plugin a TGA texture is unusable, with a one-line reason naming the plugin path
// tried; JPEG and PNG need no plugin. `hlod build --strict` fails with it (exit 2).
TEST(ImageIo, MissingPluginIsAOneLineErrorNamingTheTexture) {
    TempDir dir;
    writeWithOpenImageIO(dir.file("t.tga"), OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::UINT8), busyTexels(16, 16, 3).data());
    writeFile(dir.file("t.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    const std::string missing = dir.file("nowhere/hlod_oiio.so");
    const PluginEnvironment plugin(missing);
    const std::string problem = textureProblem(dir.file("t.tga"));
    EXPECT_NE(problem.find("is not a readable image (its format needs the OpenImageIO plugin " + missing + ", which cannot be loaded"),
              std::string::npos)
        << problem;
    EXPECT_EQ(problem.find('\n'), std::string::npos);
    try {
        loadTexture(dir.file("t.tga"));
        ADD_FAILURE() << "decoded without the plugin";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(dir.file("t.tga") + ": cannot read texture (its format needs the OpenImageIO plugin", 0), 0u)
            << e.what();
    }
    EXPECT_EQ(textureProblem(dir.file("t.png")), "");
    EXPECT_EQ(loadTexture(dir.file("t.png")).width, 16u);

    writeObj(dir.file("m.obj"), terrain(10, 100, true), "t.tga");
    const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--strict"});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    const size_t at = r.err.find("hlod build: ");
    ASSERT_NE(at, std::string::npos) << r.err;
    const std::string line = r.err.substr(at);
    EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;
    EXPECT_NE(line.find(dir.file("t.tga")), std::string::npos) << line;
    EXPECT_NE(line.find("needs the OpenImageIO plugin " + missing), std::string::npos) << line;
}

// A progressive JPEG's decoder holds every block's coefficients (128 bytes a block: jdcoefct.c's
// arrays) until its last row, a baseline one nothing beyond its rows. A block's gate counts the
// largest of its textures'; the texture store warns of one above the memory limit, once however
// many blocks use it, and decodes it as any other (until stop 48 nothing said so).
TEST(ImageIo, AProgressiveJpegsCoefficientsCountAndAreWarnedOfAboveTheLimit) {
    TempDir dir;
    const auto write = [&](const std::string& name, uint32_t w, uint32_t h, uint32_t channels, const char* subsampling, int progressive) {
        OIIO::ImageSpec spec(int(w), int(h), int(channels), OIIO::TypeDesc::UINT8);
        spec.attribute("Compression", "jpeg:83");
        spec.attribute("jpeg:subsampling", subsampling);
        spec.attribute("jpeg:progressive", progressive);
        writeWithOpenImageIO(dir.file(name), spec, busyTexels(w, h, channels).data());
        return dir.file(name);
    };
    // 65 x 33: 9 x 5 blocks a full-size component; at 4:2:0 Y rounded up to its 2 x 2 sampling,
    // 10 x 6, and Cb and Cr 5 x 3 each.
    EXPECT_EQ(textureHeader(write("b.jpg", 65, 33, 3, "4:4:4", 0)).wholeImageBytes, 0u);
    EXPECT_EQ(textureHeader(write("p444.jpg", 65, 33, 3, "4:4:4", 1)).wholeImageBytes, 3u * 45 * 128);
    EXPECT_EQ(textureHeader(write("p420.jpg", 65, 33, 3, "4:2:0", 1)).wholeImageBytes, (60u + 2 * 15) * 128);
    EXPECT_EQ(textureHeader(write("grey.jpg", 65, 33, 1, "4:4:4", 1)).wholeImageBytes, 45u * 128);
    SourceMesh mesh;
    for (const char* name : {"b.jpg", "p444.jpg", "p420.jpg"}) {
        mesh.materials.emplace_back();
        mesh.materials.back().name = name, mesh.materials.back().texturePath = dir.file(name);
    }
    mesh.piece.materials = {0, 2, 0};
    EXPECT_EQ(usedTextures(mesh).texels, 2u * 65 * 33);
    EXPECT_EQ(usedTextures(mesh).wholeImageBytes, 90u * 128) << "the largest of the used ones";
    mesh.piece.materials.push_back(1);
    EXPECT_EQ(usedTextures(mesh).wholeImageBytes, 135u * 128);

    std::ostringstream log;
    {
        ProgressOptions quiet;
        quiet.thread = false;
        Progress progress(log, quiet);
        TextureStore store(dir.file("store"), 15000);  // between p420's 11,520 and p444's 17,280 bytes
        for (const char* name : {"b.jpg", "p420.jpg", "p444.jpg", "p444.jpg"}) {
            const TextureSource source = store.open(dir.file(name), &progress);
            std::vector<uint8_t> rows(size_t(65) * 33 * 3);
            source.rows(0, 33, 0, 65, rows.data());
            EXPECT_TRUE(rows == loadTexture(dir.file(name)).pixels) << name;
            // A file the store has opened is decoded once per build: a later block is not charged it.
            EXPECT_TRUE(store.opened(dir.file(name)));
            EXPECT_EQ(usedTextures(mesh, &store).wholeImageBytes, name == std::string("p444.jpg") ? 0u : 135u * 128) << name;
        }
    }
    EXPECT_EQ(log.str(), "warning: " + dir.file("p444.jpg") +
                             ": a progressive (multi-scan) JPEG of 65 x 33: libjpeg holds all its coefficients while decoding it "
                             "(0.0 MiB), more than --memory-limit (0.0 MiB); `jpegtran -outfile BASELINE.jpg " +
                             dir.file("p444.jpg") + "` (libjpeg-turbo-progs) writes the same texels as a baseline JPEG, decoded by strips\n");

    // The build: a 2048² progressive atlas (24 MiB of coefficients) under --memory-limit 16M, shared by
    // four blocks: one warning, and the database.
    writeObj(dir.file("m.obj"), terrain(40, 100, true), "big.jpg");
    write("big.jpg", 2048, 2048, 3, "4:4:4", 1);
    const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--memory-limit", "16M", "--block-triangles", "800"});
    EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
    const std::string all = r.outAndErr(), warning = dir.file("big.jpg") + ": a progressive (multi-scan) JPEG of 2048 x 2048";
    EXPECT_NE(all.find(warning + ": libjpeg holds all its coefficients while decoding it (24.0 MiB), more than --memory-limit (16.0 MiB)"),
              std::string::npos)
        << all;
    EXPECT_EQ(all.find(warning), all.rfind(warning)) << "once";
    EXPECT_TRUE(std::filesystem::exists(dir.file("m.hlod")));
}

}  // namespace
}  // namespace hlod::test
