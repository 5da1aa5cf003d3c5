// Internal pieces of the OpenGL renderer shared by its .cpp files: the context (EGL offscreen
// or GLFW window), shader programs, GPU buffers of one node, camera matrices.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "player/gl/gl_renderer.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace hlod::gl {

// A current OpenGL 3.3+ core context. Destroying it releases the display/window.
class Context {
public:
    virtual ~Context() = default;
    // Shows the frame drawn in `framebuffer` (window: blit and swap; offscreen: nothing).
    virtual void present(GLuint /*framebuffer*/, int /*width*/, int /*height*/) {}
    virtual GLFWwindow* window() { return nullptr; }
    virtual std::string description() const = 0;
};

// Headless: Mesa surfaceless platform (or any EGL device), no config, surfaceless current.
std::unique_ptr<Context> makeEglContext();
// A visible window; throws when there is no display.
std::unique_ptr<Context> makeGlfwContext(int width, int height, const std::string& title);

// The two programs: textured (sampler) and flat (vertex colour, normal-based headlight shading).
struct Programs {
    GLuint textured = 0, flat = 0;
};
Programs buildPrograms();  // throws std::runtime_error with the compile log
void destroyPrograms(Programs& programs);

// GPU objects of one uploaded sub-mesh.
struct GpuMesh {
    GLuint vao = 0, vbo = 0, ibo = 0;
    GLsizei indexCount = 0;
    int32_t texture = -1;  // index into GpuNode::textures, -1 untextured
    bool hasColors = false;
};

struct GpuNode {
    std::vector<GpuMesh> meshes;
    std::vector<GLuint> textures;
    uint32_t triangles = 0;
};

GpuNode uploadNode(DecodedNode&& node);
void releaseNode(GpuNode& node);

// Per-vertex area-weighted normals of an indexed triangle mesh (3 floats per vertex).
std::vector<float> vertexNormals(const std::vector<float>& positions, const std::vector<uint32_t>& indices);

// Column-major 4x4 matrices for glUniformMatrix4fv.
using Mat4 = std::array<float, 16>;
Mat4 viewMatrix(const Camera& camera);
Mat4 projectionMatrix(const Camera& camera);
Mat4 multiply(const Mat4& a, const Mat4& b);

}  // namespace hlod::gl
