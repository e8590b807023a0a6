// The march of pom_inout.hlsl, in an include with #pragma once (included twice there).
#pragma once

// How the march ends: a plain enum and an enum class, as engines' HLSL 2021 writes them.
enum class MarchEnd : uint { Last, Interpolated = 4, Refined };
enum Sign { Negative = -1, Positive = 1 };

float depthAt(Texture2D map, SamplerState state, float2 uv) {
    return 1.0 - map.SampleLevel(state, uv, 0.0).r;
}
