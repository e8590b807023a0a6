// The GL textures of a study's maps (GlMapUploads, methods/shader/glsl_method.h): the height map as
// R32F (or depth), the packed layouts engines ship, the pyramid and cone maps; each uploaded once
// and deleted with its owner.
#include <algorithm>
#include <map>

#include "core/error.h"
#include "methods/shader/gl_api.h"

namespace pgt {

namespace gl {

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

}  // namespace gl

using namespace gl;

namespace {

// The map's texels as the GL takes them: 1 or 3 channels, d = 1 - h when `depth`.
std::vector<float> mapTexels(const Texture& t, bool depth) {
    const int c = t.channels >= 3 ? 3 : 1;
    std::vector<float> data(size_t(t.width) * t.height * size_t(c));
    for (size_t k = 0; k < size_t(t.width) * t.height; ++k)
        for (int ch = 0; ch < c; ++ch) {
            float h = t.texels[k * size_t(t.channels) + size_t(ch)];
            data[k * size_t(c) + size_t(ch)] = depth ? 1.0f - h : h;
        }
    return data;
}

// The height map's value (h, or d = 1 - h) in the channels of `channels` (GlslSpec::channels),
// RGBA: the other colour channels 0, A 1 unless named.
std::vector<float> channelTexels(const Texture& t, bool depth, unsigned channels) {
    const std::vector<float> v = mapTexels(t, depth);  // 1 channel: the height map's
    std::vector<float> out(v.size() * 4);
    for (size_t k = 0; k < v.size(); ++k)
        for (unsigned c = 0; c < 4; ++c)
            out[k * 4 + c] = channels & (1u << c) ? v[k] : c == 3 ? 1.0f : 0.0f;
    return out;
}

// A map as a texture: R32F (height, or depth d = 1 - h) or RGB32F (Lengyel FGED 2's normal map),
// bilinear, the map's address mode (docs/model.md §1: texel centres at (i + 0.5) / W, as GL
// samples). A map with mipmaps (heightfield/mipmaps.h) gets pgt's levels, not
// glGenerateMipmap's, and trilinear minification (GL_LINEAR_MIPMAP_LINEAR), so that C++ and
// GL filter alike.
GLuint uploadMap(const Texture& t, bool depth, unsigned channels) {
    const bool rgb = t.channels >= 3, rgba = channels != 0 && t.channels == 1;
    const GLenum internal = rgba  ? GL_RGBA32F
                            : rgb ? GL_RGB32F
                                  : GL_R32F,
                 format = rgba  ? GL_RGBA
                          : rgb ? GL_RGB
                                : GL_RED;
    auto texels = [&](const Texture& level) {
        return rgba ? channelTexels(level, depth, channels) : mapTexels(level, depth);
    };
    GLuint id = makeTexture(internal, format, t.width, t.height, texels(t).data(), GL_LINEAR,
                            t.address == Address::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    if (!t.mips || t.mips->empty()) return id;
    for (size_t k = 0; k < t.mips->size(); ++k) {
        const Texture& level = (*t.mips)[k];
        glTexImage2D(GL_TEXTURE_2D, GLint(k + 1), GLint(internal), level.width, level.height, 0,
                     format, GL_FLOAT, texels(level).data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, GLint(t.mips->size()));
    return id;
}

// Map textures alive in the process, over every GlMapUploads (for tests).
size_t gLiveMaps = 0;

// The encoded normal 0.5 + 0.5 m of each texel, RGB: level 0 from the map, each further
// level the 2x2 box of the level above (edge texels repeated), as the height map's levels.
std::vector<float> encodedNormal(const Texture& normal) {
    std::vector<float> rgb(size_t(normal.width) * normal.height * 3);
    for (size_t k = 0; k < size_t(normal.width) * normal.height; ++k)
        for (size_t c = 0; c < 3; ++c)
            rgb[k * 3 + c] = 0.5f + 0.5f * normal.texels[k * size_t(normal.channels) + c];
    return rgb;
}
std::vector<float> halvedRgb(const std::vector<float>& above, int aw, int ah, int w, int h) {
    std::vector<float> out(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                float sum = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int sx = std::min(2 * x + dx, aw - 1),
                                  sy = std::min(2 * y + dy, ah - 1);
                        sum += above[(size_t(sy) * aw + sx) * 3 + size_t(c)];
                    }
                out[(size_t(y) * w + x) * 3 + size_t(c)] = 0.25f * sum;
            }
    return out;
}
std::vector<float> rgbaTexels(const std::vector<float>& rgb, const Texture& level, bool depth) {
    const std::vector<float> a = mapTexels(level, depth);  // 1 channel: the height map's
    std::vector<float> out(a.size() * 4);
    for (size_t k = 0; k < a.size(); ++k) {
        for (size_t c = 0; c < 3; ++c) out[k * 4 + c] = rgb[k * 3 + c];
        out[k * 4 + 3] = a[k];
    }
    return out;
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

}  // namespace

unsigned GlMapUploads::texture(const Texture& map, bool depth, unsigned channels) {
    auto key = std::make_tuple(&map, depth, channels);
    auto it = ids_.find(key);
    if (it != ids_.end()) return it->second;
    GLuint id = uploadMap(map, depth, channels);
    ids_[key] = id;
    ++gLiveMaps;
    return id;
}

unsigned GlMapUploads::packed(const Texture& height, const Texture& normal, bool depth) {
    const auto key = std::make_tuple(&height, &normal, depth);
    auto it = packed_.find(key);
    if (it != packed_.end()) return it->second;
    PGT_CHECK(normal.width == height.width && normal.height == height.height &&
              normal.channels >= 3 && height.channels == 1);
    std::vector<float> rgb = encodedNormal(normal);
    GLuint id = makeTexture(GL_RGBA32F, GL_RGBA, height.width, height.height,
                            rgbaTexels(rgb, height, depth).data(), GL_LINEAR,
                            height.address == Address::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    if (height.mips && !height.mips->empty()) {
        int aw = height.width, ah = height.height;
        for (size_t k = 0; k < height.mips->size(); ++k) {
            const Texture& level = (*height.mips)[k];
            rgb = halvedRgb(rgb, aw, ah, level.width, level.height);
            aw = level.width;
            ah = level.height;
            glTexImage2D(GL_TEXTURE_2D, GLint(k + 1), GL_RGBA32F, level.width, level.height, 0,
                         GL_RGBA, GL_FLOAT, rgbaTexels(rgb, level, depth).data());
        }
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, GLint(height.mips->size()));
    }
    packed_[key] = id;
    ++gLiveMaps;
    return id;
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
    if (ids_.empty() && precomputed_.empty() && packed_.empty()) return;
    try {
        onGlThread([this] {
            std::lock_guard<std::mutex> lock(gMutex);
            ensureContext();
            for (const auto& [key, id] : ids_) {
                GLuint t = id;
                glDeleteTextures(1, &t);
                --gLiveMaps;
            }
            for (const auto& [key, id] : packed_) {
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

}  // namespace pgt
