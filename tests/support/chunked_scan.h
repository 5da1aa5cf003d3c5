// Test fixture: a scan with the structure of real photogrammetry deliveries (issue #16: ~1,000
// chunks, one material and one atlas per chunk): a mesh cut into chunks by a grid of cells over
// its bounds (by triangle centroid), written as one OBJ in which every chunk has its own copy of
// its vertices (border vertices duplicated, `jitter` apart), its own material and its
// own texture file chunk_NNN.png (or .jpg). Within a chunk the UVs are charts: the chunk's triangles are
// grouped by a finer grid (chartCells per chunk-cell side), each chart with its own vertices
// again, projected onto the chunk's two longest axes into its own tile of the atlas; 1 = one
// chart per chunk, larger = fragmented photogrammetry UVs. Texels are a smooth colour function of
// the chunk and the texel, so any texel read is plausible. Also a generated facade: a wavy wall
// with window recesses (no input file needed).
#pragma once

#include "formats/codec.h"

#include <cstdint>
#include <string>

namespace hlod {

struct ChunkedScanOptions {
    uint32_t chunks = 50;        // about this many non-empty chunks
    uint32_t chartCells = 1;     // charts per chunk: up to chartCells^3 (grid cells inside a chunk)
    uint32_t textureSize = 64;   // texels per side of every chunk's atlas
    // Each chunk's copy of a border vertex moves by up to jitter x the mesh's extent per axis (chunks
    // exported apart round apart: the copies of a border vertex are near, not bit-identical).
    double jitter = 1e-6;
    // The atlases' format: PNG (lossless, the default) or, for inputs like real photogrammetry
    // deliveries (issue #14: 41-80 x 4K JPEG atlases), chunk_NNN.jpg at jpegQuality.
    bool jpeg = false;
    int jpegQuality = 90;
    bool jpegChroma420 = false;  // the JPEG atlases' chroma: 4:2:0 (most cameras') or 4:4:4
};

struct ChunkedScan {
    std::string obj;            // the OBJ written (MTL and PNGs beside it)
    uint32_t chunks = 0;        // non-empty chunks = materials = texture files
    uint32_t charts = 0;
    uint64_t triangles = 0;
    uint64_t duplicatedVertices = 0;  // vertices written more than once (chunk and chart borders)
};

// Writes `name`.obj, `name`.mtl and the textures into `dir`; throws std::runtime_error.
ChunkedScan writeChunkedScan(const std::string& dir, const std::string& name, const MeshData& mesh,
                             const ChunkedScanOptions& options);

// A facade: a wall of width x height metres in x/z, gently curved in y, with a grid of window
// recesses (0.3 m deep); about 2 * n * n * height / width triangles, a closed sheet (no holes).
MeshData facadeMesh(uint32_t n, float width = 40, float height = 20);

}  // namespace hlod
