// Method registry: names, scene parsing, labels, dispatch.
#include "methods/registry.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "core/format.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "gl/glsl_method.h"
#include "methods/layered.h"
#include "methods/lengyel.h"
#include "methods/simple.h"

namespace pgt {

namespace {
struct NamedKind {
    const char* name;
    MethodKind kind;
};
constexpr NamedKind kMethods[] = {
    {"none", MethodKind::None},
    {"parallax", MethodKind::Parallax},
    {"offset_limited", MethodKind::OffsetLimited},
    {"steep", MethodKind::Steep},
    {"pom", MethodKind::Pom},
    {"relief", MethodKind::Relief},
    {"iterative", MethodKind::Iterative},
    {"tangent_plane", MethodKind::TangentPlane},
};
}  // namespace

std::string toString(MethodKind kind) {
    for (const auto& m : kMethods)
        if (m.kind == kind) return m.name;
    return "?";
}

const std::vector<std::string>& methodNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const auto& m : kMethods) n.push_back(m.name);
        return n;
    }();
    return names;
}

bool needsDerivedMaps(MethodKind kind) {
    return kind == MethodKind::Iterative || kind == MethodKind::TangentPlane;
}

namespace {

// {"name": "mine", "glsl": FILE, "function": F, "sampler": S, "texture": "height"|"depth",
//  "uniforms": {...}}: the file is read now, relative to the scene file's folder.
MethodConfig parseGlslMethod(JsonFields& f, const std::string& file) {
    MethodConfig cfg;
    cfg.kind = MethodKind::Glsl;
    cfg.name = f.string("name", "");
    checkLabel(cfg.name, file, f.fieldPath("name"));  // a GLSL method's name is its label
    auto spec = std::make_shared<GlslSpec>();
    std::string rel = f.string("glsl", "");
    std::filesystem::path p(rel);
    if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
    spec->path = p.lexically_normal().string();
    if (rel.empty()) f.fail("glsl", "cannot read the shader file " + spec->path);
    // A shader is a few KB; 16 MiB bounds a stray file.
    spec->source = readTextFile(spec->path, file, f.fieldPath("glsl"), "shader file", 16u << 20);
    spec->function = f.string("function", "ParallaxMapping");
    spec->sampler = f.string("sampler", "depthMap");
    // 003's derived maps for shaders that read them (iterative, tangent_plane): the unit
    // normal (RGB) and m_z * (s*h + b), built for the truth's (s, b).
    spec->normalSampler = f.string("normal_sampler", "");
    spec->parallaxSampler = f.string("parallax_sampler", "");
    spec->depthTexture = f.choice("texture", {"height", "depth"}, "height") == "depth";
    if (f.has("uniforms")) {
        const Json& u = f.raw("uniforms");
        if (!u.is_object()) f.fail("uniforms", "expected an object of name: number or [numbers]");
        for (const auto& [name, value] : u.items()) {
            GlslSpec::Uniform un;
            un.name = name;
            if (value.is_string() && (value == "scale" || value == "bias")) {
                un.bind = value.get<std::string>();
            } else if (value.is_number()) {
                un.values.push_back(value.get<double>());
                un.isInt = value.is_number_integer();
            } else if (value.is_array() && value.size() >= 2 && value.size() <= 4) {
                for (const auto& x : value) {
                    if (!x.is_number()) f.fail("uniforms." + name, "expected numbers");
                    un.values.push_back(x.get<double>());
                }
            } else {
                f.fail("uniforms." + name,
                       "expected a number, an array of 2 to 4 numbers, \"scale\" or \"bias\"");
            }
            for (double x : un.values)
                if (!std::isfinite(x)) f.fail("uniforms." + name, "is not finite");
            spec->uniforms.push_back(un);
        }
    }
    cfg.discardOutside = f.boolean("discard_outside", false);
    cfg.scale = f.number("scale", NAN, -1e3, 1e3);
    cfg.bias = f.number("bias", NAN, -1e3, 1e3);
    cfg.label = f.string("label", "");
    f.finish();
    cfg.glsl = std::move(spec);
    return cfg;
}

}  // namespace

