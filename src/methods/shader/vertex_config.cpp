// A shader entry's "vertex", "attributes" and "matrices" (methods/shader/vertex_config.h).
#include "methods/shader/vertex_config.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/json_read.h"
#include "methods/shader/hlsl.h"
#include "methods/shader/shader_words.h"
#include "methods/shader/source_text.h"
#include "methods/shader/vertex_stage.h"

namespace pgt {

namespace {

using Json = nlohmann::json;

// A stage variable's floats per column (float, vecN; matN: N) and its columns (matN: N, else
// 1); 0 components for any other type.
int components(const std::string& type) {
    if (type == "float") return 1;
    if ((type.rfind("vec", 0) == 0 || type.rfind("mat", 0) == 0) && type.size() == 4 &&
        type[3] >= '2' && type[3] <= '4')
        return type[3] - '0';
    return 0;
}
int columns(const std::string& type) { return type.rfind("mat", 0) == 0 ? components(type) : 1; }

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// pgt's vertex data an attribute takes by its name alone (docs/methods.md "The engine's vertex
// stage"): "" where the name says none.
std::string conventionalAttribute(const std::string& name) {
    const std::string n = lower(name);
    if (n.find("pos") != std::string::npos) return "position";
    if (n.find("bitan") != std::string::npos || n.find("binorm") != std::string::npos)
        return "bitangent";
    if (n.find("norm") != std::string::npos) return "normal";
    if (n.find("tang") != std::string::npos) return "tangent";
    if (n.find("uv") != std::string::npos || n.find("texcoord") != std::string::npos) return "uv";
    return "";
}

// Whether `text` declares `struct NAME` (shader_words.h: one pass, comments skipped).
bool declaresStruct(const std::string& text, const std::string& name) {
    const std::vector<ShaderWord> w = shaderWords(text);
    for (size_t k = 0; k + 1 < w.size(); ++k)
        if (wordText(text, w[k]) == "struct" && wordText(text, w[k + 1]) == name) return true;
    return false;
}

// Attributes bound by their names alone must each take other data: two that would take the
// same (a tangent under TEXCOORD1 beside the uv's TEXCOORD0) are refused, to be bound by hand.
void refuseSharedDefaults(JsonFields& f,
                          const std::vector<std::pair<std::string, std::string>>& attributes) {
    for (size_t i = 0; i < attributes.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (attributes[i].second == attributes[j].second)
                f.fail("attributes", "the vertex shader's attributes " + attributes[j].first +
                                         " and " + attributes[i].first + " would both take " +
                                         attributes[i].second +
                                         " by their names: bind them in \"attributes\"");
}

// An object field of names mapped to one of `allowed`, in the entry's order.
std::vector<std::pair<std::string, std::string>> namedChoices(
    JsonFields& f, const std::string& key, const std::vector<std::string>& allowed) {
    const Json& raw = f.raw(key);
    if (!raw.is_object()) f.fail(key, "expected an object of names");
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [name, value] : raw.items()) {
        if (!value.is_string() ||
            std::find(allowed.begin(), allowed.end(), value.get<std::string>()) == allowed.end())
            throw InputError(f.file(), f.fieldPath(key) + "." + name, shortDump(value),
                             "expected one of " + list);
        out.emplace_back(name, value.get<std::string>());
    }
    return out;
}

// Each of the fragment code's stage inputs and the vertex output that reaches it: the output
// of its location, or, where either has none, of its name.
void linkStages(JsonFields& f, GlslSpec& spec) {
    GlslSpec::VertexStage& v = spec.vertex[0];
    const std::vector<StageVariable> outs = stageVariables(v.source, "out");
    for (const StageVariable& in : stageVariables(spec.source + "\n" + spec.body, "in")) {
        // GL's matching: a block's member by its block's and its own name; a plain variable
        // by its location, else its name.
        auto match = std::find_if(outs.begin(), outs.end(), [&](const StageVariable& o) {
            if (!in.block.empty() || !o.block.empty())
                return o.block == in.block && o.member == in.member;
            return in.location >= 0 && o.location >= 0 ? o.location == in.location
                                                       : o.name == in.name;
        });
        const std::string what =
            "the fragment code's input " + in.type + " " + in.name +
            (in.location >= 0 ? " (location " + std::to_string(in.location) + ")" : "");
        // What pgt would hand on wrongly, refused: an array, an interpolation not a GPU's
        // perspective-correct default.
        if (in.array)
            f.fail("vertex", what +
                                 ": an array; pgt passes float, vec2-vec4 and mat2-mat4 "
                                 "outputs");
        if (!in.interpolation.empty() || (match != outs.end() && !match->interpolation.empty()))
            f.fail("vertex",
                   what + ": " +
                       (in.interpolation.empty() ? match->interpolation : in.interpolation) +
                       " interpolation is not handed on yet (pgt interpolates "
                       "perspective-correctly)");
        if (match == outs.end())
            f.fail("vertex", what + " has no output of that " +
                                 (in.location >= 0 ? "location" : "name") + " in " + v.path);
        if (components(in.type) == 0 || match->type != in.type)
            f.fail("vertex", what + " and the vertex output " + match->type + " " + match->name +
                                 ": pgt passes float, vec2-vec4 and mat2-mat4 outputs of one "
                                 "type");
        // Transform feedback names a block's member BLOCK.MEMBER.
        const std::string captured =
            match->block.empty() ? match->name : match->block + "." + match->member;
        v.links.push_back({captured, in.name, components(in.type), columns(in.type)});
    }
}

// Each pixel input the call reads and the vertex output of its semantic (as D3D links them).
void linkHlslStages(JsonFields& f, GlslSpec& spec, const std::vector<gl::HlslVarying>& outputs) {
    GlslSpec::VertexStage& out = spec.vertex[0];
    for (const gl::HlslVarying& in : gl::hlslPixelInputs(spec)) {
        const auto o = std::find_if(outputs.begin(), outputs.end(),
                                    [&](const auto& x) { return x.semantic == in.semantic; });
        const std::string what = "the pixel stage's input of semantic " + in.semantic;
        if (o == outputs.end())
            f.fail("vertex", what + " has no output of that semantic in " + out.path);
        if (!in.interpolation.empty() || !o->interpolation.empty())
            f.fail("vertex", what + ": " +
                                 (in.interpolation.empty() ? o->interpolation : in.interpolation) +
                                 " interpolation is not handed on yet (pgt interpolates "
                                 "perspective-correctly)");
        if (in.components == 0 || o->components != in.components || o->columns != in.columns ||
            (in.columns > 1 && in.columns != in.components))
            f.fail("vertex", what +
                                 " and the vertex output of that semantic: pgt passes float, "
                                 "float2-float4 and float2x2, float3x3, float4x4 outputs of one "
                                 "type");
        out.links.push_back({gl::hlslStageName(false, in.semantic),
                             gl::hlslStageName(true, in.semantic), in.components, in.columns});
    }
}

// An HLSL vertex stage (the entry's language): its file read as an HLSL fragment file is (its
// includes served to glslang, enums made constants), its entry and the pixel stage's input,
// then both stages translated (the scene's errors come now, naming the vertex file) and linked
// by semantic, as D3D links them.
void readHlslVertexStage(JsonFields& f, GlslSpec& spec, GlslSpec::VertexStage& v,
                         const std::string& text) {
    v.hlsl = true;
    v.entry = f.string("vertex_entry", "main");
    if (!isShaderIdentifier(v.entry))
        f.fail("vertex_entry", "expected the vertex file's entry function's name");
    v.includeFiles = hlslIncludes(v.path, text, spec.defines, spec.includePaths);
    std::string included;
    for (const auto& [name, sub] : v.includeFiles) included += sub + "\n";
    v.enums = hlslEnumNames(text + included);
    v.source = hlslSamplerDefaults(hlslEnumsAsConstants(text, v.enums));
    const std::vector<std::string> types = functionTypes(v.source + "\n" + included, v.entry);
    if (types.empty())
        f.fail("vertex_entry", "the vertex file " + v.path + " defines no function " + v.entry);
    // The default, the vertex entry's struct; where it returns anything else (void, an
    // SV_Position), its outputs are parameters, which the pixel stage declares as its main does.
    if (!f.has("stage_input") && !declaresStruct(v.source + "\n" + included, types[0]))
        f.fail("stage_input", "the vertex entry " + v.entry + " returns " + types[0] +
                                  ", not a struct of its outputs: declare the pixel stage's "
                                  "inputs as its main does (\"float2 tex : TEXCOORD0, ...\")");
    v.stageInput = f.string("stage_input", types[0] + " input");
    v.rowVectors = f.choice("vectors", {"column", "row"}, "column") == "row";
    spec.vertex = {v};
    const gl::HlslVertexStage vs = gl::hlslVertexToGlsl(spec);
    GlslSpec::VertexStage& out = spec.vertex[0];
    out.glsl = vs.glsl;
    if (f.has("attributes")) {
        out.attributes = namedChoices(f, "attributes", vertexAttributeNames());
    } else {  // by their semantics (docs/methods.md)
        for (const gl::HlslVarying& a : vs.inputs) {
            const std::string what = conventionalAttribute(a.semantic);
            if (what.empty())
                f.fail("attributes", "the vertex entry's input of semantic " + a.semantic +
                                         " has no name pgt reads as position, normal, tangent, "
                                         "bitangent (BINORMAL) or uv (TEXCOORD): bind it in "
                                         "\"attributes\"");
            out.attributes.emplace_back(a.semantic, what);
        }
        refuseSharedDefaults(f, out.attributes);
    }
    linkHlslStages(f, spec, vs.outputs);
}

}  // namespace

void readVertexStage(JsonFields& f, GlslSpec& spec, const std::string& file,
                     const std::string& path) {
    GlslSpec::VertexStage v;
    v.path = path;
    const std::string text = normaliseLineEnds(
        readTextFile(path, file, f.fieldPath("vertex"), "vertex shader", kMaxShaderBytes));
    if (f.has("matrices")) v.matrices = namedChoices(f, "matrices", vertexMatrixNames());
    if (spec.hlsl) return readHlslVertexStage(f, spec, v, text);
    for (const char* key : {"vertex_entry", "stage_input"})
        if (f.has(key)) f.fail(key, "is for an HLSL vertex stage (the entry's \"hlsl\")");
    v.rowVectors = f.choice("vectors", {"column", "row"}, "column") == "row";
    // Its #include lines expanded and the entry's defines judged as in the fragment file.
    v.source = expandGlslIncludes(path, text, spec.defines, spec.includePaths, v.origins);
    if (f.has("attributes")) {
        v.attributes = namedChoices(f, "attributes", vertexAttributeNames());
    } else {  // by their names (docs/methods.md)
        for (const StageVariable& a : stageVariables(v.source, "in")) {
            const std::string what = conventionalAttribute(a.name);
            if (what.empty())
                f.fail("attributes", "the vertex shader's attribute " + a.name +
                                         " has no name pgt reads as position, normal, tangent, "
                                         "bitangent or uv: bind it in \"attributes\"");
            v.attributes.emplace_back(a.name, what);
        }
        refuseSharedDefaults(f, v.attributes);
    }
    spec.vertex = {std::move(v)};
    linkStages(f, spec);
}

void vertexStageJson(const GlslSpec::VertexStage& v, nlohmann::json& j) {
    j["vertex"] = v.path;
    j["vertex_sha1"] = textSha1(v.source);
    if (v.hlsl) {
        j["vertex_entry"] = v.entry;
        j["stage_input"] = v.stageInput;
        for (const auto& [name, text] : v.includeFiles) j["vertex_includes"][name] = textSha1(text);
    }
    if (v.rowVectors) j["vectors"] = "row";
    for (const auto& [name, what] : v.attributes) j["attributes"][name] = what;
    for (const auto& [name, what] : v.matrices) j["matrices"][name] = what;
}

}  // namespace pgt
