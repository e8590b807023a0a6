// The GLSL wrapper and its compilation (methods/shader/program.h).
#include "methods/shader/program.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "methods/shader/hlsl.h"
#include "methods/shader/prelude.h"
#include "methods/shader/shader_gate.h"
#include "methods/shader/shader_words.h"
#include "methods/shader/source_text.h"

namespace pgt::gl {

namespace {

// The legacy dialects' texture functions (GLSL ES 1.00 and desktop 1.10/1.20, with the lod
// extensions ES 1.00 code enables), counted as the modern ones are.
constexpr const char* kLegacyNames = R"(#define texture2D pgt_texture
#define texture2DLod pgt_textureLod
#define texture2DLodEXT pgt_textureLod
#define texture2DGradEXT pgt_textureGrad
#define texture2DGradARB pgt_textureGrad
#define varying
vec4 pgt_frag_color, pgt_frag_data[8];
#define gl_FragColor pgt_frag_color
#define gl_FragData pgt_frag_data
)";

// A whole fragment shader as an engine ships it has a main() of its own: renamed (it is
// compiled, never run), so that pgt's main() runs the function.
constexpr const char* kOwnMain = "#define main pgt_user_main\n";
constexpr const char* kOwnMainEnd = "#undef main\n";

// Extensions whose functions GLSL 4.50 has built in (and glslang's include directive, which
// pgt's own #include expansion stands for): their #extension lines are blanked
// (an #extension after the prelude's code would be refused, and "require" of an ES-only name
// fails on a desktop GL).
constexpr const char* kCoreExtensions[] = {
    "GL_OES_standard_derivatives",     "GL_EXT_shader_texture_lod",
    "GL_ARB_shader_texture_lod",       "GL_ARB_separate_shader_objects",
    "GL_ARB_shading_language_420pack", "GL_GOOGLE_include_directive"};

// "inputs": "engine" (GlslSpec::engineInputs): an engine's varyings as globals any function
// reads, set by main() before the call (an HLSL method's pgt_set_engine is its own, hlsl.cpp),
// and PGT_ENGINE_INPUTS defined for the user's file to test.
constexpr const char* kEngineGlobals = R"(#define PGT_ENGINE_INPUTS 1
vec3 pgt_world_position = vec3(0.0);
vec3 pgt_world_normal = vec3(0.0);
vec4 pgt_world_tangent = vec4(0.0);
vec3 pgt_camera_position = vec3(0.0);
void pgt_set_engine(vec3 p, vec3 n, vec4 t, vec3 c) {
    pgt_world_position = p;
    pgt_world_normal = n;
    pgt_world_tangent = t;
    pgt_camera_position = c;
}
)";

constexpr const char* kMain = R"(
#ifdef PGT_ENGINE_INPUTS
uniform sampler2D pgt_engine_position, pgt_engine_normal, pgt_engine_tangent, pgt_engine_camera;
#endif
uniform sampler2D pgt_uv0;   // RG32F: uv0 per texel (packed, or the frame's pixels)
uniform sampler2D pgt_view;  // RGBA32F: tangent-space V; w: 2 a fragment, 1 a helper, 0 none
uniform sampler2D pgt_grad;  // RGBA32F: uv0's derivatives (dx.xy, dy.xy)
layout(location = 0) out vec2 pgt_out_uv;
layout(location = 1) out float pgt_out_fetches;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 v4 = texelFetch(pgt_view, p, 0);
    if (v4.w == 0.0) discard;  // only whole quads are empty: helpers keep theirs alive
    vec2 uv0 = texelFetch(pgt_uv0, p, 0).xy;
    vec3 v = v4.xyz;
    vec4 g = texelFetch(pgt_grad, p, 0);
    pgt_uv_dx = g.xy;
    pgt_uv_dy = g.zw;
#ifdef PGT_ENGINE_INPUTS
    pgt_set_engine(texelFetch(pgt_engine_position, p, 0).xyz, texelFetch(pgt_engine_normal, p, 0).xyz,
                   texelFetch(pgt_engine_tangent, p, 0), texelFetch(pgt_engine_camera, p, 0).xyz);
#endif
#ifdef PGT_VARYINGS
    pgt_set_varyings(p);
#endif
    pgt_fetches = 0;
    pgt_out_uv = PGT_FUNCTION(uv0, v);
    pgt_out_fetches = float(pgt_fetches);
}
)";

