// libFuzzer target for the glTF reader (tinygltf + pipeline/read_gltf.cpp): the input is a
// glTF JSON document (fuzz_gltf) or a GLB container (fuzz_glb, FUZZ_GLB defined), read from
// memory through readGltfBytes as readGltf reads a file. External buffers and images resolve
// in the harness's private folder (the confinement rule). A GLB also goes through the build's
// path (parseGltf with an image folder: the file mapped, its BIN-chunk images taken out by
// glbWithoutImages and written to the folder).
#include "fuzz_file.h"
#include "pipeline/pipeline.h"

#ifndef FUZZ_GLB
#define FUZZ_GLB 0
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string name = hlod::fuzz::writeInput(FUZZ_GLB ? "in.glb" : "in.gltf", data, 0);
    try {
        hlod::readGltfBytes(std::vector<uint8_t>(data, data + size), FUZZ_GLB, name);
    } catch (const hlod::InputError&) {
    }
    if (FUZZ_GLB) {
        static const hlod::ReadOptions options{false, (std::filesystem::path(name).parent_path() / "images").string()};
        try {
            hlod::RawMesh raw;
            hlod::parseGltf(hlod::fuzz::writeInput("streamed.glb", data, size), raw, options);
        } catch (const hlod::InputError&) {
        }
    }
    return 0;
}
