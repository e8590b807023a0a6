// pgt: command-line front end. Parses arguments, calls the library, maps errors to exit
// status: 0 ok, 1 internal error, 2 bad input (file, field, value), 3 output not writable.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "core/error.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "study/render.h"

namespace {

void printSummary(const pgt::RenderResult& r) {
    std::printf("%-20s %9s %9s %9s %9s %9s %8s %9s\n", "method", "mean", "p50", "p90", "p99",
                "max", "fetch/px", "ns/px");
    for (const auto& m : r.methods) {
        const auto& e = m.stats.error;
        std::printf("%-20s %9.4f %9.4f %9.4f %9.4f %9.4f %8.2f %9.1f", m.config.label.c_str(),
                    e.mean, e.p50, e.p90, e.p99, e.max, m.stats.fetchesMean, m.nsPerPixel);
        if (m.stats.nonfinite) std::printf("  nonfinite=%lld", (long long)m.stats.nonfinite);
        std::printf("\n");
    }
    if (r.haveUncertainty)
        std::printf("truth uncertainty (rate %d vs %d): p99 %.5f, max %.5f texels\n",
                    r.uncertainty.rate, r.uncertainty.rateFine, r.uncertainty.p99Texels,
                    r.uncertainty.maxTexels);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"pgt: Parallax Ground Truth - how wrong is your parallax mapping?"};
    app.require_subcommand(1);
    std::string scenePath, outDir;
    int repeats = 3;
    auto* render = app.add_subcommand("render", "Render one scene: truth, methods, error");
    render->add_option("scene", scenePath, "Scene file (JSON)")->required();
    render->add_option("--out", outDir, "Output directory")->required();
    render->add_option("--timing-repeats", repeats, "Timing passes per method (median)")
        ->check(CLI::Range(1, 100));
    CLI11_PARSE(app, argc, argv);

    try {
        if (*render) {
            pgt::Scene scene = pgt::loadScene(scenePath);
            pgt::RenderResult result = pgt::renderFrame(scene, {repeats});
            pgt::writeRenderOutputs(scene, result, outDir);
            printSummary(result);
            std::printf("wrote %s/frame.exr, %s/summary.json and %zu error maps\n",
                        outDir.c_str(), outDir.c_str(), result.methods.size());
        }
    } catch (const pgt::InputError& e) {
        std::cerr << "pgt: error: " << e.what() << "\n";
        return 2;
    } catch (const pgt::OutputError& e) {
        std::cerr << "pgt: error: " << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        std::cerr << "pgt: internal error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