constexpr const char* kVertex = R"(#version 450 core
void main() {  // one triangle covering the viewport
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// The user's file as the wrapper holds it: its #version line and the #extension lines of
// kCoreExtensions blanked, so every other line keeps its number.
}  // namespace

std::string userLines(const std::string& src) {
    std::istringstream in(src);
    std::ostringstream out;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string directive, name;
        words >> directive >> name;
        if (directive == "#version") line.clear();
        if (directive == "#extension")
            for (const char* e : kCoreExtensions)
                if (name == e) line.clear();
        out << line << "\n";
    }
    return out.str();
}

namespace {

int countLines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// Where the entry's "call" (its line) or "body" (its first line and count) sits in the
// fragment shader, for messages; 0: none.
struct EntryLines {
    int call = 0;
    int bodyFirst = 0, bodyCount = 0;
};

std::string digitsAt(const std::string& t, size_t& i) {
    size_t start = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return t.substr(start, i - start);
}

// A driver message's line and column: "S:L(C): rest" (Mesa) or "S(L) : rest"; `rest` is
// where the message text starts. False for any other line.
bool driverLine(const std::string& line, std::string& ln, std::string& col, size_t& rest) {
    size_t i = 0;
    const std::string src = digitsAt(line, i);
    bool ok = !src.empty() && i < line.size();
    if (ok && line[i] == ':') {  // Mesa: S:L(C): rest
        ++i;
        ln = digitsAt(line, i);
        ok = !ln.empty() && i < line.size() && line[i] == '(';
        if (ok) {
            ++i;
            col = digitsAt(line, i);
            ok = i + 2 < line.size() && line.compare(i, 3, "): ") == 0;
            i += 3;
        }
    } else if (ok && line[i] == '(') {  // S(L) : rest
        ++i;
        ln = digitsAt(line, i);
        ok = !ln.empty() && line.compare(i, 1, ")") == 0;
        ++i;
        while (ok && i < line.size() && (line[i] == ' ' || line[i] == ':')) ++i;
    } else {
        ok = false;
    }
    rest = i;
    return ok;
}

// Driver messages with L a line of the whole fragment shader: lines (first, first + count]
// are the user's file, `entry` the lines of the entry's "call" or "body" (Mesa does not keep
// #line's source numbers on every message, so lines are mapped by position).
std::string translateLog(const std::string& log, const std::string& file, int first, int count,
                         const EntryLines& entry, const std::vector<GlslSpec::LineOrigin>& origins,
                         const std::vector<std::string>& declared) {
    std::istringstream in(log);
    std::ostringstream out;
    std::string line;
    bool aboutCall = false;
    while (std::getline(in, line)) {
        std::string ln, col;
        size_t i = 0;
        if (!driverLine(line, ln, col, i)) {
            if (!line.empty()) out << line << "\n";
            continue;
        }
        int n = std::stoi(ln);
        const bool call = entry.call > 0 && n >= entry.call - 1 && n <= entry.call + 1;
        if (call) {  // no line: the call's own
            out << file << ": call: " << line.substr(i) << "\n";
            aboutCall = true;
            continue;
        }
        if (entry.bodyCount > 0 && n >= entry.bodyFirst && n <= entry.bodyFirst + entry.bodyCount) {
            out << file << ": body:" << (n - entry.bodyFirst + 1) << ": " << line.substr(i) << "\n";
            continue;
        }
        std::string where = n <= first ? "pgt prelude" : n <= first + count ? file : "pgt wrapper";
        if (where == "pgt wrapper" && line.find("warning") != std::string::npos)
            continue;      // e.g. an uninitialised result after a call that did not compile
        std::string note;  // what the file's own #line said of the line
        if (n > first && n <= first + count) {
            n -= first;
            if (size_t(n) <= declared.size() && !declared[size_t(n) - 1].empty())
                note = " (its #line: " + declared[size_t(n) - 1] + ")";
            if (size_t(n) <= origins.size()) {  // a line of an #included file
                where = origins[size_t(n) - 1].file;
                n = origins[size_t(n) - 1].line;
            }
        }
        out << where << ":" << n << (col.empty() ? "" : ":" + col) << note << ": " << line.substr(i)
            << "\n";
    }
    if (aboutCall)
        out << file
            << ": call: it must give uv' as a vec2, from uv, V, N, s, b and the "
               "shader's own names\n";
    return out.str();
}

// A shader's or program's info log (glGet{Shader,Program}iv + ...InfoLog).
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
    GLint len = 0;
    getIv(object, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    getLog(object, len, nullptr, log.data());
    return log.c_str();  // up to the terminating NUL
}

// Deletes the shader or program and throws InputError with its info log, mapped to the
// user's file, unless `status` (compile or link) succeeded.
template <class GetIv, class GetLog, class Delete>
void requireStatus(GLuint object, GLenum status, GetIv getIv, GetLog getLog, Delete remove,
                   const std::string& file, const std::string& field, const char* verb,
                   int userFirst, int userCount, const EntryLines& entry,
                   const std::vector<GlslSpec::LineOrigin>& origins,
                   const std::vector<std::string>& declared) {
    GLint ok = 0;
    getIv(object, status, &ok);
    if (ok) return;
    std::string log = infoLog(object, getIv, getLog);
    remove(object);
    throw InputError(file, field, "",
                     std::string("the shader does not ") + verb + ":\n" +
                         translateLog(log, file, userFirst, userCount, entry, origins, declared));
}

// `userFirst`, `userCount`: where the user's file sits in `src` (for the messages).
GLuint compile(GLenum type, const std::string& src, const std::string& file, int userFirst = 0,
               int userCount = 1 << 30, const EntryLines& entry = {},
               const std::vector<GlslSpec::LineOrigin>& origins = {},
               const std::vector<std::string>& declared = {}, const std::string& field = "glsl") {
    GLuint s = glCreateShader(type);
    const char* p = src.c_str();
    glShaderSource(s, 1, &p, nullptr);
    glCompileShader(s);
    requireStatus(s, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader, file,
                  field, "compile", userFirst, userCount, entry, origins, declared);
    return s;
}

// A desktop dialect newer than the context's GLSL is refused (ES dialects run in 4.50 core,
// which holds ES 3.20's functions).
void checkDialect(const GlslSpec& spec) {
    if (spec.isEs()) return;
    const GlInfo& gl = contextInfo();  // programFor runs on the GL thread, after ensureContext()
    if (gl.glslVersion > 0 && std::stoi(spec.version) > gl.glslVersion)
        throw InputError(spec.path, "version", spec.version,
                         "this OpenGL (" + gl.renderer + ") compiles GLSL up to " +
                             std::to_string(gl.glslVersion / 100) + "." +
                             std::to_string(gl.glslVersion % 100));
}

// Whether a GLSL source declares `name` as a uniform sampler2D.
bool declaresSampler(const std::string& src, const std::string& name) {
    return declaresGlobal(src, name, {"sampler2D"});
}

// The wrapper's parts around kMain: the prelude (pgt's counting functions, the legacy names,
// the samplers the source leaves to pgt, the entry's #defines), the user's text (HLSL:
// SPIRV-Cross's GLSL of it), and the glue that calls it.
struct Pieces {
    std::string prelude, user, glue, function;
    EntryLines entry;  // counted from the glue's first line
};

// "body": the entry's statements in a function with the names docs/methods.md lists (uv, V,
// N, s, b); "call": the same function returning the expression, which stands on a line of its
// own (a message on it or on the lines around it names the call).
constexpr const char* kBodyHead = R"(uniform float pgt_s;
uniform float pgt_b;
vec2 pgt_call(vec2 uv, vec3 V) {
    const vec3 N = vec3(0.0, 0.0, 1.0);
    float s = pgt_s;
    float b = pgt_b;
)";
const std::string kCallHead = std::string(kBodyHead) + "    vec2 pgt_r =\n";
constexpr const char* kCallTail = R"(
    ;
    return pgt_r;
}
)";

