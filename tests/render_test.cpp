// The frame pipeline end to end: head-on symmetry, closed-form error, convergence with layers,
// frame.exr and summary.json round trips.
#include "frame/render.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <fstream>
#include <map>
#include <random>
#include <set>

#include "core/error.h"
#include "core/json_read.h"
#include "frame/view_memory.h"
#include "methods/config.h"
#include "study/outputs.h"
#include "test_util.h"
#include "truth/builder.h"

namespace pgt {
namespace {

std::vector<MethodConfig> allMethods() {
    return parseMethods(nlohmann::json::parse(R"(["none","parallax","offset_limited","steep",
        "pom","relief","iterative","tangent_plane"])"),
                        "test", "methods");
}

// Head-on: truth = uv0 and every method returns uv0, so every error is ~0.
TEST(Render, HeadOnEveryMethodMatchesTruth) {
    Scene s = test::planeScene(test::smoothTexture(32, 32), 0.08, -0.04, 0, 0, 96, allMethods());
    s.truth.uncertainty = false;
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    for (const auto& m : r.methods) {
        EXPECT_GT(m.stats.error.count, 8000) << m.config.label;
        // float uv0 (6e-8 UV) and float Embree positions: well under 1e-3 texel at W = 32.
        EXPECT_LT(m.stats.error.max, 1e-3) << m.config.label;
        EXPECT_EQ(m.stats.nonfinite, 0) << m.config.label;
    }
}

// Jittered sample positions are shared by the truth's rays and the rasteriser: head-on,
// every method still matches the truth, and constant height keeps parallax exact.
TEST(Render, JitteredSamplesStayConsistent) {
    Scene s = test::planeScene(test::smoothTexture(32, 32), 0.08, -0.04, 0, 0, 64, allMethods());
    s.camera.jitter = true;
    s.camera.jitterSeed = 9;
    s.truth.uncertainty = false;
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    for (const auto& m : r.methods) EXPECT_LT(m.stats.error.max, 1e-3) << m.config.label;
    Camera cam = makeCamera(s);
    int moved = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            Vec2d p = cam.samplePosition(x, y);
            ASSERT_TRUE(p.x > x && p.x < x + 1 && p.y > y && p.y < y + 1);
            EXPECT_EQ(p, cam.samplePosition(x, y));  // deterministic
            moved += std::fabs(p.x - (x + 0.5)) > 1e-3;
            // uv0 is the jittered point's UV (head-on: a linear map of the position).
            if (r.fragments.at(x, y).covered) {
                EXPECT_NEAR(r.fragments.at(x, y).uv0.x, cam.ray(p.x, p.y).origin.x + 0.5, 1e-9);
            }
        }
    EXPECT_GT(moved, 3500);
}

// Constant height: offset limiting's error is |s*c + b| * |V.xy| * (1/V.z - 1) * W texels
// (square map) at every pixel, and parallax's is zero.
TEST(Render, OffsetLimitedErrorIsTheClosedForm) {
    const double c = 0.7, s = 0.06, b = -0.03, theta = 55;
    Texture t = test::makeTexture(64, 64, [&](int, int) { return c; });
    Scene sc = test::planeScene(
        std::move(t), s, b, theta, 70, 128,
        parseMethods(nlohmann::json::parse(R"(["parallax","offset_limited"])"), "t", "methods"));
    sc.truth.uncertainty = false;
    RenderResult r = renderFrame(sc, {.timingRepeats = 1});
    Vec3d v = viewFromAngles(theta, 70);
    double sinT = std::sqrt(v.x * v.x + v.y * v.y);
    double want = std::fabs(s * c + b) * sinT * (1 / v.z - 1) * 64;
    EXPECT_LT(r.methods[0].stats.error.max, 1e-3);
    EXPECT_NEAR(r.methods[1].stats.error.p50, want, 1e-3);
    EXPECT_NEAR(r.methods[1].stats.error.max, want, 1e-3);
    EXPECT_NEAR(r.methods[1].stats.error.p50, r.methods[1].stats.error.mean, 1e-3);
}

