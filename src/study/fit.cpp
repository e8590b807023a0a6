// Grid search with local refinement over (scale factor, bias ratio, step counts) per method,
// against one fixed truth seen from several view angles.
#include "study/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/json_fields.h"
#include "methods/registry.h"
#include "study/render.h"

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
    for (int k = 0; from + k * step <= to + 1e-9; ++k) out.push_back(from + k * step);
    return out;
}

// The step-count parameter a method's fit varies, if any.
const char* stepParameter(MethodKind kind) {
    switch (kind) {
        case MethodKind::Steep:
        case MethodKind::Pom:
            return "layers";
        case MethodKind::Relief:
            return "linear_steps";
        case MethodKind::Iterative:
            return "iterations";
        default:
            return nullptr;
    }
}

struct View {
    Image2D<TruthSample> truth;
    FragmentList frags;
    int width, height;
};

struct Score {
    double objective = INFINITY, mean = NAN, p90 = NAN;
    bool ok = false;
};

}  // namespace

nlohmann::json FitReport::toJson() const {
    Json ms = Json::array();
    for (const auto& m : methods)
        ms.push_back({{"method", m.method},
                      {"steps", m.steps},
                      {"best", m.best},
                      {"objective_texels", m.bestObjective},
                      {"mean_texels", m.bestMean},
                      {"p90_texels", m.bestP90},
                      {"as_listed_objective_texels", m.nativeObjective},
                      {"candidates", m.candidates}});
    return {{"objective", objective}, {"theta", thetas}, {"phi", phis}, {"methods", ms}};
}

