// The extension behind the Python module pgt (pgt/__init__.py wraps it; docs/python.md).
// Each call does what the CLI's command does, with the GIL released while pgt works; pgt's
// errors become pgt.InputError (bad input: the CLI's exit 2) and pgt.OutputError (exit 3)
// carrying the CLI's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cfenv>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cli/report.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "frame/render.h"
#include "io/staged_files.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "study/provenance.h"
#include "study/sweep.h"
#include "verdict/study_compare.h"

namespace py = pybind11;

namespace {

// Runs `work` on a thread of its own while the calling Python thread, without the GIL,
// checks for signals every 50 ms: Ctrl-C then requests a cancel (core/interrupt.h), the work
// unwinds within about a second (its staged files and created --out removed by their
// destructors) and KeyboardInterrupt is raised here. Called with the GIL held.
// The floating-point environment: the work runs in the default one whatever the caller set
// (a new thread inherits its creator's: a rounding mode set in Python would change pgt's
// numbers), and the caller's own (rounding, and on x86-64 MXCSR with its flush-to-zero and
// denormals-are-zero bits, which the tracing threads set for Embree) is restored on return.
template <class F>
auto interruptible(F work) -> decltype(work()) {
    using Result = decltype(work());
    std::optional<Result> result;
    std::exception_ptr error;
    bool interrupted = false;
    std::fenv_t caller;
    std::fegetenv(&caller);
    {
        py::gil_scoped_release free;
        std::mutex m;
        std::condition_variable cv;
        bool done = false;
        pgt::clearCancel();
        // SIGTERM or SIGHUP (default action) ends the interpreter: its temporaries and the
        // --out it created go first, as the CLI's do.
        pgt::SignalCleanupScope cleanup;
        std::thread worker([&] {
            std::fesetenv(FE_DFL_ENV);
            try {
                result.emplace(work());
            } catch (...) {
                error = std::current_exception();
            }
            std::lock_guard<std::mutex> l(m);
            done = true;
            cv.notify_all();
        });
        for (;;) {
            std::unique_lock<std::mutex> l(m);
            if (cv.wait_for(l, std::chrono::milliseconds(50), [&] { return done; })) break;
            l.unlock();
            if (interrupted) continue;
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) {  // the KeyboardInterrupt stays set for below
                interrupted = true;
                pgt::requestCancel();
            }
        }
        worker.join();
        pgt::clearCancel();
    }
    std::fesetenv(&caller);
    if (interrupted) throw py::error_already_set();
    if (error) std::rethrow_exception(error);
    return std::move(*result);
}

// Paths from Python are refused when they hold a NUL (C++ would read them cut at the NUL:
// another file).
void checkPath(const std::string& path, const std::string& argument) {
    if (path.find('\0') != std::string::npos)
        throw pgt::InputError(path, argument, "", "the path holds a NUL character");
}

