// The stiff suite: per scene and method the counts users look for where methods break.
#include "study/stress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "study/render.h"

namespace pgt {

namespace fs = std::filesystem;

const std::vector<std::string>& stressColumns() {
    static const std::vector<std::string> cols = {"scene",
                                                  "label",
                                                  "method",
                                                  "pixels",
                                                  "truth_only",
                                                  "raster_only",
                                                  "nonfinite",
                                                  "diverged",
                                                  "zero_divide",
                                                  "step_limit",
                                                  "mean",
                                                  "p99",
                                                  "max",
                                                  "truth_uncertainty_p99",
                                                  "truth_float_p99",
                                                  "truth_float_max",
                                                  "truth_float_samples",
                                                  "truth_edge_misses"};
    return cols;
}

namespace {
std::string num(double x) { return formatNumber(x, 6); }
}  // namespace

int runStress(const std::vector<std::string>& paths, const StressOptions& opt) {
    std::vector<std::string> files;
    for (const auto& p : paths) {
        if (fs::is_directory(p)) {
            std::vector<std::string> inDir;
            for (const auto& e : fs::directory_iterator(p))
                if (e.path().extension() == ".json") inDir.push_back(e.path().string());
            std::sort(inDir.begin(), inDir.end());
            files.insert(files.end(), inDir.begin(), inDir.end());
        } else {
            files.push_back(p);
        }
    }
    if (files.empty()) throw InputError("", "scenes", "(none)", "no scene files given");
    // Validate everything first: a bad scene fails before any output exists.
    std::vector<Scene> scenes;
    for (const auto& f : files) {
        scenes.push_back(loadScene(f));
        Scene& s = scenes.back();
        if (opt.resolution > 0) s.camera.width = s.camera.height = opt.resolution;
        checkViewMemory(s, s.camera.width, s.camera.height, s.methods.size(), false, false,
                        "camera.resolution");
    }
    prepareOutputDir(opt.outDir);

    std::ostringstream csv;
    for (size_t k = 0; k < stressColumns().size(); ++k) csv << (k ? "," : "") << stressColumns()[k];
    csv << "\n";
    std::printf("%-22s %-16s %8s %9s %8s %10s %10s %12s\n", "scene", "method", "pixels",
                "nonfinite", "diverged", "mean", "truth unc", "truth f32");
    for (size_t i = 0; i < scenes.size(); ++i) {
        Scene& s = scenes[i];
        std::string name = fs::path(files[i]).stem().string();
        TruthBuilder builder(s);
        TruthPair truths = builder.build(s.displacement, s.truth.uncertainty);
        MethodTextureCache textures(s.height, s.uvExtent);
        Camera cam = makeCamera(s);
        // No method timing: the stress table reports counts and errors, not cost.
        RenderResult r = renderView(s, cam, truths, s.methods, textures, {0, 0, 1}, false);
        PrecisionCheck pc = truths.truth->checkPrecision(cam, s.height, opt.precisionSamples);
        for (const auto& m : r.methods) {
            const FrameStats& st = m.stats;
            csv << name << ',' << m.config.label << ',' << m.config.name << ',' << st.error.count
                << ',' << st.coverage.truthOnly << ',' << st.coverage.rasterOnly << ','
                << st.nonfinite << ',' << st.diverged << ',' << st.zeroDivide << ',' << st.stepLimit
                << ',' << num(st.error.mean) << ',' << num(st.error.p99) << ',' << num(st.error.max)
                << ',' << num(r.haveUncertainty ? r.uncertainty.p99Texels : NAN) << ','
                << num(pc.p99Texels) << ',' << num(pc.maxTexels) << ',' << pc.samples << ','
                << pc.edgeMisses << '\n';
            std::printf("%-22s %-16s %8lld %9lld %8lld %10.4g %10.4g %12.4g\n", name.c_str(),
                        m.config.label.c_str(), (long long)st.error.count, (long long)st.nonfinite,
                        (long long)st.diverged, st.error.mean,
                        r.haveUncertainty ? r.uncertainty.p99Texels : NAN, pc.maxTexels);
        }
        if (opt.progress)
            std::fprintf(stderr, "stress: %zu/%zu %s\n", i + 1, scenes.size(), name.c_str());
    }
    writeTextFile((fs::path(opt.outDir) / "stress.csv").string(), csv.str());
    return int(scenes.size());
}

}  // namespace pgt