// "api": "gl": the framebuffer's y runs up, as in OpenGL and WebGL; pgt draws with y down
// (the image's rows), so a shader's y derivatives are turned round.
constexpr const char* kGlY = R"(#define dFdy(p) (-(dFdy(p)))
#define dFdyFine(p) (-(dFdyFine(p)))
#define dFdyCoarse(p) (-(dFdyCoarse(p)))
)";

// An engine vertex stage's outputs, one layer each of a float image array (unit 13), set into
// the fragment code's inputs before the call; "" without a vertex stage.
std::string varyingsGlue(const GlslSpec& spec) {
    const GlslSpec::VertexStage* v = spec.vertexStage();
    if (!v) return "";
    std::string glue = "uniform sampler2DArray pgt_varyings;\nvoid pgt_set_varyings(ivec2 p) {\n";
    const char* swizzle[5] = {"", ".x", ".xy", ".xyz", ""};
    int layer = 0;  // a matrix's columns are a layer each
    for (const GlslSpec::VertexStage::Link& l : v->links) {
        std::string value;
        for (int c = 0; c < l.columns; ++c, ++layer)
            value += std::string(c ? ", " : "") + "texelFetch(pgt_varyings, ivec3(p, " +
                     std::to_string(layer) + "), 0)" + swizzle[l.components];
        glue += "    " + l.input + " = " +
                (l.columns > 1 ? "mat" + std::to_string(l.columns) + "(" + value + ")" : value) +
                ";\n";
    }
    return glue + "}\n#define PGT_VARYINGS 1\n";
}

