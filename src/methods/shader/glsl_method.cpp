// A GLSL method's run over a fragment list: the inputs uploaded as textures, the maps bound,
// the draw (timed when asked) and the outputs read back.
#include "methods/shader/glsl_method.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <utility>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/percentile.h"
#include "methods/shader/draw_images.h"
#include "methods/shader/gl_api.h"
#include "methods/shader/program.h"
#include "methods/shader/timed_draws.h"

namespace pgt {

using namespace gl;

namespace {

GLuint gVao = 0;

// A map the GL cannot hold is bad input, named before any upload, not a GL error that a
// later call would report.
// The GL texture size a map of kind `k` takes (the pyramid: its levels stacked in rows; cone
// maps: one texel per cell).
std::pair<int, int> glSize(MapKind k, const MapRefs& maps) {
    switch (k) {
        case MapKind::Height:
            return {maps.height->width, maps.height->height};
        case MapKind::Normal:
            return {maps.normal->width, maps.normal->height};
        case MapKind::Parallax:
            return {maps.parallax->width, maps.parallax->height};
        case MapKind::Pyramid: {
            int rows = 0;
            for (const auto& l : maps.pyramid->levels) rows += l.h;
            return {maps.pyramid->levels[0].w, rows};
        }
        case MapKind::Cone:
            return {maps.cone->cellsX, maps.cone->cellsY};
        case MapKind::RelaxedCone:
            return {maps.relaxedCone->cellsX, maps.relaxedCone->cellsY};
    }
    return {0, 0};
}

// Every map the spec names fits the GL's largest texture (before anything is uploaded).
void checkMapsFit(const GlslSpec& spec, const MapRefs& maps) {
    const int maxSide = maxTextureSide();
    for (const MapKindInfo& m : kMapKindTable) {
        const std::string& name = spec.sampler(m.kind);
        if (name.empty() || !maps.has(m.kind)) continue;
        const auto [w, h] = glSize(m.kind, maps);
        if (w > maxSide || h > maxSide)
            throw InputError(spec.path, m.samplerKey, name,
                             "the map it samples is " + std::to_string(w) + "x" +
                                 std::to_string(h) +
                                 " texels, more than this GL's "
                                 "GL_MAX_TEXTURE_SIZE " +
                                 std::to_string(maxSide) + " (" + contextInfo().renderer +
                                 "); use a smaller height map or no GLSL method");
    }
}

}  // namespace

namespace {

// What a draw samples besides its fragments: GlslMaps with the uploads resolved.
struct DrawMaps : GlslMaps {
    GlMapUploads& store;
};

// One user uniform: its value(s), or the case's s or b; a type mismatch names the uniform.
void setUniform(GLuint prog, const GlslSpec& spec, const GlslSpec::Uniform& un,
                const DrawMaps& maps) {
    GLint u = uniformLocation(prog, spec.hlsl, un.name);
    if (u < 0 && spec.vertexStage()) return;  // the vertex stage's (vertex_stage.cpp checks)
    if (u < 0)
        throw InputError(spec.path, "uniforms." + un.name, "",
                         "is not an active uniform of the shader (misspelt, or unused by " +
                             spec.entryName() + ")");
    std::vector<float> f = un.at(maps.scale, maps.bias);
    drainGlErrors();  // only this uniform's own error may be blamed on it
    // One number sets a float or an int uniform alike where it is a whole number (32 and
    // 32.0 both set `float steps` and `int steps`).
    const bool whole = f.size() == 1 && un.bind.empty() &&
                       un.values[0] == std::floor(un.values[0]) &&
                       std::abs(un.values[0]) < 2147483648.0;
    if (un.isInt || (whole && f.size() == 1)) {
        glUniform1i(u, int(un.values[0]));
        if (glGetError() != GL_NO_ERROR) glUniform1f(u, f[0]);
    } else if (f.size() == 1)
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

// The GL texture of a map of kind `k` (uploaded on first use).
GLuint mapTexture(MapKind k, const GlslSpec& spec, const DrawMaps& maps) {
    switch (k) {
        case MapKind::Height:
            if (spec.packedNormal())
                return maps.store.packed(*maps.height, *maps.normal, spec.depthTexture());
            return maps.store.texture(*maps.height, spec.depthTexture(), spec.channels);
        case MapKind::Normal:
            return maps.store.texture(*maps.normal, false);
        case MapKind::Parallax:
            return maps.store.texture(*maps.parallax, false);
        case MapKind::Pyramid:
            return maps.store.pyramid(*maps.pyramid);
        case MapKind::Cone:
            return maps.store.cone(*maps.cone);
        case MapKind::RelaxedCone:
            return maps.store.cone(*maps.relaxedCone);
    }
    return 0;
}

// The uniforms that describe a map of kind `k` where the shader declares them: the pyramid's
// level rows and top; a cone map's cells, top and sign of s.
void describeMap(MapKind k, GLuint prog, const DrawMaps& maps) {
    if (k == MapKind::Pyramid) {
        int row = 0;
        for (size_t l = 0; l < maps.pyramid->levels.size(); ++l) {
            const std::string name = "pgt_pyramid_row[" + std::to_string(l) + "]";
            glUniform1i(glGetUniformLocation(prog, name.c_str()), row);
            row += maps.pyramid->levels[l].h;
        }
        glUniform1i(glGetUniformLocation(prog, "pgt_pyramid_top"), maps.pyramid->top());
    } else if (k == MapKind::Cone || k == MapKind::RelaxedCone) {
        const ConeMap& map = k == MapKind::Cone ? *maps.cone : *maps.relaxedCone;
        glUniform2i(glGetUniformLocation(prog, "pgt_cone_cells"), map.cellsX, map.cellsY);
        glUniform1f(glGetUniformLocation(prog, "pgt_cone_top"), map.top);
        glUniform1i(glGetUniformLocation(prog, "pgt_cone_inverted"), map.inverted ? 1 : 0);
    }
}

// Every map the spec names a sampler for, at its kind's texture unit (methods/maps.h).
void bindMaps(GLuint prog, const GlslSpec& spec, const DrawMaps& maps) {
    glUniform2i(glGetUniformLocation(prog, "pgt_map_size"), maps.height->width,
                maps.height->height);
    glUniform1i(glGetUniformLocation(prog, "pgt_map_repeat"),
                maps.height->address == Address::Repeat ? 1 : 0);
    for (const MapKindInfo& m : kMapKindTable) {
        const std::string& name = spec.sampler(m.kind);
        if (name.empty()) continue;
        const GLint loc = glGetUniformLocation(prog, name.c_str());
        if (loc < 0)
            throw InputError(spec.path, m.samplerKey, name,
                             "is not an active sampler2D uniform of the shader (declare it and "
                             "sample it in " +
                                 spec.entryName() + ")");
        PGT_CHECK(maps.has(m.kind));
        glActiveTexture(GLenum(GL_TEXTURE0 + m.glUnit));
        glBindTexture(GL_TEXTURE_2D, mapTexture(m.kind, spec, maps));
        glUniform1i(loc, m.glUnit);
        describeMap(m.kind, prog, maps);
        checkGl(std::string("binding the ") + m.name + " map of " + spec.path);
    }
}

// Everything the program reads. Units: 0 = the height/depth map, 1 = uv0, 2 = V,
// 3 = normal map, 4 = parallax map, 5 = the minimum-maximum pyramid, 6 = the cone map, 7 = the
// relaxed cone map, 8 = uv0's derivatives, 9-12 an engine's inputs, 13 the vertex stage's.
void bindInputs(GLuint prog, const GlslSpec& spec, const DrawMaps& maps, const DrawImages& img) {
    bindMaps(prog, spec, maps);
    const std::pair<const char*, GLuint> inputs[3] = {
        {"pgt_uv0", img.uv0}, {"pgt_view", img.view}, {"pgt_grad", img.grad}};
    const int units[3] = {1, 2, 8};
    for (int i = 0; i < 3; ++i) {
        glActiveTexture(GLenum(GL_TEXTURE0 + units[i]));
        glBindTexture(GL_TEXTURE_2D, inputs[i].second);
        glUniform1i(glGetUniformLocation(prog, inputs[i].first), units[i]);
    }
    if (img.engine) {  // units 9-12 (GlslSpec::engineInputs)
        const char* names[DrawImages::kEngineImages] = {"pgt_engine_position", "pgt_engine_normal",
                                                        "pgt_engine_tangent", "pgt_engine_camera"};
        for (int i = 0; i < DrawImages::kEngineImages; ++i) {
            glActiveTexture(GLenum(GL_TEXTURE0 + 9 + i));
            glBindTexture(GL_TEXTURE_2D, img.engineImages[size_t(i)]);
            glUniform1i(glGetUniformLocation(prog, names[i]), 9 + i);
        }
    }
    if (img.links) {  // unit 13: the vertex stage's outputs, a layer each
        glActiveTexture(GL_TEXTURE0 + 13);
        glBindTexture(GL_TEXTURE_2D_ARRAY, img.varyings);
        glUniform1i(glGetUniformLocation(prog, "pgt_varyings"), 13);
    }
    glUniform1i(glGetUniformLocation(prog, "pgt_lod_grad"), maps.lodGrad ? 1 : 0);
    for (const GlslSpec::Uniform& un : spec.uniforms) setUniform(prog, spec, un, maps);
    // A call's s and b (uniforms of pgt's glue, inactive where the call reads neither).
    glUniform1f(uniformLocation(prog, spec.hlsl, "pgt_s"), float(maps.scale));
    glUniform1f(uniformLocation(prog, spec.hlsl, "pgt_b"), float(maps.bias));
}

// Draws `img` once, or times it: one warm-up draw, then draws (each between two glFinish and
// inside a GL_TIME_ELAPSED query; every draw writes the same outputs) until `plan`'s GL
// time and repeats are reached. Sets `run`'s timing.
void draw(const DrawImages& img, const GlslTimingPlan* plan, int64_t fragments, GlslRun& run) {
    glViewport(0, 0, img.w, img.h);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    const float clear[4] = {NAN, NAN, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    glClearBufferfv(GL_COLOR, 1, clear + 2);
    const double wholeSeconds = drawInStrips(img.w, img.h);
    if (!plan) return;
    GLuint query = 0;
    glGenQueries(1, &query);
    std::vector<double> gpuNs, wallNs;
    double totalMs = 0;
    const bool software = contextInfo().software;
    while (int(gpuNs.size()) < plan->maxRepeats &&
           (int(gpuNs.size()) < plan->minRepeats || totalMs < plan->minGpuMs)) {
        std::pair<double, double> pass;
        try {
            pass = timedPass(img.w, img.h, wholeSeconds, query);
        } catch (const Cancelled&) {
            glDeleteQueries(1, &query);
            throw;
        }
        const auto [t, wall] = pass;
        gpuNs.push_back(t / double(fragments));
        wallNs.push_back(wall / double(fragments));
        totalMs += (software ? wall : t) * 1e-6;
    }
    glDeleteQueries(1, &query);
    // llvmpipe's GL_TIME_ELAPSED does not cover its deferred rasterisation (measured 0.2-16
    // ns/px against 12-80 between two glFinish): there the wall clock is the GL's time.
    std::vector<double>& main = software ? wallNs : gpuNs;
    GlslTiming& t = run.timing;
    t.repeats = int(main.size());
    t.nsPerPixel = percentile(main, 0.5);
    t.p25 = percentile(main, 0.25);
    t.p75 = percentile(main, 0.75);
    t.gpuNsPerPixel = percentile(gpuNs, 0.5);
    t.wallNsPerPixel = percentile(wallNs, 0.5);
    t.fragments = fragments;
}

// uv' and the fetch count of every fragment of `img` into `run` (indexed as GlslInputs).
void readBack(const DrawImages& img, GlslRun& run) {
    std::vector<float> uvData(size_t(img.w) * img.h * 2), fetchData(size_t(img.w) * img.h);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, img.w, img.h, GL_RG, GL_FLOAT, uvData.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, img.w, img.h, GL_RED, GL_FLOAT, fetchData.data());
    for (size_t i = 0; i < img.fragment.size(); ++i) {
        const size_t k = img.fragment[i], t = img.texel[i];
        run.uv[k] = Vec2f(uvData[2 * t], uvData[2 * t + 1]);
        run.fetches[k] = uint32_t(std::max(0.0f, fetchData[t]));
    }
}

// One draw of `img` with the spec's program; its outputs into `run` when `read`.
void drawImages(const GlslSpec& spec, const DrawMaps& maps, DrawImages& img,
                const GlslTimingPlan* plan, int64_t fragments, bool read, GlslRun& run) {
    GLuint prog = programFor(spec);
    glUseProgram(prog);
    restoreLinkedValues(prog);
    if (!gVao) glGenVertexArrays(1, &gVao);
    glBindVertexArray(gVao);
    img.upload();
    bindInputs(prog, spec, maps, img);
    draw(img, plan, fragments, run);
    checkGl("the draw of " + spec.path);
    if (read) readBack(img, run);
    checkGl("reading back " + spec.path);
}

// Fragments per packed draw: the images are 2048 wide, so this keeps them at most 2048 x
// 4096, within the 8192-texel minimum that GL 4.3 guarantees for GL_MAX_TEXTURE_SIZE; screen
// tiles are at most kTile x kTile.
constexpr size_t kChunkFragments = size_t(2048) * 4096;
constexpr int kTile = 2048;

// Every fragment of `in` drawn (packed in chunks, or screen tile by screen tile).
void drawAll(const GlslSpec& spec, const DrawMaps& maps, const GlslInputs& in, GlslRun& run) {
    if (in.frameWidth <= 0) {
        for (size_t first = 0; first < in.uv0.size(); first += kChunkFragments) {
            auto img = packedImages(in, first, std::min(in.uv0.size(), first + kChunkFragments));
            drawImages(spec, maps, *img, nullptr, 0, true, run);
        }
        return;
    }
    const int tilesX = (in.frameWidth + kTile - 1) / kTile;
    const int tilesY = (in.frameHeight + kTile - 1) / kTile;
    std::vector<std::vector<size_t>> byTile(size_t(tilesX) * size_t(tilesY)),
        helpersByTile(byTile.size());
    for (size_t k = 0; k < in.pixel.size(); ++k) {
        const int x = in.pixel[k] % in.frameWidth, y = in.pixel[k] / in.frameWidth;
        byTile[size_t(y / kTile) * size_t(tilesX) + size_t(x / kTile)].push_back(k);
    }
    for (size_t j = 0; j < in.helpers.size(); ++j) {
        const Vec2i at = in.helpers[j].at;  // x or y may be the frame's odd side
        helpersByTile[size_t(at.y / kTile) * size_t(tilesX) + size_t(at.x / kTile)].push_back(j);
    }
    for (int ty = 0; ty < tilesY; ++ty)
        for (int tx = 0; tx < tilesX; ++tx) {
            const auto& inTile = byTile[size_t(ty) * size_t(tilesX) + size_t(tx)];
            if (inTile.empty()) continue;
            // Even sides: a quad at the frame's odd right or bottom edge keeps its helpers.
            const int x0 = tx * kTile, y0 = ty * kTile;
            const int w = std::min(kTile, (in.frameWidth - x0 + 1) & ~1);
            const int h = std::min(kTile, (in.frameHeight - y0 + 1) & ~1);
            auto img = screenTile(
                in, inTile, helpersByTile[size_t(ty) * size_t(tilesX) + size_t(tx)], x0, y0, w, h);
            drawImages(spec, maps, *img, nullptr, 0, true, run);
        }
}

void checkInputs(const GlslInputs& in) {
    PGT_CHECK_EQ(in.uv0.size(), in.view.size());
    PGT_CHECK(in.uvDx.empty() ||
              (in.uvDx.size() == in.uv0.size() && in.uvDy.size() == in.uv0.size()));
    PGT_CHECK(in.frameWidth <= 0 || in.pixel.size() == in.uv0.size());
    PGT_CHECK(in.triangle.empty() || in.triangle.size() == in.uv0.size());
    PGT_CHECK(in.varyings.size() == in.uv0.size() * size_t(in.links) &&
              in.helperVaryings.size() == in.helpers.size() * size_t(in.links));
    for (const GlslInputs::Helper& h : in.helpers)
        PGT_CHECK(h.at.x >= 0 && h.at.y >= 0 && h.at.x <= in.frameWidth &&
                  h.at.y <= in.frameHeight);
}

// A job on the GL thread with the maps checked and the uploads resolved.
template <class Job>
void withMaps(const GlslSpec& spec, const GlslMaps& maps, Job job) {
    onGlThread([&] {
        GlMapUploads once;  // without an owner's uploads: this call's, freed at return
        std::lock_guard<std::mutex> lock(gMutex);
        ensureContext();
        drainGlErrors();
        checkMapsFit(spec, maps);
        const DrawMaps draw{maps, maps.uploads ? *maps.uploads : once};
        job(draw);
    });
}

}  // namespace

void compileGlsl(const GlslSpec& spec) {
    onGlThread([&] {
        std::lock_guard<std::mutex> lock(gMutex);
        ensureContext();
        programFor(spec);
    });
}

GlslRun runGlsl(const GlslSpec& spec, const GlslMaps& maps, const GlslInputs& in,
                int timingRepeats) {
    checkInputs(in);
    GlslRun run;
    run.uv.resize(in.uv0.size());
    run.fetches.resize(in.uv0.size());
    if (in.uv0.empty()) return run;
    withMaps(spec, maps, [&](const DrawMaps& draw) { drawAll(spec, draw, in, run); });
    if (timingRepeats > 0) {
        GlslTimingPlan plan;
        plan.minFragments = 0;
        plan.minGpuMs = 0;
        plan.minRepeats = plan.maxRepeats = timingRepeats;
        run.timing = timeGlsl(spec, maps, in, plan).timing;
    }
    return run;
}

GlslRun runGlsl(const GlslSpec& spec, const MapRefs& maps, double scale, double bias,
                const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view, int timingRepeats,
                GlMapUploads* uploads) {
    GlslInputs in;
    in.uv0 = uv0;
    in.view = view;
    return runGlsl(spec, GlslMaps{maps, scale, bias, uploads, false}, in, timingRepeats);
}

GlslRun timeGlsl(const GlslSpec& spec, const GlslMaps& maps, const GlslInputs& in,
                 const GlslTimingPlan& plan) {
    checkInputs(in);
    GlslRun run;
    if (in.uv0.empty()) return run;
    // The workload: the fragments repeated (packed) to at least plan.minFragments, at most
    // one chunk.
    const size_t n = in.uv0.size();
    const size_t copies =
        std::max<size_t>(1, size_t((plan.minFragments + int64_t(n) - 1) / int64_t(n)));
    const size_t total = std::min(kChunkFragments, n * copies);
    GlslInputs work;
    work.uv0.reserve(total);
    work.links = in.links;
    for (size_t k = 0; k < total; ++k) {
        for (int l = 0; l < in.links; ++l)  // an engine vertex stage's outputs
            work.varyings.push_back(in.varyings[(k % n) * size_t(in.links) + size_t(l)]);
        work.uv0.push_back(in.uv0[k % n]);
        work.view.push_back(in.view[k % n]);
        if (!in.engine.empty()) work.engine.push_back(in.engine[k % n]);
        if (!in.uvDx.empty()) {
            work.uvDx.push_back(in.uvDx[k % n]);
            work.uvDy.push_back(in.uvDy[k % n]);
        }
    }
    withMaps(spec, maps, [&](const DrawMaps& draw) {
        auto img = packedImages(work, 0, total);
        drawImages(spec, draw, *img, &plan, int64_t(total), false, run);
    });
    return run;
}

}  // namespace pgt
