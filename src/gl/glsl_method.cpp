// A GLSL method's run over a fragment list: the inputs uploaded as textures, the maps bound,
// the draw (timed when asked) and the outputs read back.
#include "gl/glsl_method.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <stdexcept>

#include "core/error.h"
#include "gl/gl_api.h"
#include "gl/program.h"

namespace pgt {

using namespace gl;

namespace {

GLuint gVao = 0;

GLuint makeTexture(GLenum internal, GLenum format, int w, int h, const void* data, GLenum filter,
                   GLenum wrap) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, GL_FLOAT, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GLint(wrap));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GLint(wrap));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    return t;
}

// Map textures (height or depth R32F, 003's RGB normal map, the parallax map): one upload per
// content (keyed by a hash of the texels, never by address), bilinear, the map's address mode
// (MODEL.md §1: texel centres at (i + 0.5) / W, as GL samples).
std::map<std::tuple<uint64_t, int, int, int, bool, int>, GLuint> gMaps;

GLuint mapTexture(const Texture& t, bool depth) {
    uint64_t hash = 1469598103934665603ull;  // FNV-1a over the texel bits
    for (float x : t.texels) {
        uint32_t bits;
        std::memcpy(&bits, &x, 4);
        hash = (hash ^ bits) * 1099511628211ull;
    }
    auto key = std::make_tuple(hash, t.width, t.height, t.channels, depth, int(t.address));
    auto it = gMaps.find(key);
    if (it != gMaps.end()) return it->second;
    const int c = t.channels >= 3 ? 3 : 1;
    std::vector<float> data(size_t(t.width) * t.height * size_t(c));
    for (size_t k = 0; k < size_t(t.width) * t.height; ++k)
        for (int ch = 0; ch < c; ++ch) {
            float h = t.texels[k * size_t(t.channels) + size_t(ch)];
            data[k * size_t(c) + size_t(ch)] = depth ? 1.0f - h : h;
        }
    GLuint id = makeTexture(c == 3 ? GL_RGB32F : GL_R32F, c == 3 ? GL_RGB : GL_RED, t.width,
                            t.height, data.data(), GL_LINEAR,
                            t.address == Address::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    gMaps[key] = id;
    return id;
}

// A map the GL cannot hold is bad input, named before any upload, not a GL error that a
// later call would report.
void checkMapFits(const GlslSpec& spec, const std::string& field, const std::string& name,
                  const Texture* t) {
    if (name.empty() || !t) return;
    const int maxSide = maxTextureSide();
    if (t->width > maxSide || t->height > maxSide)
        throw InputError(spec.path, field, name,
                         "the map it samples is " + std::to_string(t->width) + "x" +
                             std::to_string(t->height) +
                             " texels, more than this GL's "
                             "GL_MAX_TEXTURE_SIZE " +
                             std::to_string(maxSide) + " (" + contextInfo().renderer +
                             "); use a smaller height map or no GLSL method");
}

void bindSampler(GLuint prog, const GlslSpec& spec, const std::string& field,
                 const std::string& name, int unit, const Texture* t, bool depth) {
    if (name.empty()) return;
    GLint loc = glGetUniformLocation(prog, name.c_str());
    if (loc < 0)
        throw InputError(spec.path, field, name,
                         "is not an active sampler2D uniform of the shader (declare it and "
                         "sample it in " +
                             spec.function + ")");
    PGT_CHECK(t != nullptr);
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, mapTexture(*t, depth));
    glUniform1i(loc, unit);
    checkGl("uploading the map of " + field + " " + name);
}