Pieces wrapperPieces(const GlslSpec& spec) {
    Pieces p;
    p.prelude = preludeText() + (spec.legacyTextureNames() ? kLegacyNames : "") +
                (spec.api == GlslSpec::Api::Gl ? kGlY : "");
    if (spec.hlsl) {  // defines and samplers are the HLSL compiler's
        if (spec.engineInputs) p.prelude += "#define PGT_ENGINE_INPUTS 1\n";
        p.user = hlslToGlsl(spec);
        p.glue = varyingsGlue(spec);
        p.function = kHlslCall;
        return p;
    }
    if (spec.engineInputs) p.prelude += kEngineGlobals;
    for (const std::string& name : spec.samplers)
        if (!name.empty() && isShaderIdentifier(name) && !declaresSampler(spec.source, name))
            p.prelude += "uniform sampler2D " + name + ";  // declared by pgt\n";
    for (const auto& [name, value] : spec.defines)
        p.prelude += "#define " + name + " " + value + "\n";
    p.user = vulkanGlslForGl(spec.source);  // Vulkan-style layouts, stage variables, blocks
    const std::vector<std::string> mains = functionTypes(spec.source, "main");
    if (std::find(mains.begin(), mains.end(), "void") != mains.end()) {
        p.prelude += kOwnMain;
        p.glue = kOwnMainEnd;
    }
    p.glue += varyingsGlue(spec);
    p.function = spec.function;
    if (!spec.call.empty()) {
        p.entry.call = countLines(p.glue + kCallHead) + 1;
        p.glue += kCallHead + spec.call + kCallTail;
        p.function = "pgt_call";
    }
    if (!spec.body.empty()) {
        // The body in a scope of its own: its locals may take the names pgt gives it (an
        // engine's `vec3 N = ...`, `vec3 V = normalize(V)`), which a redeclaration in the
        // function's own scope would refuse.
        const std::string head = std::string(kBodyHead) + "    {\n";
        p.entry.bodyFirst = countLines(p.glue + head) + 1;
        p.glue += head + spec.body + "    }\n    return uv;  // not reached: the body returns\n}\n";
        p.entry.bodyCount = countLines(spec.body);
        p.function = "pgt_call";
    }
    return p;
}

// An active uniform's value as the program was linked (its initialiser, else zero).
struct UniformDefault {
    GLint location = -1;
    GLenum type = 0;
    std::vector<GLfloat> f;  // float, vector and matrix types
    std::vector<GLint> i;    // int, bool and sampler types
    std::vector<GLuint> u;   // unsigned types
};

