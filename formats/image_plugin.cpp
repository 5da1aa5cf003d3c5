// Texture files by format (formats/image_io.h): JPEG and PNG, recognised by their signature,
// decoded here; any other format, and the few JPEG/PNG files this code does not decode as
// OpenImageIO did (CMYK JPEG, PNG with alpha), by the OpenImageIO plugin (plugin/hlod_oiio.h),
// loaded with dlopen() the first time it is needed and kept loaded.
#include "formats/image_io.h"
#include "formats/plugin/hlod_oiio.h"

#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

namespace hlod {

namespace {

constexpr size_t kErrorSize = 1024;

// The plugin at oiioPluginPath(), or nullptr and why not (`what` needs it: "its format", "a CMYK JPEG").
const HlodOiioApi* plugin(const std::string& what, std::string& why) {
    static std::mutex mutex;
    static std::map<std::string, const HlodOiioApi*> loaded;  // by path: HLOD_OIIO_PLUGIN may change
    const std::string path = oiioPluginPath();
    if (path.empty()) {
        why = what + " needs the OpenImageIO plugin, but the hlod executable's folder is unknown (/proc/self/exe); "
                     "HLOD_OIIO_PLUGIN names its path";
        return nullptr;
    }
    const std::lock_guard lock(mutex);
    if (auto it = loaded.find(path); it != loaded.end()) return it->second;
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    const char* error = handle ? nullptr : dlerror();
    auto* entry = handle ? reinterpret_cast<const HlodOiioApi* (*)()>(dlsym(handle, kHlodOiioSymbol)) : nullptr;
    const HlodOiioApi* api = entry ? entry() : nullptr;
    if (!api || api->version != kHlodOiioVersion) {
        why = what + " needs the OpenImageIO plugin " + path + ", which cannot be loaded (" +
              (error ? std::string(error) : handle ? "not an hlod_oiio plugin of this version" : "unknown error") +
              "; HLOD_OIIO_PLUGIN names another path)";
        if (handle) dlclose(handle);
        return nullptr;
    }
    loaded.emplace(path, api);
    return api;
}

class PluginRows final : public ImageRows {
public:
    PluginRows(const std::string& path, const std::string& what) {
        std::string why;
        api_ = plugin(what, why);
        if (!api_) throw ImageError(why);
        char error[kErrorSize] = "";
        int w = 0, h = 0, c = 0;
        image_ = api_->open(path.c_str(), &w, &h, &c, error, sizeof error);
        if (!image_) throw ImageError(error);
        // Negative sizes read as 0, which the callers refuse as absurd.
        width = static_cast<uint32_t>(std::max(w, 0)), height = static_cast<uint32_t>(std::max(h, 0));
        channels = static_cast<uint32_t>(std::max(c, 0));
    }
    ~PluginRows() override { api_->close(image_); }

    void read(uint32_t count, uint32_t keep, uint8_t* out) override {
        char error[kErrorSize] = "";
        if (!api_->read(image_, static_cast<int>(next_), static_cast<int>(next_ + count), static_cast<int>(keep), out, error,
                        sizeof error))
            throw ImageError(error);
        next_ += count;
    }

private:
    const HlodOiioApi* api_ = nullptr;
    void* image_ = nullptr;
    uint32_t next_ = 0;
};

}  // namespace

std::string oiioPluginPath() {
    if (const char* path = std::getenv("HLOD_OIIO_PLUGIN"); path && *path) return path;
    std::error_code error;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error || !exe.has_parent_path()) return {};  // never a bare name: dlopen would search the library path
    return (exe.parent_path() / "hlod_oiio.so").string();
}

std::unique_ptr<ImageRows> openImageFile(const std::string& path) {
    struct stat st {};  // a FIFO would block the open (formats/errors.h refuseSpecialFile)
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) throw ImageError("not a regular file");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) throw ImageError(std::strerror(errno));
    uint8_t head[8] = {};
    const size_t n = std::fread(head, 1, sizeof head, file.get());
    std::rewind(file.get());
    const bool jpeg = hasJpegSignature({head, n}), png = hasPngSignature({head, n});
    std::string what = "its format";
    if (jpeg || png) try {
            std::unique_ptr<ImageRows> rows = jpeg ? openJpeg({file.get(), {}}) : openPng({file.get(), {}}, true);
            rows->file = std::move(file);
            return rows;
        } catch (const ImageNeedsPlugin& e) {
            what = e.what();
        }
    file.reset();
    return std::make_unique<PluginRows>(path, what);
}

}  // namespace hlod
