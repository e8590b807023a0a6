// Method names, parsing of the scene's "methods" list, and dispatch to the method functions.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "methods/method.h"

namespace pgt {

// Parses a "methods" array: each entry a name or an object {"name": ..., parameters}.
// Labels are unique: a method listed twice gets its parameters in the label ("pom_32").
std::vector<MethodConfig> parseMethods(const nlohmann::json& list, const std::string& file,
                                       const std::string& path);
MethodConfig parseMethod(const nlohmann::json& entry, const std::string& file,
                         const std::string& path);
nlohmann::json toJson(const MethodConfig& cfg);

// A label a user writes (or a GLSL method's name): 1..kMaxLabelLength characters of
// A-Z a-z 0-9 _ - +, since it names CSV rows, EXR channels and files. Throws InputError.
constexpr size_t kMaxLabelLength = 64;
void checkLabel(const std::string& label, const std::string& file, const std::string& field);

// Named configurations: engine defaults and the source documents' settings, used
// as {"preset": NAME} in a method list. `entry` is the method entry it stands for.
struct MethodPreset {
    std::string name, source, entry;
};
const std::vector<MethodPreset>& methodPresets();
// Where the shipped GLSL files are (src/shaders; PGT_SHADER_DIR in the environment wins).
std::string shaderDir();

// Runs one method on one fragment. Never throws; stiff cases land in ctx.flags.
template <class Real>
Vec2<Real> runMethod(const MethodConfig& cfg, MethodContext<Real>& ctx, Vec2<Real> uv0,
                     Vec3<Real> viewTangent);

extern template Vec2<float> runMethod<float>(const MethodConfig&, MethodContext<float>&,
                                             Vec2<float>, Vec3<float>);
extern template Vec2<double> runMethod<double>(const MethodConfig&, MethodContext<double>&,
                                               Vec2<double>, Vec3<double>);

}  // namespace pgt