// A type's components and how they are read and set: 'f' float, 'i' int, bool or opaque (a
// sampler's unit), 'u' unsigned; matrices are floats set with glUniformMatrix*.
struct UniformType {
    char kind = 'i';
    int components = 1;
    int matrix = 0;  // 2, 3, 4: a square float matrix
};
// GL's uniform types, one row each; any other type (samplers, images) is a unit: 'i', 1.
struct UniformTypeRow {
    GLenum type;
    UniformType shape;
};
constexpr UniformTypeRow kUniformTypes[] = {{GL_FLOAT, {'f', 1}},
                                            {GL_FLOAT_VEC2, {'f', 2}},
                                            {GL_FLOAT_VEC3, {'f', 3}},
                                            {GL_FLOAT_VEC4, {'f', 4}},
                                            {GL_FLOAT_MAT2, {'f', 4, 2}},
                                            {GL_FLOAT_MAT3, {'f', 9, 3}},
                                            {GL_FLOAT_MAT4, {'f', 16, 4}},
                                            {GL_INT, {'i', 1}},
                                            {GL_BOOL, {'i', 1}},
                                            {GL_INT_VEC2, {'i', 2}},
                                            {GL_BOOL_VEC2, {'i', 2}},
                                            {GL_INT_VEC3, {'i', 3}},
                                            {GL_BOOL_VEC3, {'i', 3}},
                                            {GL_INT_VEC4, {'i', 4}},
                                            {GL_BOOL_VEC4, {'i', 4}},
                                            {GL_UNSIGNED_INT, {'u', 1}},
                                            {GL_UNSIGNED_INT_VEC2, {'u', 2}},
                                            {GL_UNSIGNED_INT_VEC3, {'u', 3}},
                                            {GL_UNSIGNED_INT_VEC4, {'u', 4}}};
UniformType uniformType(GLenum type) {
    for (const UniformTypeRow& r : kUniformTypes)
        if (r.type == type) return r.shape;
    return {'i', 1};
}

// Every active uniform's linked value, element by element (block members have no location
// and are left out: pgt sets none of them).
std::vector<UniformDefault> linkedValues(GLuint prog) {
    std::vector<UniformDefault> out;
    GLint count = 0, maxLen = 0;
    glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
    glGetProgramiv(prog, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxLen);
    std::string buf(size_t(std::max(maxLen, 1)), '\0');
    for (GLint k = 0; k < count; ++k) {
        GLsizei len = 0;
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(prog, GLuint(k), GLsizei(buf.size()), &len, &size, &type, buf.data());
        std::string name(buf.data(), size_t(len));
        if (name.size() > 3 && name.compare(name.size() - 3, 3, "[0]") == 0)
            name.resize(name.size() - 3);
        const UniformType t = uniformType(type);
        for (GLint e = 0; e < size; ++e) {
            const std::string element = size > 1 ? name + "[" + std::to_string(e) + "]" : name;
            UniformDefault d;
            d.location = glGetUniformLocation(prog, element.c_str());
            if (d.location < 0) continue;
            d.type = type;
            if (t.kind == 'f') {
                d.f.resize(size_t(t.components));
                glGetUniformfv(prog, d.location, d.f.data());
            } else if (t.kind == 'u') {
                d.u.resize(size_t(t.components));
                glGetUniformuiv(prog, d.location, d.u.data());
            } else {
                d.i.resize(size_t(t.components));
                glGetUniformiv(prog, d.location, d.i.data());
            }
            out.push_back(std::move(d));
        }
    }
    drainGlErrors();  // a type this table does not know is left as it is
    return out;
}

void setValue(const UniformDefault& d) {
    const UniformType t = uniformType(d.type);
    if (t.matrix == 2) glUniformMatrix2fv(d.location, 1, GL_FALSE, d.f.data());
    if (t.matrix == 3) glUniformMatrix3fv(d.location, 1, GL_FALSE, d.f.data());
    if (t.matrix == 4) glUniformMatrix4fv(d.location, 1, GL_FALSE, d.f.data());
    if (t.matrix) return;
    using SetF = void (*)(GLint, GLsizei, const GLfloat*);
    using SetI = void (*)(GLint, GLsizei, const GLint*);
    using SetU = void (*)(GLint, GLsizei, const GLuint*);
    static const SetF setF[4] = {glUniform1fv, glUniform2fv, glUniform3fv, glUniform4fv};
    static const SetI setI[4] = {glUniform1iv, glUniform2iv, glUniform3iv, glUniform4iv};
    static const SetU setU[4] = {glUniform1uiv, glUniform2uiv, glUniform3uiv, glUniform4uiv};
    const size_t n = size_t(t.components - 1);
    if (t.kind == 'f') setF[n](d.location, 1, d.f.data());
    if (t.kind == 'i') setI[n](d.location, 1, d.i.data());
    if (t.kind == 'u') setU[n](d.location, 1, d.u.data());
}

struct Program {
    GLuint id = 0;
    std::vector<UniformDefault> linked;  // every uniform's value as linked
};

