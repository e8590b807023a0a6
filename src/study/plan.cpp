// The study plan (study/plan.h): the "sweep" block read into axes, frame settings and the
// method configurations (MethodConfig values varied by the parameter lists), the cases,
// and the identity a study directory is checked against.
#include "study/plan.h"

#include <cmath>
#include <map>

#include "core/format.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "frame/render.h"
#include "methods/config.h"
#include "methods/presets/presets.h"

namespace pgt {

namespace {

std::string num(double x) { return formatNumber(x, 9); }

// A list of values: [a, b, ...], a single number, or {"from": a, "to": b, "step": c}. Each
// value once as results.csv prints it (9 significant digits, a case's key): a value given
// twice would make two cases of one key, whose rows a resume could not tell apart.
std::vector<double> valueList(JsonFields& f, const std::string& key, double lo, double hi) {
    const Json& v = f.raw(key);
    std::vector<double> out;
    std::map<std::string, std::string> given;  // printed -> the value as the list gives it
    auto add = [&](double x, const Json& e) {
        const std::string shown = shortDump(e);
        auto [first, fresh] = given.emplace(num(x), shown);
        if (!fresh)
            f.failValue(key, e,
                        (first->second == shown ? "is listed twice"
                                                : "prints as " + num(x) + ", as " + first->second +
                                                      " listed before it does") +
                            " (results.csv's 9 significant digits): one case; give each value "
                            "once");
        out.push_back(x);
    };
    auto check = [&](const Json& e) {
        if (!e.is_number()) f.failValue(key, v, "expected numbers");
        double x = e.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi)
            f.failValue(key, v, "values must lie in [" + num(lo) + ", " + num(hi) + "]");
        add(x, e);
    };
    if (v.is_number()) {
        check(v);
    } else if (v.is_array()) {
        for (const auto& e : v) check(e);
    } else if (v.is_object()) {
        JsonFields r(v, f.file(), f.fieldPath(key));
        double from = r.number("from", lo, hi), to = r.number("to", lo, hi);
        double step = r.number("step", 1e-9, 1e9);
        r.finish();
        if (to < from) f.failValue(key, v, "\"to\" is below \"from\"");
        if ((to - from) / step > 10000) f.failValue(key, v, "more than 10000 values");
        // `to` included despite the rounding of from + k * step.
        for (int k = 0; from + k * step <= to + 1e-9 * step; ++k)
            add(from + k * step, from + k * step);
    } else {
        f.failValue(key, v, "expected a number, an array or {from, to, step}");
    }
    if (out.empty()) f.failValue(key, v, "no values");
    return out;
}

}  // namespace

std::string StudyCase::key() const {
    // The ratio too: at s = 0 every b / s gives b = 0 (the rows differ in bias_ratio only).
    std::string k =
        num(theta) + ";" + num(phi) + ";" + num(scale) + ";" + num(bias) + ";" + num(biasRatio);
    if (std::isfinite(lightTheta)) k += ";light " + num(lightTheta) + ";" + num(lightPhi);
    return k + ";seed " + num(seed);
}

