// The process's Embree device and its error callback (truth/embree_device.h).
#include "truth/embree_device.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <mutex>
#include <stdexcept>
#include <string>

namespace pgt {

namespace {

// One Embree device for the process. Errors land in the callback, which records the first
// message; the build checks it (Embree tutorials: one error callback, not per-call checks).
std::mutex gEmbreeErrorMutex;
std::string gEmbreeError;

void embreeError(void*, RTCError code, const char* message) {
    std::lock_guard<std::mutex> lock(gEmbreeErrorMutex);
    if (gEmbreeError.empty())
        gEmbreeError =
            "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

}  // namespace

RTCDevice embreeDevice() {
    static RTCDevice d = [] {
        RTCDevice dev = rtcNewDevice(nullptr);
        if (!dev) throw std::runtime_error("cannot create an Embree device");
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
