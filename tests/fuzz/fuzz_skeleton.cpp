// libFuzzer target for the skeleton reader (FORMAT.md §Header, §Skeleton): the input is a
// whole file image. The harness sets the file-size field and recomputes both checksums so
// that mutations reach the checks behind them; then the skeleton is parsed and walked the way
// `hlod inspect` walks it. Any exception other than FormatError, or a crash, is a bug.
#include "formats/inspect.h"
#include "formats/layout.h"
#include "tests/support/fix_checksums.h"

#include <algorithm>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace hlod;
    std::vector<uint8_t> file(data, data + size);
    if (file.size() >= layout::kHeaderSize) layout::store(std::span(file), layout::kOffFileSize, uint64_t(size));
    test::fixChecksums(file);
    try {
        std::span<const uint8_t> header(file.data(), std::min<size_t>(size, layout::kMaxHeaderSize));
        layout::HeaderInfo h = layout::parseHeader(header, size, "fuzz");
        Skeleton s = parseDatabase(header, std::span(file).subspan(h.skeletonOffset, h.skeletonSize), size, "fuzz");
        treeJson(s, 0);
        for (uint32_t i = 0; i < s.nodes.size() && i < 64; ++i) nodeJson(s, i);
    } catch (const FormatError&) {
    }
    return 0;
}
