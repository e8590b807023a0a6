// The one Embree device of the process (Embree tutorials: one device, one error callback
// instead of per-call checks) and the floating-point mode its tracing threads need.
#pragma once

#include <embree3/rtcore.h>

namespace pgt {

// Created on first use; throws std::runtime_error when Embree cannot make one.
RTCDevice embreeDevice();
// Throws std::runtime_error with the first error Embree reported since the last call.
void throwIfEmbreeFailed();
// Flush-to-zero and denormals-are-zero for the calling thread (Embree warns without them).
void setTracingFpMode();

}  // namespace pgt
