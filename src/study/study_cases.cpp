// A study's cases run (study/study_cases.h): one truth per (s, b), the cases of a surface in a
// pipeline, the GL's timings per view direction, draws and C++ timings kept apart.
#include "study/study_cases.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <map>
#include <mutex>
#include <tuple>

#include "core/clock.h"
#include "core/interrupt.h"
#include "evaluate/vertex_inputs.h"
#include "study/outputs.h"
#include "study/study_dir.h"

namespace pgt {

ViewSpec caseView(const Scene& scene, const Study& study, const StudyCase& c) {
    ViewSpec view = scene.view();
    view.camera.theta = c.theta;
    view.camera.phi = c.phi;
    view.camera.width = study.width;
    view.camera.height = study.height;
    view.camera.jitter = study.jitter;
    view.camera.jitterSeed = uint32_t(c.seed);
    view.displacement = {c.scale, c.bias};
    if (std::isfinite(c.lightTheta)) view.light = LightSpec{c.lightTheta, c.lightPhi};
    return view;
}

namespace {

// One case rendered with its methods' timing deferred (and, with images, its files being
// written: `writer` finishes them once the timing is in), its GLSL draws run by `glDraw`.
RenderResult renderCase(const Scene& scene, const Study& study, const CaseOptions& opt,
                        const StudyCase& c, const TruthPair& truths, MethodTextureCache& textures,
                        std::unique_ptr<RenderWriter>& writer,
                        const std::function<void(const std::function<void()>&)>& glDraw) {
    const ViewSpec view = caseView(scene, study, c);
    FrameOptions frame{.keepImages = false, .deferTiming = true, .glDraw = glDraw};
    if (!opt.imagesDir.empty()) {
        writer =
            std::make_unique<RenderWriter>(scene, caseImagesDir(opt.imagesDir, c.index),
                                           view.camera.width, view.camera.height, study.configs);
        frame.sinks.push_back(writer.get());
        frame.keepCodedErrors = true;
    }
    return renderView(scene, view, truths, study.configs, textures, study.timing, frame);
}

// Keeps GL draws and C++ timing apart: a timing shares its core with nothing but another
// case's rendering or timing (as in a 1-core run, where each runs alone), and a software
// GL's threads never take a core a timing runs on. Rendering passes freely. Fair: a waiting
// draw goes before new timings.
class DrawGate {
  public:
    template <class F>
    void timing(F work) {
        {
            std::unique_lock<std::mutex> l(mutex_);
            cv_.wait(l, [&] { return !drawing_ && waitingDraws_ == 0; });
            ++timing_;
        }
        struct Leave {
            DrawGate& g;
            ~Leave() {
                std::lock_guard<std::mutex> l(g.mutex_);
                --g.timing_;
                g.cv_.notify_all();
            }
        } leave{*this};
        isolated(work);
    }
    template <class F>
    void draw(F work) {
        {
            std::unique_lock<std::mutex> l(mutex_);
            ++waitingDraws_;
            cv_.wait(l, [&] { return !drawing_ && timing_ == 0; });
            --waitingDraws_;
            drawing_ = true;
        }
        struct Leave {
            DrawGate& g;
            ~Leave() {
                std::lock_guard<std::mutex> l(g.mutex_);
                g.drawing_ = false;
                g.cv_.notify_all();
            }
        } leave{*this};
        isolated(work);
    }

    // A thread inside a stage waits for its own tasks only: it never picks up another
    // case's stage (which could wait at this gate for the stage it interrupted).
    template <class F>
    static void isolated(F&& work) {
        tbb::this_task_arena::isolate([&] { work(); });
    }

  private:
    std::mutex mutex_;
    std::condition_variable cv_;
    int timing_ = 0, waitingDraws_ = 0;
    bool drawing_ = false;
};

// GLSL methods' cost per (configuration, view direction), timed once in a run on the first
// case of the view it reaches and shared by the view's other (s, b): a draw's cost follows
// the view's fragments, not the relief's scale (docs/studies.md); with gl_timing "per_case",
// per (configuration, case). Timed before a surface's cases run, with nothing beside them.
class GlTimings {
  public:
    // Times, alone, each GLSL configuration of `study` for the views of `cases` not timed yet,
    // on the view's timing subset with the maps of the case's (s, b).
    void timeMissing(const Scene& scene, const Study& study, const StudyCase* const* cases,
                     size_t n, MethodTextureCache& textures, StageTimes& stages) {
        if (study.timing.repeats <= 0) return;
        auto t0 = Clock::now();
        for (size_t i = 0; i < n; ++i) {
            const StudyCase& c = *cases[i];
            bool any = false;
            for (size_t k = 0; k < study.configs.size(); ++k)
                any = any || (runsInGl(study.configs[k]) && !timed_.count(key(study, k, c)));
            if (!any) continue;
            const FragmentList frags =
                viewTimingFragments(scene, caseView(scene, study, c), study.timing);
            for (size_t k = 0; k < study.configs.size(); ++k) {
                const MethodConfig& cfg = study.configs[k];
                if (!runsInGl(cfg) || timed_.count(key(study, k, c))) continue;
                const MethodTextures& tex = textures.get(cfg, {c.scale, c.bias});
                const std::optional<VertexOutputs> vertex =
                    viewVertexOutputs(scene, caseView(scene, study, c), cfg, tex.scale, tex.bias);
                timed_[key(study, k, c)] = {
                    timeMethod(cfg, frags, tex, study.timing, vertex ? &*vertex : nullptr),
                    c.index};
            }
        }
        stages.add(Stage::GlTimingWall, msSince(t0));
    }
    // A case's GLSL methods given their view's timing.
    void fill(RenderResult& r, const Study& study, const StudyCase& c) const {
        for (size_t k = 0; k < study.configs.size(); ++k) {
            auto it = timed_.find(key(study, k, c));
            if (it == timed_.end()) continue;
            MethodFrame& mf = r.methods[k];
            mf.timing = it->second.first;
            mf.nsPerPixel = mf.timing.median;
            mf.timingCase = it->second.second;
        }
    }

