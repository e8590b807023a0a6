// Output writers: EXR through OpenImageIO, JSON through nlohmann, PNG error maps with a
// legend drawn by OpenImageIO (text needs a TrueType font; without one the legend has no
// words but keeps its colour bar).
#include "study/outputs.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/json_fields.h"
#include "methods/config.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// Temporaries are hidden siblings named ".NAME.pgt-tmp.PID.RANDOM": the PID tells a later
// run whether the writer is still alive (kill(pid, 0)), so a killed run's leftovers are
// removed and a running one's are not.
constexpr const char* kTempTag = ".pgt-tmp.";

std::string tempName(const std::string& name) {
    static std::mt19937_64 rng(std::random_device{}());
    std::ostringstream os;
    os << "." << name << kTempTag << ::getpid() << "." << std::hex << (rng() & 0xffffff);
    return os.str();
}

// Writes all of `bytes` to a new file `path` and flushes it to the disk; errors name `shown`
// (the final path the user asked for).
void writeNewFile(const std::string& path, const std::string& bytes, const std::string& shown) {
    int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw OutputError("cannot create " + shown + ": " + std::strerror(errno));
    size_t off = 0;
    int err = 0;
    while (off < bytes.size() && !err) {
        ssize_t n = ::write(fd, bytes.data() + off, bytes.size() - off);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            err = n < 0 ? errno : EIO;
        else
            off += size_t(n);
    }
    if (!err && ::fsync(fd) != 0) err = errno;
    if (::close(fd) != 0 && !err) err = errno;
    if (err) {
        std::error_code ec;
        fs::remove(path, ec);
        throw OutputError("cannot write " + shown + ": " + std::strerror(err));
    }
}

// "STEM.tmpHEX.EXT" (1 to 6 hex digits; EXT exr, png, json or csv): what earlier pgt
// versions named their temporaries. Written out by hand: std::regex draws GCC 12 warnings.
bool isLegacyTemporary(const std::string& name) {
    auto dot = name.rfind('.');
    if (dot == std::string::npos) return false;
    std::string ext = name.substr(dot + 1), rest = name.substr(0, dot);
    if (ext != "exr" && ext != "png" && ext != "json" && ext != "csv") return false;
    auto tag = rest.rfind(".tmp");
    if (tag == std::string::npos || tag == 0) return false;
    std::string hex = rest.substr(tag + 4);
    return !hex.empty() && hex.size() <= 6 &&
           hex.find_first_not_of("0123456789abcdef") == std::string::npos;
}

// Removes temporaries of pgt processes that no longer run (killed mid-write), and the
// "NAME.tmpHEX.EXT" temporaries of earlier pgt versions.
void removeStaleTemporaries(const std::string& dir) {
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        bool stale = false;
        auto tag = name.find(kTempTag);
        if (!name.empty() && name[0] == '.' && tag != std::string::npos) {
            long pid = std::strtol(name.c_str() + tag + std::strlen(kTempTag), nullptr, 10);
            stale = pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
        } else {
            stale = isLegacyTemporary(name);
        }
        std::error_code rm;
        if (stale && it->is_regular_file(rm)) fs::remove(it->path(), rm);
    }
}

}  // namespace

StagedFiles::StagedFiles(std::string dir) : dir_(std::move(dir)) {}

StagedFiles::~StagedFiles() {
    std::error_code ec;
    for (const auto& [tmp, path] : staged_) fs::remove(tmp, ec);
}

void StagedFiles::add(const std::string& name, const std::string& bytes) {
    const std::string tmp = (fs::path(dir_) / tempName(name)).string();
    const std::string path = (fs::path(dir_) / name).string();
    writeNewFile(tmp, bytes, path);
    staged_.push_back({tmp, path});
}

void StagedFiles::commit() {
    for (size_t k = 0; k < staged_.size(); ++k) {
        std::error_code ec;
        fs::rename(staged_[k].first, staged_[k].second, ec);
        if (ec) {
            staged_.erase(staged_.begin(), staged_.begin() + long(k));  // renamed ones stay
            throw OutputError("cannot write " + staged_.front().second + ": " + ec.message());
        }
    }
    staged_.clear();
}

namespace {
// Creates `dir` and removes the temporaries killed pgt processes left there.
void makeOutputDir(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw OutputError("cannot create output directory " + dir +
                          (ec ? ": " + ec.message() : std::string()));
    removeStaleTemporaries(dir);
}
}  // namespace

void prepareOutputDir(const std::string& dir) {
    makeOutputDir(dir);
    StagedFiles probe(dir);  // a file can be created there (removed again, uncommitted)
    probe.add("probe", "");
}

std::string encodeImage(const std::string& name, const OIIO::ImageBuf& buf) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput memory(bytes);
    auto out = OIIO::ImageOutput::create(name, &memory);
    bool ok = out && out->supports("ioproxy") && out->open(name, buf.spec()) &&
              buf.write(out.get()) && out->close();
    if (!ok) {
        std::string why = out ? out->geterror() : OIIO::geterror();
        throw OutputError("cannot encode " + name + ": " + (why.empty() ? "no writer" : why));
    }
    return std::string(bytes.begin(), bytes.end());
}

