// HLSL to GLSL 4.50 through SPIR-V (methods/shader/hlsl.h): glslang, then SPIRV-Cross's C API.
#include "methods/shader/hlsl.h"

// Debian's glslang is built with its HLSL front end; its header shows the HLSL-only setters
// (setEnvTargetHlslFunctionality1) to code that says so.
#ifndef ENABLE_HLSL
#define ENABLE_HLSL 1
#endif
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_read.h"
#include "core/process.h"
#include "methods/shader/hlsl_fetches.h"
#include "methods/shader/shader_gate.h"
#include "methods/shader/shader_words.h"
#include "methods/shader/source_text.h"

namespace pgt::gl {

namespace {

// What pgt adds after the user's file: `pgt_s` and `pgt_b`, the case's s and b (set by
// methods/shader/glsl_method.cpp like any uniform); a "body" as a function (kBodyHead, the
// body, "}"); the entry point, which runs the call (or F(uv, V), or the body's function) with
// the names a call may use. The call stands alone on the line after kEntryNames, so that a
// message about that line names the call.
constexpr const char* kGlobals = R"(
float pgt_s;
float pgt_b;
)";
constexpr const char* kBodyHead = R"(float2 pgt_body(float2 uv, float3 V) {
    const float3 N = float3(0.0, 0.0, 1.0);
    float s = pgt_s;
    float b = pgt_b;
)";
// "inputs": "engine": an engine's varyings as static globals any function reads (in the
// preamble, before the user's file), set from the entry's inputs 2-5 (nameStageVariables).
constexpr const char* kEngineGlobals = R"(static float3 pgt_world_position;
static float3 pgt_world_normal;
static float4 pgt_world_tangent;
static float3 pgt_camera_position;
)";
// The entry point: its signature (with the engine's inputs 2-5 where asked), its opening, the
// engine's globals set, and the names a call may use.
// pgt's inputs carry semantics of their own (PGT_*), apart from any a vertex stage's outputs
// and the pixel stage's input struct use.
constexpr const char* kEntrySignature =
    "float4 pgt_hlsl_entry(float2 pgt_uv : PGT_UV, float3 pgt_v : PGT_V";
constexpr const char* kEngineSignature = R"(,
                      float3 pgt_wp : PGT_WP, float3 pgt_wn : PGT_WN,
                      float4 pgt_wt : PGT_WT, float3 pgt_wc : PGT_WC)";
constexpr const char* kEntryOpen = R"() : SV_Target {
)";
constexpr const char* kEngineAssign = R"(    pgt_world_position = pgt_wp;
    pgt_world_normal = pgt_wn;
    pgt_world_tangent = pgt_wt;
    pgt_camera_position = pgt_wc;
)";
constexpr const char* kEntryNames = R"(    float2 uv = pgt_uv;
    float3 V = pgt_v;
    const float3 N = float3(0.0, 0.0, 1.0);
    float s = pgt_s;
    float b = pgt_b;
    return float4(
)";
constexpr const char* kEntryTail = R"(
    , pgt_fetch_count, 0.0);
}
)";

int countLines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// #include "F" and <F>: relative to the including file's folder (the user's file's for the
// first), read with the limits of every shader file. A failure is glslang's own message (an
// include result with no name).
class Includer : public glslang::TShader::Includer {
  public:
    // `textures`: the pixel stage's texture names, whose includes count their fetches
    // (countFetches); null for a vertex stage.
    Includer(std::string top, std::vector<std::string> enums,
             const std::vector<std::pair<std::string, std::string>>& files,
             const std::vector<std::string>& searchPaths, const std::vector<std::string>* textures)
        : top_(std::move(top)),
          enums_(std::move(enums)),
          files_(files),
          searchPaths_(searchPaths),
          textures_(textures) {}
    IncludeResult* includeLocal(const char* requested, const char* from, size_t depth) override {
        return resolve(requested, from, depth);
    }
    IncludeResult* includeSystem(const char* requested, const char* from, size_t depth) override {
        return resolve(requested, from, depth);
    }
    void releaseInclude(IncludeResult* r) override {
        if (!r) return;
        delete static_cast<std::string*>(r->userData);
        delete r;
    }

