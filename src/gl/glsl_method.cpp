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

// A map as a texture: R32F (height, or depth d = 1 - h) or RGB32F (003's normal map),
// bilinear, the map's address mode (MODEL.md §1: texel centres at (i + 0.5) / W, as GL
// samples).
GLuint uploadMap(const Texture& t, bool depth) {
    const int c = t.channels >= 3 ? 3 : 1;
    std::vector<float> data(size_t(t.width) * t.height * size_t(c));
    for (size_t k = 0; k < size_t(t.width) * t.height; ++k)
        for (int ch = 0; ch < c; ++ch) {
            float h = t.texels[k * size_t(t.channels) + size_t(ch)];
            data[k * size_t(c) + size_t(ch)] = depth ? 1.0f - h : h;
        }
    return makeTexture(c == 3 ? GL_RGB32F : GL_R32F, c == 3 ? GL_RGB : GL_RED, t.width, t.height,
                       data.data(), GL_LINEAR,
                       t.address == Address::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
}

// Map textures alive in the process, over every GlMapUploads (for tests).
size_t gLiveMaps = 0;

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
                 const std::string& name, int unit, const Texture* t, bool depth,
                 GlMapUploads& maps) {
    if (name.empty()) return;
    GLint loc = glGetUniformLocation(prog, name.c_str());
    if (loc < 0)
        throw InputError(spec.path, field, name,
                         "is not an active sampler2D uniform of the shader (declare it and "
                         "sample it in " +
                             spec.function + ")");
    PGT_CHECK(t != nullptr);
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, maps.texture(*t, depth));
    glUniform1i(loc, unit);
    checkGl("uploading the map of " + field + " " + name);
}

}  // namespace

unsigned GlMapUploads::texture(const Texture& map, bool depth) {
    auto key = std::make_pair(&map, depth);
    auto it = ids_.find(key);
    if (it != ids_.end()) return it->second;
    GLuint id = uploadMap(map, depth);
    ids_[key] = id;
    ++gLiveMaps;
    return id;
}

