// libFuzzer target for the calibration file reader (formats/calibration.cpp): the input is a
// whole file as `hlod calibrate` writes it.
#include "fuzz_file.h"

#include "formats/calibration.h"
#include "formats/errors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hlod::readCalibration(hlod::fuzz::writeInput("calibration.txt", data, size));
    } catch (const hlod::InputError&) {
    }
    return 0;
}
