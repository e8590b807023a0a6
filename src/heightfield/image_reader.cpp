// openImageFile (heightfield/image_reader.h): the image module loaded once, on first use.
#include "heightfield/image_reader.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <system_error>

#include "core/data_dir.h"
#include "core/error.h"

namespace pgt {

namespace {

// The module's entry point, loaded on first use; throws InputError when the module is missing
// or broken (and tries again on the next call: PGT_IMAGE_MODULE may have been set meanwhile,
// as in a Python session).
OpenImageFn imageModule() {
    static std::mutex mutex;
    static OpenImageFn open = nullptr;
    std::lock_guard<std::mutex> lock(mutex);
    if (open) return open;
    std::string path = installedFile("lib/pgt/pgt_image.so", "PGT_IMAGE_MODULE");
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
    if (!ec) path = absolute.string();  // a bare name is a file here, not a library to search
    // Kept for the process's life; its symbols stay its own.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    const char* why = dlerror();
    if (handle) {
        open = reinterpret_cast<OpenImageFn>(dlsym(handle, kOpenImageSymbol));
        why = open ? nullptr : dlerror();
        if (!open) dlclose(handle);
    }
    if (!open)
        throw InputError(path, "PGT_IMAGE_MODULE", "",
                         std::string("cannot load pgt's image module: ") + (why ? why : "?"));
    return open;
}

}  // namespace

std::unique_ptr<ImageFile> openImageFile(const std::string& path, std::string& why) {
    return std::unique_ptr<ImageFile>(imageModule()(path.c_str(), &why));
}

}  // namespace pgt
