// The engine's vertex stage by transform feedback (methods/shader/vertex_stage.h).
#include "methods/shader/vertex_stage.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "core/error.h"
#include "methods/shader/gl_api.h"
#include "methods/shader/hlsl.h"
#include "methods/shader/program.h"
#include "methods/shader/shader_words.h"

namespace pgt {

glm::vec4 VertexOutputs::at(uint32_t t, const Vec3d& bary, size_t l) const {
    double v[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < 3; ++i) {
        const float* p =
            values.data() + size_t(indices[3 * size_t(t) + i]) * size_t(stride) + size_t(offset[l]);
        for (int c = 0; c < components[l]; ++c) v[c] += bary[int(i)] * double(p[c]);
    }
    return {float(v[0]), float(v[1]), float(v[2]), float(v[3])};
}

namespace {

using namespace gl;

// Programs by their text and captured outputs (the vertex stage's of each method).
std::map<std::string, GLuint> gVertexPrograms;

GLuint programOf(const GlslSpec& spec, const GlslSpec::VertexStage& v) {
    // The entry's defines after the #version line, then the file's lines (messages map them).
    // (HLSL: its translation, made when the scene was parsed, whole.)
    std::string text = v.hlsl ? "" : "#version 450 core\n";
    for (const auto& [name, value] : spec.defines)
        if (!v.hlsl) text += "#define " + name + " " + value + "\n";
    const int first = v.hlsl ? 0 : 1 + int(spec.defines.size());
    text += v.hlsl ? v.glsl : userLines(vulkanGlslForGl(v.source, true));
    std::vector<const char*> captured;
    std::string key = text;
    for (const auto& l : v.links) captured.push_back(l.output.c_str()), key += '\0' + l.output;
    auto it = gVertexPrograms.find(key);
    if (it == gVertexPrograms.end())
        it = gVertexPrograms.emplace(key, vertexProgram(text, v.path, captured, first, v.origins))
                 .first;
    return it->second;
}

// A GL buffer of `values` as attribute `location` (`n` floats a vertex).
GLuint attributeBuffer(GLint location, const float* values, size_t count, int n) {
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_ARRAY_BUFFER, b);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(count * size_t(n) * sizeof(float)), values,
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(GLuint(location));
    glVertexAttribPointer(GLuint(location), n, GL_FLOAT, GL_FALSE, 0, nullptr);
    return b;
}

// pgt's vertex data "attributes" binds, by name: its floats and their count per vertex. The
// one list of the names (vertexAttributeNames: what the scene parser lets through).
struct AttributeRow {
    const char* name;
    std::pair<const float*, int> (*data)(const VertexStageInputs&);
};
constexpr AttributeRow kAttributes[] = {
    {"position",
     [](const VertexStageInputs& in) {
         return std::pair{&in.position[0].x, 3};
     }},
    {"normal",
     [](const VertexStageInputs& in) {
         return std::pair{&in.normal[0].x, 3};
     }},
    {"tangent",
     [](const VertexStageInputs& in) {
         return std::pair{&in.tangent[0].x, 4};
     }},
    {"bitangent",
     [](const VertexStageInputs& in) {
         return std::pair{&in.bitangent[0].x, 3};
     }},
    {"uv",
     [](const VertexStageInputs& in) {
         return std::pair{&in.uv[0].x, 2};
     }},
};

// The values "matrices" binds, by name (model and normal_matrix the identity: pgt's mesh is in
// world space); camera_position, a vector, has none here (setMatrix sets it).
struct MatrixRow {
    const char* name;
    glm::mat4 (*value)(const VertexStageInputs&);
};
constexpr MatrixRow kMatrices[] = {
    {"model", [](const VertexStageInputs&) { return glm::mat4(1); }},
    {"view", [](const VertexStageInputs& in) { return in.view; }},
    {"projection", [](const VertexStageInputs& in) { return in.projection; }},
    {"model_view", [](const VertexStageInputs& in) { return in.view; }},
    {"view_projection", [](const VertexStageInputs& in) { return in.projection * in.view; }},
    {"model_view_projection", [](const VertexStageInputs& in) { return in.projection * in.view; }},
    {"normal_matrix", [](const VertexStageInputs&) { return glm::mat4(1); }},
    {"camera_position", nullptr},
};

template <class Row, size_t N>
const Row& rowNamed(const Row (&rows)[N], const std::string& name) {
    for (const Row& r : rows)
        if (name == r.name) return r;
    PGT_CHECK(false && "a name the scene parser let through");
    return rows[0];
}

// Sets a "matrices" uniform: a matrix as mat4 (or its upper 3x3 as mat3), the eye as vec3 or
// vec4 (w 1).
void setMatrix(GLuint prog, const GlslSpec::VertexStage& v, const std::string& name,
               const std::string& what, const VertexStageInputs& in) {
    const GLint u = uniformLocation(prog, v.hlsl, name);
    if (u < 0)
        throw InputError(v.path, "matrices." + name, what,
                         "is not an active uniform of the vertex shader (misspelt, or unused)");
    drainGlErrors();
    const MatrixRow& row = rowNamed(kMatrices, what);
    if (!row.value) {  // camera_position
        glUniform3f(u, in.camera.x, in.camera.y, in.camera.z);
        if (glGetError() != GL_NO_ERROR) glUniform4f(u, in.camera.x, in.camera.y, in.camera.z, 1);
    } else {
        const glm::mat4 m = row.value(in);
        // M v as GLSL's M * v and HLSL's mul(M, v) compute it (glslang makes mul(M, v) the
        // GLSL v * M, so HLSL's matrices go transposed), or v M for "vectors": "row".
        const GLboolean transpose = v.hlsl != v.rowVectors ? GL_TRUE : GL_FALSE;
        glUniformMatrix4fv(u, 1, transpose, &m[0][0]);
        if (glGetError() != GL_NO_ERROR) {
            const glm::mat3 m3(m);
            glUniformMatrix3fv(u, 1, transpose, &m3[0][0]);
        }
    }
    if (glGetError() != GL_NO_ERROR)
        throw InputError(v.path, "matrices." + name, what,
                         "does not match the uniform's type (a mat4 or mat3; the camera a vec3 "
                         "or vec4)");
}

// The entry's "uniforms" the vertex shader has (the fragment stage sets its own); one active in
// neither stage is misspelt.
void setUniforms(GLuint prog, const GlslSpec& spec, double scale, double bias) {
    for (const GlslSpec::Uniform& un : spec.uniforms) {
        const GLint u = uniformLocation(prog, spec.hlsl, un.name);
        if (u < 0) {
            if (uniformLocation(programFor(spec), spec.hlsl, un.name) < 0)
                throw InputError(spec.path, "uniforms." + un.name, "",
                                 "is an active uniform of neither the vertex shader " +
                                     spec.vertexStage()->path + " nor the fragment code");
            continue;
        }
        std::vector<float> f = un.at(scale, bias);
        drainGlErrors();
        if (f.size() == 1 && un.bind.empty() && un.values[0] == std::floor(un.values[0])) {
            glUniform1i(u, int(un.values[0]));
            if (glGetError() != GL_NO_ERROR) glUniform1f(u, f[0]);
        } else {
            void (*set[4])(GLint, GLsizei, const GLfloat*) = {glUniform1fv, glUniform2fv,
                                                              glUniform3fv, glUniform4fv};
            set[std::min<size_t>(f.size(), 4) - 1](u, 1, f.data());
        }
        if (glGetError() != GL_NO_ERROR)
            throw InputError(spec.path, "uniforms." + un.name, "",
                             "does not match the uniform's type in the vertex shader");
    }
}

// One point per vertex, the rasteriser off, the links' outputs captured.
std::vector<float> capture(GLuint prog, const GlslSpec::VertexStage& v, const VertexStageInputs& in,
                           int stride) {
    const size_t n = in.position.size();
    GLuint vao = 0, out = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    std::vector<GLuint> buffers;
    for (const auto& [name, what] : v.attributes) {
        // (HLSL: by semantic, as its translation names the input.)
        const GLint loc = glGetAttribLocation(
            prog, (v.hlsl ? gl::hlslStageName(true, gl::semanticKey(name)) : name).c_str());
        if (loc < 0)
            throw InputError(v.path, "attributes." + name, what,
                             "is not an active attribute of the vertex shader");
        const auto [data, size] = rowNamed(kAttributes, what).data(in);
        buffers.push_back(attributeBuffer(loc, data, n, size));
    }
    std::vector<float> values(n * size_t(stride));
    glGenBuffers(1, &out);
    glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, out);
    glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(values.size() * sizeof(float)), nullptr,
                 GL_STATIC_READ);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, out);
    // A draw needs a complete framebuffer, discarded or not (a headless context has none).
    GLuint fbo = 0;
    const GLuint target = makeTexture(GL_R32F, GL_RED, 1, 1, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    glEnable(GL_RASTERIZER_DISCARD);
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, GLsizei(n));
    glEndTransformFeedback();
    glDisable(GL_RASTERIZER_DISCARD);
    glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(values.size() * sizeof(float)),
                       values.data());
    checkGl("the vertex stage of " + v.path);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &target);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    glDeleteBuffers(1, &out);
    glDeleteBuffers(GLsizei(buffers.size()), buffers.data());
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    return values;
}

}  // namespace