bool needsDerivedMaps(const MethodConfig& cfg) {
    if (cfg.glsl) return !cfg.glsl->normalSampler.empty() || !cfg.glsl->parallaxSampler.empty();
    return needsDerivedMaps(cfg.kind);
}

std::string shaderDir() {
    const char* env = std::getenv("PGT_SHADER_DIR");
    return env ? env : PGT_SHADER_DIR;
}

const std::vector<MethodPreset>& methodPresets() {
    // Engine defaults and the source documents' own settings (README "Engine presets" gives
    // each one's source). GLSL presets are our re-implementations of the engines' shader
    // code paths, in src/shaders/presets/.
    static const std::vector<MethodPreset> presets = {
        {"welsh", "000 (Welsh 2004): parallax mapping at its own s 0.04, b -0.02",
         R"({"name": "parallax", "scale": 0.04, "bias": -0.02})"},
        {"learnopengl_parallax",
         "002 (LearnOpenGL): ParallaxMapping, height_scale 0.1 on a depth map",
         R"({"name": "parallax", "scale": 0.1, "bias": -0.1})"},
        {"learnopengl_steep", "002 (LearnOpenGL): steep parallax, 8-32 layers, height_scale 0.1",
         R"({"name": "steep", "min_layers": 8, "max_layers": 32, "scale": 0.1, "bias": -0.1})"},
        {"learnopengl_pom", "002 (LearnOpenGL): parallax occlusion, 8-32 layers, height_scale 0.1",
         R"({"name": "pom", "min_layers": 8, "max_layers": 32, "scale": 0.1, "bias": -0.1})"},
        {"deferred_blog", "004 (the deferred-renderer blog): numSteps 100 at height scale 0.15",
         R"({"name": "steep", "layers": 100, "max_steps": 100, "scale": 0.15, "bias": -0.15})"},
        {"godot", "Godot 4 BaseMaterial3D, height mapping on, deep parallax off: heightmap_scale 5",
         R"({"glsl": "presets/godot.glsl", "function": "GodotParallax", "sampler": "heightMap",
             "uniforms": {"heightmap_scale": 5.0}})"},
        {"godot_deep", "Godot 4 BaseMaterial3D deep parallax: heightmap_scale 5, 8-32 layers",
         R"({"glsl": "presets/godot.glsl", "function": "GodotDeepParallax", "sampler": "heightMap",
             "uniforms": {"heightmap_scale": 5.0, "heightmap_min_layers": 8.0,
                          "heightmap_max_layers": 32.0}})"},
        {"bevy_occlusion", "Bevy StandardMaterial: depth scale 0.1, 16 layers, Occlusion (default)",
         R"({"glsl": "presets/bevy.glsl", "function": "BevyOcclusion", "sampler": "depthMap",
             "texture": "depth", "uniforms": {"depth_scale": 0.1, "max_layer_count": 16.0}})"},
        {"bevy_relief", "Bevy StandardMaterial: depth scale 0.1, 16 layers, Relief with 5 steps",
         R"({"glsl": "presets/bevy.glsl", "function": "BevyRelief", "sampler": "depthMap",
             "texture": "depth", "uniforms": {"depth_scale": 0.1, "max_layer_count": 16.0,
                                              "max_steps": 5}})"},
    };
    return presets;
}

