// glTF 2.0 / GLB input through tinygltf (pipeline/tiny_gltf_config.h; Draco-compressed
// primitives are decoded by tinygltf): the default scene's node tree with its transforms
// flattened into one mesh; TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives (points and
// lines are skipped, with a warning); POSITION, the base-colour texture's TEXCOORD_n (its
// KHR_texture_transform applied; read_gltf_materials.cpp), NORMAL (transformed by
// the inverse transpose, normalised) and COLOR_0 (RGB or RGBA, float or normalised integers, to
// 8 bits) as the PLY reader reads them: an attribute is kept when every primitive has it.
// Mirroring transforms reverse the winding back. The file is memory-mapped, not copied, and
// converted into a RawMesh (raw_mesh.cpp), which `hlod build` spills to disk and streams to the
// block grid as it does a PLY (parseGltf); readGltf welds it into a SourceMesh. Base-colour
// textures: embedded images checked (one that does not decode or claims too many texels is a
// TextureProblem, its material untextured), then either decoded into memory by stb_image or,
// given ReadOptions::imageDir (as `hlod build` does), checked in strips of rows, written still encoded to that folder and
// read later by rectangles like any texture file (never all atlases decoded at once); external
// ones by path (loaded later by formats/image_io.h). External
// images and buffers are confined to the input's folder (resolveReference). Every accessor is
// checked against its buffer view and buffer before it is read: corrupt files give
// InputError("FILE: problem").
#include "pipeline/read_gltf_load.h"

#include <array>
#include <cmath>
#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <cstring>

namespace hlod {
namespace {

using Matrix = std::array<double, 16>;  // column-major, as glTF

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) r[c * 4 + row] += a[k * 4 + row] * b[c * 4 + k];
    return r;
}

Matrix localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Matrix m;
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    const auto& t = node.translation.size() == 3 ? node.translation : std::vector<double>{0, 0, 0};
    const auto& q = node.rotation.size() == 4 ? node.rotation : std::vector<double>{0, 0, 0, 1};
    const auto& s = node.scale.size() == 3 ? node.scale : std::vector<double>{1, 1, 1};
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const Matrix r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
                      2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
                      2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
                      0,                       0,                       0,                       1};
    Matrix m = r;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) m[c * 4 + row] *= s[c];
    m[12] = t[0], m[13] = t[1], m[14] = t[2];
    return m;
}

// Cofactors of the upper 3x3 (= determinant x inverse transpose), column-major like m.
std::array<double, 9> cofactors(const Matrix& m) {
    const auto e = [&](int row, int col) { return m[col * 4 + row]; };
    std::array<double, 9> c{};
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) {
            const int r1 = (row + 1) % 3, r2 = (row + 2) % 3, c1 = (col + 1) % 3, c2 = (col + 2) % 3;
            c[col * 3 + row] = e(r1, c1) * e(r2, c2) - e(r1, c2) * e(r2, c1);
        }
    return c;
}

double determinant(const Matrix& m) {
    const std::array<double, 9> c = cofactors(m);
    return m[0] * c[0] + m[4] * c[3] + m[8] * c[6];
}

struct Context {
    const tinygltf::Model& model;
    const std::string& path;
    const ReadOptions& options;
    RawMesh& raw;
    GltfMaterials materials;
    bool keepNormals = true, keepColors = true, keepTexcoords = false;  // every primitive has them / textured
    uint32_t skippedPrimitives = 0;
    // Vertices already added, by (POSITION, TEXCOORD_n, NORMAL, COLOR_0 accessors, node instance,
    // the material whose KHR_texture_transform moved its UVs or -1): primitives that share one
    // vertex buffer (one primitive per material over common accessors) share its vertices instead
    // of adding a copy each. Value: first index, vertex count.
    std::map<std::array<int, 6>, std::pair<uint32_t, size_t>> added;
};

// Accessor `index` located in its buffer: element i's first byte is data + stride * i, and
// `count` elements of `components` x componentType lie inside both its buffer view and buffer.
struct Located {
    const unsigned char* data = nullptr;
    size_t stride = 0, count = 0;
    int components = 0, componentType = 0;
    bool normalized = false;
};

