// Rendered coverage of a chunked multi-atlas scan (issue #16): a facade cut into ~70 chunks with
// one atlas each (tests/support/chunked_scan.h) is built with `hlod`; hlod0 and the leaves, drawn
// from fixed cameras by the OpenGL renderer (EGL offscreen), cover the same pixels within 2 %
// of the image: coarse levels open no hole. Skips when no EGL context exists.
#include "player/gl/gl_renderer.h"
#include "player/node_source.h"
#include "tests/support/chunked_scan.h"
#include "tests/support/run_hlod.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace hlod {
namespace {

constexpr int kWidth = 320, kHeight = 180;
constexpr double kMaxCoverageDifference = 0.02;  // issue #16: "within 2 % of pixels"

// Pixels that differ from the background (the colour of an empty frame).
uint64_t covered(const Image& image, const Image& empty) {
    uint64_t n = 0;
    for (size_t i = 0; i < image.pixels.size(); i += 3)
        if (image.pixels[i] != empty.pixels[i] || image.pixels[i + 1] != empty.pixels[i + 1] || image.pixels[i + 2] != empty.pixels[i + 2])
            ++n;
    return n;
}

TEST(ChunkedCoverage, Hlod0CoversWhatTheLeavesCover) {
    std::unique_ptr<Renderer> renderer;
    try {
        renderer = makeGlRenderer({kWidth, kHeight, false, false});
    } catch (const NoGlContext&) {
        GTEST_SKIP() << "no EGL OpenGL 3.3 context can be created here";
    }
    test::TempDir dir;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(250), {});
    const std::string db = dir.file("facade.hlod");
    const test::RunResult r = test::runHlod({"build", scan.obj, "-o", db, "-j", "1"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    const Database database = Database::open(db);
    const std::shared_ptr<const NodeSource> source = databaseSource(database);
    const Skeleton& s = source->skeleton();
    std::vector<DrawItem> hlod0, leaves;
    for (const Node& n : s.nodes) {
        std::vector<uint8_t> bytes(source->nodeSize(n.id));
        source->readChunk(n.id, 0, bytes);
        renderer->upload(source->decode(n.id, bytes));
        if (n.level == 0) hlod0.push_back({n.id, n.level});
        if (n.firstChild == kNone) leaves.push_back({n.id, n.level});
    }
    ASSERT_EQ(hlod0.size(), 1u);
    ASSERT_GT(leaves.size(), 16u);
    // The facade spans x 0..40, z 0..20, y about -2..2.3 (facing -y): cameras in front of it,
    // looking along +y (a quarter turn about x), near and far, straight and from the side.
    const double quarter = std::sqrt(0.5);
    const double positions[][3] = {{20, -40, 10}, {8, -22, 6}, {32, -22, 14}, {20, -12, 3}};
    for (const auto& p : positions) {
        Camera camera;
        std::copy_n(p, 3, camera.position);
        camera.orientation[0] = quarter, camera.orientation[3] = quarter;
        camera.aspect = double(kWidth) / kHeight;
        renderer->drawFrame(camera, {}, {});
        const Image empty = renderer->readPixels();
        renderer->drawFrame(camera, hlod0, {});
        const uint64_t coarse = covered(renderer->readPixels(), empty);
        renderer->drawFrame(camera, leaves, {});
        const uint64_t fine = covered(renderer->readPixels(), empty);
        const double total = double(kWidth) * kHeight;
        EXPECT_GT(double(fine), 0.2 * total) << "camera " << p[0] << "," << p[1] << "," << p[2];
        EXPECT_LE(std::abs(double(coarse) - double(fine)), kMaxCoverageDifference * total)
            << "camera " << p[0] << "," << p[1] << "," << p[2] << ": hlod0 " << coarse << " pixels, leaves " << fine;
        std::printf("camera %.0f,%.0f,%.0f: hlod0 covers %.2f %%, leaves %.2f %% of the pixels\n", p[0], p[1], p[2],
                    100 * coarse / total, 100 * fine / total);
    }
}

}  // namespace
}  // namespace hlod