// The pyramid's levels stacked in one RG32F image as wide as level 0: (lo, hi) per node.
GLuint uploadPyramid(const MinMaxPyramid& p) {
    int rows = 0;
    for (const auto& l : p.levels) rows += l.h;
    const int w = p.levels[0].w;
    std::vector<float> data(size_t(w) * rows * 2, 0.0f);
    int row = 0;
    for (const auto& l : p.levels) {
        for (int j = 0; j < l.h; ++j)
            for (int i = 0; i < l.w; ++i) {
                const size_t at = (size_t(row + j) * w + i) * 2, from = size_t(j) * l.w + i;
                data[at] = l.lo[from];
                data[at + 1] = l.hi[from];
            }
        row += l.h;
    }
    return makeTexture(GL_RG32F, GL_RG, w, rows, data.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
}

unsigned GlMapUploads::pyramid(const MinMaxPyramid& p) {
    auto it = precomputed_.find(&p);
    if (it != precomputed_.end()) return it->second;
    GLuint id = uploadPyramid(p);
    precomputed_[&p] = id;
    ++gLiveMaps;
    return id;
}

unsigned GlMapUploads::cone(const ConeMap& m) {
    auto it = precomputed_.find(&m);
    if (it != precomputed_.end()) return it->second;
    GLuint id = makeTexture(GL_R32F, GL_RED, m.cellsX, m.cellsY, m.ratio.data(), GL_NEAREST,
                            GL_CLAMP_TO_EDGE);
    precomputed_[&m] = id;
    ++gLiveMaps;
    return id;
}

GlMapUploads::~GlMapUploads() {
    if (ids_.empty() && precomputed_.empty()) return;
    try {
        onGlThread([this] {
            std::lock_guard<std::mutex> lock(gMutex);
            ensureContext();
            for (const auto& [key, id] : ids_) {
                GLuint t = id;
                glDeleteTextures(1, &t);
                --gLiveMaps;
            }
            for (const auto& [key, id] : precomputed_) {
                GLuint t = id;
                glDeleteTextures(1, &t);
                --gLiveMaps;
            }
        });
    } catch (const std::exception&) {
        // No context any more: the textures went with it.
    }
}

size_t GlMapUploads::liveTextures() { return gLiveMaps; }

namespace {

// What a draw samples besides its fragments: the maps (uploaded through `uploads`) and the
// case's (s, b) for uniforms bound to them.
struct DrawMaps {
    const Texture& height;
    const Texture* normal;
    const Texture* parallax;
    double scale, bias;
    GlMapUploads& uploads;
    const MinMaxPyramid* pyramid;
    const ConeMap* cone;
    const ConeMap* relaxedCone;
};

// A chunk's fragments as two input images and its two outputs: fragment k at texel
// (k % w, k / w); deleted with this object.
struct FragmentImages {
    int n = 0, w = 0, h = 0;
    GLuint uv0 = 0, view = 0, outUv = 0, outFetches = 0, fbo = 0;

    FragmentImages(const std::vector<Vec2f>& uvs, const std::vector<Vec3f>& views)
        : n(int(uvs.size())), w(std::min(n, 2048)), h((n + w - 1) / w) {
        std::vector<float> uvData(size_t(w) * h * 2, 0.0f), viewData(size_t(w) * h * 4, 0.0f);
        for (size_t k = 0; k < uvs.size(); ++k) {
            uvData[2 * k] = uvs[k].x, uvData[2 * k + 1] = uvs[k].y;
            viewData[4 * k] = views[k].x, viewData[4 * k + 1] = views[k].y;
            viewData[4 * k + 2] = views[k].z;
        }
        uv0 = makeTexture(GL_RG32F, GL_RG, w, h, uvData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
        view =
            makeTexture(GL_RGBA32F, GL_RGBA, w, h, viewData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
        outUv = makeTexture(GL_RG32F, GL_RG, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
        outFetches = makeTexture(GL_R32F, GL_RED, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, outUv, 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, outFetches, 0);
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glDrawBuffers(2, bufs);
        PGT_CHECK(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    }
    ~FragmentImages() {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &fbo);
        GLuint textures[4] = {uv0, view, outUv, outFetches};
        glDeleteTextures(4, textures);
    }
    FragmentImages(const FragmentImages&) = delete;
    FragmentImages& operator=(const FragmentImages&) = delete;
};

// One user uniform: its value(s), or the case's s or b; a type mismatch names the uniform.
void setUniform(GLuint prog, const GlslSpec& spec, const GlslSpec::Uniform& un,
                const DrawMaps& maps) {
    GLint u = glGetUniformLocation(prog, un.name.c_str());
    if (u < 0)
        throw InputError(spec.path, "uniforms." + un.name, "",
                         "is not an active uniform of the shader (misspelt, or unused by " +
                             spec.function + ")");
    std::vector<float> f(un.values.begin(), un.values.end());
    drainGlErrors();  // only this uniform's own error may be blamed on it
    if (un.bind == "scale") f = {float(maps.scale)};
    if (un.bind == "bias") f = {float(maps.bias)};
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

// maxmip's pyramid (unit 5) and the uniforms that describe it and the map, where declared.
void bindPyramid(GLuint prog, const GlslSpec& spec, const DrawMaps& maps) {
    glUniform2i(glGetUniformLocation(prog, "pgt_map_size"), maps.height.width, maps.height.height);
    glUniform1i(glGetUniformLocation(prog, "pgt_map_repeat"),
                maps.height.address == Address::Repeat ? 1 : 0);
    if (spec.pyramidSampler.empty()) return;
    GLint loc = glGetUniformLocation(prog, spec.pyramidSampler.c_str());
    if (loc < 0)
        throw InputError(spec.path, "pyramid_sampler", spec.pyramidSampler,
                         "is not an active sampler2D uniform of the shader");
    PGT_CHECK(maps.pyramid != nullptr);
    glActiveTexture(GL_TEXTURE5);
    glBindTexture(GL_TEXTURE_2D, maps.uploads.pyramid(*maps.pyramid));
    glUniform1i(loc, 5);
    int row = 0;
    for (size_t k = 0; k < maps.pyramid->levels.size(); ++k) {
        const std::string name = "pgt_pyramid_row[" + std::to_string(k) + "]";
        glUniform1i(glGetUniformLocation(prog, name.c_str()), row);
        row += maps.pyramid->levels[k].h;
    }
    glUniform1i(glGetUniformLocation(prog, "pgt_pyramid_top"), maps.pyramid->top());
    checkGl("binding the pyramid of " + spec.path);
}

// A cone map (unit 6: cone's, unit 7: relaxed_cone's), its size, the map's top and whether
// it is built for s < 0.
void bindConeMap(GLuint prog, const GlslSpec& spec, const char* field, const std::string& sampler,
                 const ConeMap* map, int unit, GlMapUploads& uploads) {
    if (sampler.empty()) return;
    GLint loc = glGetUniformLocation(prog, sampler.c_str());
    if (loc < 0)
        throw InputError(spec.path, field, sampler,
                         "is not an active sampler2D uniform of the shader");
    PGT_CHECK(map != nullptr);
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, uploads.cone(*map));
    glUniform1i(loc, unit);
    glUniform2i(glGetUniformLocation(prog, "pgt_cone_cells"), map->cellsX, map->cellsY);
    glUniform1f(glGetUniformLocation(prog, "pgt_cone_top"), map->top);
    glUniform1i(glGetUniformLocation(prog, "pgt_cone_inverted"), map->inverted ? 1 : 0);
    checkGl(std::string("binding the ") + field + " of " + spec.path);
}

// Everything the program reads. Units: 0 = the height/depth map, 1 = uv0, 2 = V,
// 3 = normal map, 4 = parallax map, 5 = the minimum-maximum pyramid, 6 = the cone map, 7 = the
// relaxed cone map.
void bindInputs(GLuint prog, const GlslSpec& spec, const DrawMaps& maps,
                const FragmentImages& img) {
    bindSampler(prog, spec, "sampler", spec.sampler, 0, &maps.height, spec.depthTexture,
                maps.uploads);
    bindSampler(prog, spec, "normal_sampler", spec.normalSampler, 3, maps.normal, false,
                maps.uploads);
    bindSampler(prog, spec, "parallax_sampler", spec.parallaxSampler, 4, maps.parallax, false,
                maps.uploads);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, img.uv0);
    glUniform1i(glGetUniformLocation(prog, "pgt_uv0"), 1);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, img.view);
    glUniform1i(glGetUniformLocation(prog, "pgt_view"), 2);
    glUniform1i(glGetUniformLocation(prog, "pgt_count"), img.n);
    glUniform1i(glGetUniformLocation(prog, "pgt_width"), img.w);
    bindPyramid(prog, spec, maps);
    bindConeMap(prog, spec, "cone_sampler", spec.coneSampler, maps.cone, 6, maps.uploads);
    bindConeMap(prog, spec, "relaxed_cone_sampler", spec.relaxedConeSampler, maps.relaxedCone, 7,
                maps.uploads);
    for (const GlslSpec::Uniform& un : spec.uniforms) setUniform(prog, spec, un, maps);
}

// The draw, `timingRepeats` times when timed (each between two glFinish and inside a
// GL_TIME_ELAPSED query; every draw writes the same outputs), once otherwise. Sets the
// medians per fragment in `run`.
void drawTimed(const FragmentImages& img, int timingRepeats, GlslRun& run) {
    glViewport(0, 0, img.w, img.h);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    const float clear[4] = {NAN, NAN, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    glClearBufferfv(GL_COLOR, 1, clear + 2);
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
            img.n);
        GLuint64 t = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &t);
        gpuNs.push_back(double(t) / img.n);
    }
    if (!query) return;
    glDeleteQueries(1, &query);
    std::sort(gpuNs.begin(), gpuNs.end());
    std::sort(wallNs.begin(), wallNs.end());
    run.gpuNsPerPixel = gpuNs[gpuNs.size() / 2];
    run.wallNsPerPixel = wallNs[wallNs.size() / 2];
}

// uv' and the fetch count of every fragment, from the two outputs.
void readBack(const FragmentImages& img, GlslRun& run) {
    std::vector<float> uvData(size_t(img.w) * img.h * 2), fetchData(size_t(img.w) * img.h);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, img.w, img.h, GL_RG, GL_FLOAT, uvData.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, img.w, img.h, GL_RED, GL_FLOAT, fetchData.data());
    run.uv.resize(size_t(img.n));
    run.fetches.resize(size_t(img.n));
    for (size_t k = 0; k < size_t(img.n); ++k) {
        run.uv[k] = Vec2f(uvData[2 * k], uvData[2 * k + 1]);
        run.fetches[k] = uint32_t(std::max(0.0f, fetchData[k]));
    }
}

