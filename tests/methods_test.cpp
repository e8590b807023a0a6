// Methods on closed forms: constant height, head-on view, loop bounds, precision option.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>

#include "core/json_read.h"
#include "frame/render.h"
#include "methods/builtin/layered.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

using test::makeTexture;
using test::method;

struct MethodRun {
    Vec2f uv;
    MethodContext<float> ctx;
};

MethodRun runFloat(const MethodConfig& cfg, const MethodTextures& tex, Vec2f uv0, Vec3f v) {
    MethodRun r;
    r.ctx = makeMethodContext<float>(tex);
    r.uv = runMethod<float>(*cfg.builtin(), r.ctx, uv0, v);
    return r;
}

// Head-on (V = +z): every method returns uv0 (docs/model.md §6b: every offset is V.xy * x).
// Exactly, except pom, whose prev * w + uv * (1 - w) with prev == uv rounds once or twice:
// at most 2 ulps of a UV in [0, 1] (2 * 2^-24 < 1.2e-7).
TEST(Methods, HeadOnViewReturnsBaseUv) {
    Texture t = test::smoothTexture(32, 32);
    MethodTextureCache cache(t, UvExtent(1.0));
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (const MethodKindInfo& kind : methodKinds()) {  // every built-in, from the table
        MethodConfig cfg = method(std::string(R"({"name":")") + kind.name + "\"}");
        const MethodTextures& tex = cache.get(cfg, Displacement{0.07, -0.035});
        for (int k = 0; k < 200; ++k) {
            Vec2f uv0(uni(rng), uni(rng));
            MethodRun r = runFloat(cfg, tex, uv0, Vec3f(0, 0, 1));
            // pom and contact interpolate: prev * w + uv * (1 - w) with prev == uv.
            const bool blends = cfg.builtin()->kind == MethodKind::Pom ||
                                cfg.builtin()->kind == MethodKind::Contact;
            float tol = blends ? 1.2e-7f : 0.0f;
            EXPECT_NEAR(r.uv.x, uv0.x, tol) << cfg.name << " uv0 " << uv0.x << "," << uv0.y;
            EXPECT_NEAR(r.uv.y, uv0.y, tol) << cfg.name << " uv0 " << uv0.x << "," << uv0.y;
        }
    }
}

// Constant height c: the true offset is V.xy / V.z * (s*c + b) (docs/model.md §3). parallax and
// pom are exact there (pom interpolates a straight line); offset limiting is off by the
// closed form |s*c + b| * |V.xy| * (1/V.z - 1).
TEST(Methods, ExactOnConstantHeight) {
    const double c = 0.3, s = 0.06, b = -0.03;
    Texture t = makeTexture(16, 16, [&](int, int) { return c; });
    MethodTextures tex = makeMethodTextures(t, s, b, 1.0, true);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        Vec2d uv0(uni(rng), uni(rng));
        Vec3d v = viewFromAngles(75 * uni(rng), 360 * uni(rng));
        Vec2d expected = uv0 + Vec2d(v.x, v.y) / v.z * (s * c + b);
        Vec2d limited = uv0 + Vec2d(v.x, v.y) * (s * c + b);
        // float inputs: uv0 and V are rounded once; 1e-6 UV covers that and the arithmetic.
        Vec2f uvf(uv0), expectedF(expected);
        Vec3f vf(v);
        auto near = [&](const char* m, Vec2f want, float tol) {
            MethodRun r = runFloat(method(m), tex, uvf, vf);
            EXPECT_NEAR(r.uv.x, want.x, tol) << m << " theta case " << k;
            EXPECT_NEAR(r.uv.y, want.y, tol) << m << " theta case " << k;
        };
        near(R"({"name":"parallax"})", expectedF, 2e-6f);
        near(R"({"name":"pom"})", expectedF, 2e-5f);
        // secant: f = d - t is linear in t, so its first secant lands on the root.
        near(R"({"name":"secant"})", expectedF, 2e-6f);
        near(R"({"name":"contact"})", expectedF, 2e-5f);
        near(R"({"name":"offset_limited"})", Vec2f(limited), 2e-6f);
        // iterative on a flat map: m = +z, P = s*c + b, four quarter steps = offset limiting.
        near(R"({"name":"iterative"})", Vec2f(limited), 2e-6f);
        // tangent plane on a flat map: n = +z, dot(n, V) = V.z: the exact offset.
        near(R"({"name":"tangent_plane"})", expectedF, 2e-6f);
        // iterative_slope on a flat map: n_z = 1, so z_k = H (1 - (1 - V.z)^k), H = s c + b,
        // and the offset is V.xy z_k / V.z (Premecz's damped steps toward the exact offset).
        const double zk = (s * c + b) * (1 - std::pow(1 - v.z, 4));
        near(R"({"name":"iterative_slope"})", Vec2f(uv0 + Vec2d(v.x, v.y) / v.z * zk), 2e-6f);
    }
}