Located locate(const Context& cx, int index, const std::string& what) {
    const tinygltf::Model& model = cx.model;
    const std::string name = cx.path + ": " + what + " accessor " + std::to_string(index);
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) throw InputError(name + " does not exist");
    const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(index)];
    if (a.sparse.isSparse) throw InputError(name + " is sparse (not supported)");
    if (a.bufferView < 0 || static_cast<size_t>(a.bufferView) >= model.bufferViews.size())
        throw InputError(name + " has no valid buffer view (corrupt or undecodable)");
    const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(a.bufferView)];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
        throw InputError(name + ": its buffer view has no valid buffer");
    const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
    Located l;
    l.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    l.componentType = a.componentType;
    l.normalized = a.normalized;
    const int bytes = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const int stride = a.ByteStride(view);
    if (l.components <= 0 || bytes <= 0 || stride <= 0) throw InputError(name + " has an unknown type or stride");
    l.stride = static_cast<size_t>(stride);
    l.count = a.count;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
        throw InputError(name + ": buffer view " + std::to_string(a.bufferView) + " runs past its buffer (truncated file?)");
    const size_t element = static_cast<size_t>(l.components) * static_cast<size_t>(bytes);
    const size_t room = a.byteOffset <= view.byteLength ? view.byteLength - a.byteOffset : 0;  // bytes from the first element
    if (a.byteOffset > view.byteLength || (l.count > 0 && (element > room || l.count - 1 > (room - element) / l.stride)))
        throw InputError(name + " runs past its buffer view (truncated file?)");
    l.data = data.data() + view.byteOffset + a.byteOffset;
    return l;
}

// Accessor `index` as floats, `width` = its components (minWidth..maxWidth); normalised
// integers map to [0, 1] (unsigned) or [-1, 1] (signed).
std::vector<float> readFloats(const Context& cx, int index, int minWidth, int maxWidth, const std::string& what, int& width) {
    const Located l = locate(cx, index, what);
    if (l.components < minWidth || l.components > maxWidth)
        throw InputError(cx.path + ": " + what + " accessor " + std::to_string(index) + " has " + std::to_string(l.components) +
                         " components");
    width = l.components;
    std::vector<float> out;
    out.reserve(l.count * static_cast<size_t>(width));
    for (size_t i = 0; i < l.count; ++i)
        for (int c = 0; c < width; ++c) {
            const unsigned char* p = l.data + l.stride * i;
            float v = 0;
            switch (l.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p + 4 * c, 4); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = p[c] / (l.normalized ? 255.0f : 1.0f); break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                const float s = static_cast<float>(static_cast<int8_t>(p[c]));
                v = l.normalized ? std::max(s / 127.0f, -1.0f) : s;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p + 2 * c, 2);
                v = u / (l.normalized ? 65535.0f : 1.0f);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t s;
                std::memcpy(&s, p + 2 * c, 2);
                v = l.normalized ? std::max(s / 32767.0f, -1.0f) : static_cast<float>(s);
                break;
            }
            default:
                throw InputError(cx.path + ": " + what + " accessor " + std::to_string(index) + " has unsupported component type " +
                                 std::to_string(l.componentType));
            }
            out.push_back(v);
        }
    return out;
}

// A per-vertex attribute: `width` components for each of the primitive's `count` vertices.
std::vector<float> readAttribute(const Context& cx, int index, int width, const std::string& what, size_t count) {
    int actual = 0;
    std::vector<float> values = readFloats(cx, index, width, width, what, actual);
    if (values.size() != count * static_cast<size_t>(width)) throw InputError(cx.path + ": " + what + " count differs from POSITION");
    return values;
}