void writeTextFile(const std::string& path, const std::string& text) {
    fs::path p(path);
    StagedFiles files(p.parent_path().empty() ? "." : p.parent_path().string());
    files.add(p.filename().string(), text);
    files.commit();
}

namespace {

std::string encodeExr(const std::vector<std::string>& names,
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
    return encodeImage("frame.exr", buf);
}

}  // namespace

namespace {
// JSON has no NaN: a statistic that was not measured is null.
Json finiteOrNull(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }
}  // namespace

Json toJson(const FrameStats& s) {
    auto num = finiteOrNull;
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
    int64_t hits = 0;
    for (const auto& t : r.truth.data) hits += t.hit;
    truth["hit_pixels"] = hits;
    if (r.haveUncertainty) {
        const TruthUncertainty& u = r.uncertainty;
        truth["uncertainty"] = {{"rate", u.rate},
                                {"rate_fine", u.rateFine},
                                {"pixels_compared", u.pixelsCompared},
                                {"hit_mismatch", u.hitMismatch},
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
    j["label"] = m.config.label;
    if (m.haveExactFrame) {
        // The error with the exact frame is the method's own; the rest of the mean is
        // what the per-vertex tangent frame adds.
        j["exact_frame"] = toJson(m.statsExactFrame);
        double a = m.stats.error.mean, e = m.statsExactFrame.error.mean;
        j["frame_share_of_mean"] =
            a > 0 && std::isfinite(a) && std::isfinite(e) ? Json(1.0 - e / a) : Json(nullptr);
    }
    j["config"] = toJson(m.config);
    j["ns_per_px"] = m.nsPerPixel;
    j["timing_backend"] = m.timingBackend;
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
            {"timings_ms", r.timingsMs},
            {"units",
             {{"error", "texels of the height map (MODEL.md section 7)"},
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

// The error map of one method as PNG bytes.
std::string encodeErrorPng(const MethodFrame& m, const Image2D<TruthSample>& truth, double scale) {
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
            if (p.covered && (!std::isfinite(p.uv.x) || !std::isfinite(p.uv.y)))
                c = kNonFinite;
            else if (p.covered && hit)
                c = errorColour(m.errTexels.data[k] / scale);
            else if (hit)
                c = kTruthOnly;
            else if (p.covered)
                c = kRasterOnly;
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
    return encodeImage("error.png", buf);
}

}  // namespace

void writeRenderOutputs(const Scene& scene, const RenderResult& r, const std::string& dir) {
    makeOutputDir(dir);  // no probe: the staged writes below check every byte themselves
    StagedFiles files(dir);
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
    add("truth.u",
        [&](size_t k) { return r.truth.data[k].hit ? float(r.truth.data[k].uv.x) : NAN; });
    add("truth.v",
        [&](size_t k) { return r.truth.data[k].hit ? float(r.truth.data[k].uv.y) : NAN; });
    add("truth.hit", [&](size_t k) { return r.truth.data[k].hit ? 1.0f : 0.0f; });
    add("base.u", [&](size_t k) {
        return r.fragments.data[k].covered ? float(r.fragments.data[k].uv0.x) : NAN;
    });
    add("base.v", [&](size_t k) {
        return r.fragments.data[k].covered ? float(r.fragments.data[k].uv0.y) : NAN;
    });
    add("base.hit", [&](size_t k) { return r.fragments.data[k].covered ? 1.0f : 0.0f; });
    for (const auto& m : r.methods) {
        add(m.config.label + ".u", [&](size_t k) {
            return m.pixels.data[k].covered ? float(m.pixels.data[k].uv.x) : NAN;
        });
        add(m.config.label + ".v", [&](size_t k) {
            return m.pixels.data[k].covered ? float(m.pixels.data[k].uv.y) : NAN;
        });
        add(m.config.label + ".err", [&](size_t k) { return m.errTexels.data[k]; });
    }
    std::vector<const Image2D<float>*> ptrs;
    for (const auto& p : planes) ptrs.push_back(&p);
    files.add("frame.exr", encodeExr(names, ptrs));
    planes.clear();

    Json summary = summaryJson(scene, r);
    for (size_t i = 0; i < r.methods.size(); ++i) {
        const MethodFrame& m = r.methods[i];
        double p99 = std::isfinite(m.stats.error.p99) ? m.stats.error.p99 : 0.0;
        double scale = errorScaleTexels(p99);
        files.add(m.config.label + "_error.png", encodeErrorPng(m, r.truth, scale));
        summary["methods"][i]["error_map"] = {{"file", m.config.label + "_error.png"},
                                              {"scale_top_texels", scale}};
    }
    // summary.json last: its presence means the whole output is there.
    files.add("summary.json", summary.dump(2) + "\n");
    files.commit();
}

}  // namespace pgt