// iterative_slope on a ramp h = a + k u (the derived normal's central differences exact inside
// the map: m = (-s k, 0, 1) / sqrt(1 + (s k)^2)): the ray parameter t (p = (uv0, 0) + t V)
// obeys t' = t (1 - m_z D) + m_z A with A = s (a + k u0) + b and D = V.z - s k V.x, so
// t_n = t* (1 - (1 - m_z D)^n), t* = A / D the exact crossing: each step shrinks the error by
// the factor 1 - m_z D = 1 - dot(m, V), and 64 steps land on the crossing.
TEST(Methods, IterativeSlopeClosedFormOnARamp) {
    const double a = 0.2, k = 0.6, s = 0.1, b = -0.07;
    const Texture ramp = makeTexture(
        32, 32, [&](int i, int) { return a + k * (i + 0.5) / 32; }, Address::Clamp);
    MethodTextures tex = makeMethodTextures(ramp, s, b, 1.0, true);
    const double mz = 1 / std::sqrt(1 + s * k * s * k);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int c = 0; c < 200; ++c) {
        // Inside the texel centres whose neighbours are interior (the normal is exact there).
        const Vec2d uv0(0.3 + 0.4 * uni(rng), 0.2 + 0.6 * uni(rng));
        const Vec3d v = viewFromAngles(75 * uni(rng), 360 * uni(rng));
        const double A = s * (a + k * uv0.x) + b, D = v.z - s * k * v.x, exact = A / D;
        for (int n : {1, 2, 4, 64}) {
            const double t = exact * (1 - std::pow(1 - mz * D, n));
            const Vec2d want = uv0 + Vec2d(v.x, v.y) * t;
            const MethodConfig cfg =
                method(R"({"name":"iterative_slope","iterations":)" + std::to_string(n) + "}");
            const MethodRun r = runFloat(cfg, tex, Vec2f(uv0), Vec3f(v));
            EXPECT_NEAR(r.uv.x, want.x, 2e-6) << "iterations " << n << " case " << c;
            EXPECT_NEAR(r.uv.y, want.y, 2e-6) << "iterations " << n << " case " << c;
            EXPECT_EQ(r.ctx.fetches, 2 * n);  // the normal and the height at each step
            EXPECT_NEAR(r.ctx.foundHeight, t * v.z, 2e-6);
            if (n == 64) {  // on the eye ray's exact crossing with the ramp
                const Vec2d crossing = uv0 + Vec2d(v.x, v.y) * exact;
                EXPECT_NEAR(r.uv.x, crossing.x, 3e-6) << "case " << c;
                EXPECT_NEAR(r.uv.y, crossing.y, 3e-6) << "case " << c;
            }
        }
    }
}

// Steep on constant depth d stops at the first layer k/n >= d: uv = start - D * ceil(d*n).
TEST(Methods, SteepStopsAtTheFirstLayerBelowTheSurface) {
    const double c = 0.35, s = 0.05, b = -0.05;  // native LearnOpenGL (b = -s)
    Texture t = makeTexture(8, 8, [&](int, int) { return c; });
    MethodTextures tex = makeMethodTextures(t, s, b, 1.0, false);
    MethodConfig cfg = method(R"({"name":"steep","layers":10})");
    Vec3d v = viewFromAngles(50, 20);
    MethodRun r = runFloat(cfg, tex, Vec2f(0.5f, 0.5f), Vec3f(v));
    Vec2d delta = Vec2d(v.x, v.y) / v.z * s / 10.0;
    // d = 0.65 lies between layers 0.6 and 0.7 (no float tie): 7 steps.
    Vec2d want = Vec2d(0.5, 0.5) - delta * 7.0;
    EXPECT_NEAR(r.uv.x, want.x, 1e-6);
    EXPECT_NEAR(r.uv.y, want.y, 1e-6);
    EXPECT_EQ(r.ctx.fetches, 1 + 7);
}

