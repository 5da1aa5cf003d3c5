// Textures read by rectangles (issue #14, pipeline/MEMORY.md): a build-wide store decodes each
// texture file once, by strips of scanlines, into a temporary file; a node reads only the
// bands of blocks its triangles reach, downsampled by a box filter, so no whole atlas is held.
#pragma once

#include "pipeline/pipeline.h"

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

namespace hlod {

class ImageRows;  // formats/image_io.h

// texture.cpp: a texture file opened for decoding (InputError "PATH: cannot read texture (...)"
// or "PATH: texture has absurd size ..."), and its next `rows` rows, `channels` (1 or 3) of each
// texel (InputError "PATH: corrupt texture (...)").
std::unique_ptr<ImageRows> openTexture(const std::string& path);
void readTextureRows(ImageRows& image, const std::string& path, uint32_t rows, uint32_t channels, uint8_t* out);
// A texture file's texels and the bytes its decoder holds for the whole image (ImageRows::
// wholeImageBytes), from its header alone; zeros when it cannot be read.
struct TextureHeader {
    uint64_t texels = 0, wholeImageBytes = 0;
};
TextureHeader textureHeader(const std::string& path);
// The source texels of the materials a block's triangles use, and the most bytes one of their
// texture files' decoders holds at once (image headers only), of the files `store` (if any) has not
// opened yet: a file is decoded once per build.
class TextureStore;
TextureHeader usedTextures(const SourceMesh& mesh, const TextureStore* store = nullptr);

// texture_store.cpp: a texture read by rectangles, with its mip pyramid: level 0 the source,
// level k + 1 the box-filtered halving of level k (mipSide per side), down to 1 x 1.
struct TextureLevel {
    uint32_t width = 0, height = 0;
    const uint8_t* pixels = nullptr;  // in memory, or
    uint64_t offset = 0;              // the level's first byte in the source's file (width x height x channels, in tiles: texture_store.cpp)
};
struct TextureSource {
    uint32_t width = 0, height = 0, channels = 0;  // level 0's
    int file = -1;                                 // the levels' file, or -1: in memory
    int jpegQuality = 0;  // the quality a JPEG source was written with (jpegQuality); 0: unknown
    std::vector<TextureLevel> levels;
    bool chroma420 = false;  // a JPEG source with 4:2:0 chroma (jpegChroma420)
    // [x0, x1) of rows [y0, y1) of a level, row by row (pread from the file: safe from any thread)
    void rows(uint32_t y0, uint32_t y1, uint32_t x0, uint32_t x1, uint8_t* out, size_t level = 0) const;
};
uint32_t mipSide(uint32_t side);  // a side of the next pyramid level: (side + 1) / 2
// Levels 1.. of an image's pyramid, in memory; a view of the image with them (`mips` outlives it).
std::vector<Image> mipLevels(const Image& image);
TextureSource textureView(const Image& image, const std::vector<Image>& mips = {});
// jpeg_quality.cpp: the libjpeg quality whose scaled standard luminance table is the JPEG's own
// (the file's, or the encoded bytes'); 0 when it is not a JPEG or its table is not such a one.
int jpegQuality(std::span<const uint8_t> bytes);
bool jpegChroma420(std::span<const uint8_t> bytes);  // a JPEG whose chroma is 4:2:0 (Y 2 x 2, Cb and Cr 1 x 1)
std::vector<uint8_t> jpegFileHead(const std::string& path);  // a file's first MiB: its JPEG header if any
uint32_t scaledSide(uint32_t side, double factor);  // a side downsampled by factor (sqrt per side; factor <= 1: as is)
// Texels [x0, x1) x [y0, y1) of the source downsampled to scaledWidth x scaledHeight: a box
// filter (each texel the area-weighted mean of the texels it covers) from the coarsest pyramid
// level at least that size on both sides (equal sizes: a copy of the level). Each texel is a
// function of the level alone, whatever the rectangle.
Image scaledRegion(const TextureSource& source, uint32_t scaledWidth, uint32_t scaledHeight, uint32_t x0, uint32_t y0, uint32_t x1,
                   uint32_t y1);
Image downsampleTexture(const Image& source, double factor);  // the whole image by scaledRegion, over its mipLevels
// The texture files of a build, each decoded once (by strips of scanlines) with its pyramid into a
// file under `dir` and read back by rectangles; dir "" keeps them decoded in memory. Thread-safe:
// open() decodes a file once whoever asks (the others wait for it), and a TextureSource is a
// read-only description of the file (pread) or of images the store keeps until it is destroyed.
// A file whose decoder holds more than `memoryLimit` bytes at once (a progressive JPEG's
// coefficients; 0: no limit) is decoded with a warning through open()'s Progress.
class TextureStore {
public:
    explicit TextureStore(const std::string& dir = "", uint64_t memoryLimit = 0);
    ~TextureStore();
    TextureStore(const TextureStore&) = delete;
    TextureStore& operator=(const TextureStore&) = delete;
    // Decodes `path` on its first call; throws InputError (corrupt, truncated) on every call.
    TextureSource open(const std::string& path, Progress* progress);
    bool opened(const std::string& path) const;  // open() was called for `path` (its decode begun or done)

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
// The blocks (`block` texels a side: JPEG's 8, or a 4:2:0 MCU's 16, whose colour samples then
// cover no two groups) of `source` downsampled by factor that `mesh`'s triangles (one material's)
// reach, packed on the scaled source's own block grid; UVs rewritten (texture.cpp). Another
// block size throws std::invalid_argument.
Image atlasTexture(const TextureSource& source, double factor, MeshData& mesh, int block = 8);
// The textures of one block's materials: a texture file through `store` (nullptr: a store of
// the block's own, in memory), an embedded image as it is. A texture that fails to decode is a
// TextureProblem and its material untextured in this block, or, with `strict`, fatal. Thread-safe
// (the nodes of a block are built in parallel).
class BlockTextures {
public:
    BlockTextures(const std::vector<Material>& materials, TextureStore* store, bool strict, std::vector<TextureProblem>& problems,
                  Progress* progress);
    const TextureSource* source(uint32_t material);  // nullptr: untextured
    // The JPEG quality of the material's node textures: `quality` (--jpeg-quality), or the source's
    // own when it is a JPEG of a lower or equal quality: a leaf's blocks are the source's own
    // blocks, which re-code at the source's quality almost losslessly (pipeline/TEXTURE_SIZE.md).
    int jpegQuality(uint32_t material, int quality);
    // Whether the material's node textures are 4:2:0: `chroma` (--jpeg-chroma), or with
    // JpegChroma::Source its source's own (a 4:2:0 JPEG; 4:4:4 chroma would store more colour
    // samples than the source has). Never for a grey or untextured material: no chroma.
    bool chroma420(uint32_t material, JpegChroma chroma);
    // atlasTexture, of 16 x 16 blocks for a 4:2:0 texture; width 0: untextured.
    Image atlas(uint32_t material, double factor, MeshData& mesh, bool chroma420);
    // The rectangle of the material's texture downsampled by `factor` that `mesh`'s UVs cover
    // (+1 texel margin), mesh's UVs rewritten onto it (what bakeTexture samples); width 0 when untextured.
    Image region(uint32_t material, double factor, MeshData& mesh);

private:
    const std::vector<Material>& materials_;
    std::unique_ptr<TextureStore> own_;
    TextureStore* store_;
    bool strict_;
    std::vector<TextureProblem>& problems_;
    Progress* progress_;
    std::mutex mutex_;  // guards sources_, mips_ and problems_
    std::map<uint32_t, std::optional<TextureSource>> sources_;
    std::map<uint32_t, std::vector<Image>> mips_;  // embedded images' pyramids, filled with sources_
};

}  // namespace hlod