// Programs by their text (the vertex stage's, then the fragment stage's, as compiled): a
// setting that changes what is compiled changes the key, with no list of settings to keep.
// What a draw sets (uniforms, textures, samplers) is set before every draw
// (methods/shader/glsl_method.cpp), so no program carries another method's state.
std::map<std::string, Program> gPrograms;

}  // namespace

GLuint programFor(const GlslSpec& spec) {
    if (!spec.hlsl && spec.call.empty() && spec.body.empty() && !isShaderIdentifier(spec.function))
        throw InputError(spec.path, "function", spec.function, "is not a GLSL identifier");
    checkDialect(spec);
    const Pieces pieces = wrapperPieces(spec);
    const std::string& prelude = pieces.prelude;
    std::vector<std::string> declared;  // the file's own #line numbering, for messages
    const std::string user = userLines(blankLineDirectives(pieces.user, declared));
    const int first = countLines(prelude), count = countLines(user);
    EntryLines entry;  // in the fragment shader
    if (!spec.hlsl) {
        const int glueAt = first + count;
        if (pieces.entry.call) entry.call = glueAt + pieces.entry.call;
        if (pieces.entry.bodyCount)
            entry = {0, glueAt + pieces.entry.bodyFirst, pieces.entry.bodyCount};
    }
    std::string fs =
        prelude + user + pieces.glue + "#define PGT_FUNCTION " + pieces.function + "\n" + kMain;
    std::string key = std::string(kVertex) + '\0' + fs;
    auto it = gPrograms.find(key);
    if (it != gPrograms.end()) return it->second.id;
    checkShaderBounds(fs, spec.path, spec.hlsl ? "hlsl" : "glsl");
    GLuint vs = compile(GL_VERTEX_SHADER, kVertex, "pgt vertex shader");
    const std::vector<GlslSpec::LineOrigin> none;
    const auto& origins = spec.hlsl ? none : spec.origins;
    GLuint f = compile(GL_FRAGMENT_SHADER, fs, spec.path, first, count, entry, origins, declared);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, f);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(f);
    requireStatus(prog, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
                  spec.path, "glsl", "link", first, count, entry, origins, declared);
    gPrograms.emplace(std::move(key), Program{prog, linkedValues(prog)});
    return prog;
}

void restoreLinkedValues(GLuint prog) {
    for (const auto& [key, p] : gPrograms)
        if (p.id == prog) {
            for (const UniformDefault& d : p.linked) setValue(d);
            drainGlErrors();
            return;
        }
}

// A uniform by the name the user knows: GLSL's own; in HLSL a global or cbuffer member, which
// SPIRV-Cross makes a member of a plain uniform struct ("_12.NAME"), found among the active
// uniforms by its member name. -1 where none is active.
GLint uniformLocation(GLuint prog, bool hlsl, const std::string& name) {
    GLint u = glGetUniformLocation(prog, name.c_str());
    if (u >= 0 || !hlsl) return u;
    GLint count = 0, maxLen = 0;
    glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
    glGetProgramiv(prog, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxLen);
    std::string buf(size_t(std::max(maxLen, 1)), '\0');
    const std::string suffix = "." + name;
    for (GLint i = 0; i < count; ++i) {
        GLsizei len = 0;
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(prog, GLuint(i), GLsizei(buf.size()), &len, &size, &type, buf.data());
        const std::string active(buf.data(), size_t(len));
        if (active.size() > suffix.size() &&
            active.compare(active.size() - suffix.size(), suffix.size(), suffix) == 0)
            return glGetUniformLocation(prog, active.c_str());
    }
    return -1;
}

GLuint vertexProgram(const std::string& text, const std::string& file,
                     const std::vector<const char*>& captured, int userFirst,
                     const std::vector<GlslSpec::LineOrigin>& origins) {
    const GLuint vs =
        compile(GL_VERTEX_SHADER, text, file, userFirst, 1 << 30, {}, origins, {}, "vertex");
    const GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glTransformFeedbackVaryings(prog, GLsizei(captured.size()), captured.data(),
                                GL_INTERLEAVED_ATTRIBS);
    glLinkProgram(prog);
    glDeleteShader(vs);
    requireStatus(prog, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram, file,
                  "vertex", "link", userFirst, 1 << 30, {}, origins, {});
    return prog;
}

}  // namespace pgt::gl