TEST(Methods, MaxStepsBoundsTheMarchAndIsFlagged) {
    Texture t = makeTexture(8, 8, [&](int, int) { return 0.0; });  // depth 1 everywhere
    MethodTextures tex = makeMethodTextures(t, 0.1, -0.1, 1.0, false);
    MethodRun r = runFloat(method(R"({"name":"steep","layers":32,"max_steps":5})"), tex,
                           Vec2f(0.5f), Vec3f(viewFromAngles(40, 0)));
    EXPECT_EQ(r.ctx.fetches, 6);
    EXPECT_TRUE(r.ctx.flags & kFlagStepLimit);
}

TEST(Methods, ReliefFetchesEveryStep) {
    Texture t = test::smoothTexture(16, 16);
    MethodTextures tex = makeMethodTextures(t, 0.05, -0.05, 1.0, false);
    MethodRun r = runFloat(method(R"({"name":"relief","linear_steps":10,"binary_steps":5})"), tex,
                           Vec2f(0.3f, 0.6f), Vec3f(viewFromAngles(60, 100)));
    EXPECT_EQ(r.ctx.fetches, 9 + 5);
}

// Double precision runs the same algorithm: on a smooth map it agrees with float to float
// rounding except where a step count flips.
TEST(Methods, DoublePrecisionAgreesWithFloatUpToRounding) {
    Texture t = test::smoothTexture(64, 64);
    MethodTextures tex = makeMethodTextures(t, 0.05, -0.025, 1.0, true);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (const char* m :
         {R"({"name":"parallax"})", R"({"name":"iterative"})", R"({"name":"tangent_plane"})"}) {
        MethodConfig cfg = method(m);
        for (int k = 0; k < 100; ++k) {
            Vec2d uv0(uni(rng), uni(rng));
            Vec3d v = viewFromAngles(60 * uni(rng), 360 * uni(rng));
            MethodContext<double> cd = makeMethodContext<double>(tex);
            Vec2d ud = runMethod<double>(*cfg.builtin(), cd, uv0, v);
            MethodRun rf = runFloat(cfg, tex, Vec2f(uv0), Vec3f(v));
            EXPECT_NEAR(ud.x, rf.uv.x, 1e-5) << m;
            EXPECT_NEAR(ud.y, rf.uv.y, 1e-5) << m;
        }
    }
}

TEST(Methods, LabelsAreUniqueAndCarryParameters) {
    auto list = parseMethods(
        nlohmann::json::parse(R"(["pom", {"name":"pom","max_layers":64}, "steep", "steep"])"), "s",
        "methods");
    ASSERT_EQ(list.size(), 4u);
    EXPECT_EQ(list[0].label, "pom_8_32");
    EXPECT_EQ(list[1].label, "pom_8_64");
    EXPECT_EQ(list[2].label, "steep_8_32");
    EXPECT_EQ(list[3].label, "steep_8_32_2");
}

// The kind table (methods/registry.h) is what parse, labels, JSON and the fit read: each row
// sits at its enum value, and a configuration with every parameter moved off its default
// survives toJson -> parseMethod unchanged.
TEST(Registry, EveryKindRoundTripsThroughItsJson) {
    ASSERT_EQ(methodKinds().size(), methodNames().size());
    for (const MethodKindInfo& k : methodKinds()) {
        ASSERT_EQ(&kindInfo(k.kind), &k) << k.name;
        MethodConfig cfg = parseMethod(nlohmann::json(k.name), "s", "m");
        BuiltinMethod& b = *cfg.builtin();
        EXPECT_EQ(b.kind, k.kind);
        int value = 2;
        for (const IntParameter& p : k.parameters)
            if (p.written) p.set(b, std::min(p.hi, p.lo + value++));
        cfg.scale = 0.07, cfg.bias = -0.01, b.doublePrecision = true;
        cfg.label = std::string(1, 'x');  // (a literal here trips GCC 12's -Wrestrict)
        nlohmann::json j = toJson(cfg);
        EXPECT_EQ(toJson(parseMethod(j, "s", "m")), j) << k.name;
    }
}

