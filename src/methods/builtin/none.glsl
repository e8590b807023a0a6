// pgt built-in "none" as GLSL (matches src/methods/builtin/simple.h): the normal-mapping baseline.
// Scene entry: {"name": "none_gl", "glsl": "none.glsl", "function": "ParallaxNone",
//               "sampler": ""}
vec2 ParallaxNone(vec2 uv, vec3 V) { return uv; }
