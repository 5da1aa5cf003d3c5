// libFuzzer target for the camera path reader (player/camera_path.cpp, CAMERA_PATH.md): the input
// is a whole .path file, parsed from memory; a parsed path is also sampled across its span.
#include "player/camera_path.h"

#include "formats/errors.h"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const hlod::CameraPath path = hlod::parseCameraPath(in, "fuzz.path");
        for (int i = -1; i <= 8; ++i) hlod::sampleCameraPath(path, path.keys.front().time + i * path.duration() / 8);
    } catch (const hlod::InputError&) {
    }
    return 0;
}