std::vector<uint32_t> readIndices(const Context& cx, int index) {
    const Located l = locate(cx, index, "index");
    const int t = l.componentType;
    if (l.components != 1 || (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                              t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        throw InputError(cx.path + ": index accessor " + std::to_string(index) + " is not unsigned integer scalars");
    std::vector<uint32_t> out(l.count);
    for (size_t i = 0; i < l.count; ++i) {
        const unsigned char* p = l.data + l.stride * i;
        if (t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            out[i] = p[0];
        } else if (t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            uint16_t u;
            std::memcpy(&u, p, 2);
            out[i] = u;
        } else {
            std::memcpy(&out[i], p, 4);
        }
    }
    return out;
}

void addNormals(Context& cx, int index, size_t count, const Matrix& m, bool mirrored) {
    const std::vector<float> n = readAttribute(cx, index, 3, "NORMAL", count);
    const std::array<double, 9> c = cofactors(m);
    const double sign = mirrored ? -1 : 1;
    for (size_t i = 0; i < count; ++i) {
        double v[3], length = 0;
        for (int r = 0; r < 3; ++r) {
            v[r] = sign * (c[r] * n[3 * i] + c[3 + r] * n[3 * i + 1] + c[6 + r] * n[3 * i + 2]);
            length += v[r] * v[r];
        }
        length = std::sqrt(length);
        float out[3];
        for (int r = 0; r < 3; ++r) out[r] = static_cast<float>(length > 0 ? v[r] / length : v[r]);
        cx.raw.addNormal(out, cx.path);
    }
}

void addColors(Context& cx, int index, size_t count) {
    int width = 0;
    const std::vector<float> c = readFloats(cx, index, 3, 4, "COLOR_0", width);
    if (c.size() != count * static_cast<size_t>(width)) throw InputError(cx.path + ": COLOR_0 count differs from POSITION");
    for (size_t i = 0; i < count; ++i) {
        uint8_t rgba[4];
        for (int k = 0; k < 4; ++k) {
            const float v = k < width ? c[i * static_cast<size_t>(width) + static_cast<size_t>(k)] : 1.0f;
            if (!std::isfinite(v)) throw InputError(cx.path + ": COLOR_0 of vertex " + std::to_string(i) + " is NaN/Inf");
            rgba[k] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
        cx.raw.colors.push(rgba, 4);
    }
}

bool isTriangles(const tinygltf::Primitive& prim) {
    return prim.mode == -1 || prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

// A primitive's vertex sequence as a triangle list (glTF 2.0 §3.7.2.1, "Topology types"): a
// TRIANGLE_STRIP's triangle i is {v_i, v_(i + 1 + i % 2), v_(i + 2 - i % 2)}, a TRIANGLE_FAN's
// {v_(i + 1), v_(i + 2), v_0}. A strip's triangles that repeat a vertex are left out: they join
// one strip to the next and have no area (a list's or a fan's are the input's, for the build to
// count as degenerate).
std::vector<uint32_t> triangleList(int mode, std::vector<uint32_t> v) {
    if (mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) return v;
    std::vector<uint32_t> list;
    for (size_t i = 0; i + 2 < v.size(); ++i) {
        const bool strip = mode == TINYGLTF_MODE_TRIANGLE_STRIP;
        const uint32_t t[3] = {strip ? v[i] : v[i + 1], strip ? v[i + 1 + i % 2] : v[i + 2], strip ? v[i + 2 - i % 2] : v[0]};
        if (!strip || (t[0] != t[1] && t[1] != t[2] && t[0] != t[2])) list.insert(list.end(), t, t + 3);
    }
    return list;
}

int attributeOf(const tinygltf::Primitive& prim, const char* name) {
    const auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
}

// Vertices are numbered in 32 bits (RawTriangle): past 2^32 - 1 the numbers wrapped onto earlier
// vertices without a word until stop 47 (a 3 MB glTF of 65,537 instances of a 65,536-vertex mesh).
void checkVertexCount(uint64_t vertices, const std::string& path) {
    if (vertices > std::numeric_limits<uint32_t>::max())
        throw InputError(path + ": " + std::to_string(vertices) + " vertices over its node instances, more than the " +
                         std::to_string(std::numeric_limits<uint32_t>::max()) + " hlod numbers");
}

// The primitive's vertices in raw (added unless an earlier primitive of the same node instance
// added the same accessors): its first index and count.
std::pair<uint32_t, size_t> addVertices(Context& cx, const tinygltf::Primitive& prim, const Matrix& m, int instance) {
    const auto attr = [&](const char* name) { return attributeOf(prim, name); };
    const bool known = prim.material >= 0 && static_cast<size_t>(prim.material) < cx.materials.uvOfGltf.size();
    const UvMapping uvMap = known ? cx.materials.uvOfGltf[static_cast<size_t>(prim.material)] : UvMapping{};
    const std::string uvName = "TEXCOORD_" + std::to_string(uvMap.set);
    const std::array<int, 6> key{attr("POSITION"), attr(uvName.c_str()), attr("NORMAL"), attr("COLOR_0"), instance,
                                 uvMap.identity() ? -1 : prim.material};
    if (const auto it = cx.added.find(key); it != cx.added.end()) return it->second;
    int width = 0;
    const std::vector<float> pos = readFloats(cx, attr("POSITION"), 3, 3, "POSITION", width);
    const size_t count = pos.size() / 3;
    RawMesh& raw = cx.raw;
    checkVertexCount(raw.positionCount() + count, cx.path);  // the tally before the read counts no UV copies
    const uint32_t base = static_cast<uint32_t>(raw.positionCount());
    for (size_t i = 0; i < count; ++i) {
        double p[3];
        for (int r = 0; r < 3; ++r) p[r] = m[r] * pos[3 * i] + m[4 + r] * pos[3 * i + 1] + m[8 + r] * pos[3 * i + 2] + m[12 + r];
        raw.addPosition(p, cx.path);
    }
    if (cx.keepTexcoords) {
        const std::vector<float> uv =
            attr(uvName.c_str()) >= 0 ? readAttribute(cx, attr(uvName.c_str()), 2, uvName, count) : std::vector<float>(2 * count, 0.0f);
        const std::array<double, 6>& a = uvMap.affine;
        for (size_t i = 0; i < count; ++i) {
            const double u = uv[2 * i], v = uv[2 * i + 1];
            raw.addTexcoord(static_cast<float>(a[0] * u + a[2] * v + a[4]), static_cast<float>(a[1] * u + a[3] * v + a[5]), cx.path);
        }
    }
    if (cx.keepNormals) addNormals(cx, attr("NORMAL"), count, m, determinant(m) < 0);
    if (cx.keepColors) addColors(cx, attr("COLOR_0"), count);
    return cx.added[key] = {base, count};
}

void addPrimitive(Context& cx, const tinygltf::Primitive& prim, const Matrix& m, int instance) {
    if (!isTriangles(prim)) {
        ++cx.skippedPrimitives;
        return;
    }
    const auto attr = [&](const char* name) { return attributeOf(prim, name); };
    if (attr("POSITION") < 0) throw InputError(cx.path + ": primitive without POSITION");
    const auto [base, count] = addVertices(cx, prim, m, instance);
    RawMesh& raw = cx.raw;
    const bool mirrored = determinant(m) < 0;
    std::vector<uint32_t> indices = prim.indices >= 0 ? readIndices(cx, prim.indices) : std::vector<uint32_t>(count);
    if (prim.indices < 0)
        for (size_t i = 0; i < count; ++i) indices[i] = static_cast<uint32_t>(i);
    indices = triangleList(prim.mode, std::move(indices));
    const uint32_t material = prim.material >= 0 && static_cast<size_t>(prim.material) < cx.materials.materialOfGltf.size()
                                  ? cx.materials.materialOfGltf[static_cast<size_t>(prim.material)]
                                  : static_cast<uint32_t>(raw.materials.size() - 1);
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        RawTriangle tri;
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = indices[t + (mirrored && k > 0 ? 3 - k : k)];
            if (i >= count) throw InputError(cx.path + ": index " + std::to_string(i) + " out of range (" + std::to_string(count) + " vertices)");
            tri.position[k] = tri.texcoord[k] = tri.normal[k] = base + i;
        }
        tri.material = material;
        raw.addTriangle(tri);
    }
}

// Every TRIANGLES-or-not primitive of the default scene's node tree (every root node when there
// is no scene) with its node's world transform and the node visit's number, in document order.
constexpr int kMaxNodeDepth = 1000;

template <class Visit>
void visitNode(const Context& cx, int index, const Matrix& parent, int depth, Visit& visit, int& visits) {
    if (index < 0 || index >= static_cast<int>(cx.model.nodes.size()))
        throw InputError(cx.path + ": corrupt node tree (node " + std::to_string(index) + " does not exist)");
    if (depth > kMaxNodeDepth)  // each level a stack frame
        throw InputError(cx.path + ": node tree deeper than " + std::to_string(kMaxNodeDepth) + " levels (not supported)");
    const tinygltf::Node& node = cx.model.nodes[static_cast<size_t>(index)];
    const Matrix m = multiply(parent, localMatrix(node));
    const int instance = visits++;
    if (node.mesh >= 0 && node.mesh < static_cast<int>(cx.model.meshes.size()))
        for (const auto& prim : cx.model.meshes[static_cast<size_t>(node.mesh)].primitives) visit(prim, m, instance);
    for (int child : node.children) visitNode(cx, child, m, depth + 1, visit, visits);
}

// glTF 2.0 §3.5.3 "the node hierarchy MUST be a set of disjoint strict trees": a node reached
// twice (two parents, a root listed twice or also a child) is refused, as its subtree would be
// visited once per path to it, 2^depth times for a chain of shared pairs.
void checkStrictTrees(const Context& cx, int scene) {
    const tinygltf::Model& model = cx.model;
    std::vector<uint8_t> reached(model.nodes.size());
    auto reach = [&](int n) {
        if (n >= 0 && static_cast<size_t>(n) < reached.size() && reached[static_cast<size_t>(n)]++)
            throw InputError(cx.path + ": node " + std::to_string(n) + " is reached twice (glTF node trees are strict trees)");
    };
    for (const auto& node : model.nodes)
        for (int c : node.children) reach(c);
    if (scene < static_cast<int>(model.scenes.size()))
        for (int n : model.scenes[static_cast<size_t>(scene)].nodes) reach(n);
}

template <class Visit>
void visitScene(const Context& cx, Visit visit) {
    const tinygltf::Model& model = cx.model;
    const Matrix identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (model.defaultScene >= 0 && scene >= static_cast<int>(model.scenes.size()))  // all root nodes until stop 46
        throw InputError(cx.path + ": corrupt glTF (scene " + std::to_string(scene) + " does not exist; " +
                         std::to_string(model.scenes.size()) + " scenes)");
    checkStrictTrees(cx, scene);
    int visits = 0;
    if (scene < static_cast<int>(model.scenes.size())) {
        for (int node : model.scenes[static_cast<size_t>(scene)].nodes) visitNode(cx, node, identity, 0, visit, visits);
        return;
    }
    std::vector<bool> isChild(model.nodes.size());
    for (const auto& node : model.nodes)
        for (int c : node.children)
            if (c >= 0 && static_cast<size_t>(c) < isChild.size()) isChild[static_cast<size_t>(c)] = true;
    for (size_t n = 0; n < model.nodes.size(); ++n)
        if (!isChild[n]) visitNode(cx, static_cast<int>(n), identity, 0, visit, visits);
}

// Primitives whose morph targets (glTF 2.0 §3.7.2.2) a non-zero default weight of their mesh or of a
// node using it would move: built at their base positions (ignored without a word until stop 46).
size_t morphedPrimitives(const tinygltf::Model& model) {
    const auto weighted = [](const std::vector<double>& w) { return std::any_of(w.begin(), w.end(), [](double x) { return x != 0; }); };
    std::vector<bool> moved(model.meshes.size());
    for (size_t i = 0; i < moved.size(); ++i) moved[i] = weighted(model.meshes[i].weights);
    for (const tinygltf::Node& node : model.nodes)
        if (node.mesh >= 0 && static_cast<size_t>(node.mesh) < moved.size() && weighted(node.weights)) moved[size_t(node.mesh)] = true;
    size_t morphed = 0;
    for (size_t i = 0; i < moved.size(); ++i)
        if (moved[i])
            for (const tinygltf::Primitive& prim : model.meshes[i].primitives) morphed += !prim.targets.empty();
    return morphed;
}

// Parses `bytes` (read_gltf_load.cpp) and appends its triangles to `raw` (not sealed).
void convert(const uint8_t* bytes, size_t size, bool binary, const std::string& path, const ReadOptions& options,
             RawMesh& raw, EmbeddedImages& images) {
    const tinygltf::Model model = loadGltfModel(bytes, size, binary, path, options, images);
    Context cx{model, path, options, raw, addGltfMaterials(model, images, path, options, raw), true, true, false, 0, {}};
    std::map<uint32_t, std::string> withoutUvs;  // textured materials a primitive uses without its TEXCOORD_n
    std::set<std::pair<int, int>> instances;      // (POSITION accessor, node instance): the vertices added
    uint64_t vertices = raw.positionCount();
    visitScene(cx, [&](const tinygltf::Primitive& prim, const Matrix&, int instance) {
        if (!isTriangles(prim)) return;
        const int position = attributeOf(prim, "POSITION");
        if (position >= 0 && instances.insert({position, instance}).second)
            vertices += locate(cx, position, "POSITION").count;  // a count its buffer view holds
        cx.keepNormals = cx.keepNormals && attributeOf(prim, "NORMAL") >= 0;
        cx.keepColors = cx.keepColors && attributeOf(prim, "COLOR_0") >= 0;
        const size_t g = static_cast<size_t>(prim.material);
        if (prim.material < 0 || g >= cx.materials.materialOfGltf.size()) return;
        const Material& m = raw.materials[cx.materials.materialOfGltf[g]];
        const std::string uvName = "TEXCOORD_" + std::to_string(cx.materials.uvOfGltf[g].set);
        if ((m.image || !m.texturePath.empty()) && attributeOf(prim, uvName.c_str()) < 0)
            withoutUvs.emplace(cx.materials.materialOfGltf[g], "material " + std::to_string(g) + " needs " + uvName);
    });
    // The textures rule (README "Textures: one rule"): every UV at 0 painted the surface one texel's
    // colour, with status 0 even with --strict, until stop 46.
    for (const auto& [index, needs] : withoutUvs) {
        Material& m = raw.materials[index];
        raw.stats.textureProblems.push_back({path + ": " + needs + " for its texture, which a primitive using it lacks", m.name});
        m.texturePath.clear(), m.image.reset();
    }
    checkVertexCount(vertices, path);  // before any is read: each node instance adds its mesh's again
    for (const Material& m : raw.materials) cx.keepTexcoords = cx.keepTexcoords || m.image || !m.texturePath.empty();
    visitScene(cx, [&](const tinygltf::Primitive& prim, const Matrix& m, int instance) { addPrimitive(cx, prim, m, instance); });
    if (const size_t morphed = morphedPrimitives(model))
        raw.stats.warnings.push_back(path + ": " + std::to_string(morphed) +
                                     " primitives have weighted morph targets, which hlod does not apply: built at their base positions");
    if (cx.skippedPrimitives)
        raw.stats.warnings.push_back(path + ": " + std::to_string(cx.skippedPrimitives) + " primitives that are not triangles skipped");
    raw.sharedIndices = true;
    raw.hasTexcoords = cx.keepTexcoords;
    raw.hasNormals = cx.keepNormals;
}

}  // namespace

SourceMesh readGltf(const std::string& path, const ReadOptions& options) {
    RawMesh raw;
    parseGltf(path, raw, options);
    return toSourceMesh(raw, path);
}

SourceMesh readGltfBytes(const std::vector<uint8_t>& bytes, bool binary, const std::string& path, const ReadOptions& options) {
    RawMesh raw;
    raw.offset = options.offset;
    EmbeddedImages images{options.imageDir, {}, {}};
    if (!images.dir.empty()) std::filesystem::create_directories(images.dir);
    convert(bytes.data(), bytes.size(), binary, path, options, raw, images);
    raw.seal();
    return toSourceMesh(raw, path);
}

void parseGltf(const std::string& path, RawMesh& raw, const ReadOptions& options) {
    raw.offset = options.offset;
    EmbeddedImages images{options.imageDir, {}, {}};
    if (!images.dir.empty()) std::filesystem::create_directories(images.dir);
    {
        const MappedFile file(path);
        const bool glb = isGlb(path);
        if (glb && !images.dir.empty()) checkGltfJson(file.data, file.size, true, path);  // before its images are written
        const std::vector<uint8_t> compact = glb && !images.dir.empty() ? glbWithoutImages(file, images) : std::vector<uint8_t>{};
        if (compact.empty()) convert(file.data, file.size, glb, path, options, raw, images);
        else convert(compact.data(), compact.size(), true, path, options, raw, images);
        if (raw.progress) raw.progress->advance(file.size);
    }
    raw.seal();
}

}  // namespace hlod
