// `hlod build`: raw scan -> HLOD database (thesis §3.2 HLOD generation, §3.3 node attributes).
// Plain structs and one free function per stage, one stage per .cpp:
//   read_ply / read_obj / read_gltf  -> SourceMesh            (input.cpp checks every input)
//   split_blocks                     -> per-block temporary files (grid over the horizontal axes)
//   build_tree (§3.2 recursion)      -> cut.cpp (Fig. 3.2), simplify.cpp, texture.cpp, error.cpp
//   pack                             -> Draco/JPEG blobs in a per-block record file
//   merge                            -> the database, block records written in block order
#pragma once

#include "formats/build_report.h"
#include "formats/codec.h"
#include "formats/constants.h"
#include "formats/db.h"
#include "pipeline/input_files.h"
#include "pipeline/progress.h"
#include "pipeline/spill_array.h"
#include "pipeline/tree_rules.h"

#include <array>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace hlod {

struct Material {
    std::string name;
    std::string texturePath;             // texture file, empty = none
    std::shared_ptr<const Image> image;  // an embedded texture (glTF), used instead of a file
    int jpegQuality = 0;                 // an embedded JPEG's own quality (jpegQuality, texture_store.h); 0: unknown
    bool jpegChroma420 = false;          // an embedded JPEG with 4:2:0 chroma (jpegChroma420, texture_store.h)
    float uvPeriod[2] = {1, 1};          // per axis, UVs repeat every: REPEAT 1, MIRRORED_REPEAT 2, clamped 0 (wrap_uvs.cpp)
    // Its triangles' texture coordinates become uv × uvScale + uvOffset as their corners are read
    // (rawCorners): an OBJ's `map_Kd -s`/`-o`, in this struct's v-down convention (read_obj.cpp).
    float uvScale[2] = {1, 1}, uvOffset[2] = {0, 0};
    bool movesUvs() const { return uvScale[0] != 1 || uvScale[1] != 1 || uvOffset[0] != 0 || uvOffset[1] != 0; }
};

// Triangles with welded vertices and one material index per triangle. Texture coordinates use
// the glTF convention (v = 0 is the first image row); readers of OBJ/PLY flip v.
struct Piece {
    MeshData mesh;
    std::vector<uint32_t> materials;  // per triangle, index into the block's material list
};

// A texture that cannot be used (README "Textures: one rule"): missing, empty, not an image, of an
// absurd size, or corrupt. By default its material is left untextured and the build goes on,
// counting it in the summary and the build report; `hlod build --strict` makes it fatal (exit 2).
struct TextureProblem {
    std::string what;      // one line naming the file: "INPUT: texture 'PATH' is empty (0 bytes)"
    std::string material;  // the material left untextured
    bool operator<(const TextureProblem& o) const { return std::tie(what, material) < std::tie(o.what, o.material); }
};

struct ReadStats {
    uint64_t degenerateDropped = 0;  // triangles with repeated vertices or zero area
    std::vector<std::string> warnings;
    std::vector<TextureProblem> textureProblems;
};

struct SourceMesh {
    Piece piece;
    std::vector<Material> materials;
    ReadStats stats;
};

