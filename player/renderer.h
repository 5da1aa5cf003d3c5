// The renderer seen by the selection engine: upload/evict decoded nodes, draw a front of nodes
// for a camera and report the frame's measured time. Implementations: CostModelRenderer
// (draws nothing, returns a modelled time; exact and repeatable) and GlRenderer (OpenGL through
// EGL offscreen or a GLFW window).
#pragma once

#include "formats/codec.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace hlod {

struct Camera {
    double position[3] = {0, 0, 0};
    double orientation[4] = {0, 0, 0, 1};  // unit quaternion x, y, z, w; camera looks down -Z, up +Y (OpenGL)
    double vfovDegrees = 60;
    double aspect = 16.0 / 9.0;
    double nearPlane = 0.1, farPlane = 10000;
};

// A node decoded by the loading thread, ready for upload: sub-meshes and their textures.
struct DecodedNode {
    uint32_t id = 0;
    std::vector<MeshData> meshes;
    std::vector<int32_t> meshTexture;  // per mesh: index into `textures`, or -1 untextured
    std::vector<Image> textures;
    uint64_t bytes() const;            // CPU bytes held (geometry + texels)
};

struct FrameOptions {
    bool colorByLevel = false;         // shade nodes by level (grey levels, as the thesis and Funkhouser & Séquin 1993 show them)
};

struct DrawItem {
    uint32_t node;
    uint32_t level;
};

class Renderer {
public:
    virtual ~Renderer() = default;
    virtual std::string name() const = 0;
    // Render thread only. upload() takes ownership of the decoded data.
    virtual void upload(DecodedNode&& node) = 0;
    virtual void evict(uint32_t node) = 0;
    // Draws the items; returns the measured frame time in milliseconds.
    virtual double drawFrame(const Camera& camera, std::span<const DrawItem> items, const FrameOptions& options) = 0;
    // Reads back the last frame as RGB (empty Image when the renderer draws nothing).
    virtual Image readPixels() { return {}; }
};

}  // namespace hlod
