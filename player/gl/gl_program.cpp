// The two shader programs of the renderer (thesis §3.3: textured and untextured triangles are
// the two kinds the cost model of eq. 3.1 weighs). Textured: the scan's texture as is (it holds
// the captured lighting). Flat: vertex colour (or uniform grey) with a headlight term
// |n·v| so shape reads without a texture. Both can be overridden by a uniform grey for
// FrameOptions::colorByLevel.
#include "player/gl/gl_detail.h"

#include <stdexcept>

namespace hlod::gl {
namespace {

constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 texcoord;
layout(location = 3) in vec4 color;
uniform mat4 viewProjection;
uniform mat4 view;
out vec3 viewNormal;
out vec2 uv;
out vec4 vertexColor;
void main() {
    gl_Position = viewProjection * vec4(position, 1.0);
    viewNormal = mat3(view) * normal;
    uv = texcoord;
    vertexColor = color;
}
)";

constexpr const char* kTexturedFragment = R"(#version 330 core
in vec3 viewNormal;
in vec2 uv;
in vec4 vertexColor;
uniform sampler2D image;
uniform float levelGrey;  // < 0: texture colours; else shade by level
out vec4 fragColor;
void main() {
    if (levelGrey < 0.0) {
        fragColor = vec4(texture(image, uv).rgb, 1.0);
    } else {
        float light = 0.6 + 0.4 * abs(normalize(viewNormal).z);
        fragColor = vec4(vec3(levelGrey * light), 1.0);
    }
}
)";

constexpr const char* kFlatFragment = R"(#version 330 core
in vec3 viewNormal;
in vec2 uv;
in vec4 vertexColor;
uniform float levelGrey;  // < 0: vertex colour; else shade by level
out vec4 fragColor;
void main() {
    float n = abs(normalize(viewNormal).z);
    if (levelGrey < 0.0) {
        fragColor = vec4(vertexColor.rgb * (0.35 + 0.65 * n), 1.0);
    } else {
        fragColor = vec4(vec3(levelGrey * (0.6 + 0.4 * n)), 1.0);
    }
}
)";

GLuint compile(GLenum kind, const char* source) {
    GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw std::runtime_error(std::string("OpenGL: shader does not compile: ") + log);
    }
    return shader;
}

GLuint link(const char* fragmentSource) {
    GLuint vertex = compile(GL_VERTEX_SHADER, kVertex);
    GLuint fragment = compile(GL_FRAGMENT_SHADER, fragmentSource);
    GLuint program = glCreateProgram();
    glAttachShader(program, vertex);
    glAttachShader(program, fragment);
    glLinkProgram(program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        throw std::runtime_error(std::string("OpenGL: program does not link: ") + log);
    }
    return program;
}

}  // namespace

Programs buildPrograms() {
    Programs programs;
    programs.textured = link(kTexturedFragment);
    try {
        programs.flat = link(kFlatFragment);
    } catch (...) {
        glDeleteProgram(programs.textured);
        throw;
    }
    return programs;
}

void destroyPrograms(Programs& programs) {
    glDeleteProgram(programs.textured);
    glDeleteProgram(programs.flat);
    programs = {};
}

}  // namespace hlod::gl
