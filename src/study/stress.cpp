// The stiff suite: per scene and method the counts users look for where methods break.
#include "study/stress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "frame/render.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "study/provenance.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// stress.csv numbers: 6 significant digits (errors in texels, counts exact).
std::string num(double x) { return formatNumber(x, 6); }

// One stress.csv row: a scene (by file stem), its frame, one method, the precision check.
struct StressRow {
    const std::string& scene;
    const RenderResult& r;
    const MethodFrame& m;
    const PrecisionCheck& pc;
};

// stress.csv (docs/studies.md "Stiff cases"): the columns in order, each with how a row writes it.
const CsvTable<StressRow>& stressTable() {
    using Col = CsvColumn<StressRow>;
    auto count = [](int64_t FrameStats::*field) {
        return [field](const StressRow& x) { return std::to_string(x.m.stats.*field); };
    };
    static const CsvTable<StressRow> table({
        Col{"scene", [](const StressRow& x) { return x.scene; }},
        Col{"label", [](const StressRow& x) { return x.m.config.label; }},
        Col{"method", [](const StressRow& x) { return x.m.config.name; }},
        Col{"pixels", [](const StressRow& x) { return std::to_string(x.m.stats.error.count); }},
        Col{"truth_only",
            [](const StressRow& x) { return std::to_string(x.m.stats.coverage.truthOnly); }},
        Col{"raster_only",
            [](const StressRow& x) { return std::to_string(x.m.stats.coverage.rasterOnly); }},
        Col{"nonfinite", count(&FrameStats::nonfinite)},
        Col{"diverged", count(&FrameStats::diverged)},
        Col{"zero_divide", count(&FrameStats::zeroDivide)},
        Col{"step_limit", count(&FrameStats::stepLimit)},
        Col{"mean", [](const StressRow& x) { return num(x.m.stats.error.mean); }},
        Col{"p99", [](const StressRow& x) { return num(x.m.stats.error.p99); }},
        Col{"max", [](const StressRow& x) { return num(x.m.stats.error.max); }},
        Col{"truth_uncertainty_p99",
            [](const StressRow& x) {
                return num(x.r.haveUncertainty ? x.r.uncertainty.p99Texels : NAN);
            }},
        Col{"truth_float_p99", [](const StressRow& x) { return num(x.pc.p99Texels); }},
        Col{"truth_float_max", [](const StressRow& x) { return num(x.pc.maxTexels); }},
        Col{"truth_float_samples", [](const StressRow& x) { return std::to_string(x.pc.samples); }},
        Col{"truth_edge_misses",
            [](const StressRow& x) { return std::to_string(x.pc.edgeMisses); }},
    });
    return table;
}

}  // namespace

const std::vector<std::string>& stressColumns() {
    static const std::vector<std::string> names = stressTable().names();
    return names;
}

namespace {

// The scene files named: files as given, folders' *.json in name order.
std::vector<std::string> sceneFiles(const std::vector<std::string>& paths) {
    std::vector<std::string> files;
    for (const auto& p : paths) {
        // A symlink loop, an unreadable folder: bad input naming it, not an internal error.
        std::error_code ec;
        const bool folder = fs::is_directory(p, ec);
        auto unreadable = [&](const std::string& path) {
            throw InputError(path, "", "", "cannot read the scene folder: " + ec.message());
        };
        if (ec && ec != std::errc::no_such_file_or_directory) unreadable(p);
        if (!folder) {
            files.push_back(p);  // loadScene names it if it cannot be read
            continue;
        }
        std::vector<std::string> inDir;
        for (fs::directory_iterator it(p, ec), end; it != end && !ec; it.increment(ec))
            if (it->path().extension() == ".json") inDir.push_back(it->path().string());
        if (ec) unreadable(p);
        std::sort(inDir.begin(), inDir.end());
        files.insert(files.end(), inDir.begin(), inDir.end());
    }
    return files;
}

}  // namespace

int runStress(const std::vector<std::string>& paths, const StressOptions& opt) {
    const std::vector<std::string> files = sceneFiles(paths);
    if (files.empty()) throw InputError("", "scenes", "(none)", "no scene files given");
    // Validate everything first: a bad scene fails before any output exists.
    std::vector<Scene> scenes;
    for (const auto& f : files) {
        scenes.push_back(loadScene(f));
        Scene& s = scenes.back();
        if (opt.resolution > 0) s.camera.width = s.camera.height = opt.resolution;
        checkViewMemory(s, s.camera.width, s.camera.height, {.configs = &s.methods},
                        "camera.resolution");
    }
    OutputDirectory out(opt.outDir);  // removed again if the suite fails

    std::string csv = stressTable().header();
    std::printf("%-22s %-16s %8s %9s %8s %10s %10s %12s\n", "scene", "method", "pixels",
                "nonfinite", "diverged", "mean", "truth unc", "truth f32");
    for (size_t i = 0; i < scenes.size(); ++i) {
        Scene& s = scenes[i];
        std::string name = fs::path(files[i]).stem().string();
        TruthBuilder builder(s);
        TruthPair truths = builder.build(s.displacement, s.truth.uncertainty);
        MethodTextureCache textures(s.height, s.uvExtent);
        // No method timing: the stress table reports counts and errors, not cost.
        RenderResult r = renderView(s, s.view(), truths, s.methods, textures, {0, 0, 1},
                                    FrameOptions{.keepImages = false, .sinks = {}});
        PrecisionCheck pc = truths.truth->checkPrecision(r.camera, s.height, opt.precisionSamples);
        for (const auto& m : r.methods) {
            const FrameStats& st = m.stats;
            csv += stressTable().line(StressRow{name, r, m, pc});
            std::printf("%-22s %-16s %8lld %9lld %8lld %10.4g %10.4g %12.4g\n", name.c_str(),
                        m.config.label.c_str(), (long long)st.error.count, (long long)st.nonfinite,
                        (long long)st.diverged, st.error.mean,
                        r.haveUncertainty ? r.uncertainty.p99Texels : NAN, pc.maxTexels);
        }
        if (opt.progress)
            std::fprintf(stderr, "stress: %zu/%zu %s\n", i + 1, scenes.size(), name.c_str());
    }
    writeTextFile((fs::path(opt.outDir) / "stress.csv").string(), csv);
    writeTextFile((fs::path(opt.outDir) / "provenance.json").string(), provenance().dump(2) + "\n");
    out.keep();
    return int(scenes.size());
}

}  // namespace pgt
