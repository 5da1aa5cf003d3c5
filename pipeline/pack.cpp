// Packing one node (thesis §3.3): geometry as Draco blobs (one per material), textures as JPEG
// blobs, and the node attributes: bounding box (of the ORIGINAL piece, so it holds every
// descendant; the simplified surface alone may not), static benefit sqrt(numTriangles * sum area),
// area-weighted average normal (formats/metrics.h), measured geometric error. The cost of
// eq. 3.1 is left to the writer (cost < 0), which computes it from the blobs and c_textured.
// Normals are not stored: they cost 0.45-0.95 B/tri in Draco and the player recomputes them.
// Positions go on the lattice of options.draco.positionStep (FORMAT.md §Geometry blobs); texture
// coordinates get options.draco.texcoordBits, or when 0 (the default) a quarter texel of the
// node's own texture (texcoordBitsForTexture).
#include "pipeline/pipeline.h"
#include "formats/errors.h"
#include "formats/layout.h"

#include "formats/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace hlod {

Box3f gridCell(const Box3f& bounds, const GridSpec& grid) {
    const auto axis = [](Vec3f& v, int a) -> float& { return a == 0 ? v.x : a == 1 ? v.y : v.z; };
    Box3f cell = bounds;
    axis(cell.max, grid.axisU) = axis(cell.min, grid.axisU) + grid.sizeU;
    axis(cell.max, grid.axisV) = axis(cell.min, grid.axisV) + grid.sizeV;
    return cell;
}

double gridPositionStep(const Box3f& bounds, const GridSpec& grid, int positionBits) {
    return positionLatticeStep(gridCell(bounds, grid), positionBits);
}

void checkPositionStep(const std::string& input, const Box3f& block, double step) {
    const double finest = positionLatticeStep(block, kMaxPositionBits);  // a power of two
    if (step > 0 && step < finest) {
        std::ostringstream what;
        what << "--draco-position-step " << formatConstant(step) << " is too fine for " << input << ": a block spans more than 2^"
             << kMaxPositionBits << " of its steps (at least " << formatConstant(finest) << ")";
        throw std::invalid_argument(what.str());
    }
    const double coarsest = positionLatticeStep(block, kMinPositionBits);
    if (step > coarsest) {
        std::ostringstream what;
        what << "--draco-position-step " << formatConstant(step) << " is too coarse for " << input << ": a block spans fewer than 2^"
             << kMinPositionBits << " of its steps (at most " << formatConstant(coarsest) << ")";
        throw std::invalid_argument(what.str());
    }
}

void checkModelExtent(const std::string& input, const Box3f& bounds) {
    const double extent = std::max({double(bounds.max.x) - bounds.min.x, double(bounds.max.y) - bounds.min.y,
                                    double(bounds.max.z) - bounds.min.z});
    if (!(extent >= kMinExtent)) {
        std::ostringstream what;
        what << input << ": the model is " << std::setprecision(3) << extent << " units across, below the " << kMinExtent
             << " hlod builds (its triangles' float areas underflow): scale it up";
        throw InputError(what.str());
    }
}

std::string floatPrecisionWarning(const std::string& input, const Box3f& bounds, double positionStep, const std::array<double, 3>& offset) {
    const double lo[3] = {bounds.min.x, bounds.min.y, bounds.min.z}, hi[3] = {bounds.max.x, bounds.max.y, bounds.max.z};
    double far = 0;
    for (int k = 0; k < 3; ++k) far = std::max({far, std::abs(lo[k]), std::abs(hi[k])});
    if (!(positionStep > 0) || !(far > 0) || !std::isfinite(far)) return "";
    const double floatStep = std::ldexp(1.0, std::ilogb(far) - 23);  // binary32: 24-bit significand
    if (floatStep <= positionStep) return "";  // the same answer as against the step rounded down to a power of two
    const double lattice = std::ldexp(1.0, std::ilogb(positionStep));  // the step the codec uses (codec.h)
    // The offset that centres the input: the one given (bounds are after it) plus the bounds' centre,
    // rounded (until stop 48 the centre alone, and following the advice swapped its signs).
    double centre[3];
    for (int k = 0; k < 3; ++k) centre[k] = 0.0 + std::round(offset[k] + (lo[k] + hi[k]) / 2);  // 0.0 +: no "-0"
    std::vector<char> text(input.size() + 400);
    std::snprintf(text.data(), text.size(),
                  "%s: coordinates reach %.6g units from the origin, where positions (32-bit floats) step by %g, coarser than "
                  "the position lattice step %g: detail finer than %g is lost; build with --offset %.0f,%.0f,%.0f (the "
                  "centre of its bounds, rounded) to keep it",
                  input.c_str(), far, floatStep, lattice, floatStep, centre[0], centre[1], centre[2]);
    return text.data();
}

NodeRecord packNode(const std::vector<SubMesh>& parts, const std::vector<Image>& textures, const std::vector<JpegSettings>& jpeg,
                    const Box3f& bounds, uint32_t parentLocal, uint32_t level, uint32_t block, double geometricError,
                    const BuildOptions& options) {
    NodeRecord record;
    record.parentLocal = parentLocal;
    NodeInput& node = record.node;
    node.level = level;
    node.block = block;
    // One geometry blob per material, and a texture before a textured one's: a node of more was
    // refused only by the merge, after the whole build, as a "corrupt block record file" (until stop 47).
    size_t blobs = 0;
    for (const Image& t : textures) blobs += t.width > 0 ? 2 : 1;
    if (blobs > layout::kMaxBlobsPerNode)
        throw InputError("block " + std::to_string(block) + ": a level-" + std::to_string(level) + " node of " +
                         std::to_string(parts.size()) + " materials needs " + std::to_string(blobs) + " blobs, more than the " +
                         std::to_string(layout::kMaxBlobsPerNode) + " a node holds (formats/FORMAT.md)");
    std::vector<MeshData> meshes;
    meshes.reserve(parts.size());
    for (size_t i = 0; i < parts.size(); ++i) {
        MeshData mesh = parts[i].mesh;
        mesh.normals.clear();
        uint32_t slot = kNone;
        DracoOptions draco = options.draco;
        if (textures[i].width > 0) {
            slot = static_cast<uint32_t>(node.blobs.size());
            node.blobs.push_back(encodeTexture(textures[i], Codec::Jpeg, jpeg[i].quality, jpeg[i].chroma420));
            if (draco.texcoordBits == 0) draco.texcoordBits = texcoordBitsForTexture(mesh.texcoords, textures[i].width, textures[i].height);
        } else {
            mesh.texcoords.clear();
        }
        EncodedBlob geometry = encodeGeometry(mesh, draco);
        geometry.textureSlot = slot;
        node.blobs.push_back(std::move(geometry));
        meshes.push_back(std::move(mesh));
    }
    const SurfaceMetrics metrics = surfaceMetrics(meshes);
    node.bounds = bounds;  // the original piece's: contains the node and all its descendants
    node.staticBenefit = metrics.staticBenefit;
    node.avgNormal = metrics.avgNormal;
    node.geometricError = static_cast<float>(geometricError);
    return record;
}

}  // namespace hlod