  private:
    // Includes nest at most kMaxIncludeDepth deep (methods/shader/source_text.h); a file with
    // `#pragma once` is included once; each is normalised as the user's file is.
    IncludeResult* resolve(const char* requested, const char* from, size_t depth) {
        const std::filesystem::path owner(from && *from ? from : top_);
        std::string name = resolveInclude(owner.string(), requested, searchPaths_);
        auto* content = new std::string;
        try {
            if (depth > kMaxIncludeDepth)
                throw InputError(owner.string(), "#include", requested,
                                 "includes nest more than " + std::to_string(kMaxIncludeDepth) +
                                     " deep (a file that includes itself?)");
            if (once_.count(name)) return new IncludeResult(name, "", 0, content);
            // The text read when the scene was parsed (the study's identity hashes it); the
            // disk only for a file that could not be read then, so that its error is named.
            const auto read = std::find_if(files_.begin(), files_.end(),
                                           [&](const auto& f) { return f.first == name; });
            *content = hlslSamplerDefaults(hlslEnumsAsConstants(
                read != files_.end()
                    ? read->second
                    : normaliseLineEnds(readTextFile(name, owner.string(), "#include",
                                                     "HLSL include", kMaxShaderBytes)),
                enums_));
            if (takePragmaOnce(*content)) once_.insert(name);
            if (textures_) *content = countFetches(*content, *textures_);
        } catch (const std::exception& e) {
            *content = e.what();
            name.clear();
        }
        return new IncludeResult(name, content->c_str(), content->size(), content);
    }
    std::string top_;
    std::vector<std::string> enums_;
    const std::vector<std::pair<std::string, std::string>>& files_;
    const std::vector<std::string>& searchPaths_;
    const std::vector<std::string>* textures_ = nullptr;
    std::set<std::string> once_;
};

// glslang's messages "ERROR: FILE:LINE: ..." with the lines pgt added named for what they
// are: the call's line as "call", the others as pgt's entry point.
std::string translateMessages(const std::string& log, const std::string& file, int userLines,
                              int callLine, int bodyFirst, int bodyCount,
                              const std::vector<std::string>& declared) {
    std::istringstream in(log);
    std::ostringstream out;
    std::string line;
    const std::string prefix = file + ":";
    bool aboutCall = false;
    while (std::getline(in, line)) {
        for (const char* kind : {"ERROR: ", "WARNING: "})
            if (line.rfind(kind, 0) == 0) line = line.substr(std::string(kind).size());
        if (line.empty() ||
            line.find("compilation errors.  No code generated.") != std::string::npos)
            continue;
        // "FILE:LINE: ..." or "FILE(LINE): ..."
        const bool colon = line.rfind(prefix, 0) == 0, paren = line.rfind(file + "(", 0) == 0;
        if (colon || paren) {
            size_t end = prefix.size();
            while (end < line.size() && std::isdigit(static_cast<unsigned char>(line[end]))) ++end;
            if (end > prefix.size()) {
                const int n = std::stoi(line.substr(prefix.size(), end - prefix.size()));
                const std::string rest = line.substr(end + (paren ? 1 : 0));
                // The call's line and the entry's lines around it, which hold its value.
                if (n >= callLine - 1 && n <= callLine + 1 && bodyCount == 0) {
                    line = file + std::string(": call").append(rest);
                    aboutCall = true;
                } else if (bodyCount > 0 && n >= bodyFirst && n <= bodyFirst + bodyCount) {
                    line = file + ": body:" + std::to_string(n - bodyFirst + 1) + rest;
                } else if (n > userLines) {
                    line = "pgt entry point" + rest;
                } else {  // with what the file's own #line said of the line
                    const bool note =
                        size_t(n) <= declared.size() && !declared[size_t(n) - 1].empty();
                    line = file + ":" + std::to_string(n) +
                           (note ? " (its #line: " + declared[size_t(n) - 1] + ")" : "") + rest;
                }
            }
        }
        out << line << "\n";
    }
    if (aboutCall)
        out << file
            << ": call: it must give uv' as a float2, from uv, V, N, s, b and the "
               "shader's own names\n";
    return out.str();
}