  private:
    // (configuration, theta, phi), or with gl_timing "per_case" (configuration, case).
    using Key = std::tuple<size_t, double, double, int>;
    static Key key(const Study& study, size_t config, const StudyCase& c) {
        if (study.timing.glPerView) return {config, c.theta, c.phi, -1};
        return {config, 0.0, 0.0, c.index};
    }
    std::map<Key, std::pair<MethodTiming, int>> timed_;
};

// What runs the cases of a study: the truth per (s, b), the maps, the GL's timings, the gate.
struct CaseRunner {
    const Scene& scene;
    const Study& study;
    const CaseOptions& opt;
    const CaseDone& done;
    StageTimes& stages;
    MethodTextureCache textures;
    GlTimings glTimings;
    DrawGate gate;
};

// One case: rendered (its stages over the cores the other cases in flight leave), its GLSL
// methods drawn alone, its C++ methods timed single-threaded, then (in case order) its rows
// appended whole.
struct CaseInFlight {
    const StudyCase* c = nullptr;
    RenderResult r;
    std::unique_ptr<RenderWriter> writer;
};

void runCase(CaseRunner& run, const TruthPair& truths, CaseInFlight& f) {
    throwIfCancelled();
    // The render's GLSL draws (a band at a time) run through the gate, alone with respect
    // to C++ timings.
    auto glDraw = [&run](const std::function<void()>& draw) { run.gate.draw(draw); };
    DrawGate::isolated([&] {
        f.r =
            renderCase(run.scene, run.study, run.opt, *f.c, truths, run.textures, f.writer, glDraw);
    });
    run.gate.timing([&] { timeMethods(f.r, run.textures, run.study.timing, false); });
    run.glTimings.fill(f.r, run.study, *f.c);
}

void finishCase(CaseRunner& run, CaseInFlight& f) {
    if (f.writer) f.writer->finish(f.r);
    run.stages += f.r.timings;
    run.done(*f.c, f.r);
}

// The cases of one (s, b) on the truth re-displaced for it, at most one in flight per core:
// each case's rows land as soon as it and the cases before it are done, so a kill loses at
// most the cases in flight.
void runSurface(CaseRunner& run, const StudyCase* const* cases, size_t n, const TruthPair& truths) {
    for (const MethodConfig& cfg : run.study.configs)  // every map made before cases share them
        run.textures.get(cfg, {cases[0]->scale, cases[0]->bias});
    run.glTimings.timeMissing(run.scene, run.study, cases, n, run.textures, run.stages);
    auto t0 = Clock::now();
    // Grazing views first: they cost the most (more steps, longer marches), so the surface
    // ends on its cheapest cases and the cores wait least for its last one.
    std::vector<const StudyCase*> order(cases, cases + n);
    std::stable_sort(order.begin(), order.end(),
                     [](const StudyCase* a, const StudyCase* b) { return a->theta > b->theta; });
    const size_t tokens = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    std::vector<CaseInFlight> slots(tokens);
    size_t next = 0;
    tbb::parallel_pipeline(
        tokens, tbb::make_filter<void, CaseInFlight*>(tbb::filter_mode::serial_in_order,
                                                      [&](tbb::flow_control& fc) -> CaseInFlight* {
                                                          if (next == n) {
                                                              fc.stop();
                                                              return nullptr;
                                                          }
                                                          CaseInFlight* f = &slots[next % tokens];
                                                          *f = CaseInFlight{};
                                                          f->c = order[next++];
                                                          return f;
                                                      }) &
                    tbb::make_filter<CaseInFlight*, CaseInFlight*>(tbb::filter_mode::parallel,
                                                                   [&](CaseInFlight* f) {
                                                                       runCase(run, truths, *f);
                                                                       return f;
                                                                   }) &
                    tbb::make_filter<CaseInFlight*, void>(tbb::filter_mode::serial_in_order,
                                                          [&](CaseInFlight* f) {
                                                              finishCase(run, *f);
                                                              f->r = RenderResult{};
                                                          }));
    run.stages.add(Stage::CasesWall, msSince(t0));
}

}  // namespace

void runStudyCases(const Scene& scene, const Study& study,
                   const std::vector<const StudyCase*>& todo, const CaseOptions& opt,
                   const CaseDone& done, StageTimes& stages) {
    TruthBuilder builder(scene);
    CaseRunner run{
        scene, study, opt, done, stages, MethodTextureCache(scene.height, scene.uvExtent), {}, {}};
    for (size_t first = 0, last = 0; first < todo.size(); first = last) {
        const double scale = todo[first]->scale, bias = todo[first]->bias;
        while (last < todo.size() && todo[last]->scale == scale && todo[last]->bias == bias) ++last;
        // One truth per (s, b), reused for every view of that surface.
        auto tb = Clock::now();
        const TruthPair& truths = builder.update({scale, bias}, scene.truth.uncertainty);
        run.textures.clear();
        stages.add(Stage::TruthBuild, msSince(tb));
        runSurface(run, &todo[first], last - first, truths);
    }
}

}  // namespace pgt
