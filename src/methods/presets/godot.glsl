// Engine preset: Godot 4's BaseMaterial3D height mapping, re-implemented from its documented
// behaviour (docs/methods.md "Engine presets"): the height map is read as depth d = 1 - h (unless
// inverted), the scale is heightmap_scale * 0.01 (default heightmap_scale = 5.0), and
// view_dir is the unit tangent-space direction to the eye. pgt's V is exactly that (u along
// the tangent, v along the bitangent, +z the normal), so no flip is needed here.
uniform sampler2D heightMap;
uniform float heightmap_scale;   // Godot default 5.0
uniform float heightmap_min_layers;  // deep parallax, default 8
uniform float heightmap_max_layers;  // deep parallax, default 32

float godotDepth(vec2 uv) { return 1.0 - texture(heightMap, uv).r; }

// Default (deep parallax off): one fetch, offset along V.xy WITHOUT dividing by V.z.
vec2 GodotParallax(vec2 base_uv, vec3 view_dir) {
    float depth = godotDepth(base_uv);
    return base_uv - view_dir.xy * depth * heightmap_scale * 0.01;
}

// Deep parallax: layers = mix(max, min, |V.z|), marching from the base UV (the top of the
// relief is the polygon) by V.xy * scale / layers -- again no division by V.z -- then the
// occlusion interpolation between the last two layers.
vec2 GodotDeepParallax(vec2 base_uv, vec3 view_dir) {
    float num_layers = mix(heightmap_max_layers, heightmap_min_layers, abs(view_dir.z));
    float layer_depth = 1.0 / num_layers;
    vec2 delta = view_dir.xy * heightmap_scale * 0.01 / num_layers;
    vec2 ofs = base_uv;
    float depth = godotDepth(ofs);
    float current_depth = 0.0;
    int guard = 0;  // pgt's runaway guard (Godot has none)
    while (current_depth < depth && guard < 65536) {
        ofs -= delta;
        depth = godotDepth(ofs);
        current_depth += layer_depth;
        ++guard;
    }
    vec2 prev_ofs = ofs + delta;
    float after_depth = depth - current_depth;
    float before_depth = godotDepth(prev_ofs) - current_depth + layer_depth;
    float weight = after_depth / (after_depth - before_depth);
    return mix(ofs, prev_ofs, weight);
}