MethodConfig parseMethod(const Json& entry, const std::string& file, const std::string& path) {
    Json object = entry.is_string() ? Json{{"name", entry}} : entry;
    if (!object.is_object())
        throw InputError(file, path, shortDump(entry), "expected a method name or object");
    if (object.contains("preset")) {
        // {"preset": NAME, "label": optional}: the preset's own entry, labelled NAME.
        JsonFields pf(object, file, path);
        std::vector<std::string> names;
        for (const auto& p : methodPresets()) names.push_back(p.name);
        std::string name = pf.choice("preset", names, "");
        std::string label = pf.string("label", name);
        pf.finish();
        for (const auto& p : methodPresets()) {
            if (p.name != name) continue;
            Json expanded = Json::parse(p.entry);
            if (expanded.contains("glsl")) {
                expanded["name"] = name;
                expanded["glsl"] = shaderDir() + "/" + expanded["glsl"].get<std::string>();
            }
            expanded["label"] = label;
            MethodConfig cfg = parseMethod(expanded, file, path);
            cfg.preset = name;
            return cfg;
        }
    }
    JsonFields f(object, file, path);
    if (object.contains("glsl")) {
        MethodConfig cfg = parseGlslMethod(f, file);
        if (f.has("label")) checkLabel(cfg.label, file, f.fieldPath("label"));
        return cfg;
    }
    MethodConfig cfg;
    cfg.name = f.choice("name", methodNames(), "");
    for (const auto& m : kMethods)
        if (cfg.name == m.name) cfg.kind = m.kind;
    constexpr int kMaxLayers = 4096;
    switch (cfg.kind) {
        case MethodKind::Steep:
        case MethodKind::Pom:
            cfg.minLayers = f.integer("min_layers", cfg.minLayers, 1, kMaxLayers);
            cfg.maxLayers = f.integer("max_layers", cfg.maxLayers, 1, kMaxLayers);
            if (f.has("layers"))  // fixed layer count: min = max
                cfg.minLayers = cfg.maxLayers = f.integer("layers", 1, kMaxLayers);
            cfg.maxSteps = f.integer("max_steps", 0, 0, kSafetyStepCap);
            break;
        case MethodKind::Relief:
            cfg.linearSteps = f.integer("linear_steps", cfg.linearSteps, 1, kMaxLayers);
            cfg.binarySteps = f.integer("binary_steps", cfg.binarySteps, 0, 64);
            break;
        case MethodKind::Iterative:
            cfg.iterations = f.integer("iterations", cfg.iterations, 1, 1024);
            break;
        default:
            break;
    }
    cfg.discardOutside = f.boolean("discard_outside", false);
    cfg.scale = f.number("scale", NAN, -1e3, 1e3);
    cfg.bias = f.number("bias", NAN, -1e3, 1e3);
    cfg.doublePrecision = f.choice("precision", {"float", "double"}, "float") == "double";
    cfg.label = f.string("label", "");
    if (f.has("label")) checkLabel(cfg.label, file, f.fieldPath("label"));
    f.finish();
    return cfg;
}

namespace {
std::string parameterSuffix(const MethodConfig& c) {
    std::string s;
    switch (c.kind) {
        case MethodKind::Steep:
        case MethodKind::Pom:
            s = c.minLayers == c.maxLayers
                    ? std::to_string(c.maxLayers)
                    : std::to_string(c.minLayers) + "_" + std::to_string(c.maxLayers);
            if (c.maxSteps) s += "_s" + std::to_string(c.maxSteps);
            break;
        case MethodKind::Relief:
            s = std::to_string(c.linearSteps) + "_" + std::to_string(c.binarySteps);
            break;
        case MethodKind::Iterative:
            s = std::to_string(c.iterations);
            break;
        default:
            break;
    }
    if (c.doublePrecision) s += s.empty() ? "f64" : "_f64";
    if (c.discardOutside) s += s.empty() ? "discard" : "_discard";
    auto num = [](double x) { return formatNumber(x, 6); };  // as an ostream's default %g
    if (std::isfinite(c.scale)) s += (s.empty() ? "s" : "_s") + num(c.scale);
    if (std::isfinite(c.bias)) s += (s.empty() ? "b" : "_b") + num(c.bias);
    return s;
}
}  // namespace

std::vector<MethodConfig> parseMethods(const Json& list, const std::string& file,
                                       const std::string& path) {
    if (!list.is_array()) throw InputError(file, path, shortDump(list), "expected an array");
    if (list.empty())
        throw InputError(file, path, "[]",
                         "the method list is empty; known methods: " + joinNames(methodNames()));
    std::vector<MethodConfig> out;
    std::map<std::string, int> nameCount;
    for (size_t i = 0; i < list.size(); ++i) {
        out.push_back(parseMethod(list[i], file, path + "[" + std::to_string(i) + "]"));
        nameCount[out.back().name]++;
    }
    // Labels name CSV rows, EXR channels and PNG files: user labels are checked where they
    // are written (checkLabel) and must be unique; generated ones are made unique with a
    // counter that skips every label already taken.
    std::set<std::string> taken;
    for (size_t i = 0; i < out.size(); ++i) {
        if (out[i].label.empty()) continue;
        if (!taken.insert(out[i].label).second)
            throw InputError(file, path + "[" + std::to_string(i) + "].label", out[i].label,
                             "two methods have this label; labels name the rows and files of "
                             "each method and must differ");
    }
    for (auto& m : out) {
        if (!m.label.empty()) continue;
        std::string label = m.name;
        std::string suffix = parameterSuffix(m);
        if (nameCount[m.name] > 1 && !suffix.empty()) label += "_" + suffix;
        std::string unique = label;
        for (int k = 2; taken.count(unique); ++k) unique = label + "_" + std::to_string(k);
        m.label = unique;
        taken.insert(unique);
    }
    return out;
}