// A fit's step count sets every field its key sets: a fixed layer count is min = max.
TEST(Registry, StepCountSetsTheFitsParameter) {
    MethodConfig pom = parseMethod(nlohmann::json("pom"), "s", "m");
    ASSERT_TRUE(setStepCount(pom, 48));
    EXPECT_EQ(pom.builtin()->as<LayerParameters>().minLayers, 48);
    EXPECT_EQ(pom.builtin()->as<LayerParameters>().maxLayers, 48);
    MethodConfig relief = parseMethod(nlohmann::json("relief"), "s", "m");
    ASSERT_TRUE(setStepCount(relief, 7));
    EXPECT_EQ(relief.builtin()->as<ReliefParameters>().linearSteps, 7);
    EXPECT_EQ(relief.builtin()->as<ReliefParameters>().binarySteps, 5);  // untouched
    MethodConfig parallax = parseMethod(nlohmann::json("parallax"), "s", "m");
    EXPECT_FALSE(setStepCount(parallax, 7));
}

// The built-in presets are the documents' settings (docs/methods.md "Engine presets"), written out.
// Every source key pgt prints (`pgt methods`: each built-in kind's, each preset's) is defined
// in docs/references.md as a row "| `key` |", and every kind but none and every preset cites
// at least one.
TEST(Sources, EveryKeyIsDefinedInTheReferences) {
    const std::string references = test::testSourceDir() + "/../docs/references.md";
    const std::string text = readTextFile(references, references, "", "the references", 1 << 20);
    auto check = [&](const std::string& owner, const std::string& keys) {
        std::istringstream in(keys);
        std::string key;
        int n = 0;
        while (in >> key) {
            ++n;
            EXPECT_NE(text.find("| `" + key + "` |"), std::string::npos) << owner << ": " << key;
        }
        EXPECT_GT(n, 0) << owner << " cites no source";
    };
    for (const MethodKindInfo& kind : methodKinds())
        if (kind.kind != MethodKind::None) check(kind.name, kind.cite);
    for (const MethodPreset& p : methodPresets()) check(p.name, presetCite(p.name));
    EXPECT_EQ(sourceKeys(method(R"({"name":"pom"})")), "brawley2004 tatarchuk2006 devries2020");
}

// The method table is the one list: README's methods table and docs/methods.md's table of
// methods and sources each have a row naming every built-in kind.
TEST(Sources, EveryKindIsInTheReadmeAndMethodsTables) {
    auto read = [](const std::string& rel) {
        const std::string path = test::testSourceDir() + "/../" + rel;
        return readTextFile(path, path, "", "the documentation", 1 << 22);
    };
    const std::string readme = read("README.md"), methods = read("docs/methods.md");
    // A section's first table: from its header row to the first blank line after it.
    auto table = [](const std::string& text, const std::string& section) {
        const size_t at = text.find("\n| ", text.find(section));
        EXPECT_NE(at, std::string::npos) << section;
        return at == std::string::npos ? std::string()
                                       : text.substr(at, text.find("\n\n", at) - at);
    };
    const std::string readmeRows = table(readme, "## Methods"),
                      methodsRows = table(methods, "## Methods and their sources");
    for (const MethodKindInfo& kind : methodKinds()) {
        const std::string name = std::string("`") + kind.name + "`";
        // README groups some rows ("| `parallax`, `offset_limited` |"): the name in a first cell.
        const std::regex readmeRow("\n\\| [^|]*" + name + "[^|]*\\|");
        EXPECT_TRUE(std::regex_search(readmeRows, readmeRow)) << kind.name << ": README";
        EXPECT_NE(methodsRows.find("\n| " + name + " |"), std::string::npos)
            << kind.name << ": docs/methods.md";
    }
}