// Pinhole: V varies per pixel (from the fragment toward the eye). On a constant height field
// parallax is exact for every V, so its error is zero wherever both cover the pixel; pom too.
TEST(Render, PinholeParallaxIsExactOnConstantHeight) {
    const double c = 0.6, s = 0.05, b = -0.04;
    Texture t = test::makeTexture(64, 64, [&](int, int) { return c; });
    Scene sc = test::planeScene(
        std::move(t), s, b, 0, 0, 128,
        parseMethods(nlohmann::json::parse(R"(["parallax","pom","none"])"), "t", "methods"));
    sc.camera.type = Projection::Pinhole;
    sc.camera.eye = Vec3d(0.3, -1.1, 0.7);
    sc.camera.target = Vec3d(0, 0.1, 0);
    sc.camera.up = Vec3d(0, 0, 1);
    sc.camera.fov = 60;
    sc.truth.uncertainty = false;
    RenderResult r = renderFrame(sc, {.timingRepeats = 1});
    EXPECT_GT(r.methods[0].stats.error.count, 3000);
    EXPECT_LT(r.methods[0].stats.error.max, 1e-3);
    EXPECT_LT(r.methods[1].stats.error.max, 2e-3);
    EXPECT_GT(r.methods[2].stats.error.mean, 0.5);  // and the baseline is visibly off
}

// More layers -> closer to the truth, on a smooth map where the march has no ties to flip.
TEST(Render, LayeredErrorShrinksAsLayersGrow) {
    auto run = [](const std::string& methodsJson) {
        Scene s = test::planeScene(test::smoothTexture(64, 64), 0.06, -0.06, 60, 20, 128,
                                   parseMethods(nlohmann::json::parse(methodsJson), "t", "m"));
        s.truth.uncertainty = false;
        RenderResult r = renderFrame(s, {.timingRepeats = 1});
        std::vector<double> mean;
        for (const auto& m : r.methods) mean.push_back(m.stats.error.mean);
        return mean;
    };
    for (const char* name : {"steep", "pom"}) {
        std::string json = "[";
        for (int n : {4, 8, 16, 32, 64})
            json += std::string(n == 4 ? "" : ",") + R"({"name":")" + name + R"(","layers":)" +
                    std::to_string(n) + "}";
        auto mean = run(json + "]");
        for (size_t i = 1; i < mean.size(); ++i)
            EXPECT_LT(mean[i], mean[i - 1]) << name << " layers step " << i;
    }
    auto relief = run(R"([{"name":"relief","linear_steps":8,"binary_steps":0},
                          {"name":"relief","linear_steps":8,"binary_steps":2},
                          {"name":"relief","linear_steps":8,"binary_steps":4},
                          {"name":"relief","linear_steps":8,"binary_steps":6}])");
    for (size_t i = 1; i < relief.size(); ++i)
        EXPECT_LT(relief[i], relief[i - 1]) << "relief binary step " << i;
}