namespace {

// The study's axes: the values of each of theta, phi, scale and bias (or b/s ratios), and
// of the light's angles (one NaN each without a light).
struct StudyAxes {
    std::vector<double> thetas, phis, scales, biases, lightThetas, lightPhis;
    std::vector<double> seeds;  // the jitter seeds: the replicates of every case
    bool ratios = false;        // `biases` are b / s
};

// What a study's axes default to: the scene's own view angles, (s, b) and light.
struct AxisDefaults {
    double theta = 0, phi = 0, scale = 0, bias = 0;
    std::optional<LightSpec> light;
    double seed = 1;  // the camera's jitter seed
    bool jitter = false;
};

// The replicates of each case: "seed": [values] or "replicates": N (seeds seed .. seed + N - 1,
// from the camera's seed); by default the camera's seed alone. More than one needs jittered
// samples: a pixel centre does not depend on the seed.
std::vector<double> readSeeds(JsonFields& f, const AxisDefaults& d) {
    if (f.has("seed") && f.has("replicates"))
        f.fail("replicates", "give either \"seed\" or \"replicates\", not both");
    std::vector<double> seeds = {d.seed};
    if (f.has("seed")) {
        seeds = valueList(f, "seed", 0, 2147483647);
        for (double v : seeds)
            if (v != std::floor(v)) f.failValue("seed", Json(v), "a seed is a whole number");
    } else if (f.has("replicates")) {
        int n = f.integer("replicates", 1, 1, 1000);
        if (d.seed + n - 1 > 2147483647)
            f.failValue("replicates", Json(n), "the seeds would pass 2147483647");
        seeds.clear();
        for (int r = 0; r < n; ++r) seeds.push_back(d.seed + r);
    }
    const bool jittered = f.has("samples") ? f.raw("samples") == Json("jittered") : d.jitter;
    if (seeds.size() > 1 && !jittered)
        f.fail(f.has("seed") ? "seed" : "replicates",
               "replicates need \"samples\": \"jittered\" (a pixel's centre has no seed)");
    return seeds;
}

StudyAxes readAxes(JsonFields& f, const AxisDefaults& d) {
    StudyAxes a;
    a.thetas = f.has("theta") ? valueList(f, "theta", 0, 90) : std::vector<double>{d.theta};
    a.phis = f.has("phi") ? valueList(f, "phi", -360, 360) : std::vector<double>{d.phi};
    a.scales = f.has("scale") ? valueList(f, "scale", -1e3, 1e3) : std::vector<double>{d.scale};
    if (f.has("bias") && f.has("bias_ratio"))
        f.fail("bias_ratio", "give either \"bias\" or \"bias_ratio\", not both");
    a.ratios = f.has("bias_ratio");
    a.biases = a.ratios        ? valueList(f, "bias_ratio", -1e3, 1e3)
               : f.has("bias") ? valueList(f, "bias", -1e3, 1e3)
                               : std::vector<double>{d.bias};
    for (const char* key : {"light_theta", "light_phi"})
        if (f.has(key) && !d.light) f.fail(key, "the scene has no \"light\" to sweep");
    // Without a light the case's light angles are NaN (results.csv's nan columns).
    a.lightThetas = f.has("light_theta") ? valueList(f, "light_theta", 0, 90)
                    : d.light            ? std::vector<double>{d.light->theta}
                                         : std::vector<double>{NAN};
    a.lightPhis = f.has("light_phi") ? valueList(f, "light_phi", -360, 360)
                  : d.light          ? std::vector<double>{d.light->phi}
                                     : std::vector<double>{NAN};
    a.seeds = readSeeds(f, d);
    return a;
}

// Resolution, pixel samples and the timing settings of a study.
void readFrameSettings(JsonFields& f, const Scene& scene, Study& st) {
    if (f.has("resolution")) {
        auto res = f.integers("resolution", 2, 1, 16384);
        st.width = res[0], st.height = res[1];
    } else {
        st.width = scene.camera.width, st.height = scene.camera.height;
    }
    st.jitter = f.choice("samples", {"centre", "jittered"},
                         scene.camera.jitter ? "jittered" : "centre") == "jittered";
    // 3 repeats over at most 4096 fragments: a median of a few ms per method and case.
    st.timing.repeats = 3;
    st.timing.maxFragments = 4096;
    if (f.has("timing")) {
        JsonFields t(f.raw("timing"), f.file(), "sweep.timing");
        st.timing.repeats = t.integer("repeats", 3, 0, 100);
        st.timing.maxFragments = t.integer("fragments", 4096, 0, 1 << 26);
        // GL: the subset repeated to this many fragments per draw, drawn for at least this
        // many ms (methods/shader/glsl_method.h GlslTimingPlan).
        st.timing.glFragments = t.integer("gl_fragments", 1 << 20, 1, 1 << 23);
        if (t.has("gl_min_ms")) st.timing.glMinMs = t.number("gl_min_ms", 0, 1e5);
        // GL cost once per (configuration, view direction), or in every case.
        st.timing.glPerView =
            t.choice("gl_timing", {"per_view", "per_case"}, "per_view") == "per_view";
        t.finish();
    }
}

// "NAME.PARAM": [values] for every method whose name or label is NAME: the lists in the
// order written, by NAME. Returns the dotted keys (for JsonFields::finish).
using ParameterLists = std::map<std::string, std::vector<std::pair<std::string, Json>>>;
std::vector<std::string> readParameterLists(JsonFields& f, const Scene& scene,
                                            ParameterLists& lists) {
    std::vector<std::string> dotted;
    for (auto it = scene.sweep.begin(); it != scene.sweep.end(); ++it) {
        auto dot = it.key().find('.');
        if (dot == std::string::npos) continue;
        dotted.push_back(it.key());
        std::string prefix = it.key().substr(0, dot), param = it.key().substr(dot + 1);
        Json values = it.value().is_array() ? it.value() : Json::array({it.value()});
        if (values.empty()) f.failValue(it.key(), it.value(), "no values");
        bool known = false;
        for (const auto& m : scene.methods)
            known = known || m.name == prefix || m.label == prefix || m.preset == prefix;
        if (!known)
            f.fail(it.key(), "no method named or labelled \"" + prefix + "\" in \"methods\"");
        lists[prefix].push_back({param, values});
    }
    return dotted;
}

// A value of a shader's list names its configuration by its label part (6 significant
// digits): a value giving an earlier one's part is the same configuration, refused.
void checkDistinctPart(std::map<std::string, std::string>& parts, const std::string& part,
                       const Json& value, const std::string& file, const std::string& field) {
    const std::string shown = shortDump(value);
    auto [first, fresh] = parts.emplace(part, shown);
    if (fresh) return;
    throw InputError(file, field, shown,
                     (first->second == shown ? "is listed twice"
                                             : "makes the label part \"" + part + "\" as " +
                                                   first->second + " listed before it does") +
                         " (a label shows 6 significant digits): one configuration; give each "
                         "value once");
}

// A generated label over kMaxGeneratedLabel bytes (long uniform names and values) is cut and
// given 8 hex digits of its SHA-1: labels name files (LABEL_error.png, with the hidden
// temporary's 34 bytes more) and EXR channels, 255 bytes at most; the params column keeps
// every value.
constexpr size_t kMaxGeneratedLabel = 200;
std::string boundedLabel(const std::string& label) {
    if (label.size() <= kMaxGeneratedLabel) return label;
    return label.substr(0, kMaxGeneratedLabel - 9) + "_" + textSha1(label).substr(0, 8);
}

// A GLSL/HLSL method's or preset's configurations: the product of the lists under its label
// (or name), each varying "scale", "bias" or "uniforms.NAME" (setShaderParameter); a varied
// configuration's label is its own with each value appended ("pom_hlsl_max_layers16").
std::vector<MethodConfig> expandShaderConfig(JsonFields& f, const MethodConfig& m,
                                             const ParameterLists& lists) {
    const std::string base = m.label.empty() ? m.name : m.label;
    std::vector<std::pair<MethodConfig, std::string>> configs = {{m, base}};
    // By its label, else by the preset's or GLSL method's own name (a built-in preset's
    // `name` is its built-in's, whose lists are the built-in's own).
    std::vector<std::string> prefixes = {base};
    const std::string own = m.preset.empty() ? m.name : m.preset;
    if (own != base) prefixes.push_back(own);
    for (const std::string& prefix : prefixes) {
        if (!lists.count(prefix)) continue;
        for (const auto& [param, values] : lists.at(prefix)) {
            if (double(configs.size()) * double(values.size()) > double(kMaxStudyConfigs))
                f.fail(prefix + "." + param, "the lists of \"" + prefix + "\" make more than " +
                                                 std::to_string(kMaxStudyConfigs) +
                                                 " configurations");
            const std::string field = f.fieldPath(prefix + "." + param);
            std::vector<std::pair<MethodConfig, std::string>> next;
            for (const auto& [c, label] : configs) {
                std::map<std::string, std::string> parts;  // label part -> the value giving it
                for (const Json& v : values) {
                    MethodConfig one = c;
                    const std::string part = setShaderParameter(one, param, v, f.file(), field);
                    checkDistinctPart(parts, part, v, f.file(), field);
                    next.push_back({std::move(one), label + "_" + part});
                }
            }
            configs = std::move(next);
        }
        break;  // the label's lists, else the name's
    }
    std::vector<MethodConfig> out;
    for (auto& [c, label] : configs) {
        if (configs.size() > 1) c.label = boundedLabel(label);
        out.push_back(std::move(c));
    }
    return out;
}

// `configs`, each once per value of the list "PREFIX.PARAM" of a built-in: validated as the
// method entry would be, naming the sweep key; a value that gives an earlier value's
// configuration (8 and 8.0) is refused.
std::vector<MethodConfig> varyBuiltIn(const JsonFields& f, const std::vector<MethodConfig>& configs,
                                      const std::string& prefix, const std::string& param,
                                      const Json& values) {
    std::vector<MethodConfig> next;
    for (const MethodConfig& c : configs) {
        std::map<std::string, std::string> made;  // the configuration -> the value making it
        for (const Json& v : values) {
            const Json entry = {{param, v}};
            JsonFields p(entry, f.file(), "sweep." + prefix);
            MethodConfig one = c;
            readMethodParameters(p, one);
            p.finish();
            auto [first, fresh] = made.emplace(toJson(one).dump(), shortDump(v));
            if (!fresh)
                throw InputError(
                    f.file(), p.fieldPath(param), shortDump(v),
                    (first->second == shortDump(v)
                         ? "is listed twice"
                         : "gives the configuration of " + first->second + ", listed before it") +
                        ": give each value once");
            next.push_back(std::move(one));
        }
    }
    return next;
}

// The configurations of a study: each built-in method times the product of its lists
// (a varied configuration's label is generated from its parameters); presets and GLSL
// methods as they are.
std::vector<MethodConfig> expandConfigs(JsonFields& f, const Scene& scene,
                                        const ParameterLists& lists) {
    std::vector<MethodConfig> out;
    for (const MethodConfig& m : scene.methods) {
        if (variedAsShader(m)) {
            for (MethodConfig& c : expandShaderConfig(f, m, lists)) out.push_back(std::move(c));
            continue;
        }
        std::vector<MethodConfig> configs = {m};
        bool varied = false;
        for (const std::string& prefix : {m.name, m.label}) {
            if (!lists.count(prefix) || (prefix == m.label && m.label == m.name && varied))
                continue;
            for (const auto& [param, values] : lists.at(prefix)) {
                if (double(configs.size()) * double(values.size()) > double(kMaxStudyConfigs))
                    f.fail(prefix + "." + param,
                           "the parameter lists of \"" + prefix + "\" make more than " +
                               std::to_string(kMaxStudyConfigs) + " configurations");
                configs = varyBuiltIn(f, configs, prefix, param, values);
                varied = true;
            }
        }
        for (MethodConfig& c : configs) {
            if (varied) c.label.clear();  // labels then carry the parameters
            out.push_back(std::move(c));
        }
    }
    assignLabels(out, f.file(), "methods");
    return out;
}

// The cases in order: grouped by (scale, bias), then theta, phi, the light's theta and phi,
// the seed.
std::vector<StudyCase> makeCases(const StudyAxes& a, const std::string& file) {
    // The case list is allocated whole: bound it before (10,001^3 values would be 10^12).
    double caseCount = double(a.scales.size()) * double(a.biases.size()) * double(a.thetas.size()) *
                       double(a.phis.size()) * double(a.lightThetas.size()) *
                       double(a.lightPhis.size()) * double(a.seeds.size());
    if (caseCount > double(kMaxStudyCases))
        throw InputError(file, "sweep", std::to_string(int64_t(caseCount)) + " cases",
                         "a study has at most " + std::to_string(kMaxStudyCases) +
                             " cases (theta x phi x scale x bias x light x seed); split it into "
                             "several");
    std::vector<StudyCase> cases;
    int index = 0;
    for (double s : a.scales)
        for (double bv : a.biases)
            for (double th : a.thetas)
                for (double ph : a.phis)
                    for (double lt : a.lightThetas)
                        for (double lp : a.lightPhis)
                            for (double seed : a.seeds) {
                                StudyCase c;
                                c.index = index++;
                                c.theta = th, c.phi = ph, c.scale = s;
                                c.bias = a.ratios ? bv * s : bv;
                                c.biasRatio = a.ratios ? bv : (s != 0 ? c.bias / s : NAN);
                                c.lightTheta = lt, c.lightPhi = lp;
                                c.seed = seed;
                                cases.push_back(c);
                            }
    return cases;
}

// What identifies a study: everything the user wrote that can change a number (not the
// description, not the fit block) beside the resolved scene, which adds the content hashes
// of its files.
Json studyIdentity(const Scene& scene, const Study& st) {
    Json cfgs = Json::array(), sources = Json::object();
    for (const auto& c : st.configs) {
        cfgs.push_back(toJson(c));
        sources[c.label] = sourceKeys(c);  // docs/references.md's keys, for the report
    }
    Json given = scene.json;
    given.erase("description");
    given.erase("fit");
    return {{"scene", resolvedSceneJson(scene)},
            {"given", given},
            {"sweep", scene.sweep},
            {"configurations", cfgs},
            {"sources", sources},
            {"cases", st.cases.size()},
            {"resolution", {st.width, st.height}},
            {"samples", st.jitter ? "jittered" : "centre"}};
}

}  // namespace

