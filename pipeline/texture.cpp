// Node textures (thesis §3.2: "the original texture data is down-sampled by this
// simplification factor as well"). Crop per material: a node's texture for one material is the
// bounding rectangle of the source texels its triangles use, plus one texel of margin so
// bilinear filtering at chart borders reads source texels (no bleeding from other content),
// downsampled so its texel count drops by the node's factor (sqrt(factor) per side) with
// OpenImageIO's box filter (an exact average of the covered texels, 8-25x faster than the
// default lanczos3 here). UVs are mapped affinely onto the crop, which keeps them exact.
#include "pipeline/pipeline.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

namespace hlod {

Image loadTexture(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw InputError(path + ": cannot read texture (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.width > 65536 || spec.height > 65536 || spec.nchannels <= 0)
        throw InputError(path + ": texture has absurd size " + std::to_string(spec.width) + "x" + std::to_string(spec.height));
    Image image;
    image.width = static_cast<uint32_t>(spec.width);
    image.height = static_cast<uint32_t>(spec.height);
    image.channels = spec.nchannels >= 3 ? 3 : 1;
    image.pixels.resize(static_cast<size_t>(image.width) * image.height * image.channels);
    if (!input->read_image(0, 0, 0, static_cast<int>(image.channels), OIIO::TypeDesc::UINT8, image.pixels.data()))
        throw InputError(path + ": corrupt texture (" + input->geterror() + ")");
    return image;
}

Image cropTexture(const Image& source, MeshData& mesh, double factor) {
    float lo[2] = {1, 1}, hi[2] = {0, 0};
    for (size_t i = 0; i < mesh.texcoords.size(); ++i) {
        const float c = std::clamp(mesh.texcoords[i], 0.0f, 1.0f);
        lo[i % 2] = std::min(lo[i % 2], c), hi[i % 2] = std::max(hi[i % 2], c);
    }
    const double size[2] = {static_cast<double>(source.width), static_cast<double>(source.height)};
    int64_t begin[2], end[2];
    for (int a = 0; a < 2; ++a) {
        begin[a] = std::max<int64_t>(0, static_cast<int64_t>(std::floor(lo[a] * size[a])) - 1);
        end[a] = std::min<int64_t>(static_cast<int64_t>(size[a]), static_cast<int64_t>(std::ceil(hi[a] * size[a])) + 1);
        end[a] = std::max(end[a], begin[a] + 1);
    }
    const int cw = static_cast<int>(end[0] - begin[0]), ch = static_cast<int>(end[1] - begin[1]);
    const int nc = static_cast<int>(source.channels);
    OIIO::ImageBuf crop(OIIO::ImageSpec(cw, ch, nc, OIIO::TypeDesc::UINT8));
    const size_t row = static_cast<size_t>(source.width) * nc;
    crop.set_pixels(OIIO::ROI(0, cw, 0, ch, 0, 1, 0, nc), OIIO::TypeDesc::UINT8,
                    source.pixels.data() + static_cast<size_t>(begin[1]) * row + static_cast<size_t>(begin[0]) * nc,
                    nc, static_cast<OIIO::stride_t>(row));
    const double scale = factor > 1 ? 1 / std::sqrt(factor) : 1;
    const int ow = std::max(1, static_cast<int>(std::lround(cw * scale)));
    const int oh = std::max(1, static_cast<int>(std::lround(ch * scale)));
    OIIO::ImageBuf out = ow == cw && oh == ch ? crop
                                               : OIIO::ImageBufAlgo::resize(crop, "box", 0, OIIO::ROI(0, ow, 0, oh, 0, 1, 0, nc), 1);
    Image image{static_cast<uint32_t>(ow), static_cast<uint32_t>(oh), static_cast<uint32_t>(nc), {}};
    image.pixels.resize(static_cast<size_t>(ow) * oh * nc);
    out.get_pixels(OIIO::ROI(0, ow, 0, oh, 0, 1, 0, nc), OIIO::TypeDesc::UINT8, image.pixels.data());
    for (size_t i = 0; i < mesh.texcoords.size(); i += 2) {
        mesh.texcoords[i] = static_cast<float>((mesh.texcoords[i] * size[0] - begin[0]) / cw);
        mesh.texcoords[i + 1] = static_cast<float>((mesh.texcoords[i + 1] * size[1] - begin[1]) / ch);
    }
    return image;
}

}  // namespace hlod
