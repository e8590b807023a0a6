// Per-triangle quads (docs/methods.md "Screen layout"): a GPU shades each triangle's pixels in
// 2x2 quads of its own, the lanes outside the triangle helper invocations on its plane, so a
// fragment's dFdx/dFdy never see a neighbouring triangle. Held to the GL itself: the same
// mesh drawn by the GL's own rasteriser (a vertex stage, perspective-correct varyings, a depth
// test) gives, pixel for pixel, the derivatives that pgt's GL path hands a shader, across
// triangle edges and UV seams, fine and coarse. Runs in Mesa llvmpipe like tests/gl_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "frame/render.h"
#include "methods/shader/gl_api.h"
#include "scene/base_surface.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

// What the GL's own draw of the mesh gives at each pixel (rows as pgt's image rows): the
// derivatives a probe returns (kProbes' order, each a vec2) and the face drawn there (-1:
// none).
struct GlDraw {
    int w = 0, h = 0;
    std::vector<std::array<float, 20>> probes;  // 10 probes x 2
    std::vector<int> face;
};

// The probes, each a vec2 as a method's uv' (pgt) or a pair of the GL draw's outputs.
constexpr const char* kProbes[10] = {
    "dFdxFine(uv)",
    "dFdyFine(uv)",
    "dFdxFine(P).xy",
    "vec2(dFdxFine(P).z, dFdyFine(P).x)",
    "dFdyFine(P).yz",
    "dFdxFine(Nrm).xy",
    "vec2(dFdxFine(Nrm).z, dFdyFine(Nrm).x)",
    "dFdyFine(Nrm).yz",
    "dFdxCoarse(uv)",
    "dFdyCoarse(uv)",
};

GLuint compile(GLenum kind, const std::string& text) {
    const GLuint s = glCreateShader(kind);
    const char* src = text.c_str();
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    EXPECT_TRUE(ok) << log;
    return s;
}

