// Shared by the reader fuzz targets: the readers of PLY, OBJ, MTL, constants and calibration
// files take a path, so the harness writes each input to a file in a private folder (one per
// process, removed at exit) and reads it back through the unchanged reader. Only the exception
// the reader documents (InputError, or std::invalid_argument for constants) may escape it;
// anything else, a crash or a sanitizer report is a bug.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace hlod::fuzz {

// DIR/NAME holding `data`, in a folder unique to this process.
inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path d = std::filesystem::temp_directory_path() / ("hlod-fuzz-" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] { std::filesystem::remove_all(std::filesystem::temp_directory_path() / ("hlod-fuzz-" + std::to_string(getpid()))); });
        return d;
    }();
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

}  // namespace hlod::fuzz
