// Output writers: EXR through OpenImageIO, JSON through nlohmann, PNG error maps with a
// legend drawn by OpenImageIO (text needs a TrueType font; without one the legend has no
// words but keeps its colour bar).
#include "study/outputs.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/error.h"
#include "core/json_fields.h"
#include "methods/registry.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// A temporary sibling of `path` with the same extension (OIIO picks the format by it).
std::string tempSibling(const std::string& path) {
    fs::path p(path);
    static std::mt19937_64 rng(std::random_device{}());
    std::ostringstream os;
    os << p.stem().string() << ".tmp" << std::hex << (rng() & 0xffffff) << p.extension().string();
    return (p.parent_path() / os.str()).string();
}

void commitTemp(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw OutputError("cannot write " + path + ": " + ec.message());
    }
}

void writeImage(const std::string& path, const OIIO::ImageBuf& buf) {
    std::string tmp = tempSibling(path);
    if (!buf.write(tmp)) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw OutputError("cannot write " + path + ": " + buf.geterror());
    }
    commitTemp(tmp, path);
}

}  // namespace

void writeTextFile(const std::string& path, const std::string& text) {
    std::string tmp = tempSibling(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw OutputError("cannot write " + path);
        }
    }
    commitTemp(tmp, path);
}

void writeExr(const std::string& path, const std::vector<std::string>& names,
              const std::vector<const Image2D<float>*>& channels) {
    PGT_CHECK_EQ(names.size(), channels.size());
    PGT_CHECK(!channels.empty());
    const int W = channels[0]->width, H = channels[0]->height, nc = int(channels.size());
    OIIO::ImageSpec spec(W, H, nc, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.attribute("compression", "zip");
    std::vector<float> interleaved(size_t(W) * H * nc);
    for (int c = 0; c < nc; ++c)
        for (size_t k = 0; k < size_t(W) * H; ++k) interleaved[k * nc + c] = channels[c]->data[k];
    OIIO::ImageBuf buf(spec, interleaved.data());
    writeImage(path, buf);
}

Json toJson(const FrameStats& s) {
    auto num = [](double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); };
    return {
        {"pixels", s.error.count},
        {"error_texels",
         {{"mean", num(s.error.mean)},
          {"rms", num(s.error.rms)},
          {"p50", num(s.error.p50)},
          {"p90", num(s.error.p90)},
          {"p99", num(s.error.p99)},
          {"max", num(s.error.max)}}},
        {"frac_gt_1texel", num(s.fracAbove1Texel)},
        {"coverage",
         {{"both", s.coverage.both},
          {"truth_only", s.coverage.truthOnly},
          {"raster_only", s.coverage.rasterOnly},
          {"neither", s.coverage.neither}}},
        {"nonfinite", s.nonfinite},
        {"diverged", s.diverged},
        {"zero_divide", s.zeroDivide},
        {"step_limit", s.stepLimit},
        {"fetches", {{"mean", s.fetchesMean}, {"max", s.fetchesMax}}},
    };
}

