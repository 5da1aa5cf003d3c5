// libFuzzer target for the PLY reader (ascii, binary little and big endian; pipeline/read_ply.cpp
// and the checks of input.cpp): the input is a whole .ply file. A header may claim any element
// count: the reader must fail at the end of the data, never allocate what the header claims.
#include "fuzz_file.h"
#include "pipeline/pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hlod::readPly(hlod::fuzz::writeInput("in.ply", data, size));
    } catch (const hlod::InputError&) {
    }
    return 0;
}
