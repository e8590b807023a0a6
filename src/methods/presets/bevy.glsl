// Engine preset: Bevy's StandardMaterial parallax mapping, re-implemented from its documented
// behaviour (docs/methods.md "Engine presets"): a depth map (sampler holds d; "texture": "depth"),
// parallax_depth_scale (default 0.1), max_parallax_layer_count (default 16), layers mixed
// from max down to 1 by |V.z| (not clamped: V.z = 0 gives no finite uv'), a march of at
// most layer_count + 1 steps from the base UV, then either the occlusion interpolation (the default method) or
// `max_steps` binary refinements (the Relief method, default 5 steps).
// Bevy's tangent-space view vector points from the camera with its y flipped for UVs whose
// v runs down the image; pgt's V points to the eye with v up, so Bevy's
// `Vt.xy * vec2(1, -1)` is `-V.xy` here.
uniform sampler2D depthMap;
uniform float depth_scale;
uniform float max_layer_count;
uniform int max_steps;

float bevyDepth(vec2 uv) { return texture(depthMap, uv).r; }

vec2 bevyMarch(vec2 uv, vec3 V, out vec2 delta_uv, out float layer_depth,
               out float current_layer_depth, out float texture_depth) {
    float view_steepness = abs(V.z);  // not clamped (Bevy's code): V.z = 0 diverges
    float layer_count = mix(max_layer_count, 1.0, view_steepness);
    layer_depth = 1.0 / layer_count;
    delta_uv = depth_scale * layer_depth * (-V.xy) / view_steepness;
    current_layer_depth = 0.0;
    texture_depth = bevyDepth(uv);
    for (int i = 0; texture_depth > current_layer_depth && i <= int(layer_count); i++) {
        current_layer_depth += layer_depth;
        uv += delta_uv;
        texture_depth = bevyDepth(uv);
    }
    return uv;
}

vec2 BevyOcclusion(vec2 uv0, vec3 V) {
    if (max_layer_count < 1.0) return uv0;
    vec2 delta_uv;
    float layer_depth, current, texture_depth;
    vec2 uv = bevyMarch(uv0, V, delta_uv, layer_depth, current, texture_depth);
    vec2 previous_uv = uv - delta_uv;
    float next_depth = texture_depth - current;
    float previous_depth = bevyDepth(previous_uv) - current + layer_depth;
    float weight = next_depth / (next_depth - previous_depth);
    return mix(uv, previous_uv, weight);
}

vec2 BevyRelief(vec2 uv0, vec3 V) {
    if (max_layer_count < 1.0) return uv0;
    vec2 delta_uv;
    float layer_depth, current, texture_depth;
    vec2 uv = bevyMarch(uv0, V, delta_uv, layer_depth, current, texture_depth);
    delta_uv *= 0.5;
    float delta_depth = 0.5 * layer_depth;
    uv -= delta_uv;
    current -= delta_depth;
    for (int i = 0; i < max_steps; i++) {
        texture_depth = bevyDepth(uv);
        delta_uv *= 0.5;
        delta_depth *= 0.5;
        if (texture_depth > current) {
            uv += delta_uv;
            current += delta_depth;
        } else {
            uv -= delta_uv;
            current -= delta_depth;
        }
    }
    return uv;
}