// docs/methods.md's table of the GLSL presets' uniforms is checked against the presets
// (methods/presets/presets.cpp, where each default is written; the C++ twins read it there):
// every GLSL preset is in a row, and every uniform it sets is listed there with its value.
TEST(Presets, TheUniformsTableIsThePresetsUniforms) {
    const std::string path = test::testSourceDir() + "/../docs/methods.md";
    const std::string text = readTextFile(path, path, "", "the documentation", 1 << 22);
    const size_t at = text.find("| preset | its uniforms (shipped values) |");
    ASSERT_NE(at, std::string::npos);
    const std::string rows = text.substr(at, text.find("\n\n", at) - at);
    // preset -> uniform -> the value its row gives ("−" is a minus).
    std::map<std::string, std::map<std::string, double>> documented;
    std::istringstream in(rows);
    std::string line;
    const std::regex name("`([a-z0-9_]+)`"), pair("`([a-z_]+)` ((?:−)?-?[0-9.]+)");
    while (std::getline(in, line)) {
        const size_t bar = line.find(" | ", 2);
        if (line.rfind("| `", 0) != 0 || bar == std::string::npos) continue;
        const std::string first = line.substr(0, bar), second = line.substr(bar);
        std::map<std::string, double> values;
        for (auto it = std::sregex_iterator(second.begin(), second.end(), pair);
             it != std::sregex_iterator(); ++it) {
            std::string v = (*it)[2];
            const bool minus = v.rfind("−", 0) == 0;
            values[(*it)[1]] = (minus ? -1 : 1) * std::stod(minus ? v.substr(3) : v);
        }
        const bool tangents = first.find("and their `_tangents`") != std::string::npos;
        for (auto it = std::sregex_iterator(first.begin(), first.end(), name);
             it != std::sregex_iterator(); ++it) {
            if ((*it)[1] == "_tangents") continue;
            documented[(*it)[1]] = values;
            if (tangents) documented[std::string((*it)[1]) + "_tangents"] = values;
        }
    }
    int checked = 0;
    for (const MethodPreset& p : methodPresets()) {
        if (p.shaderFile.empty()) continue;  // a built-in preset: no uniforms
        ASSERT_TRUE(documented.count(p.name)) << p.name << " has no row in docs/methods.md";
        for (const GlslSpec::Uniform& u : p.glsl.uniforms) {
            const auto& row = documented.at(p.name);
            ASSERT_TRUE(row.count(u.name)) << p.name << ": " << u.name << " is not in its row";
            EXPECT_DOUBLE_EQ(row.at(u.name), u.values.at(0)) << p.name << ": " << u.name;
            ++checked;
        }
    }
    EXPECT_GT(checked, 40);
}

TEST(Presets, BuiltInPresetsAreTheDocumentsSettings) {
    auto same = [](const char* preset, const char* entry) {
        nlohmann::json shipped = nlohmann::json::parse(preset);
        shipped["amplitude"] = "shipped";  // the documents' own (s, b)
        MethodConfig p = parseMethod(shipped, "s", "m");
        MethodConfig e = parseMethod(nlohmann::json::parse(entry), "s", "m");
        nlohmann::json pj = toJson(p), ej = toJson(e);
        EXPECT_EQ(pj["preset"], nlohmann::json::parse(preset)["preset"]);
        pj.erase("preset"), pj.erase("label"), ej.erase("label");
        EXPECT_EQ(pj, ej) << preset;
    };
    same(R"({"preset": "welsh"})", R"({"name": "parallax", "scale": 0.04, "bias": -0.02})");
    same(R"({"preset": "learnopengl_parallax"})",
         R"({"name": "parallax", "scale": 0.1, "bias": -0.1})");
    same(R"({"preset": "learnopengl_steep"})",
         R"({"name": "steep", "min_layers": 8, "max_layers": 32, "scale": 0.1, "bias": -0.1})");
    same(R"({"preset": "learnopengl_pom"})",
         R"({"name": "pom", "min_layers": 8, "max_layers": 32, "scale": 0.1, "bias": -0.1})");
    same(R"({"preset": "deferred_blog"})",
         R"({"name": "steep", "layers": 100, "max_steps": 100, "scale": 0.15, "bias": -0.15})");
}

}  // namespace
}  // namespace pgt