// HLSL 2021's select(c, a, b), which glslang 12 lacks (engines built with DXC use it), for
// float, int and uint scalars and vectors; given to every file but one that defines its own.
std::string selectFunctions() {
    std::string out;
    for (const char* t : {"float", "int", "uint"}) {
        out += std::string(t) + " select(bool c, " + t + " a, " + t + " b) { return c ? a : b; }\n";
        for (int n = 2; n <= 4; ++n) {
            const std::string v = t + std::to_string(n);
            out += v + " select(bool" + std::to_string(n) + " c, " + v + " a, " + v +
                   " b) { return " + v + "(";
            for (int i = 0; i < n; ++i)
                out += std::string(i ? ", " : "") + "c[" + std::to_string(i) + "] ? a[" +
                       std::to_string(i) + "] : b[" + std::to_string(i) + "]";
            out += "); }\n";
        }
    }
    return out;
}

// Where the parts pgt adds sit in the text glslang compiles (for messages).
struct TextLines {
    int user = 0, call = 0, bodyFirst = 0, bodyCount = 0;
    std::vector<std::string> declared;  // the file's own #line numbering (blankLineDirectives)
};

// The types a texture or sampler the file declares may have.
const std::vector<std::string>& textureTypes() {
    static const std::vector<std::string> types = {"Texture2D",
                                                   "texture2D",
                                                   "Texture",
                                                   "sampler2D",
                                                   "sampler",
                                                   "SamplerState",
                                                   "SamplerComparisonState"};
    return types;
}

// The declarations a file leaves to pgt, as glslang's preamble (which moves no line): each
// named sampler as a Texture2D (a DX9 file's, which names sampler2D, as a sampler2D) and
// "sampler_state" as a SamplerState, where the file does not declare them (a function that
// takes them as parameters is called with these).
std::string declarationsFor(const GlslSpec& spec) {
    std::string out;
    const std::string all = spec.source + "\n" + spec.included;
    const char* type = mentionsIdentifier(all, "sampler2D") ? "sampler2D " : "Texture2D ";
    for (const std::string& name : spec.samplers)
        if (!name.empty() && isShaderIdentifier(name) && !declaresGlobal(all, name, textureTypes()))
            out += type + name + ";\n";
    if (!spec.samplerState.empty() && !declaresGlobal(all, spec.samplerState, textureTypes()))
        out += "SamplerState " + spec.samplerState + ";\n";
    return out;
}

// glslang's preamble for the spec: what the file leaves to pgt, the engine's globals, select()
// where the file has none, and the entry's #defines.
std::string preambleFor(const GlslSpec& spec) {
    std::string preamble = declarationsFor(spec);
    if (spec.engineInputs) preamble += kEngineGlobals;  // before the user's functions
    preamble += countingFunctions();
    if (functionTypes(spec.source + "\n" + spec.included, "select").empty())
        preamble += selectFunctions();
    for (const auto& [name, value] : spec.defines)
        preamble += "#define " + name + " " + value + "\n";
    return preamble;
}

// What one glslang compile reads: the stage and its entry function, the file (messages name
// it and its field) and its includes as read with the scene.
struct CompileUnit {
    EShLanguage stage = EShLangFragment;
    std::string entry = "pgt_hlsl_entry";
    std::string path, field = "hlsl";
    const std::vector<std::pair<std::string, std::string>>& includeFiles;
    const std::vector<std::string>& enums;
    const std::vector<std::string>& includePaths;
    const std::vector<std::string>* textures = nullptr;  // where fetches are counted
};

