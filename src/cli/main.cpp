// pgt: command-line front end. Parses arguments, calls the library, maps errors to exit
// status: 0 ok, 1 internal error, 2 bad input (file, field, value), 3 output not writable.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "cli/report.h"
#include "cli/shard.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/memory.h"
#include "evaluate/evaluate.h"
#include "frame/render.h"
#include "io/image_files.h"
#include "io/staged_files.h"
#include "methods/presets/presets.h"
#include "methods/registry.h"
#include "scene/scene.h"
#include "study/fit.h"
#include "study/merge.h"
#include "study/outputs.h"
#include "study/provenance.h"
#include "study/stress.h"
#include "study/sweep.h"
#include "verdict/study_compare.h"

namespace {

// When the process reached its static initialisers: after the dynamic loader, before main.
const pgt::Clock::time_point kProcessStart = pgt::Clock::now();

void printSummary(const pgt::RenderResult& r) {
    const bool lit = r.view.light.has_value();
    std::printf("%-20s %9s %9s %9s %9s %9s %8s %9s %9s%s\n", "method", "mean", "p50", "p90", "p99",
                "max", "fetch/px", "ns/px", "depth", lit ? "   shadow" : "");
    for (const auto& m : r.methods) {
        const auto& e = m.stats.error;
        std::printf("%-20s %9.4f %9.4f %9.4f %9.4f %9.4f %8.2f %9.1f %9.4f", m.config.label.c_str(),
                    e.mean, e.p50, e.p90, e.p99, e.max, m.stats.fetchesMean, m.nsPerPixel,
                    m.stats.depthError.mean);
        if (lit)
            std::printf(" %8.2f%%",
                        100 * pgt::share(m.stats.shadow.differ, m.stats.shadow.compared));
        if (m.stats.nonfinite) std::printf("  nonfinite=%lld", (long long)m.stats.nonfinite);
        std::printf("\n");
    }
    if (r.haveUncertainty)
        std::printf("truth uncertainty (rate %d vs %d): p99 %.5f, max %.5f texels\n",
                    r.uncertainty.rate, r.uncertainty.rateFine, r.uncertainty.p99Texels,
                    r.uncertainty.maxTexels);
    if (r.haveUncertainty && lit)
        std::printf("truth shadows differing between the rates: %.2f%% of %lld pixels\n",
                    100 * pgt::share(r.uncertainty.shadowMismatch, r.uncertainty.shadowCompared),
                    (long long)r.uncertainty.shadowCompared);
    std::printf("depth: mean |depth offset error| in texels; %s\n",
                lit ? "shadow: pixels whose shadow differs from the truth's (docs/model.md §7b)"
                    : "no light: no shadows (docs/model.md §5b)");
    if (r.truthBlocks > 1)
        std::printf(
            "truth traced in %d blocks, each over the part of the plane it sees "
            "(truth.memory_mb)\n",
            r.truthBlocks);
    for (const auto& m : r.methods)
        for (const auto& w : m.warnings)
            std::fprintf(stderr, "pgt: warning: %s: %s\n", m.config.label.c_str(), w.text.c_str());
    // Nothing to compare: every mean above is NaN. A mesh facing away from the camera (its
    // back faces culled) is the usual cause.
    if (r.raster.covered == 0)
        std::fprintf(stderr,
                     "pgt: warning: no pixel of the base was rasterised (%lld triangles culled as "
                     "back faces, %lld truth hits): nothing was compared; turn the camera "
                     "(theta, phi) toward the surface's front or set base.cull_back_faces false\n",
                     (long long)r.raster.trianglesCulled, (long long)r.truthHits);
}

// `pgt render`: checks the memory estimate and --out before any work.
void renderCommand(const std::string& scenePath, const std::string& outDir,
                   const pgt::RenderOptions& options, const std::string& exrCompression,
                   const std::string& channelList) {
    const pgt::FrameChannelSet channels = pgt::parseFrameChannels(channelList, "--channels");
    pgt::Scene scene = pgt::loadScene(scenePath);
    pgt::checkViewMemory(scene, scene.camera.width, scene.camera.height,
                         {.configs = &scene.methods, .writesImages = true, .truthInBlocks = true},
                         "camera.resolution");
    pgt::OutputDirectory out(outDir);  // before the work, so a bad --out fails at once
    // The files are written as the frame's bands are made: memory follows the band.
    pgt::RenderWriter writer(scene, outDir, scene.camera.width, scene.camera.height, scene.methods,
                             exrCompression, channels);
    pgt::RenderOptions opt = options;
    opt.frame = {.keepImages = false, .sinks = {&writer}, .keepCodedErrors = true};
    const double beforeMs = pgt::msSince(kProcessStart);  // the scene, its map, the outputs
    pgt::RenderResult result = pgt::renderFrame(scene, opt);
    auto t0 = pgt::Clock::now();
    writer.finish(result);  // the error maps and summary.json
    out.keep();
    const double finishMs = pgt::msSince(t0);
    printSummary(result);
    std::printf("stages (wall ms): before the frame (scene, map, outputs) %.0f,", beforeMs);
    for (const auto& [stage, ms] : result.timings.byName())
        std::printf(" %s %.0f,", stage.c_str(), ms);
    std::printf(" maps and summary %.0f\n", finishMs);
    std::printf("wrote %s/frame.exr, %s/summary.json and %zu error maps\n", outDir.c_str(),
                outDir.c_str(), result.methods.size());
}

// `pgt sweep`: the study, resumed where it stopped, and its report.
void sweepCommand(const std::string& scenePath, pgt::SweepOptions sweepOpt, bool noReport) {
    pgt::Scene scene = pgt::loadScene(scenePath);
    pgt::Study study = pgt::parseStudy(scene);
    std::printf("study: %zu cases x %zu method configurations at %dx%d\n", study.cases.size(),
                study.configs.size(), study.width, study.height);
    if (!noReport) sweepOpt.report = pgt::writeStudyReport;
    pgt::SweepSummary sum = pgt::runSweep(scene, study, sweepOpt);
    std::printf("%d cases run, %d resumed, %d of %d done in %.1f s: %s/results.csv\n", sum.done,
                sum.resumed, sum.done + sum.resumed, sum.total, sum.wallSeconds,
                sweepOpt.outDir.c_str());
    if (!sum.stageMs.empty()) {
        std::printf("stage totals (s):");
        for (const auto& [stage, ms] : sum.stageMs.byName())
            std::printf(" %s %.2f", stage.c_str(), ms / 1000);
        std::printf("\n");
    }
    if (!sum.finished) {
        std::printf("stopped early; run the same command again to resume\n");
    } else if (sweepOpt.shardCount > 1) {
        std::printf("shard %d of %d done; join the shards with pgt merge DIR... --out DIR\n",
                    sweepOpt.shardIndex, sweepOpt.shardCount);
    } else if (sum.reportTried) {
        if (sum.reportPath.empty())
            std::printf("report not written: %s\n", sum.reportWhy.c_str());
        else
            std::printf("report: %s\n", sum.reportPath.c_str());
    }
}

// `pgt merge`: the shards joined, and the study's report.
void mergeCommand(const std::vector<std::string>& dirs, const std::string& outDir, bool noReport) {
    pgt::MergeSummary m =
        pgt::mergeShards(dirs, outDir, noReport ? pgt::ReportWriter{} : pgt::writeStudyReport);
    std::printf("merged %d shards: %d cases, %d rows: %s/results.csv\n", m.shards, m.cases, m.rows,
                outDir.c_str());
    if (noReport) return;
    if (m.reportPath.empty())
        std::printf("report not written: %s\n", m.reportWhy.c_str());
    else
        std::printf("report: %s\n", m.reportPath.c_str());
}

// `pgt compare`: the verdict printed per configuration; exit 1 on a regression.
int compareCommand(const pgt::CompareOptions& opt, bool noFigures) {
    pgt::CompareSummary sum =
        pgt::compareStudies(opt, noFigures ? pgt::CompareFigures{} : pgt::writeCompareFigures);
    for (const auto& note : sum.notes) std::fprintf(stderr, "pgt: note: %s\n", note.c_str());
    for (const auto& v : sum.last.configs) {
        int changed = 0;
        for (size_t i : v.cells) changed += sum.last.cells[i].change != pgt::Change::Unchanged;
        std::printf("%-24s %-12s %d of %zu bands changed", v.labelOld.c_str(), toString(v.change),
                    changed, v.cells.size());
        for (const auto& c : v.changed) std::printf("; %s", c.c_str());
        std::printf("\n");
    }
    if (!sum.figuresWhy.empty() && !noFigures)
        std::printf("figures not drawn: %s\n", sum.figuresWhy.c_str());
    std::printf("%s: %s\n", sum.last.regressed() ? "REGRESSION" : "no regression",
                sum.markdownPath.c_str());
    return sum.last.regressed() ? 1 : 0;
}

// `pgt methods`: every built-in with its parameters, every preset with what its engine ships.
void methodsCommand() {
    // [keys]: the sources in docs/references.md.
    auto cite = [](const std::string& keys) { return keys.empty() ? "" : " [" + keys + "]"; };
    std::printf(
        "built-in methods: \"methods\": [NAME] or [{\"name\": NAME, PARAMETER: N}]; "
        "[keys]: docs/references.md\n");
    for (const pgt::MethodKindInfo& k : pgt::methodKinds()) {
        std::printf("  %-16s %s%s\n", k.name, k.summary, cite(k.cite).c_str());
        std::string parameters;
        for (const pgt::IntParameter& p : k.parameters)
            if (p.written)
                parameters += " " + std::string(p.key) + " " + std::to_string(p.lo) + "-" +
                              std::to_string(p.hi);
        if (!parameters.empty()) std::printf("  %-16s%s\n", "", parameters.c_str());
    }
    std::printf(
        "presets: \"methods\": [{\"preset\": NAME}] (docs/methods.md \"Engine presets\")\n");
    for (const pgt::MethodPreset& p : pgt::methodPresets())
        std::printf("  %-26s %s%s\n", p.name.c_str(), p.source.c_str(),
                    cite(pgt::presetCite(p.name)).c_str());
}

// `pgt fit`: each method's own scale, bias and steps, written to fit.json and printed.
void fitCommand(const std::string& scenePath, const std::string& outDir) {
    pgt::Scene scene = pgt::loadScene(scenePath);
    pgt::OutputDirectory out(outDir);  // before the search, so a bad --out fails at once
    pgt::FitReport rep = pgt::runFit(scene, true);
    pgt::writeTextFile(outDir + "/fit.json", rep.toJson().dump(2) + "\n");
    out.keep();
    std::printf("%-16s %5s %10s %10s %10s %10s %10s\n", "method", "steps", "scale", "bias",
                rep.objective.c_str(), "p90", "as listed");
    for (const auto& m : rep.methods) {
        if (!m.best) {  // every candidate gave non-finite UVs or no pixels
            std::printf("%-16s %5d %10s %10s %10s %10s %10.4f  no candidate with finite UVs\n",
                        m.method.c_str(), m.steps, "-", "-", "-", "-", m.nativeObjective);
            continue;
        }
        // A parameter that does not reach the shader is not fitted: "-" (fit.json leaves it out).
        auto shown = [](const std::optional<double>& v) {
            char text[32] = "-";
            if (v) std::snprintf(text, sizeof text, "%.5f", *v);
            return std::string(text);
        };
        std::printf("%-16s %5d %10s %10s %10.4f %10.4f %10.4f\n", m.method.c_str(), m.steps,
                    shown(m.scale).c_str(), shown(m.bias).c_str(), m.bestObjective, m.bestP90,
                    m.nativeObjective);
    }
    std::printf(
        "objective: %s UV error in texels averaged over %zu view angles, at %s; "
        "'as listed' = the scene's own (s, b)\n",
        rep.objective.c_str(), rep.thetas.size() * rep.phis.size(),
        rep.samples == "jittered"
            ? ("jittered samples (seed " + std::to_string(rep.seed) + ")").c_str()
            : "pixel centres");
    std::printf("wrote %s/fit.json\n", outDir.c_str());
}

// Everything the command line sets, and which command it chose.
struct CommandLine {
    std::string scenePath, outDir, glDevice, exrCompression = "auto", channels = "all";
    pgt::RenderOptions renderOpt;
    pgt::SweepOptions sweepOpt;
    bool noReport = false;
    bool noTiming = false;
    std::string shard;
    std::vector<std::string> mergeDirs;
    std::vector<std::string> stressPaths;
    pgt::StressOptions stressOpt;
    pgt::CompareOptions compareOpt;
    std::vector<std::string> comparePairs;
    std::string compareBands;
    uint64_t memoryLimitMb = pgt::defaultMemoryLimitMb();
    CLI::App *render = nullptr, *sweep = nullptr, *fit = nullptr, *stress = nullptr,
             *merge = nullptr, *compare = nullptr, *methods = nullptr;
};

// `pgt compare` and its options (docs/studies.md "Gating a shader change").
void defineCompare(CLI::App& app, CommandLine& c) {
    pgt::CompareOptions& o = c.compareOpt;
    c.compare = app.add_subcommand(
        "compare", "Regression verdict: NEW studies against OLD, per angle band, with noise");
    c.compare->add_option("dirs", o.dirs, "Study directories: OLD, then NEW (or a history)")
        ->required()
        ->expected(2, 1000);
    c.compare->add_option("--out", o.outDir, "Output directory for compare.md and figures")
        ->required();
    c.compare->add_option("--metric", o.metric, "results.csv column compared")
        ->check(CLI::IsMember(pgt::compareMetrics()))
        ->default_val(o.metric);
    c.compare->add_option("--bands", c.compareBands,
                          "Band edges in degrees, e.g. 0,30,60,90 (default: each theta)");
    c.compare->add_option("--pair", c.comparePairs, "Pair renamed labels: OLD_LABEL=NEW_LABEL");
    c.compare
        ->add_option("--alpha", o.verdict.alpha,
                     "False-alarm level over all bands (Benjamini-Hochberg)")
        ->check(CLI::Range(1e-9, 0.5))
        ->default_val(o.verdict.alpha);
    c.compare->add_option("--min-effect", o.verdict.minEffect, "Smallest relative change judged")
        ->check(CLI::Range(0.0, 10.0))
        ->default_val(o.verdict.minEffect);
    c.compare->add_option("--floor", o.verdict.floor, "Texels added to every mean before a ratio")
        ->check(CLI::Range(0.0, 1e3))
        ->default_val(o.verdict.floor);
    c.compare->add_flag("--any-scene", o.anyScene, "Compare studies of different scenes");
    c.compare->add_flag("--no-figures", c.noReport, "Do not run analysis/compare.py");
}

// `pgt render` and its options.
void defineRender(CLI::App& app, CommandLine& c) {
    c.render = app.add_subcommand("render", "Render one scene: truth, methods, error");
    c.render->add_option("scene", c.scenePath, "Scene file (JSON)")->required();
    c.render->add_option("--out", c.outDir, "Output directory")->required();
    c.render
        ->add_option("--timing-repeats", c.renderOpt.timingRepeats,
                     "Timing passes per method (median)")
        ->check(CLI::Range(1, 100));
    c.render
        ->add_flag("--no-timing", c.noTiming,
                   "Measure accuracy only: no timing passes (ns/px nan), the fastest run")
        ->excludes("--timing-repeats");
    c.render
        ->add_option("--timing-fragments", c.renderOpt.timingFragments,
                     "Time methods on a seeded subset of this many fragments (0: all)")
        ->check(CLI::Range(0, 1 << 26));
    c.render
        ->add_option("--gl-timing-fragments", c.renderOpt.glTimingFragments,
                     "GLSL methods: repeat the subset to this many fragments per timed draw")
        ->check(CLI::Range(int64_t(1), int64_t(1) << 23));
    c.render
        ->add_option("--exr-compression", c.exrCompression,
                     "frame.exr's compression: auto (default: zip for narrow frames, piz for "
                     "wide ones, both lossless), piz, zip, none (fastest)")
        ->check(CLI::IsMember(pgt::exrCompressionNames()));
    c.render->add_option("--channels", c.channels,
                         "frame.exr's channel groups: all (default), none (no frame.exr), or a "
                         "list of uv, depth, shadow, inputs");
}

void defineCommands(CLI::App& app, CommandLine& c) {
    app.require_subcommand(1);
    defineRender(app, c);
    c.sweep = app.add_subcommand("sweep", "Run the scene's study (its \"sweep\" block)");
    c.sweep->add_option("scene", c.scenePath, "Scene file (JSON) with a \"sweep\" block")
        ->required();
    c.sweep->add_option("--out", c.sweepOpt.outDir, "Output directory (resumed if it exists)")
        ->required();
    c.sweep->add_flag("--images", c.sweepOpt.images, "Also write every case's images");
    c.sweep->add_flag("--fresh", c.sweepOpt.fresh, "Discard earlier results instead of resuming");
    c.sweep->add_flag("--no-report", c.noReport, "Do not run analysis/report.py at the end");
    c.sweep->add_option("--max-cases", c.sweepOpt.maxCases, "Stop after this many new cases")
        ->check(CLI::Range(0, 1 << 30));
    c.sweep->add_option("--shard", c.shard,
                        "Run only shard I of N (I/N; slurm:N or slurm: from the job array)");

    c.merge = app.add_subcommand("merge", "Join the shards of one study into one study");
    c.merge->add_option("dirs", c.mergeDirs, "The shards' output directories")->required();
    c.merge->add_option("--out", c.outDir, "Output directory for the whole study")->required();
    c.merge->add_flag("--no-report", c.noReport, "Do not run analysis/report.py at the end");

    defineCompare(app, c);
    c.methods = app.add_subcommand(
        "methods",
        "List every built-in method and engine preset: summary, parameters, source keys");

    c.fit = app.add_subcommand("fit", "Fit each method's own scale, bias and steps to the truth");
    c.fit->add_option("scene", c.scenePath, "Scene file (JSON), optional \"fit\" block")
        ->required();
    c.fit->add_option("--out", c.outDir, "Output directory for fit.json")->required();

    c.stress = app.add_subcommand("stress", "Run the stiff suite (scenes/stress/)");
    c.stress->add_option("scenes", c.stressPaths, "Scene files or folders of them")->required();
    c.stress->add_option("--out", c.stressOpt.outDir, "Output directory for stress.csv")
        ->required();
    c.stress
        ->add_option("--resolution", c.stressOpt.resolution, "Override every scene's resolution")
        ->check(CLI::Range(1, 4096));
    // GLSL methods: the GL they run in. Default: Mesa's EGL surfaceless platform
    // (llvmpipe without a GPU); egl-device:N picks the N-th EGL device (a hardware GPU).
    for (CLI::App* sub : {c.render, c.sweep, c.stress})
        sub->add_option("--gl-device", c.glDevice,
                        "GL for GLSL methods: egl-device:N (default: EGL surfaceless, Mesa)");
    for (CLI::App* sub : {c.render, c.sweep, c.fit, c.stress, c.merge})
        sub->add_option("--memory-limit", c.memoryLimitMb,
                        "Refuse inputs estimated to need more memory than this (MB)")
            ->check(CLI::Range(uint64_t(64), uint64_t(1) << 30))
            ->default_val(c.memoryLimitMb);
}

// Runs the chosen command; the exit status: 2 bad input, 3 an output that cannot be
// written, 1 anything else (README "Commands").
int runCommand(const CommandLine& c) {
    try {
        pgt::setMemoryLimitMb(c.memoryLimitMb);
        if (!c.glDevice.empty()) pgt::selectGlDevice(c.glDevice);
        if (*c.render) {
            pgt::RenderOptions opt = c.renderOpt;
            if (c.noTiming) opt.timingRepeats = 0;
            renderCommand(c.scenePath, c.outDir, opt, c.exrCompression, c.channels);
        } else if (*c.sweep) {
            pgt::SweepOptions opt = c.sweepOpt;
            if (c.sweep->count("--shard")) pgt::parseShard(c.shard, opt.outDir, opt);
            sweepCommand(c.scenePath, opt, c.noReport);
        } else if (*c.merge) {
            mergeCommand(c.mergeDirs, c.outDir, c.noReport);
        } else if (*c.compare) {
            pgt::CompareOptions opt = c.compareOpt;
            for (const auto& p : c.comparePairs) opt.pairs.push_back(pgt::parseLabelPair(p));
            if (!c.compareBands.empty())
                opt.verdict.bandEdges = pgt::parseBandEdges(c.compareBands);
            return compareCommand(opt, c.noReport);
        } else if (*c.stress) {
            int n = pgt::runStress(c.stressPaths, c.stressOpt);
            std::printf("%d scenes: %s/stress.csv\n", n, c.stressOpt.outDir.c_str());
        } else if (*c.fit) {
            fitCommand(c.scenePath, c.outDir);
        } else if (*c.methods) {
            methodsCommand();
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

// A frame's large buffers (the truth's lattice and BVH, the bands' fragments, the kept errors,
// frame.exr's rows) on transparent huge pages: glibc's malloc advises its large chunks so when
// its tunable glibc.malloc.hugetlb is 1 (glibc 2.35 on; Linux's THP mode "madvise", Debian's
// default), which it reads only when a process starts. So the process starts itself once
// more with the tunable added, unless the environment already names it (the user's choice:
// glibc.malloc.hugetlb=0 keeps 4 KB pages). Measured: the 2048^2 default frame 12 % faster,
// the same peak memory to 1 % (docs/performance.md). Where exec fails, pgt runs on as it is.
void restartOnHugePages(char** argv) {
    if (pgt::hugePagesTunableGiven()) return;
    const char* given = std::getenv("GLIBC_TUNABLES");
    const std::string value = (given && *given ? std::string(given) + ":" : std::string()) +
                              pgt::kHugePagesTunable + "=1";
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    execv("/proc/self/exe", argv);
    // Not restarted: as before, with 4 KB pages (the tunable left set for child processes).
}

}  // namespace

int main(int argc, char** argv) {
    restartOnHugePages(argv);
    pgt::installSignalCleanup();  // Ctrl-C and kill leave no temporaries or created --out
    CLI::App app{"pgt: Parallax Ground Truth - how wrong is your parallax mapping?"};
    app.set_version_flag("--version", pgt::versionText());
    pgt::setCommandLine(std::vector<std::string>(argv, argv + argc));
    CommandLine commandLine;
    defineCommands(app, commandLine);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Command-line mistakes are bad input like any other: exit 2, one line.
        std::cerr << "pgt: error: command line: " << pgt::printable(e.what(), 480) << "\n";
        return 2;
    }
    return runCommand(commandLine);
}
