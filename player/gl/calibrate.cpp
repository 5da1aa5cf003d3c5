// Calibration of the render-time model on the current machine (thesis §3.3, Table 6.1
// "c_textured: measured render time"; Funkhouser & Séquin 1993 §4 measure per-primitive costs
// the same way, full reference in player/path_gen.cpp).
// Batches of N textured and N untextured triangles are drawn; a least-squares line
// time = overhead + perTri * N per kind gives the per-triangle costs, and eq. 3.1's weight
// follows from their ratio: c_textured / (1 - c_textured) = perTextured / perUntextured.
// The fixed overhead is an empty frame (thesis §4.2 footnote: rendering disabled). The per-pixel
// term of Funkhouser & Séquin 1993 §4 (C3 x Pix(O)) and Gobbetti & Bouvier 1999 (t_pix): one
// textured batch of fixed triangle count drawn from several distances, ms fitted against the
// pixels it covers.
#include "player/gl/gl_renderer.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <utility>

namespace hlod {
namespace {

constexpr double kVfov = 60;
constexpr double kCoverage = 0.8;  // fraction of the view's width and height the grid spans

double medianFrame(Renderer& renderer, const Camera& camera, std::span<const DrawItem> items,
                   const CalibrationOptions& options) {
    for (int i = 0; i < options.warmupFrames; ++i) renderer.drawFrame(camera, items, {});
    std::vector<double> times;
    for (int i = 0; i < std::max(1, options.frames); ++i) times.push_back(renderer.drawFrame(camera, items, {}));
    std::nth_element(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2), times.end());
    return times[times.size() / 2];
}

Image checkerTexture(uint32_t size) {
    Image image{size, size, 3, std::vector<uint8_t>(size_t{size} * size * 3)};
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            uint8_t* p = &image.pixels[(size_t{y} * size + x) * 3];
            const bool dark = ((x / 32) + (y / 32)) % 2 == 0;
            p[0] = static_cast<uint8_t>(dark ? 60 : 200);
            p[1] = static_cast<uint8_t>(x & 0xFF);
            p[2] = static_cast<uint8_t>(y & 0xFF);
        }
    return image;
}

LinearFit fitSamples(const std::vector<CalibrationSample>& samples, bool textured) {
    std::vector<double> x, y;
    for (const CalibrationSample& s : samples)
        if (s.textured == textured) {
            x.push_back(s.triangles);
            y.push_back(s.ms);
        }
    return fitLine(x, y);
}

}  // namespace

LinearFit fitLine(std::span<const double> x, std::span<const double> y) {
    if (x.size() != y.size()) throw std::invalid_argument("fitLine: x and y differ in size");
    if (x.size() < 2 || std::all_of(x.begin(), x.end(), [&](double v) { return v == x[0]; }))
        throw std::invalid_argument("fitLine: needs at least two distinct x");
    Eigen::MatrixXd a(static_cast<Eigen::Index>(x.size()), 2);
    Eigen::VectorXd b(static_cast<Eigen::Index>(x.size()));
    for (size_t i = 0; i < x.size(); ++i) {
        a(static_cast<Eigen::Index>(i), 0) = 1;
        a(static_cast<Eigen::Index>(i), 1) = x[i];
        b(static_cast<Eigen::Index>(i)) = y[i];
    }
    const Eigen::Vector2d solution = a.colPivHouseholderQr().solve(b);
    return {solution(0), solution(1)};
}

double texturedWeight(double perTexturedTriMs, double perUntexturedTriMs) {
    if (!(perTexturedTriMs > 0) || !(perUntexturedTriMs > 0))
        throw std::invalid_argument("per-triangle times must be positive to weigh them (eq. 3.1)");
    return perTexturedTriMs / (perTexturedTriMs + perUntexturedTriMs);
}

Camera calibrationCamera(double aspect) {
    Camera camera;
    camera.vfovDegrees = kVfov;
    camera.aspect = aspect;
    camera.position[2] = 1.0 / std::tan(kVfov * M_PI / 360.0);  // the view spans y in [-1, 1] at z = 0
    camera.nearPlane = 0.01;
    camera.farPlane = 10;
    return camera;
}

