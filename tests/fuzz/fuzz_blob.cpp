// libFuzzer target for the blob decoders (FORMAT.md §Geometry blobs, §Texture blobs): the
// first byte picks Draco geometry, JPEG or PNG; the rest is the blob. Decoders must throw
// FormatError on malformed input, never crash or allocate absurd amounts.
#include "formats/codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace hlod;
    if (size < 1) return 0;
    std::span<const uint8_t> blob(data + 1, size - 1);
    try {
        switch (data[0] % 3) {
        case 0: decodeGeometry(blob, "fuzz"); break;
        case 1: decodeTexture(blob, Codec::Jpeg, "fuzz"); break;
        default: decodeTexture(blob, Codec::Png, "fuzz"); break;
        }
    } catch (const FormatError&) {
    }
    return 0;
}
