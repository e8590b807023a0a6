// Grid search with local refinement over (scale factor, bias ratio, step counts) per method,
// against one fixed truth seen from several view angles.
#include "study/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/format.h"
#include "core/json_fields.h"
#include "frame/render.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "study/provenance.h"

namespace pgt {

namespace {

std::vector<double> listOr(JsonFields& f, const std::string& key, std::vector<double> fallback,
                           double lo, double hi) {
    if (!f.has(key)) return fallback;
    const Json& v = f.raw(key);
    if (!v.is_array() || v.empty()) f.failValue(key, v, "expected a non-empty array of numbers");
    std::vector<double> out;
    for (const auto& e : v) {
        if (!e.is_number() || e.get<double>() < lo || e.get<double>() > hi)
            f.failValue(key, v,
                        "values must be numbers in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]");
        out.push_back(e.get<double>());
    }
    return out;
}

std::vector<double> range(double from, double to, double step) {
    std::vector<double> out;
    // `to` included despite the rounding of from + k * step (the grids here step by 0.25).
    for (int k = 0; from + k * step <= to + 1e-9; ++k) out.push_back(from + k * step);
    return out;
}

struct Score {
    double objective = INFINITY, mean = NAN, p90 = NAN;
    bool ok = false;
};

}  // namespace

nlohmann::json FitResult::entry() const {
    if (!best) return nullptr;
    Json out = toJson(*best);
    out.erase("label");
    if (!scale) out.erase("scale");
    if (!bias) out.erase("bias");
    return out;
}

nlohmann::json FitReport::toJson() const {
    Json ms = Json::array();
    for (const auto& m : methods)
        ms.push_back({{"method", m.method},
                      {"steps", m.steps},
                      {"best", m.entry()},
                      {"objective_texels", m.bestObjective},
                      {"mean_texels", m.bestMean},
                      {"p90_texels", m.bestP90},
                      {"as_listed_objective_texels", m.nativeObjective},
                      {"candidates", m.candidates}});
    Json out = {{"objective", objective}, {"samples", samples},
                {"theta", thetas},        {"phi", phis},
                {"methods", ms},          {"provenance", pgt::provenance(sceneSha1)}};
    if (samples == "jittered") out["seed"] = seed;
    return out;
}

namespace {

// What the "fit" block asks for (docs/studies.md "Fitting").
struct FitPlan {
    std::vector<double> factors, ratios, steps;
    int refine = 4;
    int width = 128, height = 128;
    // The pixels' sample positions: jittered (the default, as a study samples) with one seed for
    // every candidate, so two candidates are scored on the same samples; or the pixel centres.
    bool jitter = true;
    uint32_t seed = 1;
    std::vector<MethodConfig> methods;
};

FitPlan readFitPlan(const Scene& scene, FitReport& rep) {
    Json block = scene.fit.is_null() ? Json::object() : scene.fit;
    JsonFields f(block, scene.file, "fit");
    FitPlan plan;
    rep.objective = f.choice("objective", {"mean", "p90"}, "mean");
    rep.thetas = listOr(f, "theta", range(0, 80, 10), 0, 90);
    rep.phis = listOr(f, "phi", {scene.camera.phi}, -360, 360);
    plan.factors = listOr(f, "scale_factors", range(0.25, 2.0, 0.25), -10, 10);
    plan.ratios = listOr(f, "bias_ratios", range(-1.25, 0.25, 0.25), -10, 10);
    plan.steps = listOr(f, "steps", {8, 16, 32, 64}, 1, 4096);
    plan.refine = f.integer("refine", 4, 0, 12);
    plan.jitter = f.choice("samples", {"centre", "jittered"}, "jittered") == "jittered";
    plan.seed = uint32_t(f.integer("seed", int(scene.camera.jitterSeed), 0, 2147483647));
    rep.samples = plan.jitter ? "jittered" : "centre";
    rep.seed = plan.seed;
    if (f.has("resolution")) {
        std::vector<int> res = f.integers("resolution", 2, 1, 4096);
        plan.width = res[0], plan.height = res[1];
    }
    plan.methods = f.has("methods") ? parseMethods(f.raw("methods"), scene.file, "fit.methods",
                                                   scene.worldPerUv())
                                    : scene.methods;
    f.finish();
    return plan;
}

// The fixed truth seen from every view once, and a configuration's score over those views.
class FitScorer {
  public:
    FitScorer(const Scene& scene, const FitReport& rep, const FitPlan& plan)
        : scene_(scene), objective_(rep.objective), textures_(scene.height, scene.uvExtent) {
        TruthBuilder builder(scene);
        TruthPair truths = builder.build(scene.displacement, false);
        for (double th : rep.thetas)
            for (double ph : rep.phis) {
                ViewSpec v = scene.view();
                v.camera.theta = th, v.camera.phi = ph;
                v.camera.width = plan.width, v.camera.height = plan.height;
                v.camera.jitter = plan.jitter, v.camera.jitterSeed = plan.seed;
                views_.push_back(prepareView(scene, v, truths, plan.methods));
                if (views_.back().raster.covered == 0)  // every candidate would score nothing
                    throw InputError(scene.file, "fit.theta", formatNumber(th, 9),
                                     "the view at theta " + formatNumber(th, 9) + ", phi " +
                                         formatNumber(ph, 9) +
                                         " shows no pixel of the surface (edge-on or away); fit "
                                         "over view angles that see it");
            }
    }