std::vector<uint32_t> compileInProcess(const CompileUnit& unit, const std::string& preamble,
                                       const std::string& text, const TextLines& lines) {
    static const bool initialised = glslang::InitializeProcess();
    (void)initialised;
    glslang::TShader shader(unit.stage);
    const char* strings[] = {text.c_str()};
    const int lengths[] = {int(text.size())};
    const char* names[] = {unit.path.c_str()};
    shader.setStringsWithLengthsAndNames(strings, lengths, names, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEntryPoint(unit.entry.c_str());
    shader.setSourceEntryPoint(unit.entry.c_str());
    shader.setEnvInput(glslang::EShSourceHlsl, unit.stage, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_0);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
    shader.setEnvTargetHlslFunctionality1();  // the stage variables' semantics, by name
    shader.setAutoMapBindings(true);
    shader.setAutoMapLocations(true);
    // DX9 compatibility: a `sampler2D` global is a texture and sampler in one, read with
    // tex2D, tex2Dlod, tex2Dgrad, tex2Dbias, tex2Dproj (Cg and older engines' HLSL).
    const auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules | EShMsgReadHlsl |
                                      EShMsgHlslLegalization | EShMsgHlslDX9Compatible);
    Includer includer(unit.path, unit.enums, unit.includeFiles, unit.includePaths, unit.textures);
    glslang::TProgram program;
    bool ok = shader.parse(GetDefaultResources(), 100, false, messages, includer);
    if (ok) {
        program.addShader(&shader);
        ok = program.link(messages);
    }
    if (!ok)
        throw InputError(
            unit.path, unit.field, "",
            "the shader does not compile:\n" +
                translateMessages(std::string(shader.getInfoLog()) + program.getInfoLog(),
                                  unit.path, lines.user, lines.call, lines.bodyFirst,
                                  lines.bodyCount, lines.declared));
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.disableOptimizer = false;  // HLSL's legalisation (inlining, textures by value)
    spv::SpvBuildLogger logger;
    glslang::GlslangToSpv(*program.getIntermediate(unit.stage), spirv, &logger, &options);
    return spirv;
}

// glslang in a child process: glslang 12's HLSL front end crashes on some malformed input
// (`1.0 -- x`), and hostile input can make it run or grow without end; either must be an error
// naming the file, not a crash or a hang of pgt. The child writes 'S' and the SPIR-V words, or
// 'E' and the error message, to a pipe and exits; it is held to kCompileLimits.
std::vector<uint32_t> compileToSpirv(const CompileUnit& unit, const std::string& preamble,
                                     const std::string& text, const TextLines& lines) {
    std::string in;
    const ChildLimits limits = compileLimits();
    const ChildStatus st = runInChild(
        [&](int fd) {
            std::string out;
            try {
                const std::vector<uint32_t> words = compileInProcess(unit, preamble, text, lines);
                out.assign(1, 'S');
                out.append(reinterpret_cast<const char*>(words.data()), words.size() * 4);
            } catch (const std::exception& e) {
                out.assign(1, 'E');
                out.append(e.what());
            }
            return writeAll(fd, out) ? 0 : 1;
        },
        limits, &in);
    if (st.end == ChildEnd::Exited && !in.empty() && in[0] == 'S' && (in.size() - 1) % 4 == 0) {
        std::vector<uint32_t> words((in.size() - 1) / 4);
        std::memcpy(words.data(), in.data() + 1, in.size() - 1);
        return words;
    }
    if (st.end == ChildEnd::Exited && !in.empty() && in[0] == 'E') {
        // The child's InputError, rebuilt with its message (the file and field lead it).
        const std::string prefix = unit.path + ": " + unit.field + ": ";
        std::string message = in.substr(1);
        if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
        throw InputError(unit.path, unit.field, "", message);
    }
    throw InputError(unit.path, unit.field, "",
                     "glslang, the HLSL compiler, " + compileFailure(st, limits) +
                         " (glslang 12 also crashes on some malformed expressions, such as "
                         "1.0 -- x); check the syntax");
}

// SPIRV-Cross: a failure here is pgt's (the SPIR-V came from glslang), named as such.
void check(spvc_result r, spvc_context ctx, const std::string& file) {
    if (r != SPVC_SUCCESS)
        throw InputError(file, "hlsl", "",
                         std::string("SPIRV-Cross cannot turn the compiled shader into GLSL: ") +
                             spvc_context_get_last_error_string(ctx));
}

