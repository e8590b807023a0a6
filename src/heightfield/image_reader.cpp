// openImageFile (heightfield/image_reader.h): the image module loaded once, on first use.
#include "heightfield/image_reader.h"

#include <dlfcn.h>

#include <exception>
#include <mutex>

#include "core/data_dir.h"
#include "core/error.h"

namespace pgt {

namespace {

// The module's entry point; throws InputError when the module is missing or broken.
OpenImageFn imageModule() {
    static std::once_flag once;
    static OpenImageFn open = nullptr;
    static std::exception_ptr failure;
    std::call_once(once, [] {
        try {
            const std::string path = installedFile("lib/pgt/pgt_image.so", "PGT_IMAGE_MODULE");
            // Kept for the process's life; its symbols stay its own.
            void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            const char* why = handle ? nullptr : dlerror();
            if (handle) open = reinterpret_cast<OpenImageFn>(dlsym(handle, kOpenImageSymbol));
            if (!open)
                throw InputError(path, "PGT_IMAGE_MODULE", "",
                                 std::string("cannot load pgt's image module: ") +
                                     (why ? why : "no " + std::string(kOpenImageSymbol)));
        } catch (const InputError&) {
            failure = std::current_exception();
        }
    });
    if (failure) std::rethrow_exception(failure);
    return open;
}

}  // namespace

std::unique_ptr<ImageFile> openImageFile(const std::string& path, std::string& why) {
    return std::unique_ptr<ImageFile>(imageModule()(path.c_str(), &why));
}

}  // namespace pgt