// The mesh's front faces drawn by the GL: each vertex placed at pgt's continuous pixel
// coordinates (window y = pgt's row) with w its forward distance, so that the GL's
// perspective-correct interpolation is pgt's; depth from 1 / w as any projection gives it.
GlDraw drawMesh(const BaseMesh& mesh, const Camera& cam) {
    std::vector<float> vertexData;  // clip (4), uv (2), position (3), normal (3), face (1)
    double zMin = INFINITY, zMax = 0;
    for (uint32_t i : mesh.indices) {
        const double z = cam.toCamera(mesh.vertices[i].position).z;
        zMin = std::min(zMin, z), zMax = std::max(zMax, z);
    }
    const bool ortho = cam.isOrthographic();
    if (!ortho) {
        EXPECT_GT(zMin, 0.0);
    }
    const double n = 0.5 * zMin, f = 2 * zMax;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const BaseVertex* v[3] = {&mesh.vertices[mesh.indices[t]],
                                  &mesh.vertices[mesh.indices[t + 1]],
                                  &mesh.vertices[mesh.indices[t + 2]]};
        const Vec3d faceN =
            glm::cross(v[1]->position - v[0]->position, v[2]->position - v[0]->position);
        const Vec3d toEye = ortho ? -cam.forward() : cam.eye() - v[0]->position;
        if (glm::dot(faceN, toEye) <= 0) continue;  // pgt culls it
        for (const BaseVertex* p : v) {
            const Vec3d c = cam.toCamera(p->position);
            const Vec2d s = cam.toScreen(c);
            const double x = 2 * s.x / cam.width() - 1, y = 2 * s.y / cam.height() - 1;
            // Orthographic: w 1 and depth linear in the forward distance.
            const double w = ortho ? 1 : c.z;
            const double zc = ortho ? 1.8 * (c.z - zMin) / (zMax - zMin) - 0.9
                                    : (f + n) / (f - n) * c.z - 2 * f * n / (f - n);
            const float values[13] = {float(x * w),
                                      float(y * w),
                                      float(zc),
                                      float(w),
                                      float(p->uv.x),
                                      float(p->uv.y),
                                      float(p->position.x),
                                      float(p->position.y),
                                      float(p->position.z),
                                      float(p->normal.x),
                                      float(p->normal.y),
                                      float(p->normal.z),
                                      float(t / 3)};
            vertexData.insert(vertexData.end(), values, values + 13);
        }
    }
    std::string fs =
        "#version 450 core\n"
        "in vec2 uv; in vec3 P; in vec3 Nrm; flat in float face;\n";
    for (int i = 0; i < 6; ++i)
        fs += "layout(location = " + std::to_string(i) + ") out vec4 o" + std::to_string(i) + ";\n";
    fs += "void main() {\n";
    for (int i = 0; i < 5; ++i)
        fs += "    o" + std::to_string(i) + " = vec4(" + kProbes[2 * i] + ", " +
              kProbes[2 * i + 1] + ");\n";
    fs += "    o5 = vec4(face);\n}\n";
    const std::string vs =
        "#version 450 core\n"
        "layout(location = 0) in vec4 clip; layout(location = 1) in vec2 aUv;\n"
        "layout(location = 2) in vec3 aP; layout(location = 3) in vec3 aN;\n"
        "layout(location = 4) in float aFace;\n"
        "out vec2 uv; out vec3 P; out vec3 Nrm; flat out float face;\n"
        "void main() { gl_Position = clip; uv = aUv; P = aP; Nrm = aN; face = aFace; }\n";
    GlDraw out;
    out.w = cam.width(), out.h = cam.height();
    gl::onGlThread([&] {
        std::lock_guard<std::mutex> lock(gl::gMutex);
        gl::ensureContext();
        gl::drainGlErrors();
        const GLuint prog = glCreateProgram();
        glAttachShader(prog, compile(GL_VERTEX_SHADER, vs));
        glAttachShader(prog, compile(GL_FRAGMENT_SHADER, fs));
        glLinkProgram(prog);
        GLuint vao = 0, vbo = 0, fbo = 0, depth = 0;
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertexData.size() * sizeof(float)),
                     vertexData.data(), GL_STATIC_DRAW);
        const int sizes[5] = {4, 2, 3, 3, 1}, offsets[5] = {0, 4, 6, 9, 12};
        for (GLuint a = 0; a < 5; ++a) {
            glEnableVertexAttribArray(a);
            glVertexAttribPointer(
                a, sizes[a], GL_FLOAT, GL_FALSE, 13 * sizeof(float),
                reinterpret_cast<const void*>(size_t(offsets[a]) * sizeof(float)));
        }
        // Five float targets, the face in a sixth (cleared to -1), and a depth buffer.
        GLuint targets[6];
        GLenum bufs[6];
        glGenTextures(6, targets);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        for (int i = 0; i < 6; ++i) {
            glBindTexture(GL_TEXTURE_2D, targets[i]);
            glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, out.w, out.h);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D,
                                   targets[i], 0);
            bufs[i] = GLenum(GL_COLOR_ATTACHMENT0 + i);
        }
        glGenRenderbuffers(1, &depth);
        glBindRenderbuffer(GL_RENDERBUFFER, depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, out.w, out.h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        glDrawBuffers(6, bufs);
        EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
        glViewport(0, 0, out.w, out.h);
        const float none[4] = {-1, -1, -1, -1};
        for (int i = 0; i < 6; ++i) glClearBufferfv(GL_COLOR, i, none);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE);
        glUseProgram(prog);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertexData.size() / 13));
        gl::checkGl("the GL's own draw of the mesh");
        std::vector<float> px(size_t(out.w) * out.h * 4);
        out.probes.assign(size_t(out.w) * out.h, {});
        out.face.assign(size_t(out.w) * out.h, -1);
        for (int i = 0; i < 6; ++i) {
            glReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + i));
            glReadPixels(0, 0, out.w, out.h, GL_RGBA, GL_FLOAT, px.data());
            for (size_t k = 0; k < out.probes.size(); ++k)
                for (int c = 0; c < 4; ++c)
                    if (i < 5) out.probes[k][size_t(4 * i + c)] = px[4 * k + size_t(c)];
            if (i == 5)
                for (size_t k = 0; k < out.face.size(); ++k) out.face[k] = int(px[4 * k]);
        }
        glDisable(GL_DEPTH_TEST);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &depth);
        glDeleteTextures(6, targets);
        glDeleteBuffers(1, &vbo);
        glDeleteVertexArrays(1, &vao);
        glDeleteProgram(prog);
    });
    return out;
}