Json summaryJson(const Scene& scene, const RenderResult& r) {
    const Camera& cam = r.camera;
    Json view = {{"type", cam.isOrthographic() ? "orthographic" : "pinhole"},
                 {"resolution", {cam.width(), cam.height()}},
                 {"forward", {cam.forward().x, cam.forward().y, cam.forward().z}},
                 {"up", {cam.up().x, cam.up().y, cam.up().z}}};
    if (cam.isOrthographic()) {
        Vec3d v = -cam.forward();
        view["view_direction"] = {v.x, v.y, v.z};  // V, toward the eye
        view["theta"] = scene.camera.theta;
        view["phi"] = scene.camera.phi;
        view["target"] = {cam.target().x, cam.target().y, cam.target().z};
        view["view_height"] = cam.viewHeight();
    } else {
        view["eye"] = {cam.eye().x, cam.eye().y, cam.eye().z};
        view["target"] = {cam.target().x, cam.target().y, cam.target().z};
        view["fov"] = cam.fovDegrees();
    }
    auto build = [](const TruthBuildStats& b) {
        return Json{{"segments", {b.segmentsU, b.segmentsV}},
                    {"vertices", b.vertices},
                    {"primitives", b.primitives},
                    {"geometry_bytes", b.geometryBytes},
                    {"tessellate_ms", b.tessellateMs},
                    {"build_ms", b.buildMs}};
    };
    Json truth = {{"rate", scene.truth.rate},
                  {"geometry", scene.truth.geometry == TruthGeometry::Grid ? "grid" : "triangles"},
                  {"build", build(r.truthBuild)},
                  // > 1: traced in blocks over windows; build is then the largest block's
                  {"blocks", r.truthBlocks}};
    int64_t hits = 0;
    for (const auto& t : r.truth.data) hits += t.hit;
    truth["hit_pixels"] = hits;
    if (r.haveUncertainty) {
        const TruthUncertainty& u = r.uncertainty;
        truth["uncertainty"] = {{"rate", u.rate},
                                {"rate_fine", u.rateFine},
                                {"pixels_compared", u.pixelsCompared},
                                {"hit_mismatch", u.hitMismatch},
                                {"p50_texels", u.p50Texels},
                                {"p99_texels", u.p99Texels},
                                {"max_texels", u.maxTexels}};
        truth["build_fine"] = build(r.truthBuildFine);
    }
    Json methods = Json::array();
    for (const auto& m : r.methods) {
        Json j = toJson(m.stats);
        j["label"] = m.config.label;
        if (m.haveExactFrame) {
            // The error with the exact frame is the method's own; the rest of the mean is
            // what the per-vertex tangent frame adds.
            j["exact_frame"] = toJson(m.statsExactFrame);
            double a = m.stats.error.mean, e = m.statsExactFrame.error.mean;
            j["frame_share_of_mean"] = a > 0 && std::isfinite(a) && std::isfinite(e)
                                           ? Json(1.0 - e / a) : Json(nullptr);
        }
        j["config"] = toJson(m.config);
        j["ns_per_px"] = m.nsPerPixel;
        j["timing_backend"] = m.timingBackend;
        methods.push_back(j);
    }
    return {{"tool", "pgt"},
            {"scene_file", scene.file},
            {"scene", resolvedSceneJson(scene)},
            {"view", view},
            {"truth", truth},
            {"raster", {{"covered_pixels", r.raster.covered},
                        {"no_exact_frame_pixels", r.raster.noExactFrame},
                        {"triangles_drawn", r.raster.trianglesDrawn},
                        {"triangles_culled", r.raster.trianglesCulled}}},
            {"methods", methods},
            {"timings_ms", r.timingsMs},
            {"units", {{"error", "texels of the height map (MODEL.md section 7)"},
                       {"ns_per_px", "single-threaded method time per rasterised pixel, median"},
                       {"scale_bias", "UV units (MODEL.md section 3)"}}}};
}

double errorScaleTexels(double p99Texels) {
    const double steps[3] = {1, 2, 5};
    double v = 0.01;
    for (int k = 0; k < 45; ++k) {
        v = steps[k % 3] * std::pow(10.0, k / 3 - 2);
        if (v >= p99Texels) break;
    }
    return v;
}

namespace {

using Rgb = std::array<float, 3>;

// A perceptually ordered ramp, dark blue -> blue -> green -> yellow -> red (our own stops).
Rgb errorColour(double t) {
    static const Rgb stops[5] = {{0.05f, 0.03f, 0.35f}, {0.10f, 0.45f, 0.90f},
                                 {0.15f, 0.75f, 0.35f}, {0.95f, 0.85f, 0.10f},
                                 {0.85f, 0.10f, 0.10f}};
    t = std::clamp(t, 0.0, 1.0) * 4;
    int i = std::min(int(t), 3);
    float f = float(t - i);
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f;
    return c;
}

const Rgb kTruthOnly = {0.55f, 0.0f, 0.55f};   // truth hit, raster missed or discarded
const Rgb kRasterOnly = {0.0f, 0.65f, 0.65f};  // raster covered, truth ray missed the sheet
const Rgb kNonFinite = {1.0f, 1.0f, 1.0f};     // uv' not finite
const Rgb kNeither = {0.12f, 0.12f, 0.12f};

std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

void writeErrorPng(const std::string& path, const MethodFrame& m,
                   const Image2D<TruthSample>& truth, double scale) {
    const int W = m.errTexels.width, H = m.errTexels.height;
    const int legendH = 70, canvasW = std::max(W, 560);
    OIIO::ImageSpec spec(canvasW, H + legendH, 3, OIIO::TypeDesc::UINT8);
    OIIO::ImageBuf buf(spec);
    OIIO::ImageBufAlgo::fill(buf, {0.0f, 0.0f, 0.0f});
    auto put = [&](int x, int y, const Rgb& c) { buf.setpixel(x, y, c.data(), 3); };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t k = size_t(y) * W + x;
            const MethodPixel& p = m.pixels.data[k];
            bool hit = truth.data[k].hit;
            Rgb c = kNeither;
            if (p.covered && (!std::isfinite(p.uv.x) || !std::isfinite(p.uv.y))) c = kNonFinite;
            else if (p.covered && hit) c = errorColour(m.errTexels.data[k] / scale);
            else if (hit) c = kTruthOnly;
            else if (p.covered) c = kRasterOnly;
            put(x, y, c);
        }
    // Legend: colour bar 0..scale texels, coverage swatches, title line.
    const int barX = 10, barY = H + 30, barW = 256, barH = 14;
    for (int x = 0; x < barW; ++x)
        for (int y = 0; y < barH; ++y) put(barX + x, barY + y, errorColour(x / double(barW - 1)));
    const int swX = barX + barW + 110;
    const std::pair<const char*, Rgb> swatches[3] = {
        {"truth only", kTruthOnly}, {"raster only", kRasterOnly}, {"non-finite", kNonFinite}};
    for (int s = 0; s < 3; ++s)
        for (int x = 0; x < 10; ++x)
            for (int y = 0; y < 10; ++y) put(swX + x, H + 8 + s * 20 + y, swatches[s].second);
    const float white[3] = {1, 1, 1};
    auto text = [&](int x, int y, const std::string& s) {
        OIIO::ImageBufAlgo::render_text(buf, x, y, s, 13, "DejaVuSans", white);
    };
    std::ostringstream title;
    title << m.config.label << ": mean " << fmt(std::round(m.stats.error.mean * 1000) / 1000)
          << ", p90 " << fmt(std::round(m.stats.error.p90 * 1000) / 1000) << " texels";
    text(barX, H + 18, title.str());
    text(barX, barY + barH + 14, "0");
    text(barX + barW / 2 - 8, barY + barH + 14, fmt(scale / 2));
    text(barX + barW - 10, barY + barH + 14, fmt(scale));
    text(barX + barW + 12, barY + barH - 2, ">= top: texels");
    for (int s = 0; s < 3; ++s) text(swX + 16, H + 18 + s * 20, swatches[s].first);
    writeImage(path, buf);
}

}  // namespace