// Each separate texture + sampler pair becomes one sampler2D named after the texture (or
// TEXTURE_SAMPLER where a texture is used with several samplers).
void nameCombinedSamplers(spvc_compiler comp) {
    const spvc_combined_image_sampler* list = nullptr;
    size_t n = 0;
    spvc_compiler_get_combined_image_samplers(comp, &list, &n);
    std::map<std::string, int> uses;
    for (size_t i = 0; i < n; ++i) ++uses[spvc_compiler_get_name(comp, list[i].image_id)];
    for (size_t i = 0; i < n; ++i) {
        std::string name = spvc_compiler_get_name(comp, list[i].image_id);
        if (uses[name] > 1)
            name += std::string("_") + spvc_compiler_get_name(comp, list[i].sampler_id);
        spvc_compiler_set_name(comp, list[i].combined_id, name.c_str());
    }
}

// Gives the stage variables fixed names by their semantics, so that the wrapper can make them
// plain globals and the stages meet by semantic: pgt's inputs (PGT_*) their own names, any other
// input pgt_in_SEMANTIC and output pgt_out_SEMANTIC (a pixel stage's one output pgt_hlsl_out).
// Their float sizes go to `inputs` and `outputs` where given.
void nameStageVariables(spvc_compiler comp, spvc_context ctx, const std::string& file, bool pixel,
                        std::vector<HlslVarying>* inputs, std::vector<HlslVarying>* outputs) {
    spvc_resources res = nullptr;
    check(spvc_compiler_create_shader_resources(comp, &res), ctx, file);
    const std::map<std::string, const char*> own = {
        {"PGT_UV0", "pgt_hlsl_uv"}, {"PGT_V0", "pgt_hlsl_v"},   {"PGT_WP0", "pgt_hlsl_wp"},
        {"PGT_WN0", "pgt_hlsl_wn"}, {"PGT_WT0", "pgt_hlsl_wt"}, {"PGT_WC0", "pgt_hlsl_wc"}};
    for (const bool in : {true, false}) {
        const spvc_reflected_resource* list = nullptr;
        size_t n = 0;
        check(spvc_resources_get_resource_list_for_type(
                  res, in ? SPVC_RESOURCE_TYPE_STAGE_INPUT : SPVC_RESOURCE_TYPE_STAGE_OUTPUT, &list,
                  &n),
              ctx, file);
        for (size_t i = 0; i < n; ++i) {
            const char* raw = spvc_compiler_get_decoration_string(comp, list[i].id,
                                                                  SpvDecorationHlslSemanticGOOGLE);
            const std::string semantic = semanticKey(raw ? raw : "");
            const auto mine = own.find(semantic);
            const std::string name = !in && pixel              ? "pgt_hlsl_out"
                                     : in && mine != own.end() ? mine->second
                                                               : hlslStageName(in, semantic);
            spvc_compiler_set_name(comp, list[i].id, name.c_str());
            std::vector<HlslVarying>* into = in ? inputs : outputs;
            if (!into || (in && mine != own.end())) continue;
            const spvc_type type = spvc_compiler_get_type_handle(comp, list[i].type_id);
            const bool floats = spvc_type_get_basetype(type) == SPVC_BASETYPE_FP32 &&
                                spvc_type_get_num_array_dimensions(type) == 0;
            const char* interpolation =
                spvc_compiler_has_decoration(comp, list[i].id, SpvDecorationFlat)
                    ? "nointerpolation"
                : spvc_compiler_has_decoration(comp, list[i].id, SpvDecorationNoPerspective)
                    ? "noperspective"
                    : "";
            into->push_back({semantic, floats ? int(spvc_type_get_vector_size(type)) : 0,
                             int(spvc_type_get_columns(type)), interpolation});
        }
    }
}

