// The tangent frame Babylon.js (cotangent_frame, bumpFragmentMainFunctions) and PlayCanvas
// (TBN.js, TBN_DERIVATIVES) build per pixel on a mesh without tangents, re-implemented from
// their behaviour (docs/methods.md "Engine presets"): T and B are the screen derivatives of
// the world position turned into the gradients of u and v times the derivatives'
// determinant (not orthogonal, not unit), both scaled by one factor so that the longer has
// length 1, N the interpolated normal. V is the unit direction to the eye in that frame, by
// the frame's transpose (what both engines use in place of its inverse), so its length and
// direction follow the UV parameterisation, shear and unequal scales included. Only with
// "inputs": "engine" (PGT_ENGINE_INPUTS), which gives the world position, normal and camera.
#pragma once
#ifdef PGT_ENGINE_INPUTS
vec3 cotangentFrameV(vec2 uv) {
    vec3 p = pgt_world_position;
    vec3 n = normalize(pgt_world_normal);
    vec3 dp1 = dFdx(p);
    vec3 dp2 = dFdy(p);
    vec2 duv1 = dFdx(uv);
    vec2 duv2 = dFdy(uv);
    vec3 dp2perp = cross(dp2, n);
    vec3 dp1perp = cross(n, dp1);
    vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
    vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
    float longest = max(dot(t, t), dot(b, b));
    float scale = longest == 0.0 ? 0.0 : inversesqrt(longest);
    mat3 frame = mat3(t * scale, b * scale, n);
    return transpose(frame) * normalize(pgt_camera_position - p);
}
#endif
