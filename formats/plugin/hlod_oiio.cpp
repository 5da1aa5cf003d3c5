// The OpenImageIO plugin (hlod_oiio.h): a MODULE library, built and installed beside the hlod
// executable, that reads every texture format other than JPEG and PNG (TIFF, EXR, TGA, BMP,
// PPM, ...) as the build read them before issue #14: ImageInput::open with its defaults, then
// read_scanlines to 8 bits, a decode warning being an error.
#include "formats/plugin/hlod_oiio.h"

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <string>

namespace {

void copyError(const std::string& message, char* error, size_t size) {
    if (size == 0) return;
    const std::string line = message.substr(0, message.find('\n'));
    std::strncpy(error, line.c_str(), size - 1);
    error[size - 1] = 0;
}

void* openImage(const char* path, int* width, int* height, int* channels, char* error, size_t errorSize) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) {
        copyError(OIIO::geterror(), error, errorSize);
        return nullptr;
    }
    const OIIO::ImageSpec& spec = input->spec();
    *width = spec.width, *height = spec.height, *channels = spec.nchannels;
    return input.release();
}

int readRows(void* image, int y0, int y1, int keep, unsigned char* out, char* error, size_t errorSize) {
    auto* input = static_cast<OIIO::ImageInput*>(image);
    const int top = input->spec().y;  // the data window's first row (an EXR's may not be 0)
    if (!input->read_scanlines(0, 0, top + y0, top + y1, 0, 0, keep, OIIO::TypeDesc::UINT8, out) || input->has_error()) {
        copyError(input->geterror(), error, errorSize);
        return 0;
    }
    return 1;
}

void closeImage(void* image) { OIIO::ImageInput::unique_ptr(static_cast<OIIO::ImageInput*>(image)); }

constexpr HlodOiioApi kApi{kHlodOiioVersion, openImage, readRows, closeImage};

}  // namespace

extern "C" __attribute__((visibility("default"))) const HlodOiioApi* hlod_oiio_api(void) { return &kApi; }
