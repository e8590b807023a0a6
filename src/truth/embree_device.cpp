// The process's Embree device and its error callback (truth/embree_device.h).
#include "truth/embree_device.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <array>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace pgt {

namespace {

// One Embree device for the process. Errors land in the callback, which records the first
// message; the build checks it (Embree tutorials: one error callback, not per-call checks).
std::mutex gEmbreeErrorMutex;
std::string gEmbreeError;

void embreeError(void*, RTCError code, const char* message) {
    // A build stopped by pgt's own cancel (the progress monitor) is no error: the cancel is
    // thrown where the build returns, and a later build must not see this one's message.
    if (code == RTC_ERROR_CANCELLED) return;
    std::lock_guard<std::mutex> lock(gEmbreeErrorMutex);
    if (gEmbreeError.empty())
        gEmbreeError =
            "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

// Embree's configuration string for PGT_EMBREE_ISA (docs/testing.md): "" for Embree's own
// choice (the best kernels the CPU has), else "isa=NAME" for one of Embree's ISA names.
std::string isaConfig() {
    const char* env = std::getenv("PGT_EMBREE_ISA");
    if (!env || !*env) return "";
    static constexpr std::array<const char*, 5> kIsas = {"sse2", "sse4.2", "avx", "avx2", "avx512"};
    for (const char* isa : kIsas)
        if (std::string(env) == isa) return std::string("isa=") + isa;
    throw InputError("environment", "PGT_EMBREE_ISA", env,
                     "expected one of sse2, sse4.2, avx, avx2, avx512 (Embree's kernels), or "
                     "unset for the best the CPU has");
}

}  // namespace

RTCDevice embreeDevice() {
    static RTCDevice d = [] {
        const std::string config = isaConfig();
        RTCDevice dev = rtcNewDevice(config.empty() ? nullptr : config.c_str());
        if (!dev)
            throw std::runtime_error("cannot create an Embree device" +
                                     (config.empty() ? "" : " with " + config) +
                                     " (an ISA the CPU lacks?)");
        rtcSetDeviceErrorFunction(dev, embreeError, nullptr);
        return dev;
    }();
    return d;
}

void throwIfEmbreeFailed() {
    std::lock_guard<std::mutex> lock(gEmbreeErrorMutex);
    if (!gEmbreeError.empty()) {
        std::string e = gEmbreeError;
        gEmbreeError.clear();
        throw std::runtime_error(e);
    }
}

// Embree warns without flush-to-zero and denormals-are-zero in every tracing thread.
void setTracingFpMode() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

}  // namespace pgt