TEST(Render, OutputsRoundTrip) {
    Scene s = test::planeScene(test::smoothTexture(16, 16), 0.05, -0.025, 45, 10, 48,
                               parseMethods(nlohmann::json::parse(R"(["parallax",
                                   {"name":"pom","max_layers":16},{"name":"pom","max_layers":32}])"),
                                            "t", "m"));
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    auto dir = test::tempDir("outputs");
    writeRenderOutputs(s, r, dir.string());

    auto in = OIIO::ImageInput::open((dir / "frame.exr").string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    // Every channel of the schema (frame/frame_channels.h): the frame's own, five per method,
    // no base.Vvertex (no method reads V per vertex).
    const std::vector<std::string> want = frameChannelNames(s.methods);
    ASSERT_EQ(want.size(), 14u + 5 * 3);
    ASSERT_EQ(spec.nchannels, int(want.size()));
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    // Channels are looked up by name: OpenEXR stores them alphabetically.
    auto channel = [&](const std::string& name) {
        auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), name);
        EXPECT_NE(it, spec.channelnames.end()) << name;
        return int(it - spec.channelnames.begin());
    };
    for (const auto& name : want) channel(name);
    int checked = 0;
    for (int y = 0; y < spec.height; ++y)
        for (int x = 0; x < spec.width; ++x) {
            size_t k = size_t(y) * spec.width + x;
            const float* p = &px[k * spec.nchannels];
            EXPECT_EQ(p[channel("truth.hit")], r.truth.data[k].hit ? 1.f : 0.f);
            // The V the methods were given: on a plane under an orthographic camera both
            // frames give the view direction at (theta 45, phi 10) in tangent space.
            const Vec3d view = viewFromAngles(45, 10);
            if (r.fragments.data[k].covered)
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(p[channel(std::string("base.V.") + "xyz"[c])], view[c], 1e-6);
                    EXPECT_NEAR(p[channel(std::string("base.Vexact.") + "xyz"[c])], view[c], 1e-6);
                }
            else
                EXPECT_TRUE(std::isnan(p[channel("base.V.x")]));
            if (!r.truth.data[k].hit) {
                EXPECT_TRUE(std::isnan(p[channel("truth.u")]));
                continue;
            }
            EXPECT_EQ(p[channel("truth.u")], float(r.truth.data[k].uv.x));
            EXPECT_EQ(p[channel("truth.v")], float(r.truth.data[k].uv.y));
            float e = r.methods[2].errTexels.data[k];
            float got = p[channel("pom_8_32.err")];
            EXPECT_TRUE((std::isnan(e) && std::isnan(got)) || e == got);
            ++checked;
        }
    EXPECT_GT(checked, 500);

    std::ifstream js(dir / "summary.json");
    auto summary = nlohmann::json::parse(js);
    ASSERT_EQ(summary["methods"].size(), 3u);
    EXPECT_EQ(summary["methods"][1]["label"], "pom_8_16");
    EXPECT_TRUE(summary["truth"]["uncertainty"]["p99_texels"].is_number());
    EXPECT_TRUE(summary["methods"][0]["ns_per_px"].is_number());
    for (const char* stage : {"tessellate", "build", "trace", "raster"})
        EXPECT_TRUE(summary["timings_ms"].contains(stage)) << stage;
    EXPECT_TRUE(std::filesystem::exists(dir / "pom_8_16_error.png"));
    std::filesystem::remove_all(dir);
}

TEST(Render, UnwritableOutputIsAnOutputError) {
    Scene s = test::planeScene(test::smoothTexture(8, 8), 0.05, -0.025, 30, 0, 16,
                               parseMethods(nlohmann::json::parse(R"(["parallax"])"), "t", "m"));
    s.truth.uncertainty = false;
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    auto dir = test::tempDir("unwritable");
    std::ofstream(dir / "file") << "x";
    EXPECT_THROW(writeRenderOutputs(s, r, (dir / "file" / "sub").string()), OutputError);
    std::filesystem::remove_all(dir);
}

