// libFuzzer target for the constants file reader (formats/constants.cpp): the input is a whole
// `name = value` file, loaded for every use and then checked by validateConstants, as a
// subcommand's --config does.
#include "fuzz_file.h"

#include "formats/constants.h"
#include "formats/errors.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hlod::Constants c;
        hlod::loadConstantsFile(c, hlod::fuzz::writeInput("constants.conf", data, size), hlod::kUsedByAny);
        hlod::validateConstants(c, hlod::kUsedByAny);
    } catch (const hlod::InputError&) {
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
