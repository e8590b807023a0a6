// Internal to gl/: one GL draw's input and output images and where each fragment sits in
// them, packed or in screen layout with each triangle's own 2x2 quads
// (methods/shader/glsl_method.h GlslInputs).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "methods/shader/gl_api.h"

namespace pgt::gl {

// One draw's images, w x h: the inputs (uv0; V with the texel's state in w: 2 a fragment, 1
// a helper, 0 nothing; uv0's derivatives; an engine's varyings where the draw has them; the
// vertex stage's outputs, a layer each) and the two outputs; deleted with this object.
// `texel[i]` is where fragment `fragment[i]` of the GlslInputs sits.
struct DrawImages {
    static constexpr int kEngineImages = 4;  // position, normal, tangent, camera (RGBA32F)
    int w = 0, h = 0;
    bool engine = false;
    int links = 0;  // the vertex stage's outputs (layers of `varyings`)
    std::vector<size_t> fragment;
    std::vector<size_t> texel;
    std::vector<float> uvData, viewData, gradData, varyingData;
    std::array<std::vector<float>, kEngineImages> engineData;
    GLuint uv0 = 0, view = 0, grad = 0, varyings = 0, outUv = 0, outFetches = 0, fbo = 0;
    std::array<GLuint, kEngineImages> engineImages{};

    DrawImages(int width, int height, const GlslInputs& in);
    // Texel t gets fragment k of `in` (state 2) or, as a helper (state 1), k's values with uv0
    // (and an engine's position) moved by `offset` pixels along its derivatives.
    void put(size_t t, const GlslInputs& in, size_t k, float state, Vec2f offset = {0, 0});
    // Texel t gets helper lane j of `in` (state 1).
    void putHelper(size_t t, const GlslInputs& in, size_t j);
    float state(size_t t) const { return viewData[4 * t + 3]; }
    // The GL images (after every put).
    void upload();
    ~DrawImages();
    DrawImages(const DrawImages&) = delete;
    DrawImages& operator=(const DrawImages&) = delete;

  private:
    void putEngine(size_t t, const EngineInputs& e, Vec2f offset);
    void putVaryings(size_t t, const glm::vec4* values);
};

// Fragments [first, last) of `in` packed: the i-th at texel (i % w, i / w).
std::unique_ptr<DrawImages> packedImages(const GlslInputs& in, size_t first, size_t last);
// The screen-layout tile of `in` at (x0, y0) (both even), w x h: its fragments (`inTile`) in
// their triangles' quads, then the quads' helper lanes (`helpersInTile`).
std::unique_ptr<DrawImages> screenTile(const GlslInputs& in, const std::vector<size_t>& inTile,
                                       const std::vector<size_t>& helpersInTile, int x0, int y0,
                                       int w, int h);

}  // namespace pgt::gl