std::string spirvToGlsl(const std::vector<uint32_t>& spirv, const std::string& file,
                        bool pixel = true, std::vector<HlslVarying>* inputs = nullptr,
                        std::vector<HlslVarying>* outputs = nullptr) {
    spvc_context ctx = nullptr;
    if (spvc_context_create(&ctx) != SPVC_SUCCESS)
        throw std::runtime_error("SPIRV-Cross: no context");
    std::unique_ptr<spvc_context_s, decltype(&spvc_context_destroy)> owner(ctx,
                                                                           spvc_context_destroy);
    spvc_parsed_ir ir = nullptr;
    check(spvc_context_parse_spirv(ctx, spirv.data(), spirv.size(), &ir), ctx, file);
    spvc_compiler comp = nullptr;
    check(spvc_context_create_compiler(ctx, SPVC_BACKEND_GLSL, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                       &comp),
          ctx, file);
    spvc_compiler_options opts = nullptr;
    check(spvc_compiler_create_compiler_options(comp, &opts), ctx, file);
    spvc_compiler_options_set_uint(opts, SPVC_COMPILER_OPTION_GLSL_VERSION, 450);
    spvc_compiler_options_set_bool(opts, SPVC_COMPILER_OPTION_GLSL_ES, SPVC_FALSE);
    spvc_compiler_options_set_bool(opts, SPVC_COMPILER_OPTION_GLSL_VULKAN_SEMANTICS, SPVC_FALSE);
    spvc_compiler_options_set_bool(
        opts, SPVC_COMPILER_OPTION_GLSL_EMIT_UNIFORM_BUFFER_AS_PLAIN_UNIFORMS, SPVC_TRUE);
    check(spvc_compiler_install_compiler_options(comp, opts), ctx, file);
    spvc_variable_id dummy = 0;  // for Load/texelFetch of a texture with no sampler
    check(spvc_compiler_build_dummy_sampler_for_combined_images(comp, &dummy), ctx, file);
    check(spvc_compiler_build_combined_image_samplers(comp), ctx, file);
    nameCombinedSamplers(comp);
    nameStageVariables(comp, ctx, file, pixel, inputs, outputs);
    const char* out = nullptr;
    check(spvc_compiler_compile(comp, &out), ctx, file);
    return out;
}

// SPIRV-Cross's text as a piece of the wrapper: the stage variables plain globals, main()
// renamed, and the function the wrapper calls.
std::string asWrapperPiece(const std::string& glsl) {
    std::istringstream in(glsl);
    std::ostringstream out;
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("layout(location", 0) == 0) {
            for (const char* io : {") in ", ") out "}) {
                const size_t at = line.find(io);
                if (at != std::string::npos) line = line.substr(at + std::string(io).size());
            }
        }
        if (line == "void main()") line = "void pgt_hlsl_main()";
        out << line << "\n";
    }
    // An input the shader never reads (a call that ignores V) was optimised away with its
    // variable: only the inputs that are left are set.
    out << "vec2 " << kHlslCall << "(vec2 uv, vec3 v) {\n";
    if (mentionsIdentifier(glsl, "pgt_hlsl_uv")) out << "    pgt_hlsl_uv = uv;\n";
    if (mentionsIdentifier(glsl, "pgt_hlsl_v")) out << "    pgt_hlsl_v = v;\n";
    // The fetches the HLSL counted (its z), which outlive a fetch the compiler dropped.
    out << "    pgt_hlsl_main();\n    pgt_fetches = int(pgt_hlsl_out.z + 0.5);\n"
        << "    return pgt_hlsl_out.xy;\n}\n";
    // An engine's inputs (GlslSpec::engineInputs), set by the wrapper's main() before the call.
    out << "void pgt_set_engine(vec3 p, vec3 n, vec4 t, vec3 c) {\n";
    const char* engine[4][2] = {
        {"pgt_hlsl_wp", "p"}, {"pgt_hlsl_wn", "n"}, {"pgt_hlsl_wt", "t"}, {"pgt_hlsl_wc", "c"}};
    for (const auto& [name, value] : engine)
        if (mentionsIdentifier(glsl, name)) out << "    " << name << " = " << value << ";\n";
    out << "}\n";
    return out.str();
}

}  // namespace