Study parseStudy(const Scene& scene) {
    const std::string& file = scene.file;
    if (scene.sweep.is_null())
        throw InputError(file, "sweep", "(missing)", "the scene has no \"sweep\" block");
    if (scene.camera.type != Projection::Orthographic)
        throw InputError(file, "camera.type", toString(scene.camera.type),
                         "studies sweep the view angle: they need an orthographic camera");
    JsonFields f(scene.sweep, file, "sweep");
    Study st;
    StudyAxes axes = readAxes(
        f, {scene.camera.theta, scene.camera.phi, scene.displacement.scale, scene.displacement.bias,
            scene.light, double(scene.camera.jitterSeed), scene.camera.jitter});
    readFrameSettings(f, scene, st);
    ParameterLists lists;
    f.finish(readParameterLists(f, scene, lists));
    st.configs = expandConfigs(f, scene, lists);
    st.cases = makeCases(axes, file);
    checkViewMemory(scene, st.width, st.height, {.configs = &st.configs},
                    f.has("resolution") ? "sweep.resolution" : "camera.resolution");
    st.resolved = studyIdentity(scene, st);
    return st;
}

std::vector<StudyCase> planCases(const Json& identity, const std::string& file) {
    // The identity holds the sweep block as written and the resolved scene, whose camera and
    // displacement are the axes' defaults (readAxes).
    const Json* scene =
        identity.is_object() && identity.contains("scene") && identity.contains("sweep")
            ? &identity.at("scene")
            : nullptr;
    auto number = [&](const char* block, const char* key) {
        if (!scene || !scene->contains(block) || !scene->at(block).contains(key) ||
            !scene->at(block).at(key).is_number())
            throw InputError(file, std::string("scene.") + block + "." + key, "",
                             "not a study's study.json (made by pgt sweep)");
        return scene->at(block).at(key).get<double>();
    };
    AxisDefaults d{number("camera", "theta"), number("camera", "phi"),
                   number("displacement", "scale"), number("displacement", "bias"), std::nullopt};
    if (scene->contains("light"))
        d.light = LightSpec{number("light", "theta"), number("light", "phi")};
    // The camera's samples as resolved; its seed as given (the resolved camera names it only
    // when the camera itself jitters), 1 when not given (scene.cpp).
    d.jitter = scene->at("camera").value("samples", "centre") == "jittered";
    if (identity.contains("given") && identity.at("given").contains("camera") &&
        identity.at("given").at("camera").is_object() &&
        identity.at("given").at("camera").contains("seed") &&
        identity.at("given").at("camera").at("seed").is_number_integer())
        d.seed = identity.at("given").at("camera").at("seed").get<double>();
    JsonFields f(identity.at("sweep"), file, "sweep");
    return makeCases(readAxes(f, d), file);
}

}  // namespace pgt