// A view whose truth exceeds truth.memory_mb is traced in blocks, each over a window of
// the plane: the same truth frames (up to float ray starts), the same uncertainty, the same
// method statistics, with the peak of one block.
TEST(Render, TruthInBlocksMatchesTheWholeView) {
    Scene s =
        test::planeScene(test::smoothTexture(128, 128), 0.08, -0.04, 55, 20, 96,
                         parseMethods(nlohmann::json::parse(R"(["parallax","pom"])"), "t", "m"));
    s.truth.rate = 2;
    RenderResult whole = renderFrame(s, {.timingRepeats = 0});
    ASSERT_EQ(whole.truthBlocks, 1);
    s.truth.memoryMb = 1;  // ~26k vertices per block: forces blocks
    RenderResult blocks = renderFrame(s, {.timingRepeats = 0});
    EXPECT_GT(blocks.truthBlocks, 1);
    EXPECT_LT(blocks.truthBuild.vertices * 8, whole.truthBuild.vertices);
    int64_t mismatch = 0;
    double maxDiff = 0;
    for (size_t k = 0; k < whole.truth.size(); ++k) {
        const auto &a = whole.truth.data[k], &b = blocks.truth.data[k];
        if (a.hit != b.hit)
            ++mismatch;
        else if (a.hit)
            maxDiff = std::max(maxDiff, uvErrorTexels(a.uv, b.uv, 128, 128, Address::Repeat));
    }
    EXPECT_EQ(mismatch, 0);
    EXPECT_LT(maxDiff, 1e-4);
    EXPECT_NEAR(blocks.uncertainty.p99Texels, whole.uncertainty.p99Texels, 1e-4);
    for (size_t m = 0; m < whole.methods.size(); ++m)
        EXPECT_NEAR(blocks.methods[m].stats.error.mean, whole.methods[m].stats.error.mean, 1e-5);
}

// A plane tiled 128 times, at rate 4 with the uncertainty's 2x-rate pass: its whole lattice
// would hold 65537^2 vertices (more than 2^31: the scene was refused before), but a framed
// view builds only its window's. The scene is accepted, estimated by what it builds, renders,
// and its truth is the same surface's: it hits every pixel and its two passes agree.
TEST(Render, AFinelyTiledPlaneCountsOnlyTheWindowItBuilds) {
    const Scene s = parseScene(nlohmann::json::parse(R"({
        "heightmap": {"procedural": "sine", "size": [64, 64]}, "address": "repeat",
        "base": {"type": "plane", "size": 1.0, "tiling": 128},
        "displacement": {"scale": 0.05, "bias": -0.025},
        "camera": {"type": "orthographic", "theta": 40, "phi": 20, "frame": "fill",
                   "fill_size": 0.02, "resolution": [48, 48]},
        "methods": ["none", "pom"], "truth": {"rate": 4, "uncertainty": true}})"),
                               "tiled.json");
    const double bytes = estimateViewBytes(s, 48, 48, {.configs = &s.methods});
    EXPECT_LT(bytes, 512.0 * 1024 * 1024);
    EXPECT_LT(truthVertices(s, makeCamera(s), lightToward(s.view())), 2e7);
    const RenderResult r = renderFrame(s, {.timingRepeats = 0});
    int64_t hits = 0;
    for (const TruthSample& t : r.truth.data) hits += t.hit;
    EXPECT_EQ(hits, 48 * 48);
    EXPECT_LT(r.uncertainty.p99Texels, 0.05);
    EXPECT_GT(r.methods[1].stats.error.count, 2000);
}

// pgt fit runs one method at a time over views rasterised for all of them: a GL method's helper
// lanes are estimated whichever method comes first.
TEST(Render, AFitsEstimateHoldsTheHelperLanesOfAnyMethod) {
    const Scene s = parseScene(nlohmann::json::parse(R"({
        "heightmap": {"procedural": "sine", "size": [64, 64]}, "base": {"type": "plane"},
        "camera": {"type": "orthographic", "theta": 40, "resolution": [64, 64]},
        "methods": ["pom", {"preset": "godot"}]})"),
                               "fit.json");
    const std::vector<MethodConfig> pom = {s.methods[0]}, gl = {s.methods[1]};
    const std::vector<MethodConfig> reversed = {s.methods[1], s.methods[0]};
    const double pomFirst =
        estimateViewBytes(s, 64, 64, {.configs = &pom, .mapConfigs = &s.methods});
    const double glFirst = estimateViewBytes(s, 64, 64, {.configs = &gl, .mapConfigs = &reversed});
    EXPECT_EQ(pomFirst, glFirst);
    EXPECT_GT(pomFirst, estimateViewBytes(s, 64, 64, {.configs = &pom}));
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// Reads every channel of an EXR (by name) into one map.
std::map<std::string, std::vector<float>> readExr(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    std::map<std::string, std::vector<float>> out;
    for (int c = 0; c < spec.nchannels; ++c)
        for (size_t k = 0; k < size_t(spec.width) * spec.height; ++k)
            out[spec.channelnames[size_t(c)]].push_back(px[k * size_t(spec.nchannels) + size_t(c)]);
    return out;
}