namespace {

constexpr double kBatchAspect = 16.0 / 9.0;

// The rows and columns of quads of a batch of about `triangles` triangles.
std::pair<uint32_t, uint32_t> batchGrid(uint32_t triangles) {
    const auto rows = static_cast<uint32_t>(std::max(1.0, std::round(std::sqrt(triangles / (2 * kBatchAspect)))));
    const auto cols = std::max<uint32_t>(1, static_cast<uint32_t>(std::round(triangles / (2.0 * rows))));
    return {rows, cols};
}

}  // namespace

uint32_t calibrationBatchTriangles(uint32_t triangles) {
    const auto [rows, cols] = batchGrid(triangles);
    return 2 * rows * cols;
}

DecodedNode calibrationBatch(uint32_t id, uint32_t triangles, bool textured) {
    const double aspect = kBatchAspect;
    const auto [rows, cols] = batchGrid(triangles);
    MeshData mesh;
    for (uint32_t r = 0; r <= rows; ++r)
        for (uint32_t c = 0; c <= cols; ++c) {
            const double u = static_cast<double>(c) / cols, v = static_cast<double>(r) / rows;
            mesh.positions.insert(mesh.positions.end(), {static_cast<float>((2 * u - 1) * kCoverage * aspect),
                                                         static_cast<float>((2 * v - 1) * kCoverage), 0.0f});
            if (textured) mesh.texcoords.insert(mesh.texcoords.end(), {static_cast<float>(u), static_cast<float>(v)});
        }
    for (uint32_t r = 0; r < rows; ++r)
        for (uint32_t c = 0; c < cols; ++c) {
            const uint32_t a = r * (cols + 1) + c, b = a + 1, d = a + cols + 1, e = d + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, d});
        }
    DecodedNode node;
    node.id = id;
    node.meshes.push_back(std::move(mesh));
    node.meshTexture.push_back(textured ? 0 : -1);
    if (textured) node.textures.push_back(checkerTexture(1024));
    return node;
}

Calibration calibrate(Renderer& renderer, double aspect, const CalibrationOptions& options) {
    Calibration result;
    result.renderer = renderer.name();
    const Camera camera = calibrationCamera(aspect);
    result.fixedOverheadMs = medianFrame(renderer, camera, {}, options);
    uint32_t id = 0;
    for (uint32_t n : options.triangleCounts)
        for (bool textured : {false, true}) {
            DecodedNode node = calibrationBatch(id, n, textured);
            const auto triangles = static_cast<uint32_t>(node.meshes[0].triangleCount());
            renderer.upload(std::move(node));
            const DrawItem item{id, 0};
            result.samples.push_back({triangles, textured, medianFrame(renderer, camera, {&item, 1}, options)});
            renderer.evict(id++);
        }
    result.textured = fitSamples(result.samples, true);
    result.untextured = fitSamples(result.samples, false);
    if (!(result.textured.slope > 0) || !(result.untextured.slope > 0))
        throw std::runtime_error("calibration: frame time does not grow with the triangle count on '" + result.renderer +
                                 "' (textured " + std::to_string(result.textured.slope) + " ms/tri, untextured " +
                                 std::to_string(result.untextured.slope) + " ms/tri)");
    result.cTextured = texturedWeight(result.textured.slope, result.untextured.slope);
    result.msPerCost = result.textured.slope + result.untextured.slope;
    if (options.viewportPixels > 0 && options.pixelDistances.size() >= 2) {
        DecodedNode node = calibrationBatch(id, options.pixelTriangles, true);
        renderer.upload(std::move(node));
        const DrawItem item{id, 0};
        // the grid spans kCoverage of the view's height and kCoverage x (16/9) / aspect of its width
        const double covered = kCoverage * std::min(1.0, kCoverage * (16.0 / 9.0) / aspect) * options.viewportPixels;
        std::vector<double> x, y;
        for (double k : options.pixelDistances) {
            Camera far = camera;
            far.position[2] *= k;
            x.push_back(covered / (k * k));
            y.push_back(medianFrame(renderer, far, {&item, 1}, options));
            result.pixelSamples.emplace_back(x.back(), y.back());
        }
        renderer.evict(id++);
        result.msPerPixel = std::max(0.0, fitLine(x, y).slope);
    }
    return result;
}

}  // namespace hlod
