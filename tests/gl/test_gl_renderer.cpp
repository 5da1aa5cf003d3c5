// The OpenGL renderer through EGL (Mesa llvmpipe here): uploads, draws, reads pixels back,
// shades by level, evicts, and rejects inconsistent nodes. Skips when no EGL context exists.
#include "player/gl/gl_renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <stdexcept>

namespace hlod {
namespace {

constexpr int kWidth = 160, kHeight = 90;

std::unique_ptr<Renderer> makeOrSkip(bool timerQueries = false) {
    try {
        return makeGlRenderer({kWidth, kHeight, false, timerQueries});
    } catch (const NoGlContext&) {  // any other failure fails the test
        return nullptr;
    }
}

#define RENDERER_OR_SKIP(var, ...)                                              \
    auto var = makeOrSkip(__VA_ARGS__);                                         \
    if (!var) GTEST_SKIP() << "no EGL OpenGL 3.3 context can be created here"

// A quad in the plane z = 0 spanning [x0, x1] x [y0, y1], facing +Z (the camera).
MeshData quad(float x0, float x1, float y0, float y1, bool texcoords) {
    MeshData m;
    m.positions = {x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y1, 0};
    if (texcoords) m.texcoords = {0, 0, 1, 0, 1, 1, 0, 1};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

DecodedNode texturedQuad(uint32_t id, float x0, float x1, float y0, float y1, std::array<uint8_t, 3> rgb) {
    DecodedNode node;
    node.id = id;
    node.meshes.push_back(quad(x0, x1, y0, y1, true));
    node.meshTexture = {0};
    Image image{4, 4, 3, {}};
    for (int i = 0; i < 16; ++i) image.pixels.insert(image.pixels.end(), rgb.begin(), rgb.end());
    node.textures.push_back(std::move(image));
    return node;
}

DecodedNode flatQuad(uint32_t id, float x0, float x1, float y0, float y1) {
    DecodedNode node;
    node.id = id;
    node.meshes.push_back(quad(x0, x1, y0, y1, false));
    node.meshTexture = {-1};
    return node;
}

// Camera at z = 2 looking down -Z: the plane z = 0 shows x in about [-2.05, 2.05], y in [-1.15, 1.15].
Camera frontCamera() {
    Camera camera;
    camera.position[2] = 2;
    camera.aspect = static_cast<double>(kWidth) / kHeight;
    return camera;
}

std::array<int, 3> pixel(const Image& image, int x, int y) {
    const uint8_t* p = &image.pixels[(static_cast<size_t>(y) * image.width + static_cast<size_t>(x)) * 3];
    return {p[0], p[1], p[2]};
}

bool near(std::array<int, 3> a, std::array<int, 3> b, int tolerance = 3) {
    for (size_t i = 0; i < 3; ++i)
        if (std::abs(a[i] - b[i]) > tolerance) return false;
    return true;
}

TEST(GlRenderer, DrawsTexturedAndFlatNodesWhereExpected) {
    RENDERER_OR_SKIP(renderer);
    EXPECT_NE(renderer->name().find("opengl"), std::string::npos);
    renderer->upload(texturedQuad(1, -1.5f, -0.5f, -0.5f, 0.5f, {255, 0, 0}));
    renderer->upload(flatQuad(2, 0.5f, 1.5f, -0.5f, 0.5f));
    const DrawItem items[] = {{1, 0}, {2, 0}};
    const double ms = renderer->drawFrame(frontCamera(), items, {});
    EXPECT_GT(ms, 0.0);
    const Image image = renderer->readPixels();
    ASSERT_EQ(image.width, static_cast<uint32_t>(kWidth));
    ASSERT_EQ(image.height, static_cast<uint32_t>(kHeight));
    ASSERT_EQ(image.channels, 3u);
    ASSERT_EQ(image.pixels.size(), size_t{kWidth} * kHeight * 3);

    const auto background = pixel(image, 2, 2);
    EXPECT_TRUE(near(pixel(image, kWidth - 3, kHeight - 3), background));
    EXPECT_TRUE(near(pixel(image, 40, 45), {255, 0, 0})) << "texture colour at the left quad";
    const auto flat = pixel(image, 120, 45);
    EXPECT_FALSE(near(flat, background)) << "flat quad drawn";
    EXPECT_EQ(flat[0], flat[1]);  // default grey vertex colour, headlight-shaded
    EXPECT_GT(flat[0], 100);      // faces the camera: fully lit
    EXPECT_TRUE(near(pixel(image, 80, 45), background)) << "gap between the quads";
}

TEST(GlRenderer, ReadPixelsReturnsTopRowFirst) {
    RENDERER_OR_SKIP(renderer);
    renderer->upload(texturedQuad(7, -3, 3, 0.2f, 3, {0, 0, 255}));  // upper part of the view only
    const DrawItem item{7, 0};
    renderer->drawFrame(frontCamera(), {&item, 1}, {});
    const Image image = renderer->readPixels();
    EXPECT_TRUE(near(pixel(image, 80, 5), {0, 0, 255}));
    EXPECT_FALSE(near(pixel(image, 80, kHeight - 5), {0, 0, 255}));
}

TEST(GlRenderer, ColorByLevelGivesOneDistinctGreyPerLevel) {
    RENDERER_OR_SKIP(renderer);
    renderer->upload(texturedQuad(1, -1.9f, -1.1f, -0.5f, 0.5f, {255, 0, 0}));
    renderer->upload(flatQuad(2, -0.9f, -0.1f, -0.5f, 0.5f));
    renderer->upload(texturedQuad(3, 0.1f, 0.9f, -0.5f, 0.5f, {0, 255, 0}));
    renderer->upload(flatQuad(4, 1.1f, 1.9f, -0.5f, 0.5f));
    const DrawItem items[] = {{1, 0}, {2, 1}, {3, 2}, {4, 5}};
    FrameOptions options;
    options.colorByLevel = true;
    renderer->drawFrame(frontCamera(), items, options);
    const Image image = renderer->readPixels();
    const int xs[] = {22, 61, 99, 138};
    std::vector<int> greys;
    for (size_t i = 0; i < 4; ++i) {
        const auto p = pixel(image, xs[i], 45);
        EXPECT_EQ(p[0], p[1]) << "node " << i << " is grey";
        EXPECT_EQ(p[1], p[2]) << "node " << i << " is grey";
        EXPECT_NEAR(p[0], levelGrey(items[i].level) * 255, 2) << "node " << i;
        greys.push_back(p[0]);
    }
    for (size_t i = 1; i < greys.size(); ++i) EXPECT_LT(greys[i - 1] + 10, greys[i]) << "finer levels are lighter";
}

TEST(GlRenderer, LevelGreysAreDistinctForEightLevels) {
    for (uint32_t a = 0; a < 8; ++a) {
        EXPECT_GT(levelGrey(a), 0.0f);
        EXPECT_LE(levelGrey(a), 1.0f);
        for (uint32_t b = a + 1; b < 8; ++b) EXPECT_GT(std::abs(levelGrey(a) - levelGrey(b)) * 255, 10);
    }
}

TEST(GlRenderer, EvictedAndUnknownNodesAreNotDrawn) {
    RENDERER_OR_SKIP(renderer);
    renderer->upload(flatQuad(3, -3, 3, -3, 3));
    const DrawItem items[] = {{3, 0}, {99, 0}};
    renderer->drawFrame(frontCamera(), items, {});
    const auto covered = pixel(renderer->readPixels(), 80, 45);
    renderer->evict(3);
    renderer->evict(3);  // twice is harmless
    renderer->drawFrame(frontCamera(), items, {});
    const auto empty = pixel(renderer->readPixels(), 80, 45);
    EXPECT_FALSE(near(covered, empty));
}

TEST(GlRenderer, ReuploadReplacesANode) {
    RENDERER_OR_SKIP(renderer);
    renderer->upload(texturedQuad(5, -3, 3, -3, 3, {255, 0, 0}));
    renderer->upload(texturedQuad(5, -3, 3, -3, 3, {0, 255, 0}));
    const DrawItem item{5, 0};
    renderer->drawFrame(frontCamera(), {&item, 1}, {});
    EXPECT_TRUE(near(pixel(renderer->readPixels(), 80, 45), {0, 255, 0}));
}

TEST(GlRenderer, DepthTestKeepsTheNearerNode) {
    RENDERER_OR_SKIP(renderer);
    DecodedNode far = texturedQuad(1, -3, 3, -3, 3, {255, 0, 0});
    DecodedNode nearer = texturedQuad(2, -0.5f, 0.5f, -0.5f, 0.5f, {0, 0, 255});
    for (size_t i = 2; i < nearer.meshes[0].positions.size(); i += 3) nearer.meshes[0].positions[i] = 0.5f;
    renderer->upload(std::move(far));
    renderer->upload(std::move(nearer));
    const DrawItem items[] = {{2, 0}, {1, 0}};  // nearer first, then the far one over it
    renderer->drawFrame(frontCamera(), items, {});
    EXPECT_TRUE(near(pixel(renderer->readPixels(), 80, 45), {0, 0, 255}));
}

TEST(GlRenderer, GreyAndVertexColouredMeshesUpload) {
    RENDERER_OR_SKIP(renderer);
    DecodedNode grey = texturedQuad(1, -3, 0, -3, 3, {0, 0, 0});
    grey.textures[0] = Image{2, 2, 1, {200, 200, 200, 200}};
    DecodedNode coloured = flatQuad(2, 0, 3, -3, 3);
    coloured.meshes[0].colors = {0, 255, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255};
    renderer->upload(std::move(grey));
    renderer->upload(std::move(coloured));
    const DrawItem items[] = {{1, 0}, {2, 0}};
    renderer->drawFrame(frontCamera(), items, {});
    const Image image = renderer->readPixels();
    EXPECT_TRUE(near(pixel(image, 40, 45), {200, 200, 200}));
    const auto green = pixel(image, 120, 45);
    EXPECT_EQ(green[0], 0);
    EXPECT_GT(green[1], 200);
}

TEST(GlRenderer, TimerQueriesMeasureAFrame) {
    RENDERER_OR_SKIP(renderer, true);
    renderer->upload(flatQuad(1, -3, 3, -3, 3));
    const DrawItem item{1, 0};
    EXPECT_GT(renderer->drawFrame(frontCamera(), {&item, 1}, {}), 0.0);
}

TEST(GlRenderer, RejectsInconsistentNodesWithOneLine) {
    RENDERER_OR_SKIP(renderer);
    DecodedNode badIndex = flatQuad(1, 0, 1, 0, 1);
    badIndex.meshes[0].indices[2] = 4;
    DecodedNode badTexture = texturedQuad(2, 0, 1, 0, 1, {1, 2, 3});
    badTexture.meshTexture[0] = 1;
    DecodedNode badPixels = texturedQuad(3, 0, 1, 0, 1, {1, 2, 3});
    badPixels.textures[0].pixels.pop_back();
    DecodedNode noTexcoords = texturedQuad(4, 0, 1, 0, 1, {1, 2, 3});
    noTexcoords.meshes[0].texcoords.clear();
    DecodedNode partial = flatQuad(5, 0, 1, 0, 1);
    partial.meshes[0].positions.pop_back();
    for (DecodedNode* node : {&badIndex, &badTexture, &badPixels, &noTexcoords, &partial}) {
        const std::string id = "node " + std::to_string(node->id) + ":";
        try {
            renderer->upload(std::move(*node));
            ADD_FAILURE() << id << " accepted";
        } catch (const std::runtime_error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(id, 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
    const DrawItem item{1, 0};
    EXPECT_GT(renderer->drawFrame(frontCamera(), {&item, 1}, {}), 0.0);  // still usable
}

TEST(GlRenderer, RejectsAbsurdFrameSizes) {
    EXPECT_THROW(makeGlRenderer({0, 720, false, false}), std::runtime_error);
    EXPECT_THROW(makeGlRenderer({1280, -1, false, false}), std::runtime_error);
    EXPECT_THROW(makeGlRenderer({100000, 720, false, false}), std::runtime_error);
}

}  // namespace
}  // namespace hlod