bool sameFloat(float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// A frame of several bands (150 x 139: a full band and a short one) against the whole
// frame at once: the truth equals one traceFrame of the same surfaces, the statistics equal
// compareWithTruth over the assembled images, and the files streamed band by band equal
// those written from the kept images.
TEST(Render, BandsEqualTheWholeFrame) {
    Scene s = test::planeScene(test::smoothTexture(32, 32), 0.06, -0.03, 55, 20, 150,
                               parseMethods(nlohmann::json::parse(R"(["parallax",
                                   {"name":"pom","max_layers":16}])"),
                                            "t", "m"));
    s.camera.height = 139;
    ASSERT_GT(s.camera.height, bandRows(150));  // two bands at least
    RenderResult kept = renderFrame(s, {.timingRepeats = 1});
    const Camera cam = makeCamera(s);
    TruthBuilder builder(s);
    TruthPair truths = builder.build(s.displacement, s.truth.uncertainty);
    Image2D<TruthSample> whole = truths.truth->traceFrame(cam);
    int64_t hits = 0;
    for (size_t k = 0; k < whole.size(); ++k) {
        EXPECT_EQ(kept.truth.data[k].hit, whole.data[k].hit);
        EXPECT_EQ(kept.truth.data[k].uv, whole.data[k].uv);
        hits += whole.data[k].hit;
    }
    EXPECT_EQ(kept.truthHits, hits);
    EXPECT_EQ(kept.raster.covered,
              int64_t(compactFragments(rasterize(drawnBaseMesh(s.base, cam), cam, {true})).size()));
    for (const MethodFrame& m : kept.methods) {
        FrameStats st = compareWithTruth(whole, m.pixels, 32, 32, Address::Repeat);
        EXPECT_EQ(st.error.count, m.stats.error.count);
        EXPECT_EQ(st.error.p50, m.stats.error.p50);
        EXPECT_EQ(st.error.max, m.stats.error.max);
        EXPECT_NEAR(st.error.mean, m.stats.error.mean, 1e-12 * st.error.mean);
    }
    // Streamed: no image kept, the writer fed band by band.
    auto a = test::tempDir("bands_kept"), b = test::tempDir("bands_streamed");
    writeRenderOutputs(s, kept, a.string());
    RenderWriter writer(s, b.string(), 150, 139, s.methods);
    RenderOptions opt{.timingRepeats = 1};
    opt.frame = {.keepImages = false, .sinks = {&writer}, .keepCodedErrors = true};
    RenderResult streamed = renderFrame(s, opt);
    EXPECT_TRUE(streamed.truth.data.empty());
    writer.finish(streamed);
    auto ea = readExr((a / "frame.exr").string()), eb = readExr((b / "frame.exr").string());
    ASSERT_EQ(ea.size(), eb.size());
    for (const auto& [name, values] : ea) {
        ASSERT_EQ(values.size(), eb[name].size()) << name;
        int64_t differ = 0;
        for (size_t k = 0; k < values.size(); ++k) differ += !sameFloat(values[k], eb[name][k]);
        EXPECT_EQ(differ, 0) << name;
    }
    for (size_t i = 0; i < kept.methods.size(); ++i)
        EXPECT_EQ(kept.methods[i].stats.error.p99, streamed.methods[i].stats.error.p99);
}