// One draw over at most kChunkFragments fragments (runGlsl splits longer lists).
GlslRun runGlslChunk(const GlslSpec& spec, const Texture& height, const Texture* normal,
                     const Texture* parallax, double scale, double bias,
                     const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view,
                     int timingRepeats) {
    GlslRun run;
    const int n = int(uv0.size());
    if (n == 0) return run;
    GLuint prog = programFor(spec);
    glUseProgram(prog);
    if (!gVao) glGenVertexArrays(1, &gVao);
    glBindVertexArray(gVao);

    // Fragment k at texel (k % w, k / w) of the input and output images.
    const int w = std::min(n, 2048), h = (n + w - 1) / w;
    std::vector<float> uvData(size_t(w) * h * 2, 0.0f), viewData(size_t(w) * h * 4, 0.0f);
    for (int k = 0; k < n; ++k) {
        uvData[2 * size_t(k)] = uv0[size_t(k)].x;
        uvData[2 * size_t(k) + 1] = uv0[size_t(k)].y;
        viewData[4 * size_t(k)] = view[size_t(k)].x;
        viewData[4 * size_t(k) + 1] = view[size_t(k)].y;
        viewData[4 * size_t(k) + 2] = view[size_t(k)].z;
    }
    GLuint uvTex = makeTexture(GL_RG32F, GL_RG, w, h, uvData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint viewTex =
        makeTexture(GL_RGBA32F, GL_RGBA, w, h, viewData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint outUv = makeTexture(GL_RG32F, GL_RG, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint outFetch = makeTexture(GL_R32F, GL_RED, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, outUv, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, outFetch, 0);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    PGT_CHECK(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);

    // Units: 0 = the height/depth map, 1 = uv0, 2 = V, 3 = normal map, 4 = parallax map.
    bindSampler(prog, spec, "sampler", spec.sampler, 0, &height, spec.depthTexture);
    bindSampler(prog, spec, "normal_sampler", spec.normalSampler, 3, normal, false);
    bindSampler(prog, spec, "parallax_sampler", spec.parallaxSampler, 4, parallax, false);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, uvTex);
    glUniform1i(glGetUniformLocation(prog, "pgt_uv0"), 1);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, viewTex);
    glUniform1i(glGetUniformLocation(prog, "pgt_view"), 2);
    glUniform1i(glGetUniformLocation(prog, "pgt_count"), n);
    glUniform1i(glGetUniformLocation(prog, "pgt_width"), w);
    for (const GlslSpec::Uniform& un : spec.uniforms) {
        GLint u = glGetUniformLocation(prog, un.name.c_str());
        if (u < 0)
            throw InputError(spec.path, "uniforms." + un.name, "",
                             "is not an active uniform of the shader (misspelt, or unused by " +
                                 spec.function + ")");
        std::vector<float> f(un.values.begin(), un.values.end());
        drainGlErrors();  // only this uniform's own error may be blamed on it
        if (un.bind == "scale") f = {float(scale)};
        if (un.bind == "bias") f = {float(bias)};
        if (un.isInt)
            glUniform1i(u, int(un.values[0]));
        else if (f.size() == 1)
            glUniform1f(u, f[0]);
        else if (f.size() == 2)
            glUniform2f(u, f[0], f[1]);
        else if (f.size() == 3)
            glUniform3f(u, f[0], f[1], f[2]);
        else
            glUniform4f(u, f[0], f[1], f[2], f[3]);
        if (glGetError() != GL_NO_ERROR)
            throw InputError(spec.path, "uniforms." + un.name, "",
                             "does not match the uniform's type in the shader");
    }
    glViewport(0, 0, w, h);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    const float clear[4] = {NAN, NAN, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    glClearBufferfv(GL_COLOR, 1, clear + 2);
    // The draw, `timingRepeats` times when timed (each between two glFinish and inside a
    // GL_TIME_ELAPSED query; every draw writes the same outputs), once otherwise.
    GLuint query = 0;
    if (timingRepeats > 0) glGenQueries(1, &query);
    std::vector<double> gpuNs, wallNs;
    for (int r = 0; r < std::max(1, timingRepeats); ++r) {
        if (query) glFinish();
        auto t0 = std::chrono::steady_clock::now();
        if (query) glBeginQuery(GL_TIME_ELAPSED, query);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (!query) break;
        glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        wallNs.push_back(
            std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0)
                .count() /
            n);
        GLuint64 t = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &t);
        gpuNs.push_back(double(t) / n);
    }
    if (query) {
        glDeleteQueries(1, &query);
        std::sort(gpuNs.begin(), gpuNs.end());
        std::sort(wallNs.begin(), wallNs.end());
        run.gpuNsPerPixel = gpuNs[gpuNs.size() / 2];
        run.wallNsPerPixel = wallNs[wallNs.size() / 2];
    }
    checkGl("the draw of " + spec.path);

    std::vector<float> outUvData(size_t(w) * h * 2), outFetchData(size_t(w) * h);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RG, GL_FLOAT, outUvData.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, outFetchData.data());
    checkGl("reading back " + spec.path);
    run.uv.resize(size_t(n));
    run.fetches.resize(size_t(n));
    for (int k = 0; k < n; ++k) {
        run.uv[size_t(k)] = Vec2f(outUvData[2 * size_t(k)], outUvData[2 * size_t(k) + 1]);
        run.fetches[size_t(k)] = uint32_t(std::max(0.0f, outFetchData[size_t(k)]));
    }

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    GLuint textures[4] = {uvTex, viewTex, outUv, outFetch};
    glDeleteTextures(4, textures);
    checkGl("cleaning up after " + spec.path);
    return run;
}

// Fragments per draw: the input and output images are 2048 wide, so this keeps them at most
// 2048 x 4096, within the 8192-texel minimum that GL 4.3 guarantees for GL_MAX_TEXTURE_SIZE.
constexpr size_t kChunkFragments = size_t(2048) * 4096;

}  // namespace

GlslRun runGlsl(const GlslSpec& spec, const Texture& height, const Texture* normal,
                const Texture* parallax, double scale, double bias, const std::vector<Vec2f>& uv0,
                const std::vector<Vec3f>& view, int timingRepeats) {
    PGT_CHECK_EQ(uv0.size(), view.size());
    std::lock_guard<std::mutex> lock(gMutex);
    ensureContext();
    drainGlErrors();
    checkMapFits(spec, "sampler", spec.sampler, &height);
    checkMapFits(spec, "normal_sampler", spec.normalSampler, normal);
    checkMapFits(spec, "parallax_sampler", spec.parallaxSampler, parallax);
    if (uv0.size() <= kChunkFragments)
        return runGlslChunk(spec, height, normal, parallax, scale, bias, uv0, view, timingRepeats);
    GlslRun run;  // a long list: draw by chunks; times are the fragment-weighted mean
    for (size_t first = 0; first < uv0.size(); first += kChunkFragments) {
        size_t last = std::min(uv0.size(), first + kChunkFragments);
        std::vector<Vec2f> u(uv0.begin() + long(first), uv0.begin() + long(last));
        std::vector<Vec3f> v(view.begin() + long(first), view.begin() + long(last));
        GlslRun part =
            runGlslChunk(spec, height, normal, parallax, scale, bias, u, v, timingRepeats);
        double weight = double(last - first) / double(uv0.size());
        run.gpuNsPerPixel += part.gpuNsPerPixel * weight;
        run.wallNsPerPixel += part.wallNsPerPixel * weight;
        run.uv.insert(run.uv.end(), part.uv.begin(), part.uv.end());
        run.fetches.insert(run.fetches.end(), part.fetches.begin(), part.fetches.end());
    }
    return run;
}

}  // namespace pgt
