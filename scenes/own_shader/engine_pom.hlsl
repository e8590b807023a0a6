// A parallax occlusion function in the style of a D3D engine's shader library: typedefs and
// a height callback from an include, a cbuffer, a view vector pointing from the eye to the
// surface, and an offset returned instead of a uv. pgt's own code, the example of
// scenes/own_shader.json; it marches the same layers as pgt's pom, to which
// tests/own_shader_test.cpp holds it through a scene's "call".
#include "engine_common.hlsli"

cbuffer ParallaxParams {
    real _MinSteps;
    real _MaxSteps;
};

real2 ParallaxOcclusionOffset(real3 viewDirTS, real heightScale, real heightBias, real2 uv0) {
#ifdef ENGINE_VIEW_TOWARD_EYE
    real3 V = viewDirTS;
#else
    real3 V = -viewDirTS;  // the engine passes eye -> surface
#endif
    real a = abs(V.z);
    real layers = lerp(_MaxSteps, _MinSteps, a);
    real layerDepth = 1.0 / layers;
    real2 delta = V.xy / V.z * heightScale / layers;
    real2 uv = uv0 + V.xy / V.z * (heightScale + heightBias);
    real depth = SampleDepth(uv, 0.0);
    real layer = 0.0;
    [loop] for (int i = 0; i < 65536 && layer < depth; ++i) {
        uv -= delta;
        depth = SampleDepth(uv, 0.0);
        layer += layerDepth;
    }
    real2 prev = uv + delta;
    real after = depth - layer;
    real before = SampleDepth(prev, 0.0) - layer + layerDepth;
    real w = after / (after - before);
    return lerp(uv, prev, w) - uv0;
}