// One draw over at most kChunkFragments fragments (runGlsl splits longer lists).
GlslRun runGlslChunk(const GlslSpec& spec, const DrawMaps& maps, const std::vector<Vec2f>& uv0,
                     const std::vector<Vec3f>& view, int timingRepeats) {
    GlslRun run;
    if (uv0.empty()) return run;
    GLuint prog = programFor(spec);
    glUseProgram(prog);
    if (!gVao) glGenVertexArrays(1, &gVao);
    glBindVertexArray(gVao);
    FragmentImages img(uv0, view);
    bindInputs(prog, spec, maps, img);
    drawTimed(img, timingRepeats, run);
    checkGl("the draw of " + spec.path);
    readBack(img, run);
    checkGl("reading back " + spec.path);
    return run;
}

// Fragments per draw: the input and output images are 2048 wide, so this keeps them at most
// 2048 x 4096, within the 8192-texel minimum that GL 4.3 guarantees for GL_MAX_TEXTURE_SIZE.
constexpr size_t kChunkFragments = size_t(2048) * 4096;

}  // namespace

namespace {

// runGlsl on the GL thread.
GlslRun runGlslHere(const GlslSpec& spec, const Texture& height, const Texture* normal,
                    const Texture* parallax, double scale, double bias,
                    const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view,
                    int timingRepeats, GlMapUploads* uploads, const MinMaxPyramid* pyramid,
                    const ConeMap* cone, const ConeMap* relaxedCone) {
    GlMapUploads once;  // without an owner's uploads: this call's, freed at return (unlocked)
    std::lock_guard<std::mutex> lock(gMutex);
    ensureContext();
    drainGlErrors();
    checkMapFits(spec, "sampler", spec.sampler, &height);
    checkMapFits(spec, "normal_sampler", spec.normalSampler, normal);
    checkMapFits(spec, "parallax_sampler", spec.parallaxSampler, parallax);
    const DrawMaps maps{height,  normal, parallax,   scale, bias, uploads ? *uploads : once,
                        pyramid, cone,   relaxedCone};
    if (uv0.size() <= kChunkFragments) return runGlslChunk(spec, maps, uv0, view, timingRepeats);
    GlslRun run;  // a long list: draw by chunks; times are the fragment-weighted mean
    for (size_t first = 0; first < uv0.size(); first += kChunkFragments) {
        size_t last = std::min(uv0.size(), first + kChunkFragments);
        std::vector<Vec2f> u(uv0.begin() + long(first), uv0.begin() + long(last));
        std::vector<Vec3f> v(view.begin() + long(first), view.begin() + long(last));
        GlslRun part = runGlslChunk(spec, maps, u, v, timingRepeats);
        double weight = double(last - first) / double(uv0.size());
        run.gpuNsPerPixel += part.gpuNsPerPixel * weight;
        run.wallNsPerPixel += part.wallNsPerPixel * weight;
        run.uv.insert(run.uv.end(), part.uv.begin(), part.uv.end());
        run.fetches.insert(run.fetches.end(), part.fetches.begin(), part.fetches.end());
    }
    return run;
}

}  // namespace

GlslRun runGlsl(const GlslSpec& spec, const Texture& height, const Texture* normal,
                const Texture* parallax, double scale, double bias, const std::vector<Vec2f>& uv0,
                const std::vector<Vec3f>& view, int timingRepeats, GlMapUploads* uploads,
                const MinMaxPyramid* pyramid, const ConeMap* cone, const ConeMap* relaxedCone) {
    PGT_CHECK_EQ(uv0.size(), view.size());
    GlslRun run;
    onGlThread([&] {
        run = runGlslHere(spec, height, normal, parallax, scale, bias, uv0, view, timingRepeats,
                          uploads, pyramid, cone, relaxedCone);
    });
    return run;
}

}  // namespace pgt
