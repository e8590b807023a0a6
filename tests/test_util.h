// Helpers shared by the tests: textures from functions, programmatic scenes, temp dirs.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <system_error>
#include <vector>

#include "core/data_dir.h"
#include "heightfield/heightfield.h"
#include "heightfield/texture.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "scene/scene.h"

namespace pgt::test {

// A W x H texture whose texel (i, j) (j from the bottom) is fn(i, j).
inline Texture makeTexture(int w, int h, const std::function<double(int, int)>& fn,
                           Address address = Address::Repeat) {
    Texture t;
    t.width = w;
    t.height = h;
    t.address = address;
    t.texels.resize(size_t(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) t.texel(i, j) = float(fn(i, j));
    return t;
}

// A smooth tileable map: 0.5 + 0.35 sin(2 pi u) sin(2 pi 2v) sampled at texel centres.
inline Texture smoothTexture(int w, int h, Address address = Address::Repeat) {
    return makeTexture(
        w, h,
        [&](int i, int j) {
            double u = (i + 0.5) / w, v = (j + 0.5) / h;
            return 0.5 + 0.35 * std::sin(2 * kPi * u) * std::sin(2 * kPi * 2 * v);
        },
        address);
}

// The default scene's procedural bricks at n x n texels.
inline Texture bricks(int n) {
    return makeProceduralHeight(
        nlohmann::json::parse(R"({"procedural": "bricks", "size": [)" + std::to_string(n) + "," +
                              std::to_string(n) +
                              R"(], "bricks": [4, 8], "mortar": 0.12, "bevel": 0.2,
                              "jitter": 0.3, "seed": 7})"),
        "test", "heightmap");
}

inline MethodConfig method(const std::string& json) {
    return parseMethod(nlohmann::json::parse(json), "test", "method");
}

// A plane scene with an orthographic camera at (theta, phi).
inline Scene planeScene(Texture height, double scale, double bias, double theta, double phi,
                        int resolution, std::vector<MethodConfig> methods, int rate = 4) {
    Scene s;
    s.file = "test-scene";
    s.height = std::move(height);
    s.heightSource = "test";
    s.displacement = {scale, bias};
    s.camera.type = Projection::Orthographic;
    s.camera.theta = theta;
    s.camera.phi = phi;
    s.camera.width = s.camera.height = resolution;
    s.methods = std::move(methods);
    for (size_t i = 0; i < s.methods.size(); ++i)
        if (s.methods[i].label.empty()) s.methods[i].label = s.methods[i].name + std::to_string(i);
    s.truth.rate = rate;
    return s;
}

// Seeded fragments: uv0 over the tile, V up to theta `maxTheta` degrees in every direction.
struct Fragments {
    std::vector<Vec2f> uv0;
    std::vector<Vec3f> view;
};
inline Fragments randomFragments(int n, uint32_t seed, double maxTheta = 85) {
    Fragments in;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < n; ++k) {
        in.uv0.push_back(Vec2f(float(uni(rng)), float(uni(rng))));
        in.view.push_back(Vec3f(viewFromAngles(maxTheta * std::sqrt(uni(rng)), 360 * uni(rng))));
    }
    return in;
}

// The directories tempDir made, removed when the test process that made them ends (a forked
// child leaves them: it ends by _exit, or is not their owner); with PGT_KEEP_TEST_DIRS set they
// are kept to look at.
struct TempDirs {
    std::vector<std::filesystem::path> made;
    pid_t owner = ::getpid();
    ~TempDirs() {
        if (::getpid() != owner || std::getenv("PGT_KEEP_TEST_DIRS")) return;
        std::error_code ec;
        for (const auto& p : made) std::filesystem::remove_all(p, ec);
    }
};

// A fresh directory under the system's temporary one, removed at the end of the test process.
inline std::filesystem::path tempDir(const std::string& name) {
    static TempDirs dirs;
    auto p = std::filesystem::temp_directory_path() /
             ("pgt_test_" + name + "_" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(p);
    dirs.made.push_back(p);
    return p;
}

// The first crossing of the eye ray with s*h + b (docs/model.md §3), in double, sharing no code
// with any method: `n` (40,000) steps down from the top of the relief to its bottom (the map's
// highest and lowest texels), then bisection. uv(z) = uv0 + V.xy / V.z * z at height z.
inline Vec2d firstHit(const Texture& t, double s, double b, Vec2d uv0, Vec3d v, int n = 40000) {
    const Vec2d dir = Vec2d(v.x, v.y) / v.z;
    double lo = INFINITY, hi = -INFINITY;
    for (float x : t.texels) lo = std::min(lo, double(x)), hi = std::max(hi, double(x));
    const double top = s >= 0 ? s * hi + b : s * lo + b, bottom = s >= 0 ? s * lo + b : s * hi + b;
    auto above = [&](double z) { return z - (s * sampleBilinear<double>(t, uv0 + dir * z) + b); };
    double prev = top;
    for (int i = 1; i <= n; ++i) {
        const double z = top + (bottom - top) * i / n;
        if (above(z) <= 0) {
            double a = prev, c = z;  // above(a) > 0 >= above(c)
            for (int k = 0; k < 100; ++k) {
                const double m = 0.5 * (a + c);
                (above(m) > 0 ? a : c) = m;
            }
            return uv0 + dir * c;
        }
        prev = z;
    }
    return uv0 + dir * bottom;
}

// The tests' own files: tests/ of the source tree (PGT_TEST_SOURCE_DIR, compiled in: tests run
// in a build tree), and its data/ (the reference vectors, data/README.md);
// PGT_TEST_DATA_DIR in the environment wins (a build carried to another machine).
inline std::string testSourceDir() { return PGT_TEST_SOURCE_DIR; }
inline std::string testDataDir() {
    const char* env = std::getenv("PGT_TEST_DATA_DIR");
    return env ? env : testSourceDir() + "/data";
}
// The bundled scenes where pgt finds its shipped files (core/data_dir.h: the build tree's
// share/pgt/scenes); PGT_SCENE_DIR in the environment wins.
inline std::string sceneDir() { return dataSubdir("scenes", "PGT_SCENE_DIR"); }

}  // namespace pgt::test