void checkLabel(const std::string& label, const std::string& file, const std::string& field) {
    bool ok = !label.empty() && label.size() <= kMaxLabelLength;
    for (char c : label)
        ok =
            ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '+');
    if (!ok)
        throw InputError(file, field, label,
                         "a label is 1 to " + std::to_string(kMaxLabelLength) +
                             " characters of A-Z a-z 0-9 _ - + (it names CSV rows, EXR channels "
                             "and files)");
}

Json toJson(const MethodConfig& c) {
    Json j = {{"name", c.name}, {"label", c.label}};
    if (!c.preset.empty()) j["preset"] = c.preset;
    if (c.glsl) {
        j["glsl"] = c.glsl->path;
        j["function"] = c.glsl->function;
        j["sampler"] = c.glsl->sampler;
        j["texture"] = c.glsl->depthTexture ? "depth" : "height";
        Json u = Json::object();
        for (const auto& un : c.glsl->uniforms)
            u[un.name] = !un.bind.empty()        ? Json(un.bind)
                         : un.values.size() == 1 ? Json(un.values[0])
                                                 : Json(un.values);
        j["uniforms"] = u;
        // The shader's text is part of the identity: an edited file is another method.
        j["source_sha1"] = textSha1(c.glsl->source);
    }
    switch (c.kind) {
        case MethodKind::Steep:
        case MethodKind::Pom:
            j["min_layers"] = c.minLayers;
            j["max_layers"] = c.maxLayers;
            j["max_steps"] = c.maxSteps;
            break;
        case MethodKind::Relief:
            j["linear_steps"] = c.linearSteps;
            j["binary_steps"] = c.binarySteps;
            break;
        case MethodKind::Iterative:
            j["iterations"] = c.iterations;
            break;
        default:
            break;
    }
    j["discard_outside"] = c.discardOutside;
    if (std::isfinite(c.scale)) j["scale"] = c.scale;
    if (std::isfinite(c.bias)) j["bias"] = c.bias;
    j["precision"] = c.doublePrecision ? "double" : "float";
    return j;
}

template <class Real>
Vec2<Real> runMethod(const MethodConfig& cfg, MethodContext<Real>& ctx, Vec2<Real> uv0,
                     Vec3<Real> v) {
    switch (cfg.kind) {
        case MethodKind::None:
            return methodNone(ctx, uv0, v, cfg);
        case MethodKind::Parallax:
            return methodParallax(ctx, uv0, v, cfg);
        case MethodKind::OffsetLimited:
            return methodOffsetLimited(ctx, uv0, v, cfg);
        case MethodKind::Steep:
            return methodSteep(ctx, uv0, v, cfg);
        case MethodKind::Pom:
            return methodPom(ctx, uv0, v, cfg);
        case MethodKind::Relief:
            return methodRelief(ctx, uv0, v, cfg);
        case MethodKind::Iterative:
            return methodIterative(ctx, uv0, v, cfg);
        case MethodKind::TangentPlane:
            return methodTangentPlane(ctx, uv0, v, cfg);
        case MethodKind::Glsl:
            break;  // runs in OpenGL (study/evaluate.cpp), never here
    }
    return uv0;
}

template Vec2<float> runMethod<float>(const MethodConfig&, MethodContext<float>&, Vec2<float>,
                                      Vec3<float>);
template Vec2<double> runMethod<double>(const MethodConfig&, MethodContext<double>&, Vec2<double>,
                                        Vec3<double>);

}  // namespace pgt
