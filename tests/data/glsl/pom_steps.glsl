// The helpers of pom_include.glsl: the height from G, as depth; the layer count by angle.
#pragma once

uniform sampler2D packedMap;
uniform float min_layers;
uniform float max_layers;

float depthAt(vec2 uv) { return 1.0 - textureLod(packedMap, uv, 0.0).g; }

float layerCount(float cosine) { return max_layers * (1.0 - cosine) + min_layers * cosine; }