// A torus (seams in u and v, curvature of both signs) under a pinhole or an orthographic camera: at
// every pixel where the GL's draw and pgt's rasteriser drew the same face, the derivatives pgt's GL
// path hands a shader of uv, the world position and the interpolated normal are the GL's (fine and
// coarse), within float noise. Laid out pixel by pixel as before per-triangle quads, the
// neighbour across a triangle edge or seam is another triangle's: dFdx(uv) was the seam's
// jump (about 1 in UV), far outside the tolerance.
void compareWithTheGlsDraw(const std::string& camera) {
    const auto dir = test::tempDir("gl_quads");
    std::ofstream(dir / "probe.glsl") << "// derivative probes (the methods' bodies)\n";
    nlohmann::json methods = nlohmann::json::array();
    for (int i = 0; i < 10; ++i)
        methods.push_back({{"name", "probe" + std::to_string(i)},
                           {"glsl", "probe.glsl"},
                           {"sampler", ""},
                           {"api", "d3d"},  // y down the image, as the GL draw's rows here
                           {"inputs", "engine"},
                           {"body", std::string("vec3 P = pgt_world_position;\n"
                                                "vec3 Nrm = pgt_world_normal;\nreturn ") +
                                        kProbes[i] + ";"}});
    const Scene s =
        parseScene(nlohmann::json::parse(
                       R"({"heightmap": {"procedural": "constant", "value": 0.5, "size": [16, 16]},
                "address": "repeat",
                "base": {"type": "mesh", "cage": "torus", "major_radius": 0.5,
                         "minor_radius": 0.2, "segments": [12, 6], "tiling": [3, 2],
                         "scheme": "catmark", "refine": 1},
                "displacement": {"scale": 0.02, "bias": -0.01},
                "truth": {"rate": 1, "uncertainty": false}, "camera": )" +
                       camera + R"(, "methods": )" + methods.dump() + "}"),
                   (dir / "s.json").string());
    const RenderResult r = renderFrame(s, {.timingRepeats = 0});
    const Camera cam = makeCamera(s);
    const GlDraw gl = drawMesh(drawnBaseMesh(s.base, cam), cam);
    ASSERT_EQ(r.methods.size(), 10u);
    int same = 0, covered = 0, edges = 0, seams = 0;
    double worst[10] = {};
    for (int y = 0; y < gl.h; ++y)
        for (int x = 0; x < gl.w; ++x) {
            const size_t k = size_t(y) * size_t(gl.w) + size_t(x);
            const Fragment& f = r.fragments.data[k];
            covered += f.covered;
            if (!f.covered || gl.face[k] != int(f.triangle)) continue;
            ++same;
            // The quad's row neighbour is another triangle's fragment (edges), with uv0 a
            // seam's jump away (seams).
            if ((x ^ 1) < gl.w) {
                const Fragment& g = r.fragments.data[k ^ 1];
                edges += g.covered && g.triangle != f.triangle;
                seams += g.covered && glm::length(g.uv0 - f.uv0) > 0.5;
            }
            for (int i = 0; i < 10; ++i) {
                const Vec2d want(gl.probes[k][size_t(2 * i)], gl.probes[k][size_t(2 * i + 1)]);
                const double scale = std::max(1e-3, glm::length(want));
                worst[i] = std::max(
                    worst[i], glm::length(r.methods[size_t(i)].pixels.data[k].uv - want) / scale);
            }
        }
    std::printf(
        "%d covered pixels, %d of the same face in the GL's draw (%d beside another "
        "triangle in their quad's row, %d across a seam)\n",
        covered, same, edges, seams);
    for (int i = 0; i < 10; ++i) std::printf("%-40s worst %.2e (relative)\n", kProbes[i], worst[i]);
    EXPECT_GT(same, covered * 95 / 100);
    EXPECT_GT(edges, same / 10);
    EXPECT_GT(seams, 20);
    // Float noise: a derivative is the difference of two floats of size up to 3 (2^-22 each)
    // over steps of 0.005 and more: 1e-4 of it (measured up to 1.2e-4 in llvmpipe).
    for (int i = 0; i < 10; ++i) EXPECT_LT(worst[i], 5e-4) << kProbes[i];
    std::filesystem::remove_all(dir);
}

TEST(GlQuads, DerivativesAreTheGlsOwnDrawOfTheMesh) {
    compareWithTheGlsDraw(R"({"type": "pinhole", "eye": [0.9, -1.3, 1.0], "target": [0, 0, 0],
                             "up": [0, 0, 1], "fov": 45, "resolution": [127, 97]})");
}

TEST(GlQuads, DerivativesAreTheGlsOwnDrawOfTheMeshOrthographic) {
    compareWithTheGlsDraw(
        R"({"type": "orthographic", "theta": 55, "phi": 35, "resolution": [127, 97]})");
}

}  // namespace
}  // namespace pgt
