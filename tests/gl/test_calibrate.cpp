// Calibration of the render-time model (thesis §3.3 eq. 3.1, Table 6.1 c_textured): the line
// fit, the weight derivation, the synthetic batches, the whole procedure against a renderer
// with a known linear cost, and the constants file it writes.
#include "formats/constants.h"
#include "player/cost_model_renderer.h"
#include "player/gl/gl_renderer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace hlod {
namespace {

// A renderer whose frame time is exactly overhead + a * textured + b * untextured triangles.
class LinearRenderer final : public Renderer {
public:
    // perPixel: ms per pixel the calibration grid covers in a `viewport`-pixel view, from the
    // camera's distance (it spans 0.8 x 0.8 of a 16:9 view at calibrationCamera's distance).
    LinearRenderer(double overhead, double a, double b, double perPixel = 0, double viewport = 0)
        : overhead_(overhead), a_(a), b_(b), perPixel_(perPixel), viewport_(viewport) {}
    std::string name() const override { return "linear test renderer"; }
    void upload(DecodedNode&& node) override {
        double t = 0, u = 0;
        for (size_t i = 0; i < node.meshes.size(); ++i)
            (node.meshTexture[i] >= 0 ? t : u) += static_cast<double>(node.meshes[i].triangleCount());
        nodes_[node.id] = {t, u};
    }
    void evict(uint32_t node) override { nodes_.erase(node); }
    double drawFrame(const Camera& camera, std::span<const DrawItem> items, const FrameOptions&) override {
        double ms = overhead_;
        const double k = camera.position[2] / calibrationCamera(16.0 / 9.0).position[2];
        for (const DrawItem& item : items) {
            const auto it = nodes_.find(item.node);
            if (it != nodes_.end()) ms += a_ * it->second.first + b_ * it->second.second + perPixel_ * 0.64 * viewport_ / (k * k);
        }
        return ms;
    }
    size_t resident() const { return nodes_.size(); }

private:
    double overhead_, a_, b_, perPixel_, viewport_;
    std::map<uint32_t, std::pair<double, double>> nodes_;
};

TEST(Calibrate, FitLineRecoversAnExactLine) {
    const std::vector<double> x = {1, 2, 4, 8}, y = {5, 7, 11, 19};
    const LinearFit fit = fitLine(x, y);
    EXPECT_NEAR(fit.intercept, 3, 1e-9);
    EXPECT_NEAR(fit.slope, 2, 1e-9);
}

TEST(Calibrate, FitLineIsLeastSquares) {
    const std::vector<double> x = {0, 1, 2}, y = {0, 2, 1};
    const LinearFit fit = fitLine(x, y);
    EXPECT_NEAR(fit.slope, 0.5, 1e-9);
    EXPECT_NEAR(fit.intercept, 0.5, 1e-9);
}

TEST(Calibrate, FitLineRejectsDegenerateInput) {
    const std::vector<double> one = {1}, same = {2, 2}, two = {1, 2};
    EXPECT_THROW(fitLine(one, one), std::invalid_argument);
    EXPECT_THROW(fitLine(same, two), std::invalid_argument);
    EXPECT_THROW(fitLine(two, one), std::invalid_argument);
}

TEST(Calibrate, TexturedWeightMatchesTheRatioOfTriangleTimes) {
    // eq. 3.1: c / (1 - c) = perTextured / perUntextured
    const double c = texturedWeight(3e-4, 1e-4);
    EXPECT_NEAR(c, 0.75, 1e-12);
    EXPECT_NEAR(c / (1 - c), 3.0, 1e-9);
    EXPECT_NEAR(texturedWeight(1, 1), 0.5, 1e-12);
    EXPECT_THROW(texturedWeight(0, 1), std::invalid_argument);
    EXPECT_THROW(texturedWeight(1, -1), std::invalid_argument);
}

TEST(Calibrate, BatchesHaveAboutTheRequestedTrianglesInView) {
    for (uint32_t n : {2u, 1000u, 50000u}) {
        for (bool textured : {false, true}) {
            const DecodedNode node = calibrationBatch(9, n, textured);
            ASSERT_EQ(node.meshes.size(), 1u);
            const MeshData& m = node.meshes[0];
            EXPECT_NEAR(static_cast<double>(m.triangleCount()), n, 0.05 * n + 2);
            for (uint32_t i : m.indices) ASSERT_LT(i, m.vertexCount());
            EXPECT_EQ(m.texcoords.size(), textured ? 2 * m.vertexCount() : 0u);
            EXPECT_EQ(node.textures.size(), textured ? 1u : 0u);
            EXPECT_EQ(node.meshTexture[0], textured ? 0 : -1);
        }
    }
    // The grid stays inside the view of calibrationCamera (|x| <= aspect, |y| <= 1 at z = 0).
    const DecodedNode node = calibrationBatch(1, 1000, false);
    for (size_t i = 0; i < node.meshes[0].positions.size(); i += 3) {
        EXPECT_LE(std::abs(node.meshes[0].positions[i]), 16.0 / 9.0);
        EXPECT_LE(std::abs(node.meshes[0].positions[i + 1]), 1.0);
    }
}

TEST(Calibrate, RecoversTheCostsOfALinearRenderer) {
    LinearRenderer renderer(2.0, 3e-4, 1e-4);
    CalibrationOptions options;
    options.frames = 3;
    const Calibration c = calibrate(renderer, 16.0 / 9.0, options);
    EXPECT_EQ(c.renderer, "linear test renderer");
    EXPECT_NEAR(c.fixedOverheadMs, 2.0, 1e-9);
    EXPECT_NEAR(c.textured.slope, 3e-4, 1e-9);
    EXPECT_NEAR(c.untextured.slope, 1e-4, 1e-9);
    EXPECT_NEAR(c.textured.intercept, 2.0, 1e-6);
    EXPECT_NEAR(c.cTextured, 0.75, 1e-6);
    EXPECT_NEAR(c.msPerCost, 4e-4, 1e-9);
    EXPECT_EQ(c.samples.size(), 2 * options.triangleCounts.size());
    EXPECT_EQ(renderer.resident(), 0u) << "batches are evicted";
    // A node's eq. 3.1 cost times msPerCost is its measured time (above the overhead).
    const double cost = nodeCost(1000, 500, c.cTextured);
    EXPECT_NEAR(cost * c.msPerCost, 1000 * 3e-4 + 500 * 1e-4, 1e-6);
}

TEST(Calibrate, RecoversThePerPixelCost) {
    LinearRenderer renderer(2.0, 3e-4, 1e-4, 2e-6, 320 * 180);
    CalibrationOptions options;
    options.frames = 1;
    options.viewportPixels = 320 * 180;
    const Calibration c = calibrate(renderer, 16.0 / 9.0, options);
    EXPECT_NEAR(c.msPerPixel, 2e-6, 1e-12);
    ASSERT_EQ(c.pixelSamples.size(), options.pixelDistances.size());
    EXPECT_NEAR(c.pixelSamples[0].first, 0.64 * 320 * 180, 1e-6);  // the grid's coverage at distance 1
    EXPECT_EQ(renderer.resident(), 0u);
}

// Why the solver policies' pixel_ms is 0 on the cost model (player/SOLVERS.md "Per-pixel term"):
// its frame time never depends on what a node covers.
TEST(Calibrate, CostModelRendererHasNoPerPixelTerm) {
    CostModel model;
    model.noise = 0;
    CostModelRenderer renderer(model);
    CalibrationOptions options;
    options.frames = 1;
    options.viewportPixels = 1280 * 720;
    const Calibration c = calibrate(renderer, 16.0 / 9.0, options);
    EXPECT_LT(c.msPerPixel, 1e-15);  // the fit of a constant: zero up to rounding
    EXPECT_NEAR(c.fixedOverheadMs, model.overheadMs, 1e-9);
    EXPECT_NEAR(c.textured.slope, model.msPerTexturedTriangle, 1e-12);
}

TEST(Calibrate, FailsWhenTimeDoesNotGrowWithTriangles) {
    LinearRenderer renderer(5.0, 0, 1e-4);
    EXPECT_THROW(calibrate(renderer, 16.0 / 9.0, {}), std::runtime_error);
}

TEST(Calibrate, WritesACalibrationFileThatReadCalibrationReads) {
    LinearRenderer renderer(2.0, 3e-4, 1e-4);
    const Calibration c = calibrate(renderer, 16.0 / 9.0, {});
    const auto path = std::filesystem::temp_directory_path() / "hlod_calibrate_test.conf";
    writeCalibration(c, path.string());
    const Calibration read = readCalibration(path.string());
    EXPECT_NEAR(read.cTextured, 0.75, 1e-6);
    EXPECT_NEAR(read.msPerCost, 4e-4, 1e-9);
    EXPECT_NEAR(read.fixedOverheadMs, 2, 1e-6);
    EXPECT_NEAR(read.textured.slope, c.textured.slope, 1e-9);
    EXPECT_NEAR(read.untextured.intercept, c.untextured.intercept, 1e-6);
    EXPECT_EQ(read.renderer, c.renderer);
    EXPECT_EQ(read.msPerPixel, 0);
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
    Calibration withPixels = c;
    withPixels.msPerPixel = 3.5e-6;
    writeCalibration(withPixels, path.string());
    EXPECT_DOUBLE_EQ(readCalibration(path.string()).msPerPixel, 3.5e-6);
    std::ofstream(path) << "c_textured = 0.5\nms_per_cost = 0.001\nfixed_overhead_ms = 1\nms_per_pixel = -1e-6\n";
    EXPECT_THROW(readCalibration(path.string()), InputError);  // a per-pixel cost is never negative

    std::ofstream(path) << "c_textured = 0.5\nms_per_cost = 0.001\nfixed_overhead_ms = 1\nwhat = 3\n";
    EXPECT_THROW(readCalibration(path.string()), InputError);  // an unknown name
    std::ofstream(path) << "c_textured = 1.5\nms_per_cost = 0.001\nfixed_overhead_ms = 1\n";
    EXPECT_THROW(readCalibration(path.string()), InputError);  // c_textured outside (0, 1]
    std::ofstream(path) << "c_textured = 0.5\nms_per_cost = 0.001\nfixed_overhead_ms = 1\ntextured_intercept_ms = -0.2\n";
    EXPECT_DOUBLE_EQ(readCalibration(path.string()).textured.intercept, -0.2);  // a fitted intercept may be negative
    std::ofstream(path) << "c_textured = 0.5\nms_per_cost = -0.001\nfixed_overhead_ms = 1\n";
    EXPECT_THROW(readCalibration(path.string()), InputError);
    std::filesystem::remove(path);
}

TEST(Calibrate, UnwritablePathGivesOneLineNamingIt) {
    LinearRenderer renderer(2.0, 3e-4, 1e-4);
    const Calibration c = calibrate(renderer, 16.0 / 9.0, {});
    const std::string path = "/nonexistent-dir/hlod.conf";
    try {
        writeCalibration(c, path);
        FAIL() << "wrote into a missing directory";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
    // A folder where the file should go: the temporary beside it is removed, nothing replaced.
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("hlod_calib_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder / "c.conf");
    EXPECT_THROW(writeCalibration(c, (folder / "c.conf").string()), std::runtime_error);
    size_t entries = 0;
    for (const auto& e : std::filesystem::directory_iterator(folder)) entries += e.path().filename() != "c.conf";
    EXPECT_EQ(entries, 0u) << "a temporary was left beside the output";
    EXPECT_TRUE(std::filesystem::is_directory(folder / "c.conf"));
    std::filesystem::remove_all(folder);
}

TEST(Calibrate, MeasuresTheOpenGlRendererWhenAvailable) {
    std::unique_ptr<Renderer> renderer;
    try {
        renderer = makeGlRenderer({320, 180, false, false});
    } catch (const NoGlContext& e) {
        GTEST_SKIP() << "no EGL OpenGL context: " << e.what();
    }
    CalibrationOptions options;
    options.triangleCounts = {1000, 60000};
    options.frames = 3;
    const Calibration c = calibrate(*renderer, 16.0 / 9.0, options);
    // What the run measured: one untextured and one textured batch per count, of about that many
    // triangles, on the renderer given; the fits and weights come from those samples (whether the
    // times grow is this machine's speed, a benchmark's business, not asserted here).
    EXPECT_EQ(c.renderer, renderer->name());
    ASSERT_EQ(c.samples.size(), 2 * options.triangleCounts.size());
    for (size_t i = 0; i < c.samples.size(); ++i) {
        const CalibrationSample& s = c.samples[i];
        EXPECT_EQ(s.textured, i % 2 == 1) << i;
        EXPECT_NEAR(double(s.triangles), double(options.triangleCounts[i / 2]), 0.1 * options.triangleCounts[i / 2]) << i;
        EXPECT_GT(s.ms, 0.0) << i;
    }
    EXPECT_DOUBLE_EQ(c.cTextured, texturedWeight(c.textured.slope, c.untextured.slope));
    EXPECT_DOUBLE_EQ(c.msPerCost, c.textured.slope + c.untextured.slope);
}

}  // namespace
}  // namespace hlod