// The statistics do not depend on how the cores split the frame: a large frame's depths,
// compared on one thread and on eight (seeded random depths, so sums round differently in
// any other order), give bit-equal results, the signed depth mean included.
TEST(Render, StatisticsAreTheSameOnAnyNumberOfThreads) {
    const int w = 2048, h = 1024;
    Image2D<TruthSample> truth(w, h);
    Image2D<MethodPixel> method(w, h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (size_t k = 0; k < truth.size(); ++k) {
        TruthSample& t = truth.data[k];
        t.hit = true, t.uv = Vec2d(u(rng), u(rng)), t.depth = float(u(rng));
        MethodPixel& m = method.data[k];
        m.covered = true, m.uv = t.uv + Vec2d(0.01 * u(rng), 0), m.depth = float(u(rng));
    }
    auto stats = [&](int threads) {
        tbb::task_arena arena(threads);
        return arena.execute(
            [&] { return compareWithTruth(truth, method, 64, 64, Address::Repeat); });
    };
    const FrameStats one = stats(1);
    for (int run = 0; run < 6; ++run) {
        const FrameStats many = stats(8);
        EXPECT_EQ(many.depthSignedMean, one.depthSignedMean) << "run " << run;
        EXPECT_EQ(many.depthError.mean, one.depthError.mean);
        EXPECT_EQ(many.error.mean, one.error.mean);
        EXPECT_EQ(many.error.p90, one.error.p90);
    }
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// `pgt render --channels`: frame.exr (OpenEXR) holds exactly the groups asked for, with the
// same values as the full file; "none" writes no frame.exr (summary.json and the maps still,
// the map read back through OpenImageIO); a wrong group is refused naming it.
TEST(Render, ChannelSetKeepsOnlyTheGroupsAskedForAndTheMapsTheirLegend) {
    Scene s = test::planeScene(test::smoothTexture(16, 16), 0.05, -0.025, 45, 10, 32,
                               parseMethods(nlohmann::json::parse(R"(["parallax"])"), "t", "m"));
    RenderResult r = renderFrame(s, {.timingRepeats = 0});
    auto write = [&](const std::string& list) {
        auto dir = test::tempDir("channels_" + list.substr(0, 2));
        std::vector<MethodConfig> configs = {r.methods[0].config};
        RenderWriter writer(s, dir.string(), 32, 32, configs, "piz",
                            parseFrameChannels(list, "--channels"));
        writer.band(r, wholeFrameBand(r));
        writer.finish(r);
        return dir;
    };
    auto read = [](const std::filesystem::path& file) {
        std::map<std::string, std::vector<float>> channels;
        auto in = OIIO::ImageInput::open(file.string());
        EXPECT_TRUE(in);
        if (!in) return channels;
        const OIIO::ImageSpec& spec = in->spec();
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
        for (int c = 0; c < spec.nchannels; ++c)
            for (size_t k = 0; k < size_t(spec.width) * spec.height; ++k)
                channels[spec.channelnames[size_t(c)]].push_back(px[k * spec.nchannels + c]);
        return channels;
    };
    const auto all = write("all"), some = write("uv,inputs"), none = write("none");
    const auto full = read(all / "frame.exr"), part = read(some / "frame.exr");
    EXPECT_EQ(full.size(), 6u + 5 + 2 + 6);
    // "uv,inputs": the schema's channels of those two groups.
    std::vector<std::string> want;
    for (const FrameChannelSlot& slot : frameChannelLayout({"parallax"}, false))
        if (slot.channel->group == ChannelGroup::Uv || slot.channel->group == ChannelGroup::Inputs)
            want.push_back(slot.name);
    ASSERT_EQ(want.size(), 6u + 3 + 6);
    ASSERT_EQ(part.size(), want.size());
    for (const std::string& name : want) {
        ASSERT_TRUE(part.count(name)) << name;
        const auto &a = part.at(name), &b = full.at(name);
        ASSERT_EQ(a.size(), b.size());
        for (size_t k = 0; k < a.size(); ++k)
            EXPECT_TRUE(a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k]))) << name << k;
    }
    EXPECT_FALSE(std::filesystem::exists(none / "frame.exr"));
    EXPECT_TRUE(std::filesystem::exists(none / "summary.json"));
    EXPECT_TRUE(std::filesystem::exists(none / "parallax_error.png"));
    try {
        parseFrameChannels("uv,normals", "--channels");
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("normals"), std::string::npos) << e.what();
    }
    // The error map (libpng, FreeType): the frame's codes coloured, then a 70-row legend on a
    // canvas at least 560 wide: black beside the frame, the colour bar's first colour
    // (0.05, 0.03, 0.35) at (10, 32 + 30), and the title in white where DejaVu Sans is installed.
    auto png = OIIO::ImageInput::open((none / "parallax_error.png").string());
    ASSERT_TRUE(png);
    const OIIO::ImageSpec& ps = png->spec();
    ASSERT_EQ(ps.width, 560);
    ASSERT_EQ(ps.height, 32 + 70);
    ASSERT_EQ(ps.nchannels, 3);
    std::vector<uint8_t> rgb(size_t(ps.width) * size_t(ps.height) * 3);
    ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
    auto at = [&](int x, int y, int k) {
        return int(rgb[(size_t(y) * 560 + size_t(x)) * 3 + size_t(k)]);
    };
    EXPECT_EQ(at(100, 10, 0) + at(100, 10, 1) + at(100, 10, 2), 0);
    EXPECT_EQ(at(10, 62, 0), 13);
    EXPECT_EQ(at(10, 62, 1), 8);
    EXPECT_EQ(at(10, 62, 2), 89);
    int colouredFrame = 0, white = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) colouredFrame += at(x, y, 0) + at(x, y, 1) + at(x, y, 2) > 0;
    for (int y = 32; y < 32 + 22; ++y)
        for (int x = 0; x < 300; ++x)
            white += at(x, y, 0) > 200 && at(x, y, 1) > 200 && at(x, y, 2) > 200;
    EXPECT_EQ(colouredFrame, 32 * 32);
    if (std::filesystem::exists("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")) {
        EXPECT_GT(white, 20) << "no title text";
    }
    for (const auto& d : {all, some, none}) std::filesystem::remove_all(d);
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// Presets measure the scene's surface (docs/methods.md "Engine presets"): on a surface its
// engine expresses (b = -s for LearnOpenGL's depth map), learnopengl_pom is pom with 8-32 layers
// pixel for pixel; where the scene's b is another (-s/2), it runs at b = -s, its configuration
// says so and the warnings name the mismatch; "amplitude": "shipped" keeps the shipped (0.1,
// -0.1) under the label learnopengl_pom_shipped.
// frame.exr's schema (frame/frame_channels.h) against docs/outputs.md and its own rules:
// every channel and group is documented (a method's as `M.suffix`, x/y/z triples as
// `NAME.x/y/z`), names are unique, a method's channels sit together in the configurations'
// order, and the count without building the layout agrees.
TEST(FrameChannels, EveryChannelAndGroupIsDocumentedAndLaidOutByTheSchema) {
    const std::string path = test::testSourceDir() + "/../docs/outputs.md";
    const std::string text = readTextFile(path, path, "", "the documentation", 1 << 22);
    const size_t from = text.find("- `DIR/frame.exr`"), to = text.find("- `DIR/summary.json`");
    ASSERT_NE(from, std::string::npos);
    ASSERT_NE(to, std::string::npos);
    const std::string doc = text.substr(from, to - from);
    for (const FrameChannel& c : frameChannelSchema()) {
        std::string name = c.perMethod ? std::string("M") + c.name : c.name;
        const bool triple = name.size() > 2 && name[name.size() - 2] == '.' &&
                            std::string("xyz").find(name.back()) != std::string::npos;
        const std::string asTriple = triple ? name.substr(0, name.size() - 1) + "x/y/z" : name;
        EXPECT_TRUE(doc.find("`" + name + "`") != std::string::npos ||
                    doc.find("`" + asTriple + "`") != std::string::npos)
            << name << " is not in docs/outputs.md's frame.exr paragraph";
    }
    for (const char* g : channelGroupNames())
        EXPECT_NE(doc.find(std::string("`") + g + "`"), std::string::npos) << g;
    for (bool inputs : {false, true}) {
        const std::vector<std::string> labels = {"a", "b", "c"};
        const std::vector<FrameChannelSlot> layout = frameChannelLayout(labels, inputs);
        EXPECT_EQ(layout.size(), frameChannelCount(labels.size(), inputs));
        std::set<std::string> unique;
        size_t lastMethod = 0;
        const FrameChannel* lastRun = nullptr;
        for (const FrameChannelSlot& s : layout) {
            EXPECT_TRUE(unique.insert(s.name).second) << s.name;
            if (!s.channel->perMethod) {
                lastRun = nullptr;
                continue;
            }
            // Within a run of per-method channels, the method index never goes back.
            if (lastRun) {
                EXPECT_GE(s.method, lastMethod) << s.name;
            }
            EXPECT_EQ(s.name, labels[s.method] + s.channel->name);
            lastMethod = s.method, lastRun = s.channel;
        }
        EXPECT_EQ(unique.count("base.Vvertex.x"), inputs ? 1u : 0u);
    }
}

