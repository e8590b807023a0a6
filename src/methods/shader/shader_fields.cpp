// A shader entry's fields, one row each (methods/shader/shader_fields.h).
#include "methods/shader/shader_fields.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>

#include "core/format.h"
#include "core/json_read.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/shader/conditional_lines.h"
#include "methods/shader/shader_words.h"
#include "methods/shader/source_text.h"
#include "methods/shader/vertex_config.h"

namespace pgt {

namespace {

// Whether a number written as an integer fits the GLSL int glUniform1i sets (32 bits: 3e9 and
// 2^53 would wrap); a number written otherwise is not set as an int.
bool fitsGlslInt(const Json& v) {
    if (v.is_number_unsigned()) return v.get<uint64_t>() <= uint64_t(INT32_MAX);
    if (v.is_number_integer())
        return v.get<int64_t>() >= INT32_MIN && v.get<int64_t>() <= INT32_MAX;
    return true;
}

// One uniform's value as an entry writes it: a number (int when written as an integer), 2 to
// 4 numbers, or, where `binds`, "scale" / "bias" (the case's s / b). `fail(message)` throws.
}  // namespace

GlslSpec::Uniform uniformValue(const std::string& name, const Json& value, bool binds,
                               const std::function<void(const std::string&)>& fail) {
    GlslSpec::Uniform un{name, {}, false, "", 1};
    if (binds && value.is_string() && (value == "scale" || value == "bias")) {
        un.bind = value.get<std::string>();
    } else if (value.is_number()) {
        un.values.push_back(value.get<double>());
        un.isInt = value.is_number_integer();
        if (!fitsGlslInt(value))
            fail(
                "a number written as an integer sets an int uniform, a 32-bit int: it must "
                "lie in [-2147483648, 2147483647] (for a float uniform, write it with a "
                "decimal point or an exponent)");
    } else if (value.is_array() && value.size() >= 2 && value.size() <= 4) {
        for (const auto& x : value) {
            if (!x.is_number()) fail("expected numbers");
            un.values.push_back(x.get<double>());
        }
    } else {
        fail(binds ? "expected a number, an array of 2 to 4 numbers, \"scale\" or \"bias\""
                   : "expected a number or 2 to 4 numbers");
    }
    for (double x : un.values)
        if (!std::isfinite(x)) fail("is not finite");
    return un;
}

namespace {

// "uniforms": {name: number | [2..4 numbers] | "scale" | "bias"}.
std::vector<GlslSpec::Uniform> parseUniforms(JsonFields& f) {
    std::vector<GlslSpec::Uniform> out;
    const Json& u = f.raw("uniforms");
    if (!u.is_object()) f.fail("uniforms", "expected an object of name: number or [numbers]");
    for (const auto& [key, value] : u.items()) {
        const std::string field = "uniforms." + key;  // clang 14 captures no structured binding
        const Json& given = value;
        out.push_back(uniformValue(key, value, true, [&](const std::string& message) {
            f.failValue(field, given, message);
        }));
    }
    return out;
}

// "texture": the names of GlslSpec::Layout, in its order.
const std::vector<std::string>& layoutNames() {
    static const std::vector<std::string> names = {"height", "depth", "normal+height",
                                                   "normal+depth"};
    return names;
}
GlslSpec::Layout layoutNamed(const std::string& name) {
    const auto& n = layoutNames();
    return GlslSpec::Layout(std::find(n.begin(), n.end(), name) - n.begin());
}

// "texture": a layout, or "height.C" / "depth.C" with C one to four of r, g, b, a in that
// order (the channels that hold the value; "height.r" is "height").
void readTexture(JsonFields& f, GlslSpec& spec) {
    const std::string text = f.string("texture", "height");
    const size_t dot = text.find('.');
    const std::string layout = text.substr(0, dot);
    const auto& names = layoutNames();
    if (std::find(names.begin(), names.end(), layout) == names.end() ||
        (dot != std::string::npos && layout != "height" && layout != "depth"))
        f.failValue("texture", Json(text),
                    "expected one of " + joinNames(names) +
                        ", or height.C / depth.C with C the channels that hold it (r, g, b, a "
                        "in that order: \"height.g\", \"depth.a\", \"height.rgb\")");
    spec.layout = layoutNamed(layout);
    if (dot == std::string::npos) return;
    const std::string channels = text.substr(dot + 1);
    const std::string order = "rgba";
    size_t last = 0;
    bool ok = !channels.empty();
    for (char c : channels) {
        const size_t at = order.find(c);
        ok = ok && at != std::string::npos && (spec.channels == 0 || at > last);
        if (!ok) break;
        spec.channels |= 1u << at;
        last = at;
    }
    if (!ok)
        f.failValue("texture", Json(text),
                    "the channels after the dot are one to four of r, g, b, a, in that order");
    if (spec.channels == 1) spec.channels = 0;  // R only: the R32F texture of "height"
}

std::string textureName(const GlslSpec& g) {
    std::string name = layoutNames()[size_t(g.layout)];
    if (g.channels == 0) return name;
    name += '.';
    for (int c = 0; c < 4; ++c)
        if (g.channels & (1u << c)) name += "rgba"[c];
    return name;
}

void checkShaderLine(JsonFields& f, const std::string& field, const std::string& text);

// "body": statements ending in a return, as a string (lines split at line breaks) or an
// array of lines; each line is checked as a call is, but for its breaks.
// A body's shape, checked before a compiler sees it inside pgt's wrapper (where its errors
// would name the wrapper's lines): comments closed, brackets balanced, a return outside
// comments, statements and not a shader. Errors name "body:N", the body's own line.
void checkBodyShape(JsonFields& f, const std::string& body) {
    auto lineOf = [&](size_t at) {
        return "body:" +
               std::to_string(1 + std::count(body.begin(), body.begin() + long(at), '\n'));
    };
    auto fail = [&](size_t at, const std::string& why) { f.fail("body", lineOf(at) + ": " + why); };
    for (size_t i = body.find("/*"); i != std::string::npos; i = body.find("/*", i + 2)) {
        const size_t line = body.rfind('\n', i);
        if (body.substr(line == std::string::npos ? 0 : line,
                        i - (line == std::string::npos ? 0 : line))
                .find("//") != std::string::npos)
            continue;  // inside a // comment
        const size_t close = body.find("*/", i + 2);
        if (close == std::string::npos) fail(i, "a /* comment is not closed");
        i = close;
    }
    const std::vector<ShaderWord> words = shaderWords(body);
    std::vector<size_t> open;  // the opening brackets' words, innermost last
    bool returns = false;
    for (size_t k = 0; k < words.size(); ++k) {
        const std::string w = wordText(body, words[k]);
        returns = returns || w == "return";
        if (w == "main" && k + 1 < words.size() && wordText(body, words[k + 1]) == "(")
            fail(words[k].begin,
                 "defines or calls main(): a body is the statements of a function "
                 "(a whole shader goes in the file)");
        if (w == "{" || w == "(" || w == "[") open.push_back(k);
        if (w == "}" || w == ")" || w == "]") {
            const char want = w == "}" ? '{' : w == ")" ? '(' : '[';
            if (open.empty() || body[words[open.back()].begin] != want)
                fail(words[k].begin,
                     "'" + w + "' closes nothing" +
                         (open.empty() ? std::string()
                                       : " (" + lineOf(words[open.back()].begin) + " opened '" +
                                             body[words[open.back()].begin] + "')"));
            open.pop_back();
        }
    }
    if (!open.empty())
        fail(words[open.back()].begin, "the '" + std::string(1, body[words[open.back()].begin]) +
                                           "' opened here is not closed");
    if (!returns)
        f.fail("body", "has no return outside comments: it ends in return <uv'>; (a 2-vector)");
}

std::string readBody(JsonFields& f) {
    const Json& raw = f.raw("body");
    std::vector<std::string> lines;
    if (raw.is_string()) {
        std::istringstream in(normaliseLineEnds(raw.get<std::string>()));
        for (std::string line; std::getline(in, line);) lines.push_back(line);
    } else if (raw.is_array() && !raw.empty()) {
        for (const Json& l : raw) {
            if (!l.is_string()) f.fail("body", "expected a string or an array of lines (strings)");
            lines.push_back(l.get<std::string>());
        }
    } else {
        f.fail("body", "expected a string or an array of lines (strings)");
    }
    std::string body;
    for (const std::string& line : lines) {
        checkShaderLine(f, "body", line);
        body += line + "\n";
    }
    checkBodyShape(f, body);
    return body;
}

// A call `F(...)` of a function that the file declares only as void (it answers through
// out/inout parameters) would fail in the compiler with a message about pgt's wrapper.
void checkCallNotVoid(JsonFields& f, const GlslSpec& spec) {
    const std::vector<ShaderWord> words = shaderWords(spec.call);
    if (words.size() < 2 || !words[0].ident || spec.call[words[1].begin] != '(') return;
    const std::string name = wordText(spec.call, words[0]);
    const std::vector<std::string> types = functionTypes(spec.source, name);
    if (!types.empty() &&
        std::all_of(types.begin(), types.end(), [](const std::string& t) { return t == "void"; }))
        f.failValue("call", Json(spec.call),
                    name + " returns void in " + spec.path +
                        " (it answers through out/inout parameters): write \"body\" instead, "
                        "statements that call it and end in return <uv'>;");
}

// A define's value and a call are each one line of shader text placed into pgt's wrapper: a
// line break, a carriage return, a NUL or another control character, or a backslash (a line
// continuation) would break the wrapper's lines and blame them, so they are refused by name.
// A call is one expression: at most 64 KiB.
void checkShaderLine(JsonFields& f, const std::string& field, const std::string& text) {
    for (char ch : text) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if ((c < 0x20 && c != '\t') || c == 0x7f || c == '\\')
            f.failValue(field, Json(text),
                        "holds a line break, a control character or a backslash: it is one "
                        "line of shader text");
    }
    constexpr size_t kMaxLine = 64 * 1024;
    if (text.size() > kMaxLine)
        f.fail(field, "is " + std::to_string(text.size()) + " bytes long; at most " +
                          std::to_string(kMaxLine) + " (one expression)");
}

// "defines": {NAME: "VALUE" | number}, each an identifier.
std::vector<std::pair<std::string, std::string>> parseDefines(JsonFields& f) {
    std::vector<std::pair<std::string, std::string>> out;
    const Json& d = f.raw("defines");
    if (!d.is_object()) f.fail("defines", "expected an object of NAME: \"value\"");
    for (const auto& [name, value] : d.items()) {
        if (!isShaderIdentifier(name)) f.fail("defines", "\"" + name + "\" is not a macro name");
        std::string text;
        if (value.is_string())
            text = value.get<std::string>();
        else if (value.is_number())
            text = value.dump();
        else
            f.fail("defines." + name, "expected a string or a number");
        checkShaderLine(f, "defines." + name, text);
        out.emplace_back(name, text);
    }
    return out;
}

// The GLSL dialects pgt compiles (GlslSpec::version), and how messages list them.
const std::vector<std::string> kGlslVersions = {"100", "300 es", "310 es", "320 es", "110", "120",
                                                "130", "140",    "150",    "330",    "400", "410",
                                                "420", "430",    "440",    "450",    "460"};
constexpr const char* kGlslVersionsNamed = "100, 300 es, 310 es, 320 es, 110 ... 460";
bool knownGlslVersion(const std::string& v) {
    return std::find(kGlslVersions.begin(), kGlslVersions.end(), v) != kGlslVersions.end();
}

std::string glslVersion(JsonFields& f, const GlslSpec& spec) {
    if (f.has("version")) {
        const Json& v = f.raw("version");
        std::string named = v.is_number_integer() ? std::to_string(v.get<int64_t>())
                            : v.is_string()       ? v.get<std::string>()
                                                  : v.dump();
        if (!knownGlslVersion(named))
            f.fail("version", "\"" + named + "\" is not a GLSL version pgt compiles (" +
                                  kGlslVersionsNamed + ")");
        return named;
    }
    return versionOfSource(spec);
}

// The shader file an entry's `key` names: relative to the scene file's folder, or
// "pgt:NAME" among the shipped shaders.
std::string shaderPath(JsonFields& f, const std::string& key, const std::string& file) {
    std::string rel = f.string(key, "");
    std::filesystem::path p(rel);
    if (rel.rfind(kShippedShaderPrefix, 0) == 0) {  // "pgt:NAME.glsl": a shipped shader
        // Inside the shipped shaders only: a relative path with no ".." (the folder's own
        // entries may be links, so the check is on the name, not the resolved path).
        const std::filesystem::path name(rel.substr(std::string(kShippedShaderPrefix).size()));
        bool inside = !name.empty() && name.is_relative();
        for (const auto& part : name) inside = inside && part != ".." && part != ".";
        if (!inside)
            f.fail(key, "\"" + rel +
                            "\": pgt: names a shader shipped with pgt, e.g. "
                            "pgt:presets/godot.glsl (no \"..\", not absolute)");
        p = std::filesystem::path(shaderDir()) / name;
    } else if (p.is_relative()) {
        p = std::filesystem::path(file).parent_path() / p;
    }
    const std::string path = p.lexically_normal().string();
    if (rel.empty()) f.fail(key, "cannot read the shader file " + path);
    return path;
}

// "include_paths": folders, each relative to the scene file's folder (or absolute), that must
// exist.
std::vector<std::string> includePaths(JsonFields& f, const std::string& file) {
    const Json& raw = f.raw("include_paths");
    if (!raw.is_array()) f.fail("include_paths", "expected an array of folders");
    std::vector<std::string> out;
    for (size_t i = 0; i < raw.size(); ++i) {
        const std::string field = "include_paths[" + std::to_string(i) + "]";
        if (!raw[i].is_string() || raw[i].get<std::string>().empty())
            f.failValue(field, raw[i], "expected a folder's path");
        std::filesystem::path p(raw[i].get<std::string>());
        if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
        std::error_code ec;
        if (!std::filesystem::is_directory(p, ec))
            f.failValue(field, raw[i], "is not a folder (" + p.lexically_normal().string() + ")");
        out.push_back(p.lexically_normal().string());
    }
    return out;
}

// "call" or "body": the entry's own code, checked as one line or as a body's shape.
void readEntryCode(JsonFields& f, GlslSpec& spec) {
    spec.call = f.string("call", "");
    checkShaderLine(f, "call", spec.call);
    if (f.has("body")) {
        if (f.has("call")) f.fail("body", "a method has \"call\" or \"body\", not both");
        spec.body = readBody(f);
    }
    checkCallNotVoid(f, spec);
}

// HLSL's "sampler_state": pgt declares `SamplerState NAME;` beside the texture, so a keyword
// or the texture's own name would fail in the compiler, naming pgt's declaration instead of
// this field.
void readSamplerState(JsonFields& f, GlslSpec& spec) {
    spec.samplerState = f.string("sampler_state", "");
    const std::string& name = spec.samplerState;
    if (name.empty()) return;
    if (!spec.hlsl || !isShaderIdentifier(name))
        f.failValue("sampler_state", Json(name),
                    spec.hlsl ? "is not an HLSL identifier"
                              : "names an HLSL SamplerState; a GLSL sampler2D is \"sampler\"");
    static const std::string kHlslWords =
        " SamplerState SamplerComparisonState Texture2D Texture3D TextureCube sampler sampler2D"
        " texture float float2 float3 float4 half double int uint bool void matrix vector string"
        " return if else for while do switch case default break continue discard struct class"
        " interface namespace cbuffer tbuffer static const uniform extern in out inout true false"
        " register packoffset typedef technique pass linear centroid nointerpolation precise"
        " shared groupshared volatile row_major column_major inline export ";
    if (kHlslWords.find(" " + name + " ") != std::string::npos)
        f.failValue("sampler_state", Json(name),
                    "is an HLSL keyword or type; name the file's SamplerState variable");
    if (name == spec.samplers[size_t(MapKind::Height)])
        f.failValue("sampler_state", Json(name),
                    "is the texture's own name (\"sampler\"): a Texture2D and its "
                    "SamplerState are two variables with two names");
}

// The uniforms as the identity writes them: values, or the binding to s or b.
Json uniformsJson(const GlslSpec& g) {
    Json u = Json::object();
    for (const auto& un : g.uniforms)
        u[un.name] =
            un.bind == "offset_bias" ? Json("1 + bias / scale")
            : !un.bind.empty()
                ? Json(un.factor == 1 ? un.bind : un.bind + " * " + formatNumber(un.factor, 9))
            : un.values.size() == 1 ? Json(un.values[0])
                                    : Json(un.values);
    return u;
}

// The keys of the map kinds' samplers (methods/maps.h).
std::vector<std::string> samplerKeys() {
    std::vector<std::string> keys;
    for (const MapKindInfo& m : kMapKindTable) keys.push_back(m.samplerKey);
    return keys;
}

const std::vector<SpecField> kSpecFields = {
    // "glsl": FILE or "hlsl": FILE (one of them); or no file: a "body" in the "language"
    // named (GLSL by default), such as a generator's output (GlslSpec::ownFile), named
    // after the scene file in messages.
    {{"glsl", "hlsl", "language"},
     [](JsonFields& f, GlslSpec& s, const std::string& file) {
         s.ownFile = f.has("glsl") || f.has("hlsl");
         s.hlsl =
             s.ownFile ? f.has("hlsl") : f.choice("language", {"glsl", "hlsl"}, "glsl") == "hlsl";
         if (s.hlsl && f.has("glsl")) f.fail("hlsl", "a method has \"glsl\" or \"hlsl\", not both");
         if (!s.ownFile && !f.has("body"))
             f.fail("body", "a method without a \"glsl\" or \"hlsl\" file is its \"body\"");
         s.path = s.ownFile ? shaderPath(f, s.hlsl ? "hlsl" : "glsl", file) : file;
     },
     [](const GlslSpec& g, Json& j) {
         if (g.ownFile)
             j[g.hlsl ? "hlsl" : "glsl"] = g.path;
         else
             j["language"] = g.hlsl ? "hlsl" : "glsl";
     }},
    {{"defines"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         if (f.has("defines")) s.defines = parseDefines(f);
     },
     [](const GlslSpec& g, Json& j) {
         for (const auto& [name, value] : g.defines) j["defines"][name] = value;
     }},
    {{"include_paths"},
     [](JsonFields& f, GlslSpec& s, const std::string& file) {
         if (f.has("include_paths")) s.includePaths = includePaths(f, file);
     },
     [](const GlslSpec& g, Json& j) {
         if (!g.includePaths.empty()) j["include_paths"] = g.includePaths;
     }},
    // The file's text (and an HLSL file's includes) is part of the identity: an edited
    // file is another method. GLSL's includes are expanded into the source.
    {{},
     [](JsonFields& f, GlslSpec& s, const std::string& file) {
         if (s.ownFile) readShaderSource(s, file, f.fieldPath(s.hlsl ? "hlsl" : "glsl"));
     },
     [](const GlslSpec& g, Json& j) {
         j["source_sha1"] = textSha1(g.source);
         if (g.includeFiles.empty()) return;
         std::string all;
         for (const auto& [name, text] : g.includeFiles) all += name + '\0' + text + '\0';
         j["includes_sha1"] = textSha1(all);
     }},
    {{"function"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         s.function = f.string("function", "ParallaxMapping");
     },
     [](const GlslSpec& g, Json& j) {
         if (g.call.empty() && g.body.empty()) j["function"] = g.function;
     }},
    // HLSL reaches the GL as the GLSL 4.50 that methods/shader/hlsl.h makes of it; 110
    // (GLSL's own default) is written as none.
    {{"version"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         if (s.hlsl && f.has("version"))
             f.fail("version", "names a GLSL dialect; an HLSL method has none");
         s.version = s.hlsl ? "450" : glslVersion(f, s);
     },
     [](const GlslSpec& g, Json& j) {
         if (!g.hlsl && g.version != "110") j["version"] = g.version;
     }},
    // The sampler each map kind is bound to (methods/maps.h): the height map's
    // "depthMap" unless named ("" says it reads none), the others only where named.
    {samplerKeys(),
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         for (const MapKindInfo& m : kMapKindTable)
             s.samplers[size_t(m.kind)] =
                 f.string(m.samplerKey, m.kind == MapKind::Height ? "depthMap" : "");
     },
     [](const GlslSpec& g, Json& j) {
         for (const MapKindInfo& m : kMapKindTable)
             if (m.kind == MapKind::Height || !g.sampler(m.kind).empty())
                 j[m.samplerKey] = g.sampler(m.kind);
     }},
    {{"texture"},
     [](JsonFields& f, GlslSpec& s, const std::string&) { readTexture(f, s); },
     [](const GlslSpec& g, Json& j) { j["texture"] = textureName(g); }},
    {{"call", "body"},
     [](JsonFields& f, GlslSpec& s, const std::string&) { readEntryCode(f, s); },
     [](const GlslSpec& g, Json& j) {
         if (!g.call.empty()) j["call"] = g.call;
         if (!g.body.empty()) j["body"] = g.body;
     }},
    {{"sampler_state"},
     [](JsonFields& f, GlslSpec& s, const std::string&) { readSamplerState(f, s); },
     [](const GlslSpec& g, Json& j) {
         if (!g.samplerState.empty()) j["sampler_state"] = g.samplerState;
     }},
    {{"api"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         s.api = s.hlsl ? GlslSpec::Api::D3d : GlslSpec::Api::Gl;
         if (f.has("api"))
             s.api = f.choice("api", {"gl", "d3d"}, "") == "gl" ? GlslSpec::Api::Gl
                                                                : GlslSpec::Api::D3d;
     },
     [](const GlslSpec& g, Json& j) {
         if (!g.defaultApi()) j["api"] = g.api == GlslSpec::Api::Gl ? "gl" : "d3d";
     }},
    {{"inputs"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         s.engineInputs = f.choice("inputs", {"tangent", "engine"}, "tangent") == "engine";
     },
     [](const GlslSpec& g, Json& j) {
         if (g.engineInputs) j["inputs"] = "engine";
     }},
    {{"vertex", "attributes", "matrices", "vectors", "vertex_entry", "stage_input"},
     [](JsonFields& f, GlslSpec& s, const std::string& file) {
         if (f.has("vertex")) return readVertexStage(f, s, file, shaderPath(f, "vertex", file));
         for (const char* key :
              {"attributes", "matrices", "vectors", "vertex_entry", "stage_input"})
             if (f.has(key)) f.fail(key, "is for an engine vertex stage (the entry's \"vertex\")");
     },
     [](const GlslSpec& g, Json& j) {
         if (const GlslSpec::VertexStage* v = g.vertexStage()) vertexStageJson(*v, j);
     }},
    {{"uniforms"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         if (f.has("uniforms")) s.uniforms = parseUniforms(f);
     },
     [](const GlslSpec& g, Json& j) { j["uniforms"] = uniformsJson(g); }},
    {{"steps_uniform"},
     [](JsonFields& f, GlslSpec& s, const std::string&) {
         s.stepsUniform = f.string("steps_uniform", "");
         if (!s.stepsUniform.empty() && !mentionsIdentifier(s.source, s.stepsUniform))
             f.fail("steps_uniform",
                    "the shader " + s.path + " has no uniform \"" + s.stepsUniform + "\"");
     },
     [](const GlslSpec& g, Json& j) {
         if (!g.stepsUniform.empty()) j["steps_uniform"] = g.stepsUniform;
     }},
};

}  // namespace

const std::vector<SpecField>& specFields() { return kSpecFields; }

// The dialect: the entry's "version" (a string, or a desktop number such as 330), else the
// file's #version line ("#version 300 es", "#version 330 core"), else 110, GLSL's default.
// The dialect a file's #version line names ("110" without one, GLSL's own default).
std::string versionOfSource(const GlslSpec& spec) {
    std::istringstream lines(blankComments(spec.source));  // a #version in a comment is none
    std::string line;
    for (int n = 1; std::getline(lines, line); ++n) {
        std::istringstream words(line);
        std::string directive, number, profile;
        words >> directive >> number >> profile;
        if (directive != "#version") continue;
        const std::string named = profile == "es" ? number + " es" : number;
        if (!knownGlslVersion(named))
            throw InputError(spec.path, "#version", line,
                             "line " + std::to_string(n) + ": not a GLSL version pgt compiles (" +
                                 kGlslVersionsNamed + ")");
        return named;
    }
    return "110";
}

}  // namespace pgt