namespace {

// A pixel stage's translation and the stage inputs it reads beyond pgt's own.
struct Translation {
    std::string glsl;
    std::vector<HlslVarying> inputs;
};

const Translation& translate(const GlslSpec& spec) {
    const std::string preamble = preambleFor(spec);
    // The textures the preamble, the file, its includes and a body declare (their Load and
    // subscripts are counted reads).
    const std::vector<std::string> textures =
        textureNames(preamble + "\n" + spec.source + "\n" + spec.included + "\n" + spec.body);
    std::vector<std::string> declared;
    std::string user = countFetches(blankLineDirectives(spec.source, declared), textures);
    TextLines lines;
    lines.user = countLines(user);
    lines.declared = std::move(declared);
    std::string text = user + kGlobals;
    std::string call = spec.call.empty() ? spec.function + "(uv, V)" : spec.call;
    if (!spec.body.empty()) {
        // In a scope of its own, as in GLSL (methods/shader/program.cpp): locals named N or V.
        text += std::string(kBodyHead) + "    {\n";
        lines.bodyFirst = countLines(text) + 1;
        lines.bodyCount = countLines(spec.body);
        text += countFetches(spec.body, textures) +
                "    }\n    return uv;  // not reached: the body returns\n}\n";
        call = "pgt_body(uv, V)";
    }
    // An HLSL vertex stage's outputs arrive as the pixel stage's input struct, by semantic.
    const GlslSpec::VertexStage* vertex = spec.vertexStage();
    const std::string stageInput = vertex && vertex->hlsl ? ", " + vertex->stageInput : "";
    text += std::string(kEntrySignature) + (spec.engineInputs ? kEngineSignature : "") +
            stageInput + kEntryOpen + (spec.engineInputs ? kEngineAssign : "") + kEntryNames;
    lines.call = countLines(text) + 1;
    text += countFetches(call, textures) + kEntryTail;
    // Translations by everything glslang reads: the preamble, the text, and the includes (found
    // from the file's folder; their text as read with the scene). One per process, as programs.
    std::string key = preamble + '\0' + text + '\0' + spec.path + '\0' + spec.included;
    for (const std::string& e : spec.enums) key += '\0' + e;
    static std::mutex mutex;
    static std::map<std::string, Translation> translations;
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = translations.find(key); it != translations.end()) return it->second;
    }
    Translation t;
    t.glsl =
        asWrapperPiece(spirvToGlsl(compileToSpirv(CompileUnit{.path = spec.path,
                                                              .includeFiles = spec.includeFiles,
                                                              .enums = spec.enums,
                                                              .includePaths = spec.includePaths,
                                                              .textures = &textures},
                                                  preamble, text, lines),
                                   spec.path, true, &t.inputs));
    std::lock_guard<std::mutex> lock(mutex);
    return translations.emplace(std::move(key), std::move(t)).first->second;
}

}  // namespace

std::string hlslToGlsl(const GlslSpec& spec) { return translate(spec).glsl; }

HlslVertexStage hlslVertexToGlsl(const GlslSpec& spec) {
    const GlslSpec::VertexStage& v = spec.vertex.at(0);
    std::vector<std::string> declared;
    const std::string text = blankLineDirectives(v.source, declared);
    TextLines lines;
    lines.user = countLines(text) + 1;
    lines.call = -2;  // no call: every line is the file's
    lines.declared = std::move(declared);
    std::string included;
    for (const auto& [name, sub] : v.includeFiles) included += sub + "\n";
    std::string preamble;
    if (functionTypes(v.source + "\n" + included, "select").empty()) preamble += selectFunctions();
    for (const auto& [name, value] : spec.defines)
        preamble += "#define " + name + " " + value + "\n";
    HlslVertexStage out;
    out.glsl = spirvToGlsl(compileToSpirv(CompileUnit{.stage = EShLangVertex,
                                                      .entry = v.entry,
                                                      .path = v.path,
                                                      .field = "vertex",
                                                      .includeFiles = v.includeFiles,
                                                      .enums = v.enums,
                                                      .includePaths = spec.includePaths},
                                          preamble, text, lines),
                           v.path, false, &out.inputs, &out.outputs);
    return out;
}

std::vector<HlslVarying> hlslPixelInputs(const GlslSpec& spec) { return translate(spec).inputs; }

std::string semanticKey(std::string s) {
    for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (s.empty() || !std::isdigit(static_cast<unsigned char>(s.back()))) s += "0";
    return s;
}

}  // namespace pgt::gl
