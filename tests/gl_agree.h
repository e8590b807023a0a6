// The C++ method and a GLSL method on the same float inputs (tests of GLSL twins and user
// shaders against the built-ins): how many fragments differ by more than a tolerance.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "compare/statistics.h"
#include "frame/render.h"
#include "heightfield/heightfield.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "methods/shader/glsl_method.h"
#include "test_util.h"
#include "truth/builder.h"

namespace pgt::test {

struct Agreement {
    int64_t n = 0, over = 0;    // fragments, and those differing by more than the tolerance
    double maxTexels = 0;       // largest difference among the others
    int64_t fetchMismatch = 0;  // fragments whose fetch counts differ
};

// The C++ side of a comparison with the GL: a hardware GPU filters with 8 fractional bits of
// weight (docs/methods.md "GPU filter precision"), so there the C++ method filters as
// "filter": "gpu8" does; a software GL (llvmpipe, CI) filters exactly, as pgt's C++ does.
inline MethodConfig filteredAsTheGl(MethodConfig cpu) {
    if (BuiltinMethod* b = cpu.builtin(); b && !glContext().software) b->gpu8Filter = true;
    return cpu;
}

// The C++ method and its GLSL twin on the same inputs.
inline Agreement agree(const MethodConfig& cpuAsListed, const MethodConfig& gl, const Texture& t,
                       double s, double b, const Fragments& in, double tolTexels) {
    const MethodConfig cpu = filteredAsTheGl(cpuAsListed);
    DerivedMaps dm = makeDerivedMaps(t, s, b);
    const MinMaxPyramid pyramid = buildMinMaxPyramid(t);
    const ConeMap cone = buildConeMap(t, s < 0);
    const ConeMap relaxedCone =
        needs(cpu).has(MapKind::RelaxedCone) ? buildRelaxedConeMap(t, cone) : ConeMap{};
    const MapRefs maps{&t, &dm.normal, &dm.parallax, &pyramid, &cone, &relaxedCone};
    GlslRun run = runGlsl(*gl.shader(), maps, s, b, in.uv0, in.view);
    Agreement a;
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        MethodContext<float> c;
        static_cast<MapRefs&>(c) = maps;
        c.scale = float(s);
        c.bias = float(b);
        Vec2f want = runMethod<float>(*cpu.builtin(), c, in.uv0[k], in.view[k]);
        double d = uvErrorTexels(Vec2d(run.uv[k]), Vec2d(want), t.width, t.height, Address::Clamp);
        // Relative to the offset too: tangent_plane divides by dot(n, V), which magnifies
        // the last-bit difference of GL's normalize where the normal tilts towards the eye
        // (offsets of many texels); 1e-5 of the offset is ~100 float ulps.
        double offset =
            uvErrorTexels(Vec2d(want), Vec2d(in.uv0[k]), t.width, t.height, Address::Clamp);
        ++a.n;
        if (!(d <= std::max(tolTexels, 1e-5 * offset))) {
            ++a.over;
            if (std::getenv("PGT_GL_DEBUG"))
                std::printf("  k %zu d %.3g offset %.3g uv0 %.9g %.9g V %.9g %.9g %.9g\n", k, d,
                            offset, in.uv0[k].x, in.uv0[k].y, in.view[k].x, in.view[k].y,
                            in.view[k].z);
        } else
            a.maxTexels = std::max(a.maxTexels, d);
        if (run.fetches[k] != uint32_t(c.fetches)) ++a.fetchMismatch;
    }
    return a;
}

}  // namespace pgt::test
