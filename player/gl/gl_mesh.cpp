// Upload of one decoded HLOD node (thesis §3.3: a node is geometry + its texture image) into
// GPU objects: per sub-mesh one VBO holding positions | normals | texcoords | colours, one IBO
// and a VAO; per image a mipmapped GL_R8/RG8/RGB8/RGBA8 texture. Absent normals are computed
// from the triangles (area-weighted), so the untextured shading has something to work with.
// Inconsistent data is rejected with one line instead of letting the GPU read out of bounds.
#include "player/gl/gl_detail.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hlod::gl {
namespace {

void check(bool ok, const DecodedNode& node, const std::string& problem) {
    if (!ok) throw std::runtime_error("node " + std::to_string(node.id) + ": " + problem);
}

void validate(const DecodedNode& node) {
    check(node.meshTexture.empty() || node.meshTexture.size() == node.meshes.size(), node,
          "meshTexture has " + std::to_string(node.meshTexture.size()) + " entries for " +
              std::to_string(node.meshes.size()) + " meshes");
    for (size_t i = 0; i < node.meshes.size(); ++i) {
        const MeshData& m = node.meshes[i];
        const size_t n = m.vertexCount();
        const std::string name = "mesh " + std::to_string(i) + ": ";
        check(m.positions.size() % 3 == 0 && m.indices.size() % 3 == 0, node, name + "partial vertex or triangle");
        check(m.texcoords.empty() || m.texcoords.size() == 2 * n, node, name + "texcoord count mismatch");
        check(m.normals.empty() || m.normals.size() == 3 * n, node, name + "normal count mismatch");
        check(m.colors.empty() || m.colors.size() == 4 * n, node, name + "colour count mismatch");
        check(std::all_of(m.indices.begin(), m.indices.end(), [n](uint32_t v) { return v < n; }), node,
              name + "vertex index out of range");
        const int32_t t = node.meshTexture.empty() ? -1 : node.meshTexture[i];
        check(t >= -1 && t < static_cast<int32_t>(node.textures.size()), node, name + "texture index out of range");
        check(t < 0 || !m.texcoords.empty(), node, name + "textured but has no texcoords");
    }
    for (const Image& image : node.textures)
        check(image.channels >= 1 && image.channels <= 4 && image.width > 0 && image.height > 0 &&
                  image.pixels.size() == size_t{image.width} * image.height * image.channels,
              node, "texture size does not match its pixels");
}

GLuint uploadTexture(const Image& image) {
    static constexpr GLenum kInternal[] = {GL_R8, GL_RG8, GL_RGB8, GL_RGBA8};
    static constexpr GLenum kFormat[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(kInternal[image.channels - 1]), static_cast<GLsizei>(image.width),
                 static_cast<GLsizei>(image.height), 0, kFormat[image.channels - 1], GL_UNSIGNED_BYTE,
                 image.pixels.data());
    if (image.channels <= 2) {  // grey (+ alpha) images show as grey
        const GLint swizzle[] = {GL_RED, GL_RED, GL_RED, image.channels == 2 ? GL_GREEN : GL_ONE};
        glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
    }
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

// One attribute array appended to the bound VBO at `offset`.
void attribute(GLuint location, GLint size, GLenum type, bool normalized, GLsizeiptr offset) {
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, size, type, normalized ? GL_TRUE : GL_FALSE, 0,
                          reinterpret_cast<const void*>(offset));
}

GpuMesh uploadMesh(const MeshData& mesh, int32_t texture) {
    GpuMesh gpu;
    gpu.texture = texture;
    gpu.hasColors = !mesh.colors.empty();
    gpu.indexCount = static_cast<GLsizei>(mesh.indices.size());
    const std::vector<float> computed = mesh.normals.empty() ? vertexNormals(mesh.positions, mesh.indices) : std::vector<float>{};
    const std::vector<float>& normals = mesh.normals.empty() ? computed : mesh.normals;

    const GLsizeiptr positionBytes = static_cast<GLsizeiptr>(mesh.positions.size() * sizeof(float));
    const GLsizeiptr normalBytes = static_cast<GLsizeiptr>(normals.size() * sizeof(float));
    const GLsizeiptr texcoordBytes = static_cast<GLsizeiptr>(mesh.texcoords.size() * sizeof(float));
    const GLsizeiptr colorBytes = static_cast<GLsizeiptr>(mesh.colors.size());

    glGenVertexArrays(1, &gpu.vao);
    glBindVertexArray(gpu.vao);
    glGenBuffers(1, &gpu.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
    glBufferData(GL_ARRAY_BUFFER, positionBytes + normalBytes + texcoordBytes + colorBytes, nullptr, GL_STATIC_DRAW);
    glBufferSubData(GL_ARRAY_BUFFER, 0, positionBytes, mesh.positions.data());
    glBufferSubData(GL_ARRAY_BUFFER, positionBytes, normalBytes, normals.data());
    attribute(0, 3, GL_FLOAT, false, 0);
    attribute(1, 3, GL_FLOAT, false, positionBytes);
    GLsizeiptr offset = positionBytes + normalBytes;
    if (texcoordBytes > 0) {
        glBufferSubData(GL_ARRAY_BUFFER, offset, texcoordBytes, mesh.texcoords.data());
        attribute(2, 2, GL_FLOAT, false, offset);
        offset += texcoordBytes;
    }
    if (colorBytes > 0) {
        glBufferSubData(GL_ARRAY_BUFFER, offset, colorBytes, mesh.colors.data());
        attribute(3, 4, GL_UNSIGNED_BYTE, true, offset);
    }
    glGenBuffers(1, &gpu.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
                 mesh.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    return gpu;
}

}  // namespace

std::vector<float> vertexNormals(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
    std::vector<float> normals(positions.size(), 0.0f);
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        const float* a = &positions[3 * size_t{indices[t]}];
        const float* b = &positions[3 * size_t{indices[t + 1]}];
        const float* c = &positions[3 * size_t{indices[t + 2]}];
        const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        for (size_t k = 0; k < 3; ++k)
            for (size_t d = 0; d < 3; ++d) normals[3 * size_t{indices[t + k]} + d] += n[d];  // |n| = 2 * area
    }
    for (size_t i = 0; i + 2 < normals.size(); i += 3) {
        const float length = std::sqrt(normals[i] * normals[i] + normals[i + 1] * normals[i + 1] + normals[i + 2] * normals[i + 2]);
        if (length > 0)
            for (size_t d = 0; d < 3; ++d) normals[i + d] /= length;
    }
    return normals;
}

GpuNode uploadNode(DecodedNode&& node) {
    validate(node);
    GpuNode gpu;
    for (const Image& image : node.textures) gpu.textures.push_back(uploadTexture(image));
    for (size_t i = 0; i < node.meshes.size(); ++i) {
        gpu.meshes.push_back(uploadMesh(node.meshes[i], node.meshTexture.empty() ? -1 : node.meshTexture[i]));
        gpu.triangles += static_cast<uint32_t>(node.meshes[i].triangleCount());
    }
    node = {};  // the CPU copy is no longer needed
    return gpu;
}

void releaseNode(GpuNode& node) {
    for (GpuMesh& mesh : node.meshes) {
        glDeleteVertexArrays(1, &mesh.vao);
        glDeleteBuffers(1, &mesh.vbo);
        glDeleteBuffers(1, &mesh.ibo);
    }
    if (!node.textures.empty()) glDeleteTextures(static_cast<GLsizei>(node.textures.size()), node.textures.data());
    node = {};
}

}  // namespace hlod::gl