// raw_mesh.cpp: a PLY, OBJ or glTF mesh as parsed, before welding. The arrays live in memory (a block
// file; a single input while they fit a budget) or spill to disk (a single large input is never
// held whole), from where split_stream.cpp routes the triangles to per-block files in one pass.
// Adding an attribute checks it is finite (InputError naming the vertex).
struct RawTriangle {
    uint32_t position[3], texcoord[3], normal[3];  // indices into the arrays (PLY: all = position, texcoord its own with per-face UVs;
                                                    // texcoord kNone: an OBJ face without `vt`, read as (0, 0))
    uint32_t material;                              // into materials; kNone = the default material
};
struct RawMesh {
    SpillArray<float> positions, texcoords, normals;  // 3, 2, 3 floats per element
    SpillArray<uint8_t> colors;                       // 4 per position, or none
    SpillArray<RawTriangle> triangles;
    bool hasTexcoords = false, hasNormals = false;    // every triangle has them (OBJ: texcoords when any face has them)
    bool sharedIndices = false;                       // texcoord/normal indices equal position's (PLY without per-face UVs)
    bool texcoordsPerCorner = false;                  // one texcoord per corner, welded by value (PLY with per-face UVs)
    Box3f bounds{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    std::vector<Material> materials;
    ReadStats stats;
    Progress* progress = nullptr;  // advanced by the bytes read
    uint64_t spillBudget = UINT64_MAX;  // spillBeyond
    std::string spillDir;
    std::array<double, 3> offset{};  // subtracted from every position before it becomes a float

    void spillTo(const std::string& dir);  // keep the arrays in files under dir (before parsing, or midway)
    // Keep the arrays in memory while they touch at most `budget` bytes (capacity ≤ budget/2), then in files under dir.
    void spillBeyond(uint64_t budget, const std::string& dir) { spillBudget = budget, spillDir = dir; }
    // p minus `offset`, computed in double, then stored as floats (ReadOptions::offset).
    void addPosition(const double p[3], const std::string& name);
    void addTriangle(const RawTriangle& t);
    void addTexcoord(float u, float v, const std::string& name);
    void addNormal(const float n[3], const std::string& name);
    void seal();  // parsing done
    size_t positionCount() const { return positions.size() / 3; }
};
// What readers may open besides the input itself (README "Reliability"): every file an input refers
// to stays inside the input's folder unless allowOutsideInput (--allow-outside-input) is set.
struct ReadOptions {
    bool allowOutsideInput = false;
    // glTF: embedded PNG/JPEG images are checked and written here, still encoded, and become the
    // materials' texture paths (a GLB's are taken out of its BIN chunk first); empty: decoded into
    // Material::image. `hlod build` sets it to a folder in its temporary folder.
    std::string imageDir;
    // Subtracted from every input position in double precision before it is stored as a float
    // (`hlod build --offset`): a model far from the origin keeps its detail (README "Far from the
    // origin"); the database records it as META `offset`.
    std::array<double, 3> offset{};
    // The files the run writes (runBuild sets them: the database and its build report): a reference
    // that resolves to one is refused, so a build never replaces its own texture or MTL library
    // (the report replaced an MTL named `DB.build.json` until stop 47).
    std::vector<std::string> outputs;
};
void parsePly(const std::string& path, RawMesh& raw, const ReadOptions& options = {});
void parseObj(const std::string& path, RawMesh& raw, const ReadOptions& options = {});
void parseGltf(const std::string& path, RawMesh& raw, const ReadOptions& options = {});  // read_gltf.cpp
// Welds the corners (OBJ, and PLY with per-face UVs: by position/texcoord/normal index triple,
// in first-use order) into an indexed SourceMesh and sanitizes it.
SourceMesh toSourceMesh(const RawMesh& raw, const std::string& name);
// The three corners of triangle t with every attribute of the layout; InputError for an index out of range; false: degenerate.
struct Corner {
    float position[3], texcoord[2], normal[3];
    uint8_t color[4];
};
bool rawCorners(const RawMesh& raw, size_t t, Corner out[3], const std::string& name);
Box3f usedBounds(const RawMesh& raw);  // of the positions triangles use: the grid's and lattice's (raw_mesh.cpp)
// The read buffer of the PLY and OBJ parsers: the file's size (+1, at least 4 KiB), at most
// 1 MiB, so that small files (and the fuzzers' many small inputs) do not pay for a large one.
size_t readBufferBytes(std::FILE* file);

// Readers. Throw InputError("FILE: problem") on a missing, truncated or corrupt file. References outside
// the folder of `path` are refused (resolveReference); unusable textures: a TextureProblem, untextured.
SourceMesh readPly(const std::string& path, const ReadOptions& options = {});
SourceMesh readObj(const std::string& path, const ReadOptions& options = {});
SourceMesh readGltf(const std::string& path, const ReadOptions& options = {});
// A glTF (binary: GLB) held in memory, named `path` (its external buffers and images resolve
// from the folder of `path`): what readGltf reads, and the fuzz targets' entry point.
SourceMesh readGltfBytes(const std::vector<uint8_t>& bytes, bool binary, const std::string& path,
                         const ReadOptions& options = {});
SourceMesh readMesh(const std::string& path, const ReadOptions& options = {});  // by extension
// The largest texture decoded (a 16K x 16K atlas, 768 MiB as RGB): a header claiming more is an
// error (texture files) or leaves the material untextured with a warning (embedded glTF images).
inline constexpr uint64_t kMaxTextureTexels = 16384ull * 16384ull;
// Largest |coordinate| a mesh may have (after --offset): areas and squared distances of larger
// ones overflow float (1e37 built, then failed validation with a non-finite benefit before stop
// 36). 1e15 is the camera path's limit too; Earth-centred coordinates in mm are ~6.4e9.
inline constexpr double kMaxCoordinate = 1e15;
// Smallest extent (largest side of the bounding box) a mesh may have: the triangles of a smaller
// one have float areas near underflow and are lost as degenerate (a model 1e-13 across was built
// as 245 of its 6,244 triangles with exit 0 until stop 45, its lattice clamped at 1e-9).
inline constexpr double kMinExtent = 1e-12;

// input.cpp: rejects NaN/Inf attributes, out-of-range indices and empty meshes (InputError naming
// `name`), drops degenerate triangles (counted in stats), unusable textures: TextureProblems (untextured).
void sanitize(SourceMesh& source, const std::string& name);
// The cross product of the edges is exactly zero (the test sanitize() drops triangles by).
bool zeroArea(const float* a, const float* b, const float* c);
// Every texture file checked up front (textureProblem: missing, empty, not an image, absurd size):
// a TextureProblem in stats and the material untextured. No texture coordinates: a warning, and
// the material is untextured.
void checkTextures(std::vector<Material>& materials, bool hasTexcoords, const std::string& name, ReadStats& stats);
// The one confinement rule for every file an input refers to (MTL libraries and their
// textures, PLY TextureFile comments, glTF buffers and images, the meshes of a folder input):
// `reference` (a `kind`, e.g. "texture") is resolved against `folder` (the input's folder) and
// returned resolved; unless options.allowOutsideInput, an absolute path, a '..' component or a
// path that resolves (after symlinks) outside `folder` throws InputError
// "INPUT: KIND 'REFERENCE' ... (refused; --allow-outside-input allows it)"; one that is
// one of options.outputs throws InputError whatever the options. A reference that does not exist as
// written is looked for as Windows tools mean it (backslash separators, any case, an absolute
// Windows path's name beside the input; input.cpp), inside the same confinement.
std::string resolveReference(const std::string& input, const std::string& folder, const std::string& reference,
                             const std::string& kind, const ReadOptions& options);
// The folder of a mesh file (its parent; "." for a bare name), the base of its references.
std::string folderOf(const std::string& meshPath);

// cut.cpp (Fig. 3.2): splits by the plane x[axis] = position. Triangles crossing it become three
// with two new vertices on the plane, attributes interpolated linearly. `below` gets x <= p.
struct CutResult {
    Piece below, above;
};
CutResult cutPiece(const Piece& piece, int axis, float position);
// A piece's six sides (bit 2a: its low side on axis a, bit 2a + 1: its high side) beyond which
// another piece may share its border: a cut plane of the block grid or of §3.2's division, or any
// side of a block whose neighbours are unknown (a folder input's). A border vertex on the
// bounding-box face of such a side is locked (sharedVertices); the other sides border nothing.
using Sides = uint8_t;
inline constexpr Sides kAllSides = 0x3F;
inline constexpr Sides sideBit(int axis, bool high) { return static_cast<Sides>(1u << (2 * axis + (high ? 1 : 0))); }
// §3.2 division into `count` pieces by count-1 planes perpendicular to the longest bounding-box
// dimension. Planes::Balanced: each plane minimises 3 x crossing triangles + the triangle-count
// imbalance over 64 candidate positions through existing vertices (cut.cpp says why);
// Planes::Even: evenly spaced over the bounding box. Empty pieces are dropped. `shared`: the
// piece's sides; `childSides` (when given) receives each piece's, those and its cut ones.
std::vector<Piece> dividePiece(const Piece& piece, uint32_t count, Planes planes = Planes::Balanced, Sides shared = kAllSides,
                               std::vector<Sides>* childSides = nullptr);
Box3f pieceBounds(const MeshData& mesh);

// split_blocks.cpp: a grid over the two longest (horizontal) axes of the input bounds.
struct GridSpec {
    int axisU = 0, axisV = 1;
    uint32_t cellsU = 1, cellsV = 1;
    float minU = 0, minV = 0, sizeU = 1, sizeV = 1;  // cell size
};
inline constexpr uint64_t kMaxGridBlocks = 65536;  // chooseGrid refuses finer grids (invalid_argument)
GridSpec chooseGrid(const Box3f& bounds, uint64_t triangles, uint64_t targetTrianglesPerBlock,
                    double blockSize);
// Grid line k (1 .. cells-1) along U (alongV false) or V: the plane both splits cut at.
inline float gridPlane(const GridSpec& g, bool alongV, uint32_t k) {
    return alongV ? g.minV + g.sizeV * static_cast<float>(k) : g.minU + g.sizeU * static_cast<float>(k);
}
// Cuts `piece` along the grid lines; returns one piece per cell (row-major in V then U).
std::vector<Piece> splitByGrid(const Piece& piece, const GridSpec& grid);
// The sides of a block of the grid (bounds: its own) that lie on a grid line, the only places a
// neighbouring block shares its border: the input's outline, and a block's side that stops short
// of its cell's line, border nothing.
Sides blockSides(const Box3f& block, const GridSpec& grid);

// split_stream.cpp: splitByGrid out of core, for a RawMesh read from its spill files: each
// triangle goes to every cell its bounds reach (buffers of about `bufferBytes` in all, flushed to
// a file per cell), then each cell is welded and clipped to its rectangle by the same cuts.
// Returns the non-empty cells in row-major order; degenerate triangles are counted in `stats`.
struct CellFile {
    uint32_t cell = 0;
    std::string file;  // a loadPiece file
    uint64_t triangles = 0;
};
std::vector<CellFile> streamSplit(const RawMesh& raw, const GridSpec& grid, const std::string& dir, uint64_t bufferBytes,
                                  const std::string& name, ReadStats& stats, Progress* progress);

// Temporary per-block storage: a Piece appended to / read from a binary file; loading welds
// identical vertices (all attributes equal) of the appended chunks.
void appendPiece(const std::string& file, const Piece& piece);
Piece loadPiece(const std::string& file);

// weld.cpp: before the recursion, vertices closer than `epsilon` move onto one position (a
// vertex on the piece's bounding-box faces never moves), degenerate triangles and coincident
// copies are dropped, normals dropped, and every vertex serves one material (identical vertices merged).
Piece weldPiece(const Piece& piece, double epsilon);

// simplify.cpp. simplifyNode simplifies a (welded) piece as one mesh to about triangleCount / factor
// with quadric error metrics, material and UV changes being attribute seams; locked are the vertices
// neighbours share: open-border vertices on the piece's bounding-box faces of its `shared` sides (the
// cut planes). When seams keep it above kTargetSlack x the target, it simplifies the geometry alone
// (geometryOnly: no texture coordinates, all material 0; never for a piece without seams). When a
// result exceeds kTargetSlack x the target, closable scan holes are filled and it is simplified
// again. `ceiling` (input units, meshoptimizer only): the kept pass stops there, its rounds sharing
// the ceiling, so it may keep more triangles (pipeline/TREE.md).
enum class Simplifier { Meshopt, OpenMesh };
// The chroma of node textures (--jpeg-chroma, pipeline/TEXTURE_SIZE.md "Stop 17"): each material's
// JPEG source's own (4:2:0 for a 4:2:0 JPEG, else 4:4:4), or one for all.
enum class JpegChroma { Source, Full, Half };
inline const char* jpegChromaName(JpegChroma c) { return c == JpegChroma::Source ? "source" : c == JpegChroma::Full ? "4:4:4" : "4:2:0"; }
struct SubMesh {
    uint32_t material = 0;
    MeshData mesh;
    std::vector<uint8_t> locked;  // per vertex, from splitByMaterial (sharedVertices of the piece)
};
struct SimplifiedNode {
    Piece piece;
    bool geometryOnly = false;  // the source UVs no longer apply: the node needs a baked texture
    // The simplifier's own estimate of its error, input units (--bottom-up-error simplifier, --error-cap): meshoptimizer's,
    // summed over the rounds of the pass kept; 0 with OpenMesh and for an unsimplified piece. Not a distance bound.
    double error = 0;
};
std::vector<uint8_t> sharedVertices(const Piece& piece, Sides shared = kAllSides);  // per vertex: must stay for crack-free borders
// withLocked false: SubMesh::locked left empty (the build's nodes, which only pack and measure
// their parts, skip the border search: ~3 % of a bottom-up build).
std::vector<SubMesh> splitByMaterial(const Piece& piece, bool withLocked = true);
SimplifiedNode simplifyNode(const Piece& piece, double factor, Simplifier simplifier, Sides shared = kAllSides, double ceiling = HUGE_VAL);
// One mesh on its own (positions and attributes as they are); `locked` per vertex of `mesh`;
// when empty, sharedVertices of the mesh alone.
MeshData simplifyMesh(const MeshData& mesh, double factor, Simplifier simplifier, const std::vector<uint8_t>& locked = {});

// fill_holes.cpp: triangles (indices into `mesh`'s vertices) closing the scan holes of the
// triangles `indices`: border loops (on positions) through one UV chart with no `locked` vertex,
// other than the outline of their connected surface, of at most 64 vertices; no vertex is added.
std::vector<uint32_t> holePatches(const MeshData& mesh, const std::vector<uint32_t>& indices, const std::vector<uint8_t>& locked);

// error.cpp: largest distance from points sampled on `simplified` (edge midpoints, centroids) to `original`; 0 if either is empty.
double surfaceDistance(const std::vector<SubMesh>& simplified, const std::vector<SubMesh>& original);
// The node's geometric error: the two-sided (symmetric) Hausdorff distance between the node and
// the original surface, both sampled at most `spacing` apart (a hole wider than 2 x spacing is measured),
// each side against an AABB tree of the other; where only one side has triangles of area, its box diagonal.
struct SurfaceError {
    double oneSided = 0;  // simplified -> original only (the measure before issue #16)
    double max = 0;       // two-sided Hausdorff distance
    double mean = 0;      // mean distance over the sample points of both sides
    size_t samples = 0;   // the points measured, both sides (error.cpp's samples)
};
SurfaceError surfaceError(const std::vector<SubMesh>& simplified, const MeshData& original, double spacing);

// texture.cpp. A node's texture for one material: the source atlas downsampled by the node's
// factor (sqrt(factor) per side, box filter), of which only the JPEG blocks its triangles reach
// are read (texture_store.cpp) and repacked into one atlas, charts sharing a block as one group;
// UVs translated per group, exactly.
Image loadTexture(const std::string& path);  // 8-bit, 1 or 3 channels; throws InputError (corrupt, truncated)
// What makes a texture file unusable, found from its header alone ("is missing", "is empty (0
// bytes)", "is not a readable image (...)", "has absurd size ..."), or "" when it looks usable
// (its pixels are decoded, and a truncated or corrupt body found, when a block loads it).
std::string textureProblem(const std::string& path);
class TextureStore;  // pipeline/texture_store.h

// bake.cpp (charts: chart.cpp; pipeline/BAKE.md): a new parameterisation of a simplified node
// and a texture baked from its original surface, for nodes whose source UVs no longer apply.
// `simplified` carries positions and indices (texcoords, if any, are replaced); each source is the
// original triangles of one material and its texture (nullptr = untextured: vertex colours, else
// grey), best prefiltered to about the node's texel density (downsampleTexture by the node's
// factor): each texel takes 2 x 2 bilinear sub-samples. The result's triangles are grouped by
// chart, its vertices split where charts meet, its zero-area triangles (zeroArea) dropped; the atlas
// (RGB) holds at most texelBudget texels unless there are more than texelBudget / 64 charts.
struct BakeSource { const MeshData* mesh = nullptr; const Image* texture = nullptr; };  // original triangles of one material; texture nullptr = untextured
struct BakedTexture {
    MeshData mesh;              // `simplified` with new texcoords (vertices split where charts meet)
    Image image;                // the baked atlas
    double psnr = 0;            // dB, baked vs source colours over covered texels
    uint64_t coveredTexels = 0;
};
BakedTexture bakeTexture(const MeshData& simplified, const std::vector<BakeSource>& original, uint64_t texelBudget);

struct BuildOptions {
    Constants constants;
    Simplifier simplifier = Simplifier::Meshopt;
    LeafRule leafRule = LeafRule::BelowOne;  // tree_rules.h, pipeline/TREE.md
    BuildMode mode = BuildMode::TopDown;     // tree_rules.h, pipeline/BUILD_SPEED.md
    BottomUpError bottomUpError = BottomUpError::Bound;  // --mode bottom-up only
    Planes planes = Planes::Balanced;
    std::optional<bool> errorCap;  // --error-cap; unset: on but with --bottom-up-error simplifier (errorCapped, pipeline/TREE.md)
    DracoOptions draco{.texcoordBits = 0};  // texcoordBits 0: per node, a quarter texel of its texture (pack.cpp)
    int jpegQuality = 85;
    JpegChroma jpegChroma = JpegChroma::Source;  // 4:2:0 atlases hold 16 x 16 blocks, 4:4:4 ones 8 x 8
    bool leafPsnr = false;         // --leaf-psnr: measure each leaf's stored textures against the source
    uint64_t blockTriangles = 0;   // target triangles per block of a single-mesh input; 0 = auto (671,088)
    double blockSize = 0;          // block side in input units; overrides blockTriangles when > 0
    uint64_t memoryLimit = 1ull << 30;
    int jobs = 0;                  // 0 = all cores; at most kMaxJobs (checkBuildOptions)
    std::string tempDir;           // runBuild: empty = next to the output; buildBlock: runBuild's own folder (empty: the system's)
    ReadOptions read;              // --allow-outside-input
    bool strict = false;           // --strict: a TextureProblem is fatal (InputError, exit 2)
    std::string up;                // --up y|z; empty: by the input's format (chooseUpAxis)
    TextureStore* textures = nullptr;  // runBuild's (texture files decoded once per build); nullptr: per block
};


// memory_gate.cpp: admits blocks into the parallel build while their estimated working sets fit
// --memory-limit together; a block larger than the limit alone waits until it runs by itself.
// A block builds nodes in parallel on further working sets it obtains with tryAcquire.
class MemoryGate {
public:
    explicit MemoryGate(uint64_t limit) : limit_(limit) {}
    void acquire(uint64_t bytes);
    bool tryAcquire(uint64_t bytes);  // acquires when bytes fit beside what is in use, without waiting
    void release(uint64_t bytes);
    uint64_t inUse() const;
    uint64_t peak() const;  // the largest inUse() so far

private:
    uint64_t limit_, used_ = 0, peak_ = 0;
    mutable std::mutex mutex_;
    std::condition_variable freed_;
};
// Working set of buildBlock for a block (measured, see memory_gate.cpp): its triangles, its source
// textures and the texture work of one node (c_desiredTris of its triangles' share of the texels).
uint64_t blockWorkingSet(uint64_t triangles, uint64_t textureTexels, double desiredTris);

// One node of a block, encoded and ready for the writer. parentLocal indexes the block's
// node list (kNone for the block's hlod0).
struct NodeRecord {
    uint32_t parentLocal = kNone;
    NodeInput node;
};

// A stored texture against its source over the texels triangles use (texture_fidelity.cpp):
// PSNR = psnrDb(squaredError, samples) (formats/metrics.h), samples = texels x channels.
struct TextureFidelity {
    uint64_t texels = 0, samples = 0;
    double squaredError = 0;
};

struct BlockStats {
    uint64_t inputTriangles = 0, flattened = 0, straddling = 0, degenerateDropped = 0;  // lattice_flattened.h; wrapUvCharts
    Box3f fileBounds; double floatStepOver = 0;  // a folder's file: its bounds; its lattice step when floats step coarser
    std::vector<float> geometricErrors;  // per local node: max of its own measure and its children's
    std::vector<SurfaceError> measured;  // per local node: its own measure (0 for leaves)
    std::vector<uint8_t> baked;          // per local node: simplified geometry only, texture baked
    std::vector<float> bakePsnr;         // per local node: the baked texture's PSNR (dB), 0 when none
    std::vector<uint32_t> levels;        // per local node
    std::vector<uint64_t> triangles, texels;  // per local node, as stored
    std::vector<TextureFidelity> fidelity;    // per local node: its leaf textures (--leaf-psnr), else none
    std::vector<uint64_t> nodesPerLevel;
    std::vector<std::string> warnings;
    std::vector<TextureProblem> textureProblems;  // of reading the block, and textures that failed to decode
};

// build_tree.cpp: the §3.2 recursion over one block; nodes breadth-first, hlod0 first.
// `emit` receives each node as soon as it is packed (bounded memory). All its nodes are encoded
// on the position lattice options.draco.positionStep; when 0, the block's own
// positionLatticeStep (blocks then share borders exactly only if their steps agree).
// `shared`: the block's sides another block may share a border across (blockSides).
// Throws std::invalid_argument (a usage error) for --mode bottom-up --bottom-up-error simplifier
// with --simplifier openmesh: OpenMesh's decimater reports no error of its own.
BlockStats buildBlock(const Piece& block, const std::vector<Material>& materials, uint32_t blockIndex,
                      const BuildOptions& options, Progress* progress,
                      const std::function<void(NodeRecord&&)>& emit, Sides shared = kAllSides);
// The checks of buildBlock, for runBuild and writeSplitWork to refuse early (std::invalid_argument): jobs
// in 0..kMaxJobs, a finite blockSize and position step >= 0, a bottom-up error the simplifier can give.
inline constexpr int kMaxJobs = 1024;
void checkBuildOptions(const BuildOptions& options);
bool errorCapped(const BuildOptions& o);  // --error-cap as the build runs it (build_tree.cpp): meshoptimizer only

// pack.cpp: encodes a node's sub-meshes (Draco) and textures (JPEG) and fills §3.3 attributes.
// gridCell: one cell of `grid` over `bounds` (sizeU x sizeV x the third axis); gridPositionStep: the
// lattice step for every block of the grid (BuildOptions::draco.positionStep: one lattice for the
// whole database, so that neighbouring blocks share their borders exactly).
Box3f gridCell(const Box3f& bounds, const GridSpec& grid);
double gridPositionStep(const Box3f& bounds, const GridSpec& grid, int positionBits);
// checkPositionStep: std::invalid_argument naming `input` when a given step (> 0) puts more than
// 2^kMaxPositionBits steps across `block`, more than a blob's integer positions hold, or fewer
// than 2^kMinPositionBits (the model collapses).
void checkPositionStep(const std::string& input, const Box3f& block, double step);
// Throws InputError "INPUT: the model is E units across, below ..." when `bounds` spans less than kMinExtent.
void checkModelExtent(const std::string& input, const Box3f& bounds);
// floatPrecisionWarning: "" unless float positions (as readers store them) step more coarsely at the largest
// coordinate of `bounds` than the lattice `positionStep` (far from the origin: a scan in UTM metres), when the
// warning names `input`, the spacing lost and the --offset that keeps it (`offset` given plus the bounds' centre).
std::string floatPrecisionWarning(const std::string& input, const Box3f& bounds, double positionStep,
                                  const std::array<double, 3>& offset = {});
// `jpeg`: per part, the JPEG quality and chroma of its texture (BlockTextures::jpegQuality, chroma420).
struct JpegSettings {
    int quality = 85;
    bool chroma420 = false;
};
NodeRecord packNode(const std::vector<SubMesh>& parts, const std::vector<Image>& textures, const std::vector<JpegSettings>& jpeg,
                    const Box3f& bounds, uint32_t parentLocal, uint32_t level, uint32_t block, double geometricError,
                    const BuildOptions& options);

// merge.cpp: block record files and shards.
class BlockRecordWriter {
public:
    explicit BlockRecordWriter(const std::string& file);  // throws std::runtime_error
    ~BlockRecordWriter();
    void add(const NodeRecord& record);
    // Rewrites the geometric error of every added node (made monotone after the block is built).
    void setGeometricErrors(const std::vector<float>& errors);
    void finish();  // writes the node count; a record file without it is refused by merge

private:
    struct Impl;
    Impl* impl_;
};
std::vector<NodeRecord> readBlockRecords(const std::string& file, size_t maxRecords);

// A shard: a folder with shard.json (block count, metadata) and block_NNNNNN.nodes files.
struct ShardInfo {
    uint32_t blockCount = 0;         // blocks of the whole input
    std::vector<uint32_t> blocks;    // blocks this shard holds
    std::vector<std::pair<std::string, std::string>> meta;
};
void writeShardInfo(const std::string& dir, const ShardInfo& info);
ShardInfo readShardInfo(const std::string& dir);
std::string blockRecordPath(const std::string& dir, uint32_t block);
// Writes the database from shard folders: all hlod0 nodes in block order, then each block's
// remaining nodes in record order. Throws std::runtime_error on missing/duplicate blocks or
// shards built with different inputs/options.
void mergeShards(const std::vector<std::string>& shardDirs, const std::string& output, double cTextured);

// build.cpp: the whole build. `blocks` selects a subset [first, last) for sharding; output is a
// database, or a shard folder when `shard` is set.
struct BuildRequest {
    std::string input;          // a mesh file, or a folder of meshes (one block each, by name)
    std::string output;         // database path (or shard folder when shard is true)
    bool shard = false;
    uint32_t firstBlock = 0, lastBlock = UINT32_MAX;
    BuildOptions options;
};
struct BuildSummary {
    uint32_t blockCount = 0;
    std::vector<TextureProblem> textureProblems;  // distinct, sorted; each material left untextured
    uint64_t inputTriangles = 0;
    std::vector<uint64_t> nodesPerLevel;
    std::vector<NodeQuality> nodes;  // per node of the blocks built (the build report's "nodes")
    uint64_t gatePeak = 0;           // the memory gate's largest estimate of the blocks built at once
};
BuildSummary runBuild(const BuildRequest& request, Progress& progress);

// Deterministic build metadata (no timestamps, paths of temporaries or -j).
std::vector<std::pair<std::string, std::string>> buildMeta(const std::string& input,
                                                           const BuildOptions& options);

}  // namespace hlod
