// openImageFile (heightfield/image_reader.h): the image module loaded once, on first use.
#include "heightfield/image_reader.h"

#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <vector>

#include "core/data_dir.h"
#include "core/error.h"

namespace pgt {

namespace {

// Why `path` cannot be the image module, or "" when it can be handed to dlopen: a regular
// file (a FIFO or a device would block or never end; opened without blocking to find out)
// holding a whole 64-bit ELF shared object for this machine, every program header and loaded
// segment within the file. dlopen maps a truncated one and dies of SIGBUS touching the rest.
std::string moduleFileProblem(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return std::strerror(errno);
    struct Close {
        int fd;
        ~Close() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) return std::strerror(errno);
    if (!S_ISREG(st.st_mode)) return "not a regular file";
    const uint64_t size = uint64_t(st.st_size);
    auto readAt = [&](void* out, size_t n, uint64_t at) {
        return at + n <= size && ::pread(fd, out, n, off_t(at)) == ssize_t(n);
    };
    Elf64_Ehdr eh{};
    if (!readAt(&eh, sizeof eh, 0) || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0)
        return "not an ELF file";
    if (eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_ident[EI_DATA] != ELFDATA2LSB ||
        eh.e_type != ET_DYN)
        return "not a 64-bit little-endian ELF shared object";
#if defined(__x86_64__)
    if (eh.e_machine != EM_X86_64) return "an ELF file for another machine";
#elif defined(__aarch64__)
    if (eh.e_machine != EM_AARCH64) return "an ELF file for another machine";
#endif
    if (eh.e_phentsize != sizeof(Elf64_Phdr) || eh.e_phnum == 0 || eh.e_phnum > 4096)
        return "an ELF file without valid program headers";
    std::vector<Elf64_Phdr> ph(eh.e_phnum);
    if (!readAt(ph.data(), ph.size() * sizeof(Elf64_Phdr), eh.e_phoff))
        return "a truncated ELF file (its program headers lie beyond its end)";
    for (const Elf64_Phdr& p : ph)
        if ((p.p_type == PT_LOAD || p.p_type == PT_DYNAMIC) &&
            (p.p_offset > size || p.p_filesz > size - p.p_offset))
            return "a truncated ELF file (a segment lies beyond its end: " + std::to_string(size) +
                   " bytes)";
    if (eh.e_shoff != 0 && eh.e_shoff + uint64_t(eh.e_shnum) * eh.e_shentsize > size)
        return "a truncated ELF file (its section headers lie beyond its end: " +
               std::to_string(size) + " bytes)";
    return "";
}

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
    const std::string problem = moduleFileProblem(path);
    if (!problem.empty())
        throw InputError(path, "PGT_IMAGE_MODULE", "",
                         "cannot load pgt's image module: " + problem);
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

std::unique_ptr<ImageFile> openImageFile(const std::string& path, std::string& why,
                                         ImageDecoder decoder) {
    if (decoder != ImageDecoder::Module) {
        bool handled = false;
        auto direct = openNativeImage(path, why, handled);
        if (direct || handled) return direct;
        if (decoder == ImageDecoder::Direct) {
            why = "left to the image module (a format or layout the direct readers do not take)";
            return nullptr;
        }
    }
    return std::unique_ptr<ImageFile>(imageModule()(path.c_str(), &why));
}

}  // namespace pgt
