// OpenGL contexts. Headless: EGL on Mesa's surfaceless platform (no /dev/dri needed; llvmpipe)
// or the default display elsewhere, a context created without a config and made current
// without a surface (EGL_KHR_surfaceless_context); drawing goes to an FBO. Window: GLFW.
#include "player/gl/gl_detail.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>
#include <stdexcept>

namespace hlod::gl {
namespace {

std::string glDescription() {
    auto text = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    return text(GL_RENDERER) + " (OpenGL " + text(GL_VERSION) + ")";
}

EGLDisplay openEglDisplay() {
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay) {
        EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) return display;
    }
    EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) return display;
    throw NoGlContext("EGL: no display could be initialised (neither surfaceless nor default)");
}

class EglContext final : public Context {
public:
    EglContext() : display_(openEglDisplay()) {
        if (!eglBindAPI(EGL_OPENGL_API)) fail("eglBindAPI(OpenGL) failed");
        const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
        context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
        if (context_ == EGL_NO_CONTEXT) fail("no OpenGL 3.3 core context without config");
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) fail("surfaceless make-current failed");
    }
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
        eglReleaseThread();
        // No eglTerminate: the display stays initialised for the process (eglInitialize of an
        // initialised display is a no-op, so a later renderer reuses it). Terminating makes Mesa
        // unload its driver, after which LeakSanitizer reports the driver's allocations unwound.
    }
    std::string description() const override { return glDescription() + " via EGL"; }

private:
    [[noreturn]] void fail(const std::string& what) {
        EGLint error = eglGetError();
        if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
        eglTerminate(display_);
        char code[16];
        std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(error));
        throw NoGlContext("EGL: " + what + " (error " + code + ")");
    }
    EGLDisplay display_;
    EGLContext context_ = EGL_NO_CONTEXT;
};

class GlfwContext final : public Context {
public:
    GlfwContext(int width, int height, const std::string& title) {
        if (!glfwInit()) fail("cannot initialise (no display?)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
        window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (!window_) {
            glfwTerminate();
            fail("cannot create a " + std::to_string(width) + "x" + std::to_string(height) + " OpenGL 3.3 core window");
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(0);  // frame times are measured, not synchronised to the display
    }
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    void present(GLuint framebuffer, int width, int height) override {
        int windowWidth = 0, windowHeight = 0;
        glfwGetFramebufferSize(window_, &windowWidth, &windowHeight);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glBlitFramebuffer(0, 0, width, height, 0, 0, windowWidth, windowHeight, GL_COLOR_BUFFER_BIT, GL_LINEAR);
        glfwSwapBuffers(window_);
    }
    GLFWwindow* window() override { return window_; }
    std::string description() const override { return glDescription() + " in a GLFW window"; }

private:
    // GLFW's own description of its last error (say, "X11: Failed to open display :99") after ours.
    [[noreturn]] static void fail(const std::string& what) {
        const char* description = nullptr;
        glfwGetError(&description);
        throw NoGlContext("GLFW: " + what + (description ? std::string(": ") + description : std::string()));
    }
    GLFWwindow* window_ = nullptr;
};

}  // namespace

std::unique_ptr<Context> makeEglContext() { return std::make_unique<EglContext>(); }

std::unique_ptr<Context> makeGlfwContext(int width, int height, const std::string& title) {
    return std::make_unique<GlfwContext>(width, height, title);
}

}  // namespace hlod::gl
