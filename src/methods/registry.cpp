// Method registry: names, scene parsing, labels, dispatch.
#include "methods/registry.h"

#include <cmath>
#include <map>
#include <sstream>

#include "core/json_fields.h"
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
    {"none", MethodKind::None},         {"parallax", MethodKind::Parallax},
    {"offset_limited", MethodKind::OffsetLimited}, {"steep", MethodKind::Steep},
    {"pom", MethodKind::Pom},           {"relief", MethodKind::Relief},
    {"iterative", MethodKind::Iterative}, {"tangent_plane", MethodKind::TangentPlane},
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

MethodConfig parseMethod(const Json& entry, const std::string& file, const std::string& path) {
    Json object = entry.is_string() ? Json{{"name", entry}} : entry;
    if (!object.is_object())
        throw InputError(file, path, shortDump(entry), "expected a method name or object");
    JsonFields f(object, file, path);
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
    if (f.has("label") && (cfg.label.empty() || cfg.label.find_first_of(" ./\\") !=
                                                    std::string::npos))
        f.fail("label", "must be non-empty without spaces, dots or slashes");
    f.finish();
    return cfg;
}

namespace {
std::string parameterSuffix(const MethodConfig& c) {
    std::string s;
    switch (c.kind) {
        case MethodKind::Steep:
        case MethodKind::Pom:
            s = c.minLayers == c.maxLayers ? std::to_string(c.maxLayers)
                                           : std::to_string(c.minLayers) + "_" +
                                                 std::to_string(c.maxLayers);
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
    auto num = [](double x) {
        std::ostringstream os;
        os << x;
        return os.str();
    };
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
    std::map<std::string, int> labelCount;
    for (auto& m : out) {
        if (m.label.empty()) {
            m.label = m.name;
            std::string suffix = parameterSuffix(m);
            if (nameCount[m.name] > 1 && !suffix.empty()) m.label += "_" + suffix;
        }
    }
    for (size_t i = 0; i < out.size(); ++i) {
        int seen = labelCount[out[i].label]++;
        if (seen > 0) out[i].label += "_" + std::to_string(seen + 1);
    }
    return out;
}

Json toJson(const MethodConfig& c) {
    Json j = {{"name", c.name}, {"label", c.label}};
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
        case MethodKind::None: return methodNone(ctx, uv0, v, cfg);
        case MethodKind::Parallax: return methodParallax(ctx, uv0, v, cfg);
        case MethodKind::OffsetLimited: return methodOffsetLimited(ctx, uv0, v, cfg);
        case MethodKind::Steep: return methodSteep(ctx, uv0, v, cfg);
        case MethodKind::Pom: return methodPom(ctx, uv0, v, cfg);
        case MethodKind::Relief: return methodRelief(ctx, uv0, v, cfg);
        case MethodKind::Iterative: return methodIterative(ctx, uv0, v, cfg);
        case MethodKind::TangentPlane: return methodTangentPlane(ctx, uv0, v, cfg);
    }
    return uv0;
}

template Vec2<float> runMethod<float>(const MethodConfig&, MethodContext<float>&, Vec2<float>,
                                      Vec3<float>);
template Vec2<double> runMethod<double>(const MethodConfig&, MethodContext<double>&,
                                        Vec2<double>, Vec3<double>);

}  // namespace pgt
