// Wall-clock stage timings: one clock, one milliseconds helper, and the stages pgt times as
// one table (docs/outputs.md "timings_ms"; a sweep's stage totals).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <map>
#include <string>

namespace pgt {

using Clock = std::chrono::steady_clock;

// Milliseconds from `t0` to now.
inline double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Every stage a frame or a study times.
enum class Stage {
    Raster,          // rasterising the base, bin by bin
    Trace,           // tracing the truth
    TraceFine,       // tracing its 2x-rate twin (the uncertainty)
    MethodsEval,     // the methods' evaluation
    Methods,         // evaluation and comparison with the truth
    Statistics,      // each method's percentiles over the frame
    MethodTiming,    // the timing passes
    Write,           // frame.exr's rows
    Tessellate,      // the truth's tessellation (a mesh's)
    Build,           // its displacement and Embree build
    TessellateFine,  // the same of the 2x-rate twin
    BuildFine,
    TruthTotal,    // the whole set-up of a view's truth
    TruthBuild,    // a study: the truths of its surfaces
    CasesWall,     // a study: its cases, wall clock
    GlTimingWall,  // a study: its GLSL methods' timings, wall clock
    VertexStage,   // the engine vertex stages' runs on the drawn mesh
    Count
};
inline constexpr size_t kStages = size_t(Stage::Count);
// Their names (summary.json's timings_ms keys), in the enum's order.
inline constexpr std::array<const char*, kStages> kStageNames = {
    "raster",        "trace",       "trace_fine", "methods_eval",   "methods",         "statistics",
    "method_timing", "write",       "tessellate", "build",          "tessellate_fine", "build_fine",
    "truth_total",   "truth_build", "cases_wall", "gl_timing_wall", "vertex_stage"};

// Milliseconds per stage; a stage never added or set is absent (the frame did not run it).
class StageTimes {
  public:
    void add(Stage s, double ms) { ms_[size_t(s)] += ms, present_[size_t(s)] = true; }
    void set(Stage s, double ms) { ms_[size_t(s)] = ms, present_[size_t(s)] = true; }
    double operator[](Stage s) const { return ms_[size_t(s)]; }
    bool has(Stage s) const { return present_[size_t(s)]; }
    bool empty() const {
        return std::none_of(present_.begin(), present_.end(), [](bool p) { return p; });
    }
    // Each stage of `o` added (a study's totals over its frames).
    StageTimes& operator+=(const StageTimes& o) {
        for (size_t i = 0; i < kStages; ++i)
            if (o.present_[i]) ms_[i] += o.ms_[i], present_[i] = true;
        return *this;
    }
    // The present stages by name, in the names' order (as printed and written).
    std::map<std::string, double> byName() const {
        std::map<std::string, double> out;
        for (size_t i = 0; i < kStages; ++i)
            if (present_[i]) out[kStageNames[i]] = ms_[i];
        return out;
    }

  private:
    std::array<double, kStages> ms_{};
    std::array<bool, kStages> present_{};
};

}  // namespace pgt
