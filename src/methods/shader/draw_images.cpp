// A GL draw's images and layouts (methods/shader/draw_images.h).
#include "methods/shader/draw_images.h"

#include <algorithm>
#include <unordered_map>

#include "core/error.h"

namespace pgt::gl {

DrawImages::DrawImages(int width, int height, const GlslInputs& in)
    : w(width),
      h(height),
      engine(!in.engine.empty()),
      links(in.links),
      uvData(size_t(w) * h * 2, 0.0f),
      viewData(size_t(w) * h * 4, 0.0f),
      gradData(size_t(w) * h * 4, 0.0f),
      varyingData(size_t(w) * h * 4 * size_t(links), 0.0f) {
    if (engine)
        for (auto& d : engineData) d.assign(size_t(w) * h * 4, 0.0f);
}

void DrawImages::put(size_t t, const GlslInputs& in, size_t k, float state, Vec2f offset) {
    Vec2f uv = in.uv0[k];
    if (!in.uvDx.empty()) {
        uv += in.uvDx[k] * offset.x + in.uvDy[k] * offset.y;
        gradData[4 * t] = in.uvDx[k].x, gradData[4 * t + 1] = in.uvDx[k].y;
        gradData[4 * t + 2] = in.uvDy[k].x, gradData[4 * t + 3] = in.uvDy[k].y;
    }
    uvData[2 * t] = uv.x, uvData[2 * t + 1] = uv.y;
    viewData[4 * t] = in.view[k].x, viewData[4 * t + 1] = in.view[k].y;
    viewData[4 * t + 2] = in.view[k].z, viewData[4 * t + 3] = state;
    if (engine) putEngine(t, in.engine[k], offset);
    if (links) putVaryings(t, &in.varyings[k * size_t(links)]);
    if (state == 2.0f) {
        fragment.push_back(k);
        texel.push_back(t);
    }
}

void DrawImages::putHelper(size_t t, const GlslInputs& in, size_t j) {
    const GlslInputs::Helper& lane = in.helpers[j];
    if (!in.uvDx.empty()) {
        gradData[4 * t] = lane.uvDx.x, gradData[4 * t + 1] = lane.uvDx.y;
        gradData[4 * t + 2] = lane.uvDy.x, gradData[4 * t + 3] = lane.uvDy.y;
    }
    uvData[2 * t] = lane.uv0.x, uvData[2 * t + 1] = lane.uv0.y;
    viewData[4 * t] = lane.view.x, viewData[4 * t + 1] = lane.view.y;
    viewData[4 * t + 2] = lane.view.z, viewData[4 * t + 3] = 1.0f;
    if (engine) putEngine(t, lane.engine, {0, 0});
    if (links) putVaryings(t, &in.helperVaryings[j * size_t(links)]);
}

void DrawImages::putEngine(size_t t, const EngineInputs& e, Vec2f offset) {
    const Vec3f p = e.position + e.positionDx * offset.x + e.positionDy * offset.y;
    const float values[kEngineImages][4] = {{p.x, p.y, p.z, 1.0f},
                                            {e.normal.x, e.normal.y, e.normal.z, 0.0f},
                                            {e.tangent.x, e.tangent.y, e.tangent.z, e.tangentW},
                                            {e.camera.x, e.camera.y, e.camera.z, 1.0f}};
    for (int i = 0; i < kEngineImages; ++i)
        std::copy_n(values[i], 4, engineData[size_t(i)].data() + 4 * t);
}

void DrawImages::putVaryings(size_t t, const glm::vec4* values) {
    const size_t layer = size_t(w) * size_t(h) * 4;
    for (size_t l = 0; l < size_t(links); ++l)
        std::copy_n(&values[l].x, 4, varyingData.data() + l * layer + 4 * t);
}

void DrawImages::upload() {
    uv0 = makeTexture(GL_RG32F, GL_RG, w, h, uvData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    view = makeTexture(GL_RGBA32F, GL_RGBA, w, h, viewData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    grad = makeTexture(GL_RGBA32F, GL_RGBA, w, h, gradData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    uvData = {}, viewData = {}, gradData = {};
    if (engine)
        for (size_t i = 0; i < engineImages.size(); ++i) {
            engineImages[i] = makeTexture(GL_RGBA32F, GL_RGBA, w, h, engineData[i].data(),
                                          GL_NEAREST, GL_CLAMP_TO_EDGE);
            engineData[i] = {};
        }
    if (links) {
        glGenTextures(1, &varyings);
        glBindTexture(GL_TEXTURE_2D_ARRAY, varyings);
        glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA32F, w, h, links, 0, GL_RGBA, GL_FLOAT,
                     varyingData.data());
        glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        varyingData = {};
    }
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

DrawImages::~DrawImages() {
    if (!fbo) return;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    GLuint textures[5] = {uv0, view, grad, outUv, outFetches};
    glDeleteTextures(5, textures);
    if (engine) glDeleteTextures(kEngineImages, engineImages.data());
    if (varyings) glDeleteTextures(1, &varyings);
}

std::unique_ptr<DrawImages> packedImages(const GlslInputs& in, size_t first, size_t last) {
    const int n = int(last - first), w = std::min(n, 2048);
    auto img = std::make_unique<DrawImages>(w, (n + w - 1) / w, in);
    for (size_t k = first; k < last; ++k) img->put(k - first, in, k, 2.0f);
    return img;
}

namespace {

// Where each fragment of a screen tile is drawn: the origin of its triangle's quad in the draw
// image (GlslInputs), and the rows the quads moved below the tile take.
struct QuadLayout {
    std::vector<Vec2i> origin;                   // per fragment of the tile, in the tile's order
    std::unordered_map<uint64_t, Vec2i> blocks;  // (quad << 32 | triangle) -> origin
    int rows = 0;                                // the image's height
};

QuadLayout quadLayout(const GlslInputs& in, const std::vector<size_t>& inTile, int x0, int y0,
                      int w, int h) {
    QuadLayout q;
    q.rows = h;
    const int quadsX = w / 2;
    std::vector<uint32_t> inPlace(size_t(quadsX) * size_t(h / 2), UINT32_MAX);
    int moved = 0;
    for (size_t k : inTile) {
        const int x = in.pixel[k] % in.frameWidth - x0, y = in.pixel[k] / in.frameWidth - y0;
        const size_t quad = size_t(y / 2) * size_t(quadsX) + size_t(x / 2);
        const uint32_t tri = in.triangle.empty() ? 0 : in.triangle[k];
        const uint64_t key = uint64_t(quad) << 32 | tri;
        auto found = q.blocks.find(key);
        if (found == q.blocks.end()) {
            Vec2i at(x & ~1, y & ~1);
            if (inPlace[quad] == UINT32_MAX)
                inPlace[quad] = tri;
            else  // another triangle's fragments in this quad: a quad below the tile
                at = Vec2i(2 * (moved % quadsX), h + 2 * (moved / quadsX)), ++moved;
            found = q.blocks.emplace(key, at).first;
        }
        q.origin.push_back(found->second);
    }
    q.rows = h + 2 * ((moved + quadsX - 1) / quadsX);
    return q;
}

}  // namespace

std::unique_ptr<DrawImages> screenTile(const GlslInputs& in, const std::vector<size_t>& inTile,
                                       const std::vector<size_t>& helpersInTile, int x0, int y0,
                                       int w, int h) {
    const QuadLayout layout = quadLayout(in, inTile, x0, y0, w, h);
    auto img = std::make_unique<DrawImages>(w, layout.rows, in);
    auto texelOf = [&](Vec2i origin, int x, int y) {
        return size_t(origin.y + (y & 1)) * size_t(w) + size_t(origin.x + (x & 1));
    };
    for (size_t i = 0; i < inTile.size(); ++i) {
        const size_t k = inTile[i];
        img->put(
            texelOf(layout.origin[i], in.pixel[k] % in.frameWidth, in.pixel[k] / in.frameWidth), in,
            k, 2.0f);
    }
    for (size_t j : helpersInTile) {
        const GlslInputs::Helper& hl = in.helpers[j];
        const int x = hl.at.x - x0, y = hl.at.y - y0;
        const uint64_t quad = uint64_t(y / 2) * uint64_t(w / 2) + uint64_t(x / 2);
        const auto block = layout.blocks.find(quad << 32 | hl.triangle);
        if (block == layout.blocks.end()) continue;
        const size_t t = texelOf(block->second, x, y);
        if (img->state(t) == 0.0f) img->putHelper(t, in, j);
    }
    // Lanes left: along a fragment's row or column first (exact: what fine derivatives
    // read), then the diagonal ones (extrapolated along both).
    for (int diagonal = 0; diagonal < 2; ++diagonal)
        for (size_t i = 0; i < inTile.size(); ++i) {
            const size_t k = inTile[i];
            const int x = in.pixel[k] % in.frameWidth, y = in.pixel[k] / in.frameWidth;
            const int nx = x ^ 1, ny = y ^ 1;
            const int at[3][2] = {{nx, y}, {x, ny}, {nx, ny}};
            for (int a = diagonal ? 2 : 0; a < (diagonal ? 3 : 2); ++a) {
                const size_t t = texelOf(layout.origin[i], at[a][0], at[a][1]);
                if (img->state(t) == 0.0f)
                    img->put(t, in, k, 1.0f, Vec2f(float(at[a][0] - x), float(at[a][1] - y)));
            }
        }
    return img;
}

}  // namespace pgt::gl
