// Texture blobs: JPEG (default) or PNG (FORMAT.md §Texture blobs), through libjpeg-turbo and
// libpng (formats/image_io.h). JPEG is baseline sequential, with Huffman tables fitted to the
// image (formats/jpeg_tables.h: the same coefficients, so the same decoded texels, in ~7 % fewer
// bytes than the standard tables OpenImageIO's writer used; pipeline/TEXTURE_SIZE.md). Dimensions
// are checked before pixels are allocated.
#include "formats/codec.h"
#include "formats/image_io.h"
#include "formats/layout.h"

#include <algorithm>

namespace hlod {

EncodedBlob encodeTexture(const Image& image, Codec codec, int jpegQuality, bool chroma420) {
    if (codec != Codec::Jpeg && codec != Codec::Png) throw std::runtime_error("encodeTexture: not an image codec");
    bool channelsOk = codec == Codec::Jpeg ? (image.channels == 1 || image.channels == 3)
                                           : (image.channels >= 1 && image.channels <= 4);
    if (!channelsOk || image.width == 0 || image.height == 0 || image.width > layout::kMaxTextureSide ||
        image.height > layout::kMaxTextureSide ||
        image.pixels.size() != size_t(image.width) * image.height * image.channels)
        throw std::runtime_error("encodeTexture: bad image dimensions, channels or pixel count");

    EncodedBlob blob;
    blob.bytes = codec == Codec::Jpeg ? encodeJpeg(image, jpegQuality, chroma420, true, false) : encodePng(image);
    BlobRef& r = blob.info;
    r.kind = BlobKind::Texture;
    r.codec = codec;
    r.width = image.width;
    r.height = image.height;
    r.channels = uint8_t(image.channels);
    return blob;
}

namespace {

// The header of a texture blob, checked: the record's codec, sane dimensions, no more texels than
// the bytes can hold.
std::unique_ptr<ImageRows> openTexture(std::span<const uint8_t> bytes, Codec codec, const std::string& name) {
    if (codec != Codec::Jpeg && codec != Codec::Png) throw FormatError(name + ": not an image codec");
    // Checking the signature first keeps decoding to the one codec the record names.
    const std::string format = codec == Codec::Png ? "PNG" : "JPEG";
    if (!(codec == Codec::Png ? hasPngSignature(bytes) : hasJpegSignature(bytes)))
        throw FormatError(name + ": bad " + format + " texture: wrong signature");
    std::unique_ptr<ImageRows> in;
    try {
        in = codec == Codec::Png ? openPng({nullptr, bytes}, false) : openJpeg({nullptr, bytes});
    } catch (const ImageError& e) {
        throw FormatError(name + ": bad " + format + " texture: " + firstLine(e.what()));
    }
    if (in->width == 0 || in->height == 0 || in->width > layout::kMaxTextureSide || in->height > layout::kMaxTextureSide ||
        in->channels < 1 || in->channels > 4)
        throw FormatError(name + ": texture has absurd dimensions " + std::to_string(in->width) + "x" +
                          std::to_string(in->height) + "x" + std::to_string(in->channels));
    if (uint64_t(in->width) * in->height > layout::kMaxTexelsPerBlobByte * bytes.size() + layout::kFreeTexels)
        throw FormatError(name + ": texture claims " + std::to_string(in->width) + "x" + std::to_string(in->height) +
                          " texels in " + std::to_string(bytes.size()) + " bytes (more than the codec can compress)");
    return in;
}

}  // namespace

Image decodeTexture(std::span<const uint8_t> bytes, Codec codec, const std::string& name) {
    const std::unique_ptr<ImageRows> in = openTexture(bytes, codec, name);
    Image image;
    image.width = in->width;
    image.height = in->height;
    image.channels = in->channels;
    image.pixels.resize(size_t(image.width) * image.height * image.channels);
    try {
        in->read(image.height, image.channels, image.pixels.data());
    } catch (const ImageError& e) {
        throw FormatError(name + ": bad texture data: " + firstLine(e.what()));
    }
    return image;
}

}  // namespace hlod