// The CLI's bounds of render's timing options (src/cli/main.cpp), as InputError.
void checkRange(int64_t value, int64_t lo, int64_t hi, const std::string& argument) {
    if (value < lo || value > hi)
        throw pgt::InputError(
            "pgt.render", argument, std::to_string(value),
            "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

// A scene from its file (`text` empty) or from JSON text, with `file` naming it in messages
// and anchoring its relative paths.
pgt::Scene readScene(const std::string& file, const std::string& text) {
    if (text.empty()) return pgt::loadScene(file);
    return pgt::parseScene(pgt::parseJsonText(text, file), file);
}

struct Rendered {
    std::vector<std::string> names;
    std::vector<float> pixels;  // height x width x channels
    int width = 0, height = 0;
    std::string summary;  // summary.json's text
};

// `pgt render`, kept in memory: the frame's channels as frame.exr holds them; with `out`, the
// CLI's files too.
Rendered render(const std::string& file, const std::string& text, const std::string& out,
                int repeats, int fragments, int64_t glFragments) {
    Rendered r;
    const pgt::Scene scene = readScene(file, text);
    r.width = scene.camera.width, r.height = scene.camera.height;
    pgt::checkViewMemory(scene, r.width, r.height,
                         {.configs = &scene.methods,
                          .writesImages = !out.empty(),
                          .keepsImages = true,
                          .truthInBlocks = true},
                         "camera.resolution");
    std::unique_ptr<pgt::OutputDirectory> outDir;
    if (!out.empty()) outDir = std::make_unique<pgt::OutputDirectory>(out);
    pgt::RenderOptions options{.timingRepeats = repeats};
    options.timingFragments = fragments;
    options.glTimingFragments = glFragments;
    options.frame.keepImages = true;
    options.frame.keepCodedErrors = !out.empty();  // the error maps are drawn from them
    const pgt::RenderResult result = pgt::renderFrame(scene, options);
    r.names = pgt::frameChannelNames(scene.methods);
    r.pixels.resize(size_t(r.width) * size_t(r.height) * r.names.size());
    pgt::interleaveFrameBand(pgt::wholeFrameBand(result), r.pixels.data());
    if (!out.empty()) {  // the summary as written, with its files named
        r.summary = pgt::writeRenderOutputs(scene, result, out).dump();
        outDir->keep();
    } else {
        r.summary = pgt::summaryJson(scene, result).dump();
    }
    return r;
}

py::tuple renderToPython(const std::string& file, const std::string& text, const std::string& out,
                         int64_t repeats, int64_t fragments, int64_t glFragments) {
    checkPath(file, "scene");
    checkPath(out, "out");
    pgt::setCommandLine("python: pgt.render(" + file + (out.empty() ? "" : ", out=" + out) + ")");
    checkRange(repeats, 1, 100, "timing_repeats");
    checkRange(fragments, 0, int64_t(1) << 26, "timing_fragments");
    checkRange(glFragments, 1, int64_t(1) << 23, "gl_timing_fragments");
    auto r = std::make_unique<Rendered>(interruptible(
        [&] { return render(file, text, out, int(repeats), int(fragments), glFragments); }));
    const auto channels = py::ssize_t(r->names.size());
    const std::vector<py::ssize_t> shape = {r->height, r->width, channels};
    const std::vector<py::ssize_t> strides = {py::ssize_t(sizeof(float)) * r->width * channels,
                                              py::ssize_t(sizeof(float)) * channels,
                                              py::ssize_t(sizeof(float))};
    float* data = r->pixels.data();
    py::list names = py::cast(r->names);
    py::str summary(r->summary);
    // The array owns the result: no copy of the pixels.
    py::capsule owner(r.get(), [](void* p) { delete static_cast<Rendered*>(p); });
    r.release();
    return py::make_tuple(names, py::array_t<float>(shape, strides, data, owner), summary);
}

// `pgt sweep`: the study, resumed unless `fresh`; the summary as a dict.
py::dict sweep(const std::string& file, const std::string& text, const std::string& out, bool fresh,
               bool report, bool images, bool progress) {
    checkPath(file, "scene");
    checkPath(out, "out");
    pgt::setCommandLine("python: pgt.sweep(" + file + ", " + out + ")");
    const pgt::SweepSummary sum = interruptible([&] {
        const pgt::Scene scene = readScene(file, text);
        const pgt::Study study = pgt::parseStudy(scene);
        pgt::SweepOptions options;
        options.outDir = out;
        options.fresh = fresh;
        if (report) options.report = pgt::writeStudyReport;
        options.images = images;
        options.progress = progress;
        return pgt::runSweep(scene, study, options);
    });
    py::dict d;
    d["cases"] = sum.total;
    d["run"] = sum.done;
    d["resumed"] = sum.resumed;
    d["finished"] = sum.finished;
    d["wall_seconds"] = sum.wallSeconds;
    d["stage_ms"] = sum.stageMs.byName();
    d["report"] = sum.reportPath;
    d["report_not_written"] = sum.reportWhy;
    return d;
}

// `pgt compare`: the verdict (compare.json's) as a dict; figures when `figures`.
py::dict compare(const std::vector<std::string>& dirs, const std::string& out,
                 const std::string& metric, const std::vector<double>& bands,
                 const std::vector<std::pair<std::string, std::string>>& pairs, double alpha,
                 double minEffect, double floor, bool anyScene, bool figures) {
    for (const auto& d : dirs) checkPath(d, "dirs");
    checkPath(out, "out");
    std::string shown;
    for (const auto& d : dirs) shown += d + ", ";
    pgt::setCommandLine("python: pgt.compare(" + shown + "out=" + out + ")");
    pgt::CompareOptions o;
    o.dirs = dirs, o.outDir = out, o.metric = metric, o.pairs = pairs, o.anyScene = anyScene;
    o.verdict = {bands, alpha, minEffect, floor};
    const pgt::CompareSummary sum = interruptible([&] {
        return pgt::compareStudies(o, figures ? pgt::writeCompareFigures : pgt::CompareFigures{});
    });
    py::dict d;
    d["regression"] = sum.last.regressed();
    d["markdown"] = sum.markdownPath;
    d["figures_not_drawn"] = sum.figuresWhy;
    d["notes"] = sum.notes;
    return d;
}

}  // namespace

PYBIND11_MODULE(_pgt, m) {
    m.doc() = "pgt's C++ core; use the package pgt (docs/python.md)";
    static py::exception<pgt::InputError> inputError(m, "InputError", PyExc_ValueError);
    static py::exception<pgt::OutputError> outputError(m, "OutputError", PyExc_OSError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const pgt::InputError& e) {
            inputError(e.what());
        } catch (const pgt::OutputError& e) {
            outputError(e.what());
        }
    });
    m.def("render", &renderToPython, py::arg("file"), py::arg("text"), py::arg("out"),
          py::arg("timing_repeats"), py::arg("timing_fragments"), py::arg("gl_timing_fragments"));
    m.def("sweep", &sweep, py::arg("file"), py::arg("text"), py::arg("out"), py::arg("fresh"),
          py::arg("report"), py::arg("images"), py::arg("progress"));
    m.def("compare", &compare, py::arg("dirs"), py::arg("out"), py::arg("metric"), py::arg("bands"),
          py::arg("pairs"), py::arg("alpha"), py::arg("min_effect"), py::arg("floor"),
          py::arg("any_scene"), py::arg("figures"));
    m.def("set_memory_limit_mb", &pgt::setMemoryLimitMb, py::arg("mb"));
}