    // The configuration measured on every view by the one per-view pipeline (frame/render.h).
    Score score(const MethodConfig& cfg) {
        Score sc;
        const std::vector<MethodConfig> one = {cfg};
        double obj = 0, mean = 0, p90 = 0;
        for (const PreparedView& v : views_) {
            const FrameStats fs =
                renderPrepared(scene_, v, one, textures_, {.keepImages = false}).methods[0].stats;
            // A candidate that yields non-finite UVs is not a default anyone should ship.
            if (fs.nonfinite > 0 || fs.error.count == 0) return sc;
            obj += objective_ == "mean" ? fs.error.mean : fs.error.p90;
            mean += fs.error.mean;
            p90 += fs.error.p90;
        }
        double n = double(views_.size());
        return {obj / n, mean / n, p90 / n, true};
    }

  private:
    const Scene& scene_;
    std::string objective_;
    MethodTextureCache textures_;
    std::vector<PreparedView> views_;
};

// One method at one step count: the grid of (scale factor, bias ratio), then a compass
// search from its best point.
FitResult fitOne(const MethodConfig& listed, const FitPlan& plan, FitScorer& scorer, double s0) {
    FitResult fr;
    fr.method = listed.label;
    fr.nativeObjective = scorer.score(listed).objective;
    const bool usesHeight = readsDisplacement(listed);
    // A shader that s or b does not reach is fitted in the other alone (and reported so).
    const bool scaleReaches = usesHeight && reaches(listed, "scale"),
               biasReaches = usesHeight && reaches(listed, "bias");
    std::vector<double> fs = scaleReaches ? plan.factors : std::vector<double>{1};
    std::vector<double> rs = biasReaches ? plan.ratios : std::vector<double>{0};
    MethodConfig best;
    Score bestScore;
    bool found = false;
    auto consider = [&](double factor, double ratio) {
        MethodConfig c = listed;
        if (scaleReaches) c.scale = s0 * factor;
        if (biasReaches) c.bias = s0 * factor * ratio;
        Score sc = scorer.score(c);
        ++fr.candidates;
        if (sc.ok && sc.objective < bestScore.objective) bestScore = sc, best = c, found = true;
    };
    for (double fa : fs)
        for (double ra : rs) consider(fa, ra);
    // Compass search from the best grid point: move to a better 3 x 3 neighbour while there
    // is one (at most 32 moves per level), then halve the spacing; `refine` levels in all,
    // starting at half the grid's spacing.
    double df = fs.size() > 1 ? fs[1] - fs[0] : 0, dr = rs.size() > 1 ? rs[1] - rs[0] : 0;
    for (int level = 0; level < plan.refine && found && usesHeight; ++level) {
        df /= 2, dr /= 2;
        for (int move = 0; move < 32; ++move) {
            double before = bestScore.objective;
            const double sBest = scaleReaches ? best.scale : s0;
            double f0 = sBest / s0, r0 = biasReaches ? best.bias / sBest : 0;
            for (int i = -1; i <= 1; ++i)
                for (int k = -1; k <= 1; ++k)
                    if (i || k) consider(f0 + i * df, r0 + k * dr);
            if (!(bestScore.objective < before)) break;
        }
    }
    if (found) {
        fr.best = best;
        if (scaleReaches) fr.scale = best.scale;
        if (biasReaches) fr.bias = best.bias;
        fr.bestObjective = bestScore.objective;
        fr.bestMean = bestScore.mean;
        fr.bestP90 = bestScore.p90;
    }
    return fr;
}

}  // namespace

FitReport runFit(const Scene& scene, bool progress) {
    if (scene.camera.type != Projection::Orthographic)
        throw InputError(scene.file, "camera.type", toString(scene.camera.type),
                         "fitting sweeps the view angle: it needs an orthographic camera");
    FitReport rep;
    rep.sceneSha1 = pgt::sceneSha1(scene);
    const FitPlan plan = readFitPlan(scene, rep);
    // Presets are fixed configurations (fit the built-in they stand for instead); a GLSL/HLSL
    // method is fitted where s and b reach it (a uniform bound to them, or a call), at each
    // step count of its "steps_uniform".
    auto fixed = [](const MethodConfig& m) { return fittable(m) != Fittable::Yes; };
    if (std::all_of(plan.methods.begin(), plan.methods.end(), fixed))
        throw InputError(scene.file, scene.fit.contains("methods") ? "fit.methods" : "methods", "",
                         "nothing to fit: presets are fixed configurations, and a GLSL/HLSL "
                         "method is fitted only where its scale reaches the shader (a uniform "
                         "bound to \"scale\" or a call); list the methods to fit (a preset's "
                         "built-in is in docs/methods.md)");
    // Every view's truth frame and fragments are kept for the whole search: estimated as one
    // frame as tall as all of them, with one method's images at a time.
    const size_t viewCount = rep.thetas.size() * rep.phis.size();
    const std::vector<MethodConfig> one(plan.methods.begin(), plan.methods.begin() + 1);
    checkViewMemory(
        scene, plan.width, int(std::min<size_t>(viewCount * size_t(plan.height), 1u << 30)),
        {.configs = &one, .mapConfigs = &plan.methods, .keepsImages = true}, "fit.resolution");
    FitScorer scorer(scene, rep, plan);
    for (const MethodConfig& base : plan.methods) {
        if (fixed(base)) {
            if (progress)
                std::fprintf(stderr, "fit: %s skipped (%s)\n", base.label.c_str(),
                             fittable(base) == Fittable::ScaleUnused
                                 ? "its scale does not reach the shader: bind a uniform to "
                                   "\"scale\" or use s in a call"
                                 : "presets are fixed");
            continue;
        }
        const bool hasSteps = hasStepCount(base);
        for (double stepCount : hasSteps ? plan.steps : std::vector<double>{0}) {
            MethodConfig listed = base;
            if (hasSteps) setStepCount(listed, int(stepCount));
            FitResult fr = fitOne(listed, plan, scorer, scene.displacement.scale);
            fr.steps = int(stepCount);
            if (progress)
                std::fprintf(stderr,
                             "fit: %s steps %d: %d candidates, best %s %.4f (as listed %.4f)\n",
                             fr.method.c_str(), fr.steps, fr.candidates, rep.objective.c_str(),
                             fr.bestObjective, fr.nativeObjective);
            rep.methods.push_back(fr);
        }
    }
    return rep;
}

}  // namespace pgt
