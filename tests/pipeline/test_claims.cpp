// No reader allocates more than the file can justify (README "Reliability"): a header or an
// accessor claiming 2^40 elements in a file of a few hundred bytes fails at once with one line.
// Each read runs in a child process whose address space is limited to what it already uses
// plus 256 MiB, so an allocation of what the file claims would fail the test (as bad_alloc)
// instead of passing slowly. Skipped under AddressSanitizer, whose shadow memory needs an
// unlimited address space.
#include "helpers.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>


namespace hlod::test {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAsan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAsan = true;
#else
constexpr bool kAsan = false;
#endif
#else
constexpr bool kAsan = false;
#endif

// Reads `file` in a child limited to its current address space + 256 MiB and to 20 CPU-seconds
// (a reader that walks a claimed count instead of the bytes there never ends: SIGXCPU); returns
// the first line of the InputError, or "bad_alloc" / "no error" / "other exception" / "killed by
// signal N".
std::string readBounded(const std::string& file) {
    int pipeFds[2];
    EXPECT_EQ(pipe(pipeFds), 0);
    const pid_t child = fork();
    if (child == 0) {
        close(pipeFds[0]);
        long pages = 0;
        std::ifstream("/proc/self/statm") >> pages;
        const rlim_t limit = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (256ull << 20);
        const rlimit r{limit, limit};
        setrlimit(RLIMIT_AS, &r);
        const rlimit cpu{20, 20};
        setrlimit(RLIMIT_CPU, &cpu);
        std::string message = "no error";
        try {
            readMesh(file);
        } catch (const InputError& e) {
            message = e.what();
        } catch (const std::bad_alloc&) {
            message = "bad_alloc";
        } catch (...) {
            message = "other exception";
        }
        (void)!write(pipeFds[1], message.data(), message.size());
        _exit(0);
    }
    close(pipeFds[1]);
    std::string message;
    char buffer[512];
    for (ssize_t n; (n = read(pipeFds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, static_cast<size_t>(n));
    close(pipeFds[0]);
    int status = 0;
    waitpid(child, &status, 0);
    if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
    return message;
}


TEST(Claims, PlyHeaderClaimingTwoToTheFortyElements) {
    if (kAsan) GTEST_SKIP() << "RLIMIT_AS and AddressSanitizer do not mix";
    TempDir dir;
    const std::string vertices = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string list = "property list uchar int vertex_indices\n";
    for (const char* format : {"ascii", "binary_little_endian"}) {
        const std::string data = std::string(format) == "ascii" ? "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" : std::string(40, '\0');
        std::ofstream(dir.file("f.ply")) << "ply\nformat " << format << " 1.0\n" << vertices << "element face 1099511627776\n"
                                         << list << "end_header\n" << data;
        EXPECT_EQ(readBounded(dir.file("f.ply")), dir.file("f.ply") + ": truncated PLY (data ends early)") << format;
        std::ofstream(dir.file("v.ply")) << "ply\nformat " << format << " 1.0\nelement vertex 1099511627776\n"
                                         << "property float x\nproperty float y\nproperty float z\nend_header\n" << data;
        EXPECT_EQ(readBounded(dir.file("v.ply")), dir.file("v.ply") + ": truncated PLY (data ends early)") << format;
    }
    std::ofstream(dir.file("l.ply")) << "ply\nformat ascii 1.0\n" << vertices << "element face 1\n" << list
                                     << "end_header\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n";
    EXPECT_NE(readBounded(dir.file("l.ply")).find("corrupt PLY (face with 4000000000"), std::string::npos);
}

TEST(Claims, ObjFaceNamingVertexTwoToTheForty) {
    if (kAsan) GTEST_SKIP() << "RLIMIT_AS and AddressSanitizer do not mix";
    TempDir dir;
    std::ofstream(dir.file("f.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1099511627776\n";
    EXPECT_EQ(readBounded(dir.file("f.obj")), dir.file("f.obj") + ":4: corrupt OBJ (face index 1099511627776 out of range)");
    std::ofstream(dir.file("g.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n";
    EXPECT_EQ(readBounded(dir.file("g.obj")), dir.file("g.obj") + ":4: face index 4000000000 names one of 3 vertices");
}

TEST(Claims, GltfAccessorsAndBuffersClaimingTwoToTheForty) {
    if (kAsan) GTEST_SKIP() << "RLIMIT_AS and AddressSanitizer do not mix";
    TempDir dir;
    const std::string data = "data:application/octet-stream;base64," + base64(std::vector<uint8_t>(36, 0));
    const auto gltf = [&](const std::string& count, const std::string& viewLength, const std::string& bufferLength) {
        std::ofstream(dir.file("a.gltf"))
            << R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "buffers": [{"uri": ")" << data << R"(", "byteLength": )" << bufferLength << R"(}],
  "bufferViews": [{"buffer": 0, "byteLength": )" << viewLength << R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" << count << R"(, "type": "VEC3"}]})";
        return readBounded(dir.file("a.gltf"));
    };
    EXPECT_NE(gltf("1099511627776", "36", "36").find("POSITION accessor 0 runs past its buffer view"), std::string::npos);
    EXPECT_NE(gltf("3", "1099511627776", "36").find("runs past its buffer (truncated file?)"), std::string::npos);
    EXPECT_NE(gltf("3", "36", "1099511627776").find("corrupt glTF"), std::string::npos);
}

}  // namespace
}  // namespace hlod::test
