// libFuzzer target for MTL material libraries (tinyobjloader's LoadMtl as read_obj.cpp calls it,
// then the texture references through resolveReference): the input is a whole .mtl file, read
// through a fixed OBJ that names it and uses its materials.
#include "fuzz_file.h"
#include "pipeline/pipeline.h"

namespace {
const char kObj[] = "mtllib in.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                    "usemtl material0\nf 1/1 2/2 3/3\nusemtl a\nf 1/1 3/3 2/2\n";
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    hlod::fuzz::writeInput("in.mtl", data, size);
    static const std::string obj =
        hlod::fuzz::writeInput("mtl.obj", reinterpret_cast<const uint8_t*>(kObj), sizeof kObj - 1);
    try {
        hlod::readObj(obj);
    } catch (const hlod::InputError&) {
    }
    return 0;
}
