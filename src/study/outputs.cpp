// Output writers: frame.exr, summary.json (nlohmann), the PNG error maps with their legends
// (the images through io/image_files.h; the legend's text needs DejaVu Sans, without which
// it has no words but keeps its colour bar).
#include "study/outputs.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/json_fields.h"
#include "io/image_files.h"
#include "io/staged_files.h"
#include "methods/config.h"
#include "study/provenance.h"
#include "study/result_columns.h"

namespace pgt {

namespace {
// JSON has no NaN: a statistic that was not measured is null.
Json finiteOrNull(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }
}  // namespace

double share(int64_t part, int64_t whole) { return whole > 0 ? double(part) / double(whole) : NAN; }

Json toJson(const FrameStats& s) {
    // What results.csv has no column for; the rest are its columns' keys (ResultColumn::jsonKey).
    Json j = {{"coverage", {{"both", s.coverage.both}, {"neither", s.coverage.neither}}},
              {"diverged", s.diverged},
              {"depth_error_texels",
               {{"pixels", s.depthError.count}, {"p50", finiteOrNull(s.depthError.p50)}}},
              {"shadow", {{"uv_right", s.shadow.right}, {"uv_wrong", s.shadow.wrong}}}};
    statsColumnsJson(s, j);
    return j;
}

namespace {

// summary.json's "view": the camera as built (and the view angles it was built from).
Json viewJson(const RenderResult& r) {
    const Camera& cam = r.camera;
    Json view = {{"type", cam.isOrthographic() ? "orthographic" : "pinhole"},
                 {"resolution", {cam.width(), cam.height()}},
                 {"forward", {cam.forward().x, cam.forward().y, cam.forward().z}},
                 {"up", {cam.up().x, cam.up().y, cam.up().z}}};
    if (cam.isOrthographic()) {
        Vec3d v = -cam.forward();
        view["view_direction"] = {v.x, v.y, v.z};  // V, toward the eye
        view["theta"] = r.view.camera.theta;
        view["phi"] = r.view.camera.phi;
        view["target"] = {cam.target().x, cam.target().y, cam.target().z};
        view["view_height"] = cam.viewHeight();
    } else {
        view["eye"] = {cam.eye().x, cam.eye().y, cam.eye().z};
        view["target"] = {cam.target().x, cam.target().y, cam.target().z};
        view["fov"] = cam.fovDegrees();
    }
    return view;
}

Json buildJson(const TruthBuildStats& b) {
    return Json{{"segments", {b.segmentsU, b.segmentsV}},
                {"vertices", b.vertices},
                {"primitives", b.primitives},
                {"geometry_bytes", b.geometryBytes},
                {"tessellate_ms", b.tessellateMs},
                {"build_ms", b.buildMs}};
}

// summary.json's "truth": its settings, build, hits and the truth-vs-truth uncertainty.
Json truthJson(const Scene& scene, const RenderResult& r) {
    Json truth = {{"rate", scene.truth.rate},
                  {"geometry", scene.truth.geometry == TruthGeometry::Grid ? "grid" : "triangles"},
                  {"build", buildJson(r.truthBuild)},
                  // > 1: traced in blocks over windows; build is then the largest block's
                  {"blocks", r.truthBlocks}};
    truth["hit_pixels"] = r.truthHits;
    truth["holes"] = r.truthHoles;  // 0 unless the sheet leaks (docs/model.md §5)
    if (r.haveUncertainty) {
        const TruthUncertainty& u = r.uncertainty;
        truth["uncertainty"] = {{"rate", u.rate},
                                {"rate_fine", u.rateFine},
                                {"pixels_compared", u.pixelsCompared},
                                {"hit_mismatch", u.hitMismatch},
                                {"holes_fine", u.holesFine},
                                {"shadow_mismatch", u.shadowMismatch},
                                {"shadow_compared", u.shadowCompared},
                                {"p50_texels", finiteOrNull(u.p50Texels)},
                                {"p99_texels", finiteOrNull(u.p99Texels)},
                                {"max_texels", finiteOrNull(u.maxTexels)}};
        truth["build_fine"] = buildJson(r.truthBuildFine);
    }
    return truth;
}

// One method's entry of summary.json's "methods".
Json methodJson(const MethodFrame& m) {
    Json j = toJson(m.stats);
    methodColumnsJson(m, j);  // the label and the timing, as results.csv's columns say them
    if (m.haveExactFrame) {
        // The error with the exact frame is the method's own; the rest of the mean is
        // what the per-vertex tangent frame adds. Both over the pixels with an exact frame.
        j["exact_frame"] = toJson(m.statsExactFrame);
        j["frame_share_of_mean"] = finiteOrNull(frameShareOfMean(m));
    }
    j["config"] = toJson(m.config);
    j["warnings"] = Json::array();
    for (const MethodWarning& w : m.warnings)
        j["warnings"].push_back({{"kind", w.kind}, {"text", w.text}});
    return j;
}

}  // namespace

Json summaryJson(const Scene& scene, const RenderResult& r) {
    Json methods = Json::array();
    for (const auto& m : r.methods) methods.push_back(methodJson(m));
    return {{"tool", "pgt"},
            {"scene_file", scene.file},
            {"scene", resolvedSceneJson(scene, r.view)},
            {"view", viewJson(r)},
            {"truth", truthJson(scene, r)},
            {"raster",
             {{"covered_pixels", r.raster.covered},
              {"no_exact_frame_pixels", r.raster.noExactFrame},
              {"triangles_drawn", r.raster.trianglesDrawn},
              {"triangles_culled", r.raster.trianglesCulled}}},
            {"methods", methods},
            {"provenance", provenance(sceneSha1(scene))},
            {"timings_ms", r.timings.byName()},
            {"units",
             {{"error", "texels of the height map (docs/model.md §7)"},
              {"ns_per_px", "single-threaded method time per rasterised pixel, median"},
              {"precompute_ms", "build time of the method's precomputed maps, once per map"},
              {"scale_bias", "UV units (docs/model.md §3)"}}}};
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
    static const Rgb stops[5] = {{0.05f, 0.03f, 0.35f},
                                 {0.10f, 0.45f, 0.90f},
                                 {0.15f, 0.75f, 0.35f},
                                 {0.95f, 0.85f, 0.10f},
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

std::string fmt(double v) { return formatNumber(v, 6); }  // as an ostream's default %g

Rgb errorMapColour(float code, double scale) {
    if (code >= 0) return errorColour(code / scale);
    return code == kCodeTruthOnly    ? kTruthOnly
           : code == kCodeRasterOnly ? kRasterOnly
           : code == kCodeNonFinite  ? kNonFinite
                                     : kNeither;
}

// A colour channel in [0, 1] as a byte, rounded.
uint8_t toByte(float c) { return uint8_t(std::clamp(c, 0.f, 1.f) * 255 + 0.5f); }

// The legend under an error map, drawn into `rgb` (canvasW x legendH, black): colour bar
// 0..scale texels, coverage swatches, title line.
void drawErrorLegend(uint8_t* rgb, const MethodFrame& m, int canvasW, int legendH, double scale) {
    auto put = [&](int x, int y, const Rgb& c) {
        for (int k = 0; k < 3; ++k)
            rgb[(size_t(y) * size_t(canvasW) + size_t(x)) * 3 + size_t(k)] = toByte(c[size_t(k)]);
    };
    const int barX = 10, barY = 30, barW = 256, barH = 14;
    for (int x = 0; x < barW; ++x)
        for (int y = 0; y < barH; ++y) put(barX + x, barY + y, errorColour(x / double(barW - 1)));
    const int swX = barX + barW + 110;
    const std::pair<const char*, Rgb> swatches[3] = {
        {"truth only", kTruthOnly}, {"raster only", kRasterOnly}, {"non-finite", kNonFinite}};
    for (int s = 0; s < 3; ++s)
        for (int x = 0; x < 10; ++x)
            for (int y = 0; y < 10; ++y) put(swX + x, 8 + s * 20 + y, swatches[s].second);
    auto text = [&](int x, int y, const std::string& s) {
        drawText(rgb, canvasW, legendH, x, y, s, 13);
    };
    std::ostringstream title;
    title << m.config.label << ": mean " << fmt(std::round(m.stats.error.mean * 1000) / 1000)
          << ", p90 " << fmt(std::round(m.stats.error.p90 * 1000) / 1000) << " texels";
    text(barX, 18, title.str());
    text(barX, barY + barH + 14, "0");
    text(barX + barW / 2 - 8, barY + barH + 14, fmt(scale / 2));
    text(barX + barW - 10, barY + barH + 14, fmt(scale));
    text(barX + barW + 12, barY + barH - 2, ">= top: texels");
    for (int s = 0; s < 3; ++s) text(swX + 16, 18 + s * 20, swatches[s].first);
}

// One method's error map into `out`: the frame (coloured over all cores), then the legend.
void writeErrorPng(StagedStream& out, const std::string& name, const MethodFrame& m,
                   const Image2D<float>& codes, double scale) {
    const int W = codes.width, H = codes.height;
    const int legendH = 70, canvasW = std::max(W, 560);
    std::vector<uint8_t> rgb(size_t(canvasW) * size_t(H + legendH) * 3, 0);
    tbb::parallel_for(0, H, [&](int y) {
        uint8_t* row = &rgb[size_t(y) * size_t(canvasW) * 3];
        for (int x = 0; x < W; ++x) {
            const Rgb c = errorMapColour(codes.at(x, y), scale);
            for (int k = 0; k < 3; ++k) row[size_t(x) * 3 + size_t(k)] = toByte(c[size_t(k)]);
        }
    });
    drawErrorLegend(&rgb[size_t(H) * size_t(canvasW) * 3], m, canvasW, legendH, scale);
    writePng(out, name, canvasW, H + legendH, rgb.data());
}

}  // namespace

FrameChannelSet parseFrameChannels(const std::string& list, const std::string& field) {
    if (list == "all") return {};
    FrameChannelSet set{{false, false, false, false}};
    if (list == "none") return set;
    const auto& names = channelGroupNames();
    size_t start = 0;
    while (start <= list.size()) {
        const size_t end = std::min(list.find(',', start), list.size());
        const std::string group = list.substr(start, end - start);
        const size_t g = size_t(std::find(names.begin(), names.end(), group) - names.begin());
        if (g == names.size())  // the item quoted, escaped and shortened (any text can come)
            throw InputError("command line", field, shortDump(Json(list)),
                             "expected all, none or a comma-separated list of " +
                                 joinNames(std::vector<std::string>(names.begin(), names.end())) +
                                 " (" + shortDump(Json(group)) + " is none of them)");
        set.groups[g] = true;
        start = end + 1;
    }
    return set;
}

FrameBand wholeFrameBand(const RenderResult& r) {
    FrameBand whole{0, r.camera.height(), &r.truth, &r.fragments, {}, {}};
    if (r.fragmentInputs.data.size() == r.fragments.data.size() && !r.fragments.data.empty())
        whole.inputs = &r.fragmentInputs;
    for (const MethodFrame& m : r.methods) {
        whole.pixels.push_back(&m.pixels);
        whole.errTexels.push_back(&m.errTexels);
    }
    return whole;
}

RenderWriter::RenderWriter(const Scene& scene, const std::string& dir, int width, int height,
                           const std::vector<MethodConfig>& configs,
                           const std::string& exrCompression, const FrameChannelSet& channels)
    : scene_(scene), width_(width), height_(height), dir_(dir) {
    std::error_code ec;
    createdDir_ = !std::filesystem::exists(std::filesystem::symlink_status(dir, ec));
    makeOutputDir(dir);  // no probe: the staged writes check every byte themselves
    files_ = std::make_unique<StagedFiles>(dir);
    const std::vector<FrameChannelSlot> layout = frameChannelLayout(configs);
    channels_ = layout.size();
    methods_ = configs.size();
    std::vector<std::string> kept;
    for (size_t c = 0; c < layout.size(); ++c)
        if (channels.holds(layout[c].channel->group))
            keep_.push_back(c), kept.push_back(layout[c].name);
    if (keep_.empty()) return;  // no frame.exr
    // PIZ (lossless wavelet + Huffman) by default: measured on the default scene at 2048^2,
    // 1.2 s against zip's 2.0 s of encoding for a file 2 % larger (116 vs 114 MB); "none"
    // writes 252 MB and saves the encoder's CPU (docs/outputs.md).
    exrFile_ = &files_->stream("frame.exr");
    // Its provenance as known when the file is begun (the GL, once it ran, is in summary.json).
    const Json prov = provenance(sceneSha1(scene_));
    exr_ = std::make_unique<ExrWriter>(
        *exrFile_, "frame.exr", width, height, kept, exrCompression,
        std::map<std::string, std::string>{{"pgt:version", prov["pgt"]["version"]},
                                           {"pgt:commit", prov["pgt"]["commit"]},
                                           {"pgt:command", prov["command"]},
                                           {"pgt:date", prov["date"]},
                                           {"pgt:scene_sha1", prov["scene_sha1"]},
                                           {"pgt:provenance", prov.dump()}});
}

// A writer dropped before its files were committed (a full disk, a cancelled study) takes
// its temporaries with it, and the directory it created if that is left empty: no empty
// images/case_N of a case that wrote nothing.
RenderWriter::~RenderWriter() {
    if (committed_ || !createdDir_) return;
    if (encoding_.valid()) encoding_.wait();
    exr_.reset();
    files_.reset();
    std::error_code ec;
    std::filesystem::remove(dir_, ec);  // only an empty directory goes
}

void RenderWriter::band(const RenderResult&, const FrameBand& b) {
    PGT_CHECK_EQ(b.pixels.size(), methods_);
    PGT_CHECK_EQ(frameChannelCount(methods_, b.inputs != nullptr), channels_);
    const size_t n = size_t(width_) * size_t(b.y1 - b.y0);
    // Two row buffers: this band is interleaved while the previous one is still encoded.
    std::vector<float>& rows = rows_[nextRows_];
    nextRows_ ^= 1;
    if (keep_.empty()) return;
    rows.resize(n * channels_);
    interleaveFrameBand(b, rows.data());
    if (keep_.size() < channels_) {  // the kept channels packed in place, pixel by pixel
        const size_t nk = keep_.size();
        for (size_t k = 0; k < n; ++k)
            for (size_t j = 0; j < nk; ++j) rows[k * nk + j] = rows[k * channels_ + keep_[j]];
    }
    // The encoder (on OpenEXR's threads) runs beside the next band's work.
    waitForRows();
    encoding_ = std::async(std::launch::async, [this, &rows, y0 = b.y0, y1 = b.y1] {
        exr_->writeRows(y0, y1, rows.data());
    });
}

void RenderWriter::waitForRows() {
    if (encoding_.valid()) encoding_.get();
}

nlohmann::json RenderWriter::finish(const RenderResult& r) {
    // frame.exr's last rows and its close (the file's offsets, the staged copy's flush) beside
    // the error maps' encoding.
    std::future<void> exrClosed = std::async(std::launch::async, [this] {
        waitForRows();
        rows_[0] = {}, rows_[1] = {};
        if (exr_) exr_->close();
    });
    Json summary = summaryJson(scene_, r);
    std::vector<double> scales(r.methods.size());
    std::vector<StagedStream*> pngs;
    for (size_t i = 0; i < r.methods.size(); ++i) {
        const MethodFrame& m = r.methods[i];
        PGT_CHECK(m.coded.width == width_ && m.coded.height == height_);  // keepCodedErrors
        scales[i] = errorScaleTexels(std::isfinite(m.stats.error.p99) ? m.stats.error.p99 : 0.0);
        pngs.push_back(&files_->stream(m.config.label + "_error.png"));
        summary["methods"][i]["error_map"] = {{"file", m.config.label + "_error.png"},
                                              {"scale_top_texels", scales[i]}};
    }
    // The maps are independent: one per core.
    tbb::parallel_for(size_t(0), r.methods.size(), [&](size_t i) {
        writeErrorPng(*pngs[i], r.methods[i].config.label + "_error.png", r.methods[i],
                      r.methods[i].coded, scales[i]);
    });
    exrClosed.get();
    // summary.json last: its presence means the whole output is there.
    files_->add("summary.json", summary.dump(2) + "\n");
    files_->commit();
    committed_ = true;
    return summary;
}

nlohmann::json writeRenderOutputs(const Scene& scene, const RenderResult& r,
                                  const std::string& dir) {
    std::vector<MethodConfig> configs;
    for (const MethodFrame& m : r.methods) configs.push_back(m.config);
    RenderWriter writer(scene, dir, r.camera.width(), r.camera.height(), configs);
    writer.band(r, wholeFrameBand(r));
    return writer.finish(r);
}

}  // namespace pgt