FitReport runFit(const Scene& scene, bool progress) {
    if (scene.camera.type != "orthographic")
        throw InputError(scene.file, "camera.type", scene.camera.type,
                         "fitting sweeps the view angle: it needs an orthographic camera");
    Json block = scene.fit.is_null() ? Json::object() : scene.fit;
    JsonFields f(block, scene.file, "fit");
    FitReport rep;
    rep.objective = f.choice("objective", {"mean", "p90"}, "mean");
    rep.thetas = listOr(f, "theta", range(0, 80, 10), 0, 90);
    rep.phis = listOr(f, "phi", {scene.camera.phi}, -360, 360);
    std::vector<double> factors = listOr(f, "scale_factors", range(0.25, 2.0, 0.25), -10, 10);
    std::vector<double> ratios = listOr(f, "bias_ratios", range(-1.25, 0.25, 0.25), -10, 10);
    std::vector<double> steps = listOr(f, "steps", {8, 16, 32, 64}, 1, 4096);
    int refine = f.integer("refine", 4, 0, 12);
    std::vector<int> res =
        f.has("resolution") ? f.integers("resolution", 2, 1, 4096) : std::vector<int>{128, 128};
    std::vector<MethodConfig> methods =
        f.has("methods") ? parseMethods(f.raw("methods"), scene.file, "fit.methods")
                         : scene.methods;
    f.finish();
    // Every view's truth frame and fragments are kept for the whole search: estimated as one
    // frame as tall as all of them, with one method's images at a time.
    const size_t viewCount = rep.thetas.size() * rep.phis.size();
    checkViewMemory(scene, res[0], int(std::min<size_t>(viewCount * size_t(res[1]), 1u << 30)), 1,
                    false, false, "fit.resolution");

    // The fixed truth, seen from every view once.
    TruthBuilder builder(scene);
    TruthPair truths = builder.build(scene.displacement, false);
    std::vector<View> views;
    for (double th : rep.thetas)
        for (double ph : rep.phis) {
            Scene v = scene;
            v.camera.theta = th, v.camera.phi = ph;
            v.camera.width = res[0], v.camera.height = res[1];
            Camera cam = makeCamera(v);
            View view{
                truths.truth->traceFrame(cam),
                compactFragments(rasterize(sceneBaseMesh(v, cam), cam, {scene.cullBackFaces})),
                res[0], res[1]};
            views.push_back(std::move(view));
        }
    MethodTextureCache textures(scene.height, scene.uvExtent);
    const double s0 = scene.displacement.scale, b0 = scene.displacement.bias;

    auto score = [&](const MethodConfig& cfg) {
        Score sc;
        double s = std::isfinite(cfg.scale) ? cfg.scale : s0;
        double b = std::isfinite(cfg.bias) ? cfg.bias : b0;
        const MethodTextures& tex = textures.get(s, b, needsDerivedMaps(cfg));
        double obj = 0, mean = 0, p90 = 0;
        for (const View& v : views) {
            auto px = evaluateMethod(cfg, v.frags, tex, v.width, v.height);
            FrameStats fs = compareWithTruth(v.truth, px, scene.height.width, scene.height.height,
                                             scene.height.address);
            // A candidate that yields non-finite UVs is not a default anyone should ship.
            if (fs.nonfinite > 0 || fs.error.count == 0) return sc;
            obj += rep.objective == "mean" ? fs.error.mean : fs.error.p90;
            mean += fs.error.mean;
            p90 += fs.error.p90;
        }
        double n = double(views.size());
        sc = {obj / n, mean / n, p90 / n, true};
        return sc;
    };

    for (const MethodConfig& base : methods) {
        // Presets are fixed configurations (fit the built-in they stand for instead), and a
        // GLSL method's parameters are its uniforms, which pgt does not vary.
        if (base.glsl || !base.preset.empty()) {
            if (progress)
                std::fprintf(stderr, "fit: %s skipped (presets and GLSL methods are fixed)\n",
                             base.label.c_str());
            continue;
        }
        const char* stepKey = stepParameter(base.kind);
        std::vector<double> stepList = stepKey ? steps : std::vector<double>{0};
        bool usesHeight = base.kind != MethodKind::None;
        std::vector<double> fs = usesHeight ? factors : std::vector<double>{1};
        std::vector<double> rs = usesHeight ? ratios : std::vector<double>{0};
        for (double stepCount : stepList) {
            FitResult fr;
            fr.method = base.label;
            fr.steps = int(stepCount);
            Json listed = toJson(base);
            if (stepKey) listed[stepKey] = fr.steps;
            fr.nativeObjective = score(parseMethod(listed, scene.file, "fit")).objective;
            Json bestJ;
            Score best;
            auto consider = [&](double factor, double ratio) {
                Json j = listed;
                if (usesHeight) {
                    j["scale"] = s0 * factor;
                    j["bias"] = s0 * factor * ratio;
                }
                Score sc = score(parseMethod(j, scene.file, "fit"));
                ++fr.candidates;
                if (sc.ok && sc.objective < best.objective) best = sc, bestJ = j;
            };
            for (double fa : fs)
                for (double ra : rs) consider(fa, ra);
            // Compass search from the best grid point: move to a better 3 x 3 neighbour while
            // there is one (at most 32 moves per level), then halve the spacing; `refine`
            // levels in all, starting at half the grid's spacing.
            double df = fs.size() > 1 ? fs[1] - fs[0] : 0, dr = rs.size() > 1 ? rs[1] - rs[0] : 0;
            for (int level = 0; level < refine && !bestJ.is_null() && usesHeight; ++level) {
                df /= 2, dr /= 2;
                for (int move = 0; move < 32; ++move) {
                    double before = best.objective;
                    double f0 = bestJ["scale"].get<double>() / s0;
                    double r0 = bestJ["bias"].get<double>() / bestJ["scale"].get<double>();
                    for (int i = -1; i <= 1; ++i)
                        for (int k = -1; k <= 1; ++k)
                            if (i || k) consider(f0 + i * df, r0 + k * dr);
                    if (!(best.objective < before)) break;
                }
            }
            if (!bestJ.is_null()) {
                Json out = toJson(parseMethod(bestJ, scene.file, "fit"));
                out.erase("label");
                fr.best = out;
                fr.bestObjective = best.objective;
                fr.bestMean = best.mean;
                fr.bestP90 = best.p90;
            }
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
