// libFuzzer target for the OBJ reader (pipeline/read_obj.cpp and the checks of input.cpp): the
// input is a whole .obj file; its mtllib and texture references resolve in the harness's
// private folder (MTL files themselves: fuzz_mtl).
#include "fuzz_file.h"
#include "pipeline/pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hlod::readObj(hlod::fuzz::writeInput("in.obj", data, size));
    } catch (const hlod::InputError&) {
    }
    return 0;
}