void writeRenderOutputs(const Scene& scene, const RenderResult& r, const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw OutputError("cannot create output directory " + dir +
                          (ec ? ": " + ec.message() : std::string()));
    const int W = r.camera.width(), H = r.camera.height();

    // frame.exr: truth, base (rasterised uv0) and each method's uv' and error.
    std::vector<std::string> names;
    std::vector<Image2D<float>> planes;
    planes.reserve(6 + 3 * r.methods.size());
    auto add = [&](const std::string& name, auto fn) {
        Image2D<float> img(W, H);
        for (size_t k = 0; k < img.size(); ++k) img.data[k] = fn(k);
        names.push_back(name);
        planes.push_back(std::move(img));
    };
    add("truth.u", [&](size_t k) { return r.truth.data[k].hit ? float(r.truth.data[k].uv.x) : NAN; });
    add("truth.v", [&](size_t k) { return r.truth.data[k].hit ? float(r.truth.data[k].uv.y) : NAN; });
    add("truth.hit", [&](size_t k) { return r.truth.data[k].hit ? 1.0f : 0.0f; });
    add("base.u", [&](size_t k) { return r.fragments.data[k].covered ? float(r.fragments.data[k].uv0.x) : NAN; });
    add("base.v", [&](size_t k) { return r.fragments.data[k].covered ? float(r.fragments.data[k].uv0.y) : NAN; });
    add("base.hit", [&](size_t k) { return r.fragments.data[k].covered ? 1.0f : 0.0f; });
    for (const auto& m : r.methods) {
        add(m.config.label + ".u", [&](size_t k) { return m.pixels.data[k].covered ? float(m.pixels.data[k].uv.x) : NAN; });
        add(m.config.label + ".v", [&](size_t k) { return m.pixels.data[k].covered ? float(m.pixels.data[k].uv.y) : NAN; });
        add(m.config.label + ".err", [&](size_t k) { return m.errTexels.data[k]; });
    }
    std::vector<const Image2D<float>*> ptrs;
    for (const auto& p : planes) ptrs.push_back(&p);
    writeExr((fs::path(dir) / "frame.exr").string(), names, ptrs);

    Json summary = summaryJson(scene, r);
    for (size_t i = 0; i < r.methods.size(); ++i) {
        const MethodFrame& m = r.methods[i];
        double p99 = std::isfinite(m.stats.error.p99) ? m.stats.error.p99 : 0.0;
        double scale = errorScaleTexels(p99);
        writeErrorPng((fs::path(dir) / (m.config.label + "_error.png")).string(), m, r.truth, scale);
        summary["methods"][i]["error_map"] = {{"file", m.config.label + "_error.png"},
                                              {"scale_top_texels", scale}};
    }
    writeTextFile((fs::path(dir) / "summary.json").string(), summary.dump(2) + "\n");
}

}  // namespace pgt
