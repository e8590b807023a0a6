// The presets (methods/presets/presets.h): each with the document or engine setting it stands for.
#include "methods/presets/presets.h"

#include <cstdlib>
#include <filesystem>

#include "core/data_dir.h"
#include "core/error.h"
#include "core/json_read.h"
#include "methods/registry.h"
#include "methods/shader/source_text.h"

namespace pgt {

namespace {

// A single-fetch built-in (parallax, offset_limited) with its own (s, b).
MethodConfig singleFetch(MethodKind kind, double scale, double bias) {
    MethodConfig c;
    c.method = builtinOf(kind);
    c.name = toString(kind);
    c.scale = scale, c.bias = bias;
    return c;
}

// Steep or pom with a layer range, a step cap (0 = none) and its own (s, b).
MethodConfig layered(MethodKind kind, int minLayers, int maxLayers, int maxSteps, double scale,
                     double bias) {
    MethodConfig c = singleFetch(kind, scale, bias);
    auto& m = c.builtin()->as<LayerParameters>();
    m.minLayers = minLayers, m.maxLayers = maxLayers, m.maxSteps = maxSteps;
    return c;
}

// Tatarchuk's soft shadow (methods/builtin/shadow.h) in place of the hard march.
MethodConfig softShadowed(MethodConfig c) {
    c.builtin()->shadow = ShadowMarch::Soft;
    return c;
}

// A preset's source by the first word of its name (docs/references.md's keys).
constexpr std::pair<const char*, const char*> kPresetCites[] = {
    {"welsh", "welsh2004"},
    {"learnopengl", "devries2020"},
    {"deferred", "deferredblog2025"},
    {"tatarchuk", "tatarchuk2006"},
    {"godot", "godot4"},
    {"bevy", "bevy"},
    {"unity", "unityhdrp"},
    {"jme", "jme3"},
    {"playcanvas", "playcanvas"},
    {"ogre", "ogre"},
    {"o3de", "o3de"},
    {"darkplaces", "darkplaces"},
    {"babylon", "babylonjs"},
    {"threejs", "threejs"},
};

MethodPreset builtinPreset(const char* name, const char* source, MethodConfig config) {
    MethodPreset p;
    p.name = name, p.source = source, p.config = std::move(config);
    return p;
}

GlslSpec::Uniform uniform(const char* name, double value, bool isInt = false) {
    return {name, {value}, isInt, "", 1};
}

// A GLSL preset: the shader file under shaderDir(), its function, sampler and uniforms.
MethodPreset glslPreset(const char* name, const char* source, const char* file,
                        const char* function, const char* sampler, bool depthTexture,
                        std::vector<GlslSpec::Uniform> uniforms) {
    MethodPreset p;
    p.name = name, p.source = source, p.shaderFile = file;
    p.glsl.function = function;
    p.glsl.samplers[size_t(MapKind::Height)] = sampler;
    p.glsl.layout = depthTexture ? GlslSpec::Layout::Depth : GlslSpec::Layout::Height;
    p.glsl.uniforms = std::move(uniforms);
    return p;
}

// three.js r131's ParallaxShader at its example's defaults (scale 0.005 passed negated,
// layers 20-25) in one of its modes; world_per_uv 1 (set it to the base's l elsewhere).
MethodPreset threePreset(const char* name, const char* mode, const char* function) {
    std::vector<GlslSpec::Uniform> uniforms = {uniform("parallax_scale", -0.005),
                                               uniform("world_per_uv", 1.0)};
    if (std::string(function) != "ThreeBasic")  // basic reads no layer count
        uniforms.insert(uniforms.end(), {uniform("parallax_min_layers", 20.0),
                                         uniform("parallax_max_layers", 25.0)});
    return glslPreset(name,
                      (std::string("three.js r131 ParallaxShader ") + mode +
                       " at its example's defaults: scale 0.005 (passed negated), layers 20-25")
                          .c_str(),
                      "presets/threejs.glsl", function, "heightMap", false, std::move(uniforms));
}

// O3DE Atom's parallax at its material defaults (factor 0.05, offset 0, quality Low: 16 steps).
MethodPreset o3dePreset(const char* name, const char* algorithm, const char* function) {
    std::vector<GlslSpec::Uniform> uniforms = {uniform("factor", 0.05)};
    if (std::string(function) != "O3deBasic") uniforms.push_back(uniform("steps", 16, true));
    return glslPreset(name,
                      (std::string("O3DE Atom parallax ") + algorithm +
                       ", material defaults: factor 0.05, offset 0, quality Low (16 steps)")
                          .c_str(),
                      "presets/o3de.glsl", function, "heightMap", false, std::move(uniforms));
}

// jMonkeyEngine, PlayCanvas and Ogre.
std::vector<MethodPreset> enginePresetsA() {
    return {
        glslPreset("jme",
                   "jMonkeyEngine 3 Lighting/PBRLighting: classic parallax (SteepParallax off), "
                   "ParallaxHeight 0.05",
                   "presets/jme.glsl", "JmeParallax", "heightMap", false,
                   {uniform("parallax_height", 0.05)}),
        glslPreset("jme_steep",
                   "jMonkeyEngine 3 Lighting/PBRLighting: SteepParallax on, ParallaxHeight 0.05",
                   "presets/jme.glsl", "JmeSteepParallax", "heightMap", false,
                   {uniform("parallax_height", 0.05)}),
        glslPreset("jme_steep_fixed",
                   "jme_steep with no offset head-on instead of a NaN (pgt's variant)",
                   "presets/jme.glsl", "JmeSteepParallaxFixed", "heightMap", false,
                   {uniform("parallax_height", 0.05)}),
        glslPreset("playcanvas",
                   "PlayCanvas standard material to v2.22.0-beta.19: heightMapFactor 1 "
                   "(s 0.025), h s - s/2, V.xy / (V.z + 0.42), its v offset inverted",
                   "presets/playcanvas.glsl", "PlayCanvasParallax", "heightMap", false,
                   {uniform("height_map_factor", 1.0)}),
        glslPreset("playcanvas_fixed",
                   "playcanvas with its v offset's sign corrected (pgt's variant)",
                   "presets/playcanvas.glsl", "PlayCanvasParallaxFixed", "heightMap", false,
                   {uniform("height_map_factor", 1.0)}),
        glslPreset("playcanvas_offset_limited",
                   "PlayCanvas v2.22.0-beta.20: heightMapFactor 1 (s 0.1), h s - s/2, offset "
                   "limiting along the unit V",
                   "presets/playcanvas.glsl", "PlayCanvasOffsetLimited", "heightMap", false,
                   {uniform("height_map_factor", 1.0)}),
        glslPreset("ogre_parallax",
                   "Ogre RTSS normal_map parallax: height scale 0.04, depth 1 - alpha",
                   "presets/ogre.glsl", "OgreParallax", "heightMap", false,
                   {uniform("height_scale", 0.04)}),
        glslPreset("ogre_pom",
                   "Ogre RTSS normal_map parallax_occlusion: height scale 0.04, 32 layers, "
                   "no division by V.z",
                   "presets/ogre.glsl", "OgreOcclusion", "heightMap", false,
                   {uniform("height_scale", 0.04), uniform("layer_count", 32, true)}),
        glslPreset("ogre_pom_fixed",
                   "ogre_pom with each step compared at its own layer: no one-layer overshoot "
                   "(pgt's variant)",
                   "presets/ogre.glsl", "OgreOcclusionFixed", "heightMap", false,
                   {uniform("height_scale", 0.04), uniform("layer_count", 32, true)}),
    };
}

// O3DE, DarkPlaces, Babylon.js and three.js.
std::vector<MethodPreset> enginePresetsB() {
    return {
        o3dePreset("o3de_pom", "POM (the default)", "O3dePom"),
        o3dePreset("o3de_steep", "Steep", "O3deSteep"),
        o3dePreset("o3de_relief", "Relief", "O3deRelief"),
        o3dePreset("o3de_contact", "ContactRefinement", "O3deContact"),
        o3dePreset("o3de_basic", "Basic", "O3deBasic"),
        glslPreset("darkplaces_offset",
                   "DarkPlaces/Xonotic offset mapping: scale 0.04, 2 steps, bias 0",
                   "presets/darkplaces.glsl", "DarkPlacesOffset", "heightMap", false,
                   {uniform("offset_scale", 0.04), uniform("offset_bias", 0.0),
                    uniform("offset_steps", 2, true)}),
        glslPreset("darkplaces_relief",
                   "DarkPlaces/Xonotic relief mapping (effects-ultimate): scale 0.04, 10 steps, "
                   "5 refinements, bias 0",
                   "presets/darkplaces.glsl", "DarkPlacesRelief", "heightMap", false,
                   {uniform("offset_scale", 0.04), uniform("offset_bias", 0.0),
                    uniform("offset_steps", 10, true), uniform("refine_steps", 5, true)}),
        glslPreset("babylon_offset",
                   "Babylon.js useParallax: parallaxScaleBias 0.05, offset limiting",
                   "presets/babylon.glsl", "BabylonOffset", "heightMap", false,
                   {uniform("parallax_scale", 0.05)}),
        glslPreset("babylon_occlusion",
                   "Babylon.js useParallaxOcclusion: parallaxScaleBias 0.05, 15 + 11 cos(theta) "
                   "samples, at most 15",
                   "presets/babylon.glsl", "BabylonOcclusion", "heightMap", false,
                   {uniform("parallax_scale", 0.05)}),
        glslPreset("babylon_occlusion_fixed",
                   "babylon_occlusion as its comment intends: mix(15, 4, cos(theta)) samples, "
                   "as many passes, no NaN head-on (pgt's variant)",
                   "presets/babylon.glsl", "BabylonOcclusionFixed", "heightMap", false,
                   {uniform("parallax_scale", 0.05)}),
        threePreset("threejs_relief", "relief (the example's default mode)", "ThreeRelief"),
        threePreset("threejs_occlusion", "occlusion", "ThreeOcclusion"),
        threePreset("threejs_steep", "steep", "ThreeSteep"),
        threePreset("threejs_basic", "basic", "ThreeBasic"),
    };
}

// How an engine hands its parallax function V where that is not pgt's per-pixel V of the base's
// frame (docs/methods.md "Engine presets"): built per pixel from screen derivatives (three.js
// always; Babylon.js and PlayCanvas on a mesh without tangents), or per vertex and
// interpolated (jMonkeyEngine's Lighting.vert). The preset runs that path; NAME_tangents is the
// same function fed the base frame's per-pixel V (the engine's path with mesh tangents, or
// PBRLighting's per-fragment V; three.js has none: there it is pgt's variant).
// The functions of babylon.glsl and playcanvas.glsl are written for V as their derivative
// frames hand it (Babylon's, on a left-handed WebGL scene, (-V.x, -V.y); PlayCanvas's
// TBN_DERIVATIVES (V.x, -V.y)), while their paths with mesh tangents (Babylon's bumpVertex
// TANGENT, PlayCanvas's TBN_TANGENTS) hand the same code +V: NAME_tangents feeds the function
// V with those signs undone (signX, signY).
struct EngineFrame {
    const char* prefix;
    const char* view;    // the GLSL giving V from the engine's inputs; null: V per vertex
    const char* unread;  // a uniform of the _tangents variant the engine's path does not read
    const char* engineNote;
    const char* tangentsNote;
    double signX = 1, signY = 1;
    // The GLSL giving the _tangents variant's V from the engine's inputs, where the engine's
    // tangent path is not pgt's per-pixel frame; null: that frame's V.
    const char* tangentsView = nullptr;
};
constexpr EngineFrame kEngineFrames[] = {
    {"threejs_", "threeEngineV(uv)", "world_per_uv",
     "; V from screen derivatives (perturbUv), as three.js has it",
     "; fed the base frame's per-pixel V (pgt's variant: three.js has no tangent path)"},
    {"babylon_", "cotangentFrameV(uv)", "",
     "; V in the cotangent frame of screen derivatives (a mesh without tangents)",
     "; V per pixel in the mesh tangents' frame, handed to the function as +V (bumpVertex "
     "TANGENT)",
     -1, -1},
    {"playcanvas", "cotangentFrameV(uv)", "",
     "; V in the frame of screen derivatives (TBN_DERIVATIVES: a mesh without tangents)",
     "; V per pixel in the mesh tangents' frame, handed to the function as +V (TBN_TANGENTS)", 1,
     -1},
    {"jme", nullptr, "", "; V per vertex, interpolated (Lighting.vert)",
     "; V per fragment from the vertex tangents, normalised, not made orthogonal to the normal "
     "(PBRLighting)",
     1, 1, "jmePbrV()"},
};

// Each engine preset, and beside those of kEngineFrames their _tangents variants.
std::vector<MethodPreset> withEngineFrames(std::vector<MethodPreset> list) {
    std::vector<MethodPreset> out;
    for (MethodPreset& p : list) {
        const EngineFrame* frame = nullptr;
        for (const EngineFrame& f : kEngineFrames)
            if (p.name.rfind(f.prefix, 0) == 0) frame = &f;
        if (!frame) {
            out.push_back(std::move(p));
            continue;
        }
        MethodPreset tangents = p;
        tangents.name += "_tangents";
        tangents.source += frame->tangentsNote;
        if (frame->tangentsView) {
            tangents.glsl.engineInputs = true;
            tangents.glsl.call = p.glsl.function + "(uv, " + frame->tangentsView + ")";
        }
        if (frame->signX != 1 || frame->signY != 1) {
            auto sign = [](double s, const char* c) {
                return std::string(s < 0 ? "-V." : "V.") + c;
            };
            tangents.glsl.call = p.glsl.function + "(uv, vec3(" + sign(frame->signX, "x") + ", " +
                                 sign(frame->signY, "y") + ", V.z))";
            tangents.tangentsSignX = frame->signX, tangents.tangentsSignY = frame->signY;
        }
        p.source += frame->engineNote;
        if (frame->view) {
            p.glsl.engineInputs = true;
            p.glsl.call = p.glsl.function + "(uv, " + frame->view + ")";
            std::erase_if(p.glsl.uniforms,
                          [&](const GlslSpec::Uniform& u) { return u.name == frame->unread; });
        } else {
            p.config.viewPerVertex = true;
        }
        out.push_back(std::move(p));
        out.push_back(std::move(tangents));
    }
    return out;
}

// Each preset's surface at a scene's (s, b): the b its engine expresses and the uniforms
// that carry s (docs/methods.md "Engine presets" derives each from the shader).
struct SurfaceRule {
    const char* prefix;  // the presets whose names start with it (first match)
    PresetSurface surface;
};
PresetSurface surface(double biasPerScale, const char* scaleUniform = "", double factor = 1,
                      bool perWorldUnit = false, const char* biasUniform = "",
                      const char* worldPerUvUniform = "") {
    return {biasPerScale, scaleUniform, factor, perWorldUnit, biasUniform, worldPerUvUniform};
}
const SurfaceRule kSurfaces[] = {
    {"welsh", surface(NAN)},  // Welsh's MAD has a scale and a bias: any b
    {"learnopengl_", surface(-1)},
    {"deferred_blog", surface(-1)},
    {"tatarchuk_soft", surface(-1)},
    {"godot", surface(-1, "heightmap_scale", 100)},  // x 0.01 in the shader
    {"bevy_", surface(-1, "depth_scale")},
    {"unity_hdrp", surface(-1, "height_amplitude")},
    {"tatarchuk", surface(-1, "height_map_scale")},
    {"jme_steep", surface(-1, "parallax_height", 1 / 0.3)},  // its ray spans 0.3 ParallaxHeight
    {"jme", surface(-0.6, "parallax_height")},               // h s - 0.6 s
    {"playcanvas_offset_limited", surface(-0.5, "height_map_factor", 10)},  // s = 0.1 factor
    {"playcanvas", surface(-0.5, "height_map_factor", 40)},                 // s = 0.025 factor
    {"ogre_", surface(-1, "height_scale")},
    {"o3de_", surface(-1, "factor")},
    {"darkplaces_", surface(NAN, "offset_scale", 1, false, "offset_bias")},
    {"babylon_offset", surface(0, "parallax_scale")},  // h s V.xy: the relief above the polygon
    {"babylon_", surface(-1, "parallax_scale")},
    // the example's negated scale: -s l (its V.xy is in world units per UV unit)
    {"threejs_", surface(0, "parallax_scale", -1, true, "", "world_per_uv")},
};

// The document and built-in presets, then the engine presets; each with its surface.
std::vector<MethodPreset> withEngines(std::vector<MethodPreset> presets) {
    for (auto list : {enginePresetsA(), enginePresetsB()})
        for (auto& p : withEngineFrames(std::move(list))) presets.push_back(std::move(p));
    for (MethodPreset& p : presets) {
        const SurfaceRule* rule = nullptr;
        for (const SurfaceRule& r : kSurfaces)
            if (!rule && p.name.rfind(r.prefix, 0) == 0) rule = &r;
        PGT_CHECK(rule);
        p.surface = rule->surface;
    }
    return presets;
}

}  // namespace

const std::vector<MethodPreset>& methodPresets() {
    // LearnOpenGL's height_scale 0.1 on a depth map d = 1 - h is s = 0.1, b = -0.1 (docs/model.md
    // §3); the deferred-renderer blog's height scale 0.15 likewise.
    using K = MethodKind;
    static const std::vector<MethodPreset> presets = withEngines({
        builtinPreset("welsh", "Welsh 2004: parallax mapping at its own s 0.04, b -0.02",
                      singleFetch(K::Parallax, 0.04, -0.02)),
        builtinPreset("learnopengl_parallax",
                      "LearnOpenGL: ParallaxMapping, height_scale 0.1 on a depth map",
                      singleFetch(K::Parallax, 0.1, -0.1)),
        builtinPreset("learnopengl_steep",
                      "LearnOpenGL: steep parallax, 8-32 layers, height_scale 0.1",
                      layered(K::Steep, 8, 32, 0, 0.1, -0.1)),
        builtinPreset("learnopengl_pom",
                      "LearnOpenGL: parallax occlusion, 8-32 layers, height_scale 0.1",
                      layered(K::Pom, 8, 32, 0, 0.1, -0.1)),
        builtinPreset("deferred_blog",
                      "the deferred-renderer blog: numSteps 100 at height scale 0.15",
                      layered(K::Steep, 100, 100, 100, 0.15, -0.15)),
        builtinPreset("tatarchuk_soft",
                      "Tatarchuk I3D 2006 / DirectX SDK: pom with lerp(50, 8) samples by V.z "
                      "at height scale 0.02 below the polygon, and the sample's soft "
                      "self-shadow (softening 0.58)",
                      softShadowed(layered(K::Pom, 8, 50, 0, 0.02, -0.02))),
        glslPreset("godot",
                   "Godot 4 BaseMaterial3D, height mapping on, deep parallax off: "
                   "heightmap_scale 5",
                   "presets/godot.glsl", "GodotParallax", "heightMap", false,
                   {uniform("heightmap_scale", 5.0)}),
        glslPreset("godot_deep",
                   "Godot 4 BaseMaterial3D deep parallax: heightmap_scale 5, 8-32 layers",
                   "presets/godot.glsl", "GodotDeepParallax", "heightMap", false,
                   {uniform("heightmap_max_layers", 32.0), uniform("heightmap_min_layers", 8.0),
                    uniform("heightmap_scale", 5.0)}),
        glslPreset("bevy_occlusion",
                   "Bevy StandardMaterial: depth scale 0.1, 16 layers, Occlusion (default)",
                   "presets/bevy.glsl", "BevyOcclusion", "depthMap", true,
                   {uniform("depth_scale", 0.1), uniform("max_layer_count", 16.0)}),
        glslPreset("bevy_relief",
                   "Bevy StandardMaterial: depth scale 0.1, 16 layers, Relief with 5 steps",
                   "presets/bevy.glsl", "BevyRelief", "depthMap", true,
                   {uniform("depth_scale", 0.1), uniform("max_layer_count", 16.0),
                    uniform("max_steps", 5, true)}),
        glslPreset("unity_hdrp",
                   "Unity HDRP Lit pixel displacement: amplitude 2 cm on a 1 m primitive "
                   "(0.02 UV), 5-15 samples by view angle, 3 secant steps",
                   "presets/unity_hdrp.glsl", "UnityHdrpPom", "heightMap", false,
                   {uniform("height_amplitude", 0.02), uniform("ppd_min_samples", 5.0),
                    uniform("ppd_max_samples", 15.0)}),
        glslPreset("tatarchuk",
                   "Tatarchuk I3D 2006 / DirectX SDK POM sample: height scale 0.02, "
                   "lerp(50, 8) samples by dot(V, N)",
                   "presets/tatarchuk.glsl", "TatarchukPom", "heightMap", false,
                   {uniform("height_map_scale", 0.02), uniform("min_samples", 8.0),
                    uniform("max_samples", 50.0)}),
    });
    return presets;
}

namespace {

// The preset's spec and configuration on the scene's surface: s (and b where its engine has a
// bias) bound to the uniforms that carry them, its engine's b fixed as a multiple of s.
void onSceneSurface(const MethodPreset& preset, MethodConfig& cfg, GlslSpec* spec,
                    double worldPerUv) {
    const PresetSurface& surface = preset.surface;
    cfg.scale = cfg.bias = NAN;
    cfg.biasPerScale = surface.biasPerScale;
    if (!spec) return;
    for (GlslSpec::Uniform& u : spec->uniforms) {
        if (u.name == surface.scaleUniform)
            u = {u.name,
                 {},
                 false,
                 "scale",
                 surface.factor * (surface.perWorldUnit ? worldPerUv : 1)};
        if (u.name == surface.biasUniform) u = {u.name, {}, false, "offset_bias", 1};
        if (u.name == surface.worldPerUvUniform) u.values = {worldPerUv};
    }
}

}  // namespace

MethodConfig presetConfig(const MethodPreset& preset, const std::string& label,
                          const std::string& file, const std::string& field,
                          PresetAmplitude amplitude, double worldPerUv) {
    MethodConfig cfg = preset.config;
    cfg.label = label;
    cfg.preset = preset.name;
    const bool scene = amplitude == PresetAmplitude::Scene;
    if (preset.shaderFile.empty() && scene) onSceneSurface(preset, cfg, nullptr, worldPerUv);
    if (!preset.shaderFile.empty()) {  // a GLSL preset: its shader, read now
        cfg.name = preset.name;
        auto spec = std::make_shared<GlslSpec>(preset.glsl);
        if (scene) onSceneSurface(preset, cfg, spec.get(), worldPerUv);
        spec->path = (std::filesystem::path(shaderDir()) / preset.shaderFile).lexically_normal();
        readShaderSource(*spec, file, field);
        cfg.method = ShaderMethod{std::move(spec)};
    }
    return cfg;
}

std::string shaderDir() { return dataSubdir("shaders", "PGT_SHADER_DIR"); }

std::string presetCite(const std::string& preset) {
    const std::string first = preset.substr(0, preset.find('_'));
    for (const auto& [word, key] : kPresetCites)
        if (first == word) return key;
    return "";
}

std::string sourceKeys(const MethodConfig& config) {
    if (!config.preset.empty()) return presetCite(config.preset);
    if (const BuiltinMethod* b = config.builtin()) return kindInfo(b->kind).cite;
    return "";
}

}  // namespace pgt