VertexOutputs runVertexStage(const GlslSpec& spec, const VertexStageInputs& in, double scale,
                             double bias) {
    const GlslSpec::VertexStage* v = spec.vertexStage();
    PGT_CHECK(v && !in.position.empty());
    VertexOutputs o;
    for (const auto& l : v->links) {
        for (int c = 0; c < l.columns; ++c) {  // a matrix's columns one after another
            o.offset.push_back(o.stride);
            o.components.push_back(l.components);
            o.stride += l.components;
        }
    }
    o.indices = in.indices;
    if (v->links.empty()) return o;  // the fragment code reads none of its outputs
    onGlThread([&] {
        std::lock_guard<std::mutex> lock(gMutex);
        ensureContext();
        drainGlErrors();
        const GLuint prog = programOf(spec, *v);
        glUseProgram(prog);
        for (const auto& [name, what] : v->matrices) setMatrix(prog, *v, name, what, in);
        setUniforms(prog, spec, scale, bias);
        o.values = capture(prog, *v, in, o.stride);
    });
    return o;
}

const std::vector<std::string>& vertexAttributeNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const AttributeRow& r : kAttributes) out.push_back(r.name);
        return out;
    }();
    return names;
}

const std::vector<std::string>& vertexMatrixNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const MatrixRow& r : kMatrices) out.push_back(r.name);
        return out;
    }();
    return names;
}

}  // namespace pgt
