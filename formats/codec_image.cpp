// Texture blobs: JPEG (default) or PNG (FORMAT.md §Texture blobs). JPEG is written by libjpeg
// (libjpeg-turbo) in memory: baseline sequential, with Huffman tables optimised for the image
// (optimize_coding: the same coefficients, so the same decoded texels, in ~7 % fewer bytes than
// the standard tables OpenImageIO's writer uses; pipeline/TEXTURE_SIZE.md). PNG is written, and
// both are decoded, by OpenImageIO through IOProxy objects. Dimensions are checked before pixels
// are allocated.
#include "formats/codec.h"
#include "formats/layout.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>

#include <jpeglib.h>

namespace hlod {

namespace {

const char* memoryName(Codec codec) { return codec == Codec::Png ? "texture.png" : "texture.jpg"; }

struct JpegError {
    jpeg_error_mgr manager;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

// JPEG at `quality`, chroma at full resolution (4:4:4) or halved per axis (4:2:0).
std::vector<uint8_t> encodeJpeg(const Image& image, int quality, bool chroma420) {
    jpeg_compress_struct cinfo{};
    JpegError error{};
    cinfo.err = jpeg_std_error(&error.manager);
    error.manager.error_exit = [](j_common_ptr c) {
        JpegError* e = reinterpret_cast<JpegError*>(c->err);
        e->manager.format_message(c, e->message);
        std::longjmp(e->jump, 1);
    };
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    if (setjmp(error.jump)) {
        jpeg_destroy_compress(&cinfo);
        std::free(buffer);
        throw std::runtime_error(std::string("encodeTexture: ") + error.message);
    }
    jpeg_create_compress(&cinfo);
    jpeg_mem_dest(&cinfo, &buffer, &size);
    cinfo.image_width = image.width;
    cinfo.image_height = image.height;
    cinfo.input_components = static_cast<int>(image.channels);
    cinfo.in_color_space = image.channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, quality, TRUE);
    cinfo.optimize_coding = TRUE;
    if (image.channels == 3) {
        // 4:4:4 (default): 8 x 8 chroma blocks, which node atlases align their charts to
        cinfo.comp_info[0].h_samp_factor = cinfo.comp_info[0].v_samp_factor = chroma420 ? 2 : 1;
        for (int c = 1; c < 3; ++c) cinfo.comp_info[c].h_samp_factor = cinfo.comp_info[c].v_samp_factor = 1;
    }
    jpeg_start_compress(&cinfo, TRUE);
    const size_t rowBytes = size_t(image.width) * image.channels;
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW row = const_cast<JSAMPROW>(image.pixels.data() + cinfo.next_scanline * rowBytes);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    std::vector<uint8_t> bytes(buffer, buffer + size);
    jpeg_destroy_compress(&cinfo);
    std::free(buffer);
    return bytes;
}

}  // namespace

EncodedBlob encodeTexture(const Image& image, Codec codec, int jpegQuality, bool chroma420) {
    if (codec != Codec::Jpeg && codec != Codec::Png) throw std::runtime_error("encodeTexture: not an image codec");
    bool channelsOk = codec == Codec::Jpeg ? (image.channels == 1 || image.channels == 3)
                                           : (image.channels >= 1 && image.channels <= 4);
    if (!channelsOk || image.width == 0 || image.height == 0 || image.width > layout::kMaxTextureSide ||
        image.height > layout::kMaxTextureSide ||
        image.pixels.size() != size_t(image.width) * image.height * image.channels)
        throw std::runtime_error("encodeTexture: bad image dimensions, channels or pixel count");

    EncodedBlob blob;
    if (codec == Codec::Jpeg) {
        blob.bytes = encodeJpeg(image, jpegQuality, chroma420);
    } else {
        OIIO::Filesystem::IOVecOutput proxy(blob.bytes);
        auto out = OIIO::ImageOutput::create(memoryName(codec));
        if (!out) throw std::runtime_error("encodeTexture: " + OIIO::geterror());
        OIIO::ImageSpec spec(int(image.width), int(image.height), int(image.channels), OIIO::TypeDesc::UINT8);
        spec.attribute("oiio:UnassociatedAlpha", 1);  // store alpha as given, never premultiplied
        bool ok = out->set_ioproxy(&proxy) && out->open(memoryName(codec), spec) &&
                  out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data()) && out->close();
        if (!ok) throw std::runtime_error("encodeTexture: " + out->geterror());
    }

    BlobRef& r = blob.info;
    r.kind = BlobKind::Texture;
    r.codec = codec;
    r.width = image.width;
    r.height = image.height;
    r.channels = uint8_t(image.channels);
    return blob;
}

Image decodeTexture(std::span<const uint8_t> bytes, Codec codec, const std::string& name) {
    if (codec != Codec::Jpeg && codec != Codec::Png) throw FormatError(name + ": not an image codec");
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    // OIIO probes every other format plugin when the bytes do not look like the named
    // format; checking the signature first keeps decoding to the one codec the record names.
    static constexpr uint8_t kJpegMagic[] = {0xFF, 0xD8, 0xFF};
    static constexpr uint8_t kPngMagic[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::span<const uint8_t> magic = codec == Codec::Png ? std::span<const uint8_t>(kPngMagic) : kJpegMagic;
    if (bytes.size() < magic.size() || !std::equal(magic.begin(), magic.end(), bytes.begin()))
        throw FormatError(name + ": bad " + (codec == Codec::Png ? "PNG" : "JPEG") + " texture: wrong signature");
    auto in = OIIO::ImageInput::create(memoryName(codec), false, nullptr, &proxy);
    OIIO::ImageSpec spec, config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (!in || !in->set_ioproxy(&proxy) || !in->open(memoryName(codec), spec, config)) {
        std::string why = in ? in->geterror() : OIIO::geterror();
        throw FormatError(name + ": bad " + (codec == Codec::Png ? "PNG" : "JPEG") + " texture: " +
                          why.substr(0, why.find('\n')));
    }
    if (spec.width <= 0 || spec.height <= 0 || spec.width > int(layout::kMaxTextureSide) ||
        spec.height > int(layout::kMaxTextureSide) || spec.nchannels < 1 || spec.nchannels > 4 || spec.depth != 1)
        throw FormatError(name + ": texture has absurd dimensions " + std::to_string(spec.width) + "x" +
                          std::to_string(spec.height) + "x" + std::to_string(spec.nchannels));
    if (uint64_t(spec.width) * uint64_t(spec.height) > layout::kMaxTexelsPerBlobByte * bytes.size() + layout::kFreeTexels)
        throw FormatError(name + ": texture claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          " texels in " + std::to_string(bytes.size()) + " bytes (more than the codec can compress)");
    Image image;
    image.width = uint32_t(spec.width);
    image.height = uint32_t(spec.height);
    image.channels = uint32_t(spec.nchannels);
    image.pixels.resize(size_t(image.width) * image.height * image.channels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, image.pixels.data())) {
        std::string why = in->geterror();
        throw FormatError(name + ": bad texture data: " + why.substr(0, why.find('\n')));
    }
    in->close();
    return image;
}

}  // namespace hlod
