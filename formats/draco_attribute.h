// Internal to formats/: decoding a Draco geometry blob and checking an attribute's layout, shared
// by the blob decoder (codec_draco.cpp) and the 3D Tiles export (tiles_glb.cpp). Only the layouts hlod writes
// are accepted (a corrupt stream may declare others, e.g. bool attributes whose bytes are not
// valid bools).
#pragma once

#include <draco/mesh/mesh.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace hlod {

// The mesh of a Draco bitstream; throws FormatError "NAME: bad Draco geometry: ..." when it does
// not decode.
std::unique_ptr<draco::Mesh> decodeDracoMesh(std::span<const uint8_t> bytes, const std::string& name);

// The mesh's attribute of `type`, or nullptr when it has none; throws FormatError "NAME: ..."
// when it has one of another data type or component count.
const draco::PointAttribute* checkedDracoAttribute(const draco::Mesh& mesh, draco::GeometryAttribute::Type type,
                                                   draco::DataType dataType, int minComponents, int maxComponents,
                                                   const std::string& name);

}  // namespace hlod
