// The OpenGL Renderer (player/renderer.h). Every frame is drawn into an FBO (so offscreen EGL
// and a window behave alike and readPixels works in both); its time is measured around the
// draw calls with glFinish, or with a GL_TIME_ELAPSED query — the "actual render time" that
// the feedback loop of thesis §4.2 compares with the estimate, and Fig. 6.4/6.5 plot.
#include "player/gl/gl_detail.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <unordered_map>

namespace hlod {
namespace {

constexpr float kBackground[3] = {0.53f, 0.63f, 0.75f};

struct Uniforms {
    GLint viewProjection = -1, view = -1, levelGrey = -1;
};

Uniforms uniformsOf(GLuint program) {
    return {glGetUniformLocation(program, "viewProjection"), glGetUniformLocation(program, "view"),
            glGetUniformLocation(program, "levelGrey")};
}

class GlRenderer final : public Renderer {
public:
    explicit GlRenderer(const GlOptions& options)
        : options_(options),
          context_(options.window ? gl::makeGlfwContext(options.width, options.height, options.title)
                                  : gl::makeEglContext()) {
        programs_ = gl::buildPrograms();
        textured_ = uniformsOf(programs_.textured);
        flat_ = uniformsOf(programs_.flat);
        glUseProgram(programs_.textured);
        glUniform1i(glGetUniformLocation(programs_.textured, "image"), 0);
        createFramebuffer();
        if (options.timerQueries) glGenQueries(1, &query_);
        glEnable(GL_DEPTH_TEST);
        if (glGetError() != GL_NO_ERROR) throw std::runtime_error("OpenGL: setting up the renderer failed");
    }

    ~GlRenderer() override {
        for (auto& [id, node] : nodes_) gl::releaseNode(node);
        if (query_) glDeleteQueries(1, &query_);
        glDeleteRenderbuffers(2, renderbuffers_);
        glDeleteFramebuffers(1, &framebuffer_);
        gl::destroyPrograms(programs_);
    }

    std::string name() const override { return "opengl: " + context_->description(); }

    void upload(DecodedNode&& node) override {
        const uint32_t id = node.id;
        gl::GpuNode gpu = gl::uploadNode(std::move(node));
        evict(id);
        nodes_.emplace(id, std::move(gpu));
    }

    void evict(uint32_t node) override {
        auto it = nodes_.find(node);
        if (it == nodes_.end()) return;
        gl::releaseNode(it->second);
        nodes_.erase(it);
    }

    double drawFrame(const Camera& camera, std::span<const DrawItem> items, const FrameOptions& options) override {
        const gl::Mat4 view = gl::viewMatrix(camera);
        const gl::Mat4 viewProjection = gl::multiply(gl::projectionMatrix(camera), view);
        const auto start = std::chrono::steady_clock::now();
        if (query_) glBeginQuery(GL_TIME_ELAPSED, query_);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
        glViewport(0, 0, options_.width, options_.height);
        glClearColor(kBackground[0], kBackground[1], kBackground[2], 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        for (const DrawItem& item : items) drawNode(item, view, viewProjection, options);
        double ms = 0;
        if (query_) {
            glEndQuery(GL_TIME_ELAPSED);
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
            ms = static_cast<double>(ns) * 1e-6;
        } else {
            glFinish();
            ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        }
        context_->present(framebuffer_, options_.width, options_.height);
        return ms;
    }

    Image readPixels() override {
        Image image;
        image.width = static_cast<uint32_t>(options_.width);
        image.height = static_cast<uint32_t>(options_.height);
        image.channels = 3;
        const size_t row = size_t{image.width} * 3;
        std::vector<uint8_t> bottomUp(row * image.height);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, options_.width, options_.height, GL_RGB, GL_UNSIGNED_BYTE, bottomUp.data());
        image.pixels.resize(bottomUp.size());
        for (size_t y = 0; y < image.height; ++y)
            std::copy_n(bottomUp.begin() + static_cast<std::ptrdiff_t>((image.height - 1 - y) * row), row,
                        image.pixels.begin() + static_cast<std::ptrdiff_t>(y * row));
        return image;
    }

    GLFWwindow* window() { return context_->window(); }

private:
    void createFramebuffer() {
        glGenFramebuffers(1, &framebuffer_);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
        glGenRenderbuffers(2, renderbuffers_);
        glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[0]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, options_.width, options_.height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers_[0]);
        glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[1]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, options_.width, options_.height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffers_[1]);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("OpenGL: framebuffer of " + std::to_string(options_.width) + "x" +
                                     std::to_string(options_.height) + " is incomplete");
    }

    void drawNode(const DrawItem& item, const gl::Mat4& view, const gl::Mat4& viewProjection, const FrameOptions& options) {
        auto it = nodes_.find(item.node);
        if (it == nodes_.end()) return;  // not resident: the selection engine draws only what is loaded
        const float grey = options.colorByLevel ? levelGrey(item.level) : -1.0f;
        const gl::GpuNode& node = it->second;
        for (const gl::GpuMesh& mesh : node.meshes) {
            const bool textured = mesh.texture >= 0;
            const Uniforms& u = textured ? textured_ : flat_;
            glUseProgram(textured ? programs_.textured : programs_.flat);
            glUniformMatrix4fv(u.viewProjection, 1, GL_FALSE, viewProjection.data());
            glUniformMatrix4fv(u.view, 1, GL_FALSE, view.data());
            glUniform1f(u.levelGrey, grey);
            if (textured) glBindTexture(GL_TEXTURE_2D, node.textures[static_cast<size_t>(mesh.texture)]);
            glBindVertexArray(mesh.vao);
            if (!mesh.hasColors) glVertexAttrib4f(3, 0.7f, 0.7f, 0.7f, 1.0f);
            glDrawElements(GL_TRIANGLES, mesh.indexCount, GL_UNSIGNED_INT, nullptr);
        }
        glBindVertexArray(0);
    }

    GlOptions options_;
    std::unique_ptr<gl::Context> context_;  // first member destroyed last: GL calls above need it
    gl::Programs programs_;
    Uniforms textured_, flat_;
    GLuint framebuffer_ = 0, renderbuffers_[2] = {0, 0}, query_ = 0;
    std::unordered_map<uint32_t, gl::GpuNode> nodes_;
};

}  // namespace

std::unique_ptr<Renderer> makeGlRenderer(const GlOptions& options) {
    if (options.width <= 0 || options.height <= 0 || options.width > 16384 || options.height > 16384)
        throw std::runtime_error("OpenGL: frame size " + std::to_string(options.width) + "x" +
                                 std::to_string(options.height) + " is not within 1..16384");
    return std::make_unique<GlRenderer>(options);
}

GLFWwindow* glfwWindowOf(Renderer& renderer) {
    auto* gl = dynamic_cast<GlRenderer*>(&renderer);
    return gl ? gl->window() : nullptr;
}

float levelGrey(uint32_t level) { return 0.25f + 0.1f * static_cast<float>(level % 8); }

}  // namespace hlod