TEST(Presets, OnTheScenesSurfaceADocumentPresetIsItsBuiltIn) {
    auto scene = [](double s, double b) {
        return parseScene(nlohmann::json::parse(R"({
            "heightmap": {"procedural": "bricks", "size": [64, 64]},
            "displacement": {"scale": )" + std::to_string(s) +
                                                R"(, "bias": )" + std::to_string(b) + R"(},
            "base": {"type": "plane", "infinite": true},
            "camera": {"type": "orthographic", "theta": 60, "phi": 30, "frame": "fill",
                       "resolution": [48, 48]},
            "methods": [{"name": "pom", "min_layers": 8, "max_layers": 32},
                        {"preset": "learnopengl_pom"},
                        {"preset": "learnopengl_pom", "amplitude": "shipped"}],
            "truth": {"rate": 1, "uncertainty": false}})"),
                          "presets.json");
    };
    const RenderResult same = renderFrame(scene(0.04, -0.04), {.timingRepeats = 0});
    ASSERT_EQ(same.methods.size(), 3u);
    EXPECT_EQ(same.methods[1].config.label, "learnopengl_pom");
    EXPECT_EQ(same.methods[2].config.label, "learnopengl_pom_shipped");
    int differ = 0, apart = 0;
    for (size_t k = 0; k < same.methods[0].pixels.data.size(); ++k) {
        const Vec2d a = same.methods[0].pixels.data[k].uv, b = same.methods[1].pixels.data[k].uv;
        differ += !(a == b || (std::isnan(a.x) && std::isnan(b.x)));
        apart += glm::length(same.methods[2].pixels.data[k].uv - a) * 64 > 0.1;
    }
    EXPECT_EQ(differ, 0);
    EXPECT_GT(apart, 500);  // the shipped (0.1, -0.1) is another surface
    EXPECT_EQ(same.methods[1].stats.error.mean, same.methods[0].stats.error.mean);
    // b = -s/2: the preset runs at b = -s (its configuration says so), pom at the scene's b.
    const RenderResult other = renderFrame(scene(0.04, -0.02), {.timingRepeats = 0});
    EXPECT_EQ(toJson(other.methods[1].config).value("bias_per_scale", 0.0), -1.0);
    EXPECT_GT(other.methods[1].stats.error.mean, 2 * other.methods[0].stats.error.mean);
    bool named = false;
    for (const MethodWarning& w : other.methods[1].warnings)
        named = named || (w.kind == "worse_than_none" &&
                          w.text.find("amplitude or bias mismatch") != std::string::npos);
    std::printf("learnopengl_pom at b = -s/2: %.4f texels, pom %.4f\n",
                other.methods[1].stats.error.mean, other.methods[0].stats.error.mean);
    if (!other.methods[1].warnings.empty()) {
        EXPECT_TRUE(named);
    }
}

}  // namespace
}  // namespace pgt
