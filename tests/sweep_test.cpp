// Studies: CSV columns and rows, resume after an interruption, study identity, parsing.
#include "study/sweep.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_read.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "methods/shader/glsl_spec.h"
#include "study/study_dir.h"
#include "test_util.h"

namespace pgt {
namespace {

const char* kStudyScene = R"({
  "heightmap": {"procedural": "sine", "size": [16, 16], "frequency": [2, 1]},
  "base": {"type": "plane", "infinite": true},
  "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [24, 24]},
  "methods": ["parallax", {"name": "pom", "min_layers": 4, "max_layers": 8}],
  "truth": {"rate": 2},
  "sweep": {"theta": {"from": 20, "to": 60, "step": 40}, "scale": [0.03, 0.06],
            "bias_ratio": [-0.5, -1], "pom.max_layers": [8, 16],
            "timing": {"repeats": 1, "fragments": 64}}
})";

Scene studyScene(const char* json = kStudyScene) {
    return parseScene(nlohmann::json::parse(json), test::testSourceDir() + "/study.json");
}

std::vector<std::string> readLines(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

// Everything but the timing column, which is measured and differs run to run.
std::multiset<std::string> rowsWithoutTiming(const std::filesystem::path& p) {
    auto lines = readLines(p);
    const auto& cols = resultColumns();
    std::vector<size_t> timed;  // measured, not computed: differ between runs
    for (const std::string& c : measuredResultColumns())
        timed.push_back(size_t(std::find(cols.begin(), cols.end(), c) - cols.begin()));
    std::multiset<std::string> out;
    for (size_t i = 1; i < lines.size(); ++i) {
        // params is the only quoted field and holds commas: split around it.
        std::string l = lines[i];
        auto q0 = l.find('"'), q1 = l.rfind('"');
        std::string quoted = l.substr(q0, q1 - q0 + 1);
        l.replace(q0, q1 - q0 + 1, "PARAMS");
        std::vector<std::string> f;
        std::stringstream ss(l);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        if (!l.empty() && l.back() == ',') f.emplace_back();  // an empty last field
        EXPECT_EQ(f.size(), cols.size()) << lines[i];
        for (size_t c : timed)
            if (c < f.size()) f[c].assign(1, '-');
        std::string joined;
        for (const std::string& x : f) {
            joined.append(x == "PARAMS" ? quoted : x);
            joined.push_back(',');
        }
        out.insert(joined);
    }
    return out;
}

// The documented columns, in order: docs/outputs.md's results.csv paragraph names each column
// in backquotes, in the order the schema (study/result_columns.h) writes them.
std::vector<std::string> documentedColumns() {
    const std::string path = test::testSourceDir() + "/../docs/outputs.md";
    const std::string text = readTextFile(path, path, "", "the documentation", 1 << 22);
    const size_t from = text.find("- **`DIR/results.csv`**");
    const size_t to = text.find("The timing columns are", from);
    EXPECT_NE(from, std::string::npos);
    EXPECT_NE(to, std::string::npos);
    std::vector<std::string> out;
    const std::regex column("`([a-z][a-z0-9_]*)`");
    const std::string paragraph = text.substr(from, to - from);
    for (auto it = std::sregex_iterator(paragraph.begin(), paragraph.end(), column);
         it != std::sregex_iterator(); ++it)
        if ((*it)[1] != "cpu" && (*it)[1] != "nan") out.push_back((*it)[1]);
    return out;
}

TEST(Sweep, ResultsHaveTheDocumentedColumnsAndOneRowPerCaseAndConfiguration) {
    const std::vector<std::string> documented = documentedColumns();
    EXPECT_EQ(resultColumns(), documented);
    Scene scene = studyScene();
    Study study = parseStudy(scene);
    ASSERT_EQ(study.cases.size(), 2u * 2u * 2u);  // theta x scale x bias ratio
    ASSERT_EQ(study.configs.size(), 3u);          // parallax, pom_4_8, pom_4_16
    EXPECT_EQ(study.configs[1].label, "pom_4_8");
    EXPECT_EQ(study.configs[2].label, "pom_4_16");
    EXPECT_DOUBLE_EQ(study.cases[0].bias, -0.5 * 0.03);
    auto dir = test::tempDir("sweep_rows");
    SweepOptions opt;
    opt.outDir = dir.string();
    opt.progress = false;
    SweepSummary sum = runSweep(scene, study, opt);
    EXPECT_TRUE(sum.finished);
    auto lines = readLines(dir / "results.csv");
    ASSERT_EQ(lines.size(), 1 + 8 * 3u);
    std::string header;
    for (const auto& c : documented) header += (header.empty() ? "" : ",") + c;
    EXPECT_EQ(lines[0], header);
    // Every (case, label) exactly once.
    auto rows = rowsWithoutTiming(dir / "results.csv");
    EXPECT_EQ(rows.size(), 24u);
    std::filesystem::remove_all(dir);
}

// Nothing lost: stop after k cases (and tear the last line as a kill mid-write would), run
// again on the same directory: the same rows as one uninterrupted run, in any order.
TEST(Sweep, ResumeAfterAnInterruptionGivesTheSameResults) {
    Scene scene = studyScene();
    Study study = parseStudy(scene);
    auto whole = test::tempDir("sweep_whole"), parts = test::tempDir("sweep_parts");
    SweepOptions opt;
    opt.progress = false;
    opt.outDir = whole.string();
    runSweep(scene, study, opt);

    opt.outDir = parts.string();
    opt.maxCases = 3;
    SweepSummary first = runSweep(scene, study, opt);
    EXPECT_EQ(first.done, 3);
    EXPECT_FALSE(first.finished);
    EXPECT_EQ(readLines(parts / "results.csv").size(), 1 + 3 * 3u);
    std::ofstream(parts / "results.csv", std::ios::app) << "5,40,0,0.06,-0.03,-0.5,pom,po";
    opt.maxCases = -1;
    SweepSummary second = runSweep(scene, study, opt);
    EXPECT_EQ(second.resumed, 3);
    EXPECT_EQ(second.done, 5);
    EXPECT_TRUE(second.finished);
    EXPECT_EQ(rowsWithoutTiming(whole / "results.csv"), rowsWithoutTiming(parts / "results.csv"));
    // A third run has nothing left to do.
    SweepSummary third = runSweep(scene, study, opt);
    EXPECT_EQ(third.done, 0);
    EXPECT_EQ(third.resumed, 8);
    std::filesystem::remove_all(whole);
    std::filesystem::remove_all(parts);
}

// The light's angles are an axis of their own: a case per light angle, resumed by its key
// (two cases share theta, phi, s and b and differ only in the light), and refused in a scene
// without a light.
TEST(Sweep, LightAnglesAreAnAxisAndResumeKeepsThem) {
    const char* json = R"({
      "heightmap": {"procedural": "bricks", "size": [32, 32], "bricks": [2, 4]},
      "base": {"type": "plane", "infinite": true},
      "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [32, 32]},
      "light": {"theta": 45, "phi": 90},
      "methods": ["pom"],
      "truth": {"rate": 2, "uncertainty": false},
      "sweep": {"theta": [30], "scale": [0.1], "bias_ratio": [-1], "light_theta": [20, 75],
                "timing": {"repeats": 1, "fragments": 64}}
    })";
    Scene scene = studyScene(json);
    Study study = parseStudy(scene);
    ASSERT_EQ(study.cases.size(), 2u);
    EXPECT_NE(study.cases[0].key(), study.cases[1].key());
    auto whole = test::tempDir("sweep_light"), parts = test::tempDir("sweep_light_parts");
    SweepOptions opt;
    opt.progress = false;
    opt.outDir = whole.string();
    runSweep(scene, study, opt);
    const auto lines = readLines(whole / "results.csv");
    ASSERT_EQ(lines.size(), 3u);
    // The light's angles in their columns; a low light casts more shadow than a high one.
    const auto& cols = resultColumns();
    auto column = [&](const std::string& line, const std::string& name) {
        auto q0 = line.find('"'), q1 = line.rfind('"');
        std::string l = line;
        l.replace(q0, q1 - q0 + 1, "PARAMS");
        std::vector<std::string> f;
        std::stringstream ss(l);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        return std::stod(f[size_t(std::find(cols.begin(), cols.end(), name) - cols.begin())]);
    };
    EXPECT_EQ(column(lines[1], "light_theta"), 20);
    EXPECT_EQ(column(lines[2], "light_theta"), 75);
    EXPECT_EQ(column(lines[2], "light_phi"), 90);
    EXPECT_LT(column(lines[1], "truth_shadowed"), column(lines[2], "truth_shadowed"));
    opt.outDir = parts.string();
    opt.maxCases = 1;
    EXPECT_EQ(runSweep(scene, study, opt).done, 1);
    opt.maxCases = -1;
    SweepSummary second = runSweep(scene, study, opt);
    EXPECT_EQ(second.resumed, 1);
    EXPECT_EQ(second.done, 1);
    EXPECT_EQ(rowsWithoutTiming(whole / "results.csv"), rowsWithoutTiming(parts / "results.csv"));
    std::filesystem::remove_all(whole);
    std::filesystem::remove_all(parts);

    nlohmann::json dark = nlohmann::json::parse(json);
    dark.erase("light");
    try {
        parseStudy(parseScene(dark, "dark.json"));
        ADD_FAILURE() << "a light sweep without a light was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sweep.light_theta"), std::string::npos) << e.what();
    }
}

TEST(Sweep, ADirectoryHoldsOneStudy) {
    Scene scene = studyScene();
    auto dir = test::tempDir("sweep_other");
    SweepOptions opt;
    opt.outDir = dir.string();
    opt.progress = false;
    opt.maxCases = 1;
    runSweep(scene, parseStudy(scene), opt);
    auto j = nlohmann::json::parse(kStudyScene);
    j["sweep"]["scale"] = {0.05};
    Scene other = parseScene(j, "other.json");
    EXPECT_THROW(runSweep(other, parseStudy(other), opt), InputError);
    opt.fresh = true;  // ... unless asked to start over
    EXPECT_NO_THROW(runSweep(other, parseStudy(other), opt));
    std::filesystem::remove_all(dir);
}

TEST(Sweep, BadSweepEntriesNameTheKey) {
    auto bad = [](const std::string& key, nlohmann::json value) {
        auto j = nlohmann::json::parse(kStudyScene);
        j["sweep"][key] = value;
        try {
            parseStudy(parseScene(j, "s.json"));
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(bad("pom.linear_steps", {4}).find("sweep.pom.linear_steps"), std::string::npos);
    EXPECT_NE(bad("relief.binary_steps", {4}).find("no method named"), std::string::npos);
    EXPECT_NE(bad("theta", {10, 95}).find("sweep.theta"), std::string::npos);
    EXPECT_NE(bad("thetas", {10}).find("did you mean \"theta\""), std::string::npos);
    EXPECT_NE(bad("bias", {0.0}).find("either"), std::string::npos);
}

// A user's GLSL file runs in a sweep like a built-in: LearnOpenGL's
// ParallaxMapping on a depth map with height_scale bound to the case's s is the built-in
// parallax at b = -s, so at bias ratio -1 the two rows of every case agree; its rows carry
// the GL renderer as their timing backend.
TEST(Sweep, UserGlslMethodAppearsInTheResults) {
    auto dir = test::tempDir("glsl_sweep");
    std::ofstream(dir / "mine.glsl")
        << "#version 330 core\n"
           "uniform sampler2D depthMap;\n"
           "uniform float height_scale;\n"
           "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {\n"
           "    float height = texture(depthMap, texCoords).r;\n"
           "    vec2 p = viewDir.xy / viewDir.z * (height * height_scale);\n"
           "    return texCoords - p;\n"
           "}\n";
    nlohmann::json j = nlohmann::json::parse(kStudyScene);
    j["methods"] = nlohmann::json::parse(
        R"(["parallax", {"name": "mine", "glsl": "mine.glsl", "texture": "depth",
                         "uniforms": {"height_scale": "scale"}}])");
    j["sweep"].erase("pom.max_layers");
    j["sweep"]["bias_ratio"] = {-1};
    Scene scene = parseScene(j, (dir / "scene.json").string());
    Study study = parseStudy(scene);
    ASSERT_EQ(study.configs.size(), 2u);
    SweepOptions opt;
    opt.outDir = (dir / "out").string();
    opt.progress = false;
    SweepSummary sum = runSweep(scene, study, opt);
    ASSERT_TRUE(sum.finished);
    auto lines = readLines(dir / "out" / "results.csv");
    std::map<std::string, std::map<std::string, double>> meanBy;  // case -> label -> mean
    int glRows = 0;
    for (size_t i = 1; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        std::string c = l.substr(0, l.find(','));
        bool mine = l.find(",mine,mine,") != std::string::npos;
        if (mine) {
            EXPECT_TRUE(l.find("gl wall clock: ") != std::string::npos ||
                        l.find("gl timer query: ") != std::string::npos)
                << l;
            ++glRows;
        }
        // mean is the 11th column; params (9th) is the only field before it with commas.
        std::string after = l.substr(l.find("}\",", l.find(",\"{")) + 3);
        std::stringstream ss(after);
        std::string pixels, mean;
        std::getline(ss, pixels, ',');
        std::getline(ss, mean, ',');
        meanBy[c][mine ? "mine" : "parallax"] = std::stod(mean);
    }
    EXPECT_EQ(glRows, int(study.cases.size()));
    for (const auto& [c, m] : meanBy) {
        ASSERT_EQ(m.size(), 2u);
        EXPECT_NEAR(m.at("mine"), m.at("parallax"), 1e-3 + 1e-4 * m.at("parallax")) << "case " << c;
    }
}

// results.csv's records as column -> value maps.
std::vector<std::map<std::string, std::string>> readRecords(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::map<std::string, std::string>> out;
    bool torn = false;
    for (const auto& f : splitCsvRecords(text, resultHeader().size(), &torn)) {
        std::map<std::string, std::string> r;
        for (size_t i = 0; i < f.size() && i < resultColumns().size(); ++i)
            r[resultColumns()[i]] = f[i];
        out.push_back(r);
    }
    EXPECT_FALSE(torn);
    return out;
}

// A GLSL method is timed once per (configuration, view direction), on the first case of the
// view, and that timing is shared by the view's other (s, b); C++ methods are timed in every
// case. gl_timing "per_case" times every case again.
TEST(Sweep, GlslTimingIsSharedAcrossTheScalesOfAView) {
    auto dir = test::tempDir("gl_timing_per_view");
    nlohmann::json j = nlohmann::json::parse(kStudyScene);
    j["methods"] = nlohmann::json::parse(
        R"(["parallax", {"name": "g", "glsl": "pgt:parallax.glsl", "function": "ParallaxMapping",
                         "sampler": "heightMap",
                         "uniforms": {"height_scale": "scale", "height_bias": "bias"}}])");
    j["sweep"].erase("pom.max_layers");
    j["sweep"]["bias_ratio"] = {-0.5};
    for (const char* mode : {"per_view", "per_case"}) {
        j["sweep"]["timing"]["gl_timing"] = mode;
        Scene scene = parseScene(j, (dir / "scene.json").string());
        Study study = parseStudy(scene);
        ASSERT_EQ(study.cases.size(), 4u);  // (s 0.03: theta 20, 60), (s 0.06: theta 20, 60)
        SweepOptions opt;
        opt.outDir = (dir / mode).string();
        opt.progress = false;
        ASSERT_TRUE(runSweep(scene, study, opt).finished);
        std::map<std::pair<std::string, std::string>, std::map<std::string, std::string>> row;
        for (const auto& r : readRecords(dir / mode / "results.csv"))
            row[{r.at("case"), r.at("label")}] = r;
        ASSERT_EQ(row.size(), 8u);
        for (const char* c : {"0", "1", "2", "3"}) {
            const auto key = std::pair<std::string, std::string>(c, "parallax");
            EXPECT_EQ(row[key].at("timing_case"), c);
            EXPECT_GT(std::stod(row[std::pair<std::string, std::string>(c, "g")].at("ns_per_px")),
                      0)
                << c;
        }
        const bool perView = std::string(mode) == "per_view";
        for (const auto& [later, first] : {std::pair{"2", "0"}, std::pair{"3", "1"}}) {
            const auto &a = row[std::pair<std::string, std::string>(later, "g")],
                       &b = row[std::pair<std::string, std::string>(first, "g")];
            EXPECT_EQ(b.at("timing_case"), first);
            EXPECT_EQ(a.at("timing_case"), perView ? first : later) << mode;
            if (!perView) continue;
            for (const char* col : {"ns_per_px", "ns_per_px_p25", "ns_per_px_p75"})
                EXPECT_EQ(a.at(col), b.at(col)) << col;
        }
    }
}

// One list of measured columns: the C++ one is the Python tests' and scripts' one
// (analysis/columns.py), and each of them is a results.csv column.
TEST(Sweep, MeasuredColumnsAreOneListInBothLanguages) {
    std::ifstream in(test::testSourceDir() + "/../analysis/columns.py");
    ASSERT_TRUE(in) << "analysis/columns.py";
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto start = text.find("MEASURED_COLUMNS = (");
    ASSERT_NE(start, std::string::npos);
    const std::string tuple = text.substr(start, text.find(')', start) - start);
    std::vector<std::string> python;
    for (size_t q = tuple.find('"'); q != std::string::npos; q = tuple.find('"', q + 1)) {
        const size_t end = tuple.find('"', q + 1);
        python.push_back(tuple.substr(q + 1, end - q - 1));
        q = end;
    }
    EXPECT_EQ(python, measuredResultColumns());
    for (const std::string& c : measuredResultColumns())
        EXPECT_NE(std::find(resultColumns().begin(), resultColumns().end(), c),
                  resultColumns().end())
            << c;
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// A GLSL method swept over a uniform ("LABEL.uniforms.NAME"), as built-ins are over their
// parameters: one configuration per value, labelled with it; LearnOpenGL's ParallaxMapping on
// a depth map at height_scale = s is the built-in parallax at b = -s, so the configuration
// whose height_scale equals the case's s agrees with parallax and the other does not. A
// preset's uniforms are overridden by its entry; unknown labels and uniforms are refused.
TEST(Sweep, GlslUniformsAreSweptAndPresetsOverridden) {
    auto dir = test::tempDir("glsl_uniform_sweep");
    std::ofstream(dir / "mine.glsl")
        << "#version 330 core\nuniform sampler2D depthMap;\nuniform float height_scale;\n"
           "vec2 ParallaxMapping(vec2 uv, vec3 V) {\n"
           "    return uv - V.xy / V.z * (texture(depthMap, uv).r * height_scale);\n}\n";
    nlohmann::json j = nlohmann::json::parse(kStudyScene);
    j["methods"] = nlohmann::json::parse(
        R"(["parallax", {"name": "mine", "glsl": "mine.glsl", "texture": "depth",
                         "uniforms": {"height_scale": 1.0}},
            {"preset": "godot", "uniforms": {"heightmap_scale": 2.5}}])");
    j["sweep"].erase("pom.max_layers");
    j["sweep"]["scale"] = {0.03};
    j["sweep"]["bias_ratio"] = {-1};
    j["sweep"]["mine.uniforms.height_scale"] = {0.03, 0.06};
    const Scene scene = parseScene(j, (dir / "scene.json").string());
    const Study study = parseStudy(scene);
    ASSERT_EQ(study.configs.size(), 4u);
    EXPECT_EQ(study.configs[1].label, "mine_height_scale0.03");
    EXPECT_EQ(study.configs[2].label, "mine_height_scale0.06");
    EXPECT_EQ(study.configs[2].shader()->uniforms.at(0).values, std::vector<double>{0.06});
    EXPECT_EQ(study.configs[3].shader()->uniforms.at(0).values, std::vector<double>{2.5});
    SweepOptions opt;
    opt.outDir = (dir / "out").string();
    opt.progress = false;
    ASSERT_TRUE(runSweep(scene, study, opt).finished);
    std::map<std::string, std::map<std::string, double>> mean;  // case -> label -> mean
    for (const auto& r : readRecords(dir / "out" / "results.csv"))
        mean[r.at("case")][r.at("label")] = std::stod(r.at("mean"));
    for (const auto& [c, m] : mean) {
        EXPECT_NEAR(m.at("mine_height_scale0.03"), m.at("parallax"), 1e-3) << "case " << c;
        EXPECT_GT(m.at("mine_height_scale0.06"), m.at("parallax") + 1e-2) << "case " << c;
    }
    auto error = [&](const std::string& key, const nlohmann::json& value) {
        nlohmann::json k = j;
        k["sweep"][key] = value;
        try {
            parseStudy(parseScene(k, (dir / "scene.json").string()));
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error("nosuch.uniforms.x", {1}).find("no method named"), std::string::npos);
    EXPECT_NE(error("mine.uniforms.nothere", {1}).find("has no uniform \"nothere\""),
              std::string::npos);
    EXPECT_NE(error("mine.min_layers", {8}).find("uniforms.NAME"), std::string::npos);
    // A built-in preset stays one configuration beside its built-in's lists
    // (learnopengl_pom's name is "pom", whose max_layers the study varies).
    nlohmann::json q = nlohmann::json::parse(kStudyScene);
    q["methods"].push_back({{"preset", "learnopengl_pom"}});
    const Study withPreset = parseStudy(parseScene(q, (dir / "scene.json").string()));
    EXPECT_EQ(std::count_if(withPreset.configs.begin(), withPreset.configs.end(),
                            [](const MethodConfig& c) { return c.preset == "learnopengl_pom"; }),
              1);
    // godot's height scale is its uniform: its own "scale" would reach nothing.
    EXPECT_NE(error("godot.scale", {0.05}).find("would not reach"), std::string::npos);
    nlohmann::json p = j;
    p["methods"][2]["uniforms"] = {{"nosuch", 1}};
    try {
        parseScene(p, (dir / "scene.json").string());
        ADD_FAILURE() << "a preset's unknown uniform was taken";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("uniforms.nosuch"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// A study's sources (the methods' citation keys) are not its identity: a study.json of an
// older pgt, without them, is the same study and resumes; any other difference is another.
TEST(Sweep, SourcesAreNotPartOfAStudysIdentity) {
    const nlohmann::json now = {{"cases", 2}, {"sources", {{"pom", "tatarchuk2006"}}}};
    EXPECT_TRUE(sameStudy(now, {{"cases", 2}}));
    EXPECT_FALSE(sameStudy(now, {{"cases", 3}}));
    const auto dir = test::tempDir("sources_identity");
    const std::string path = (dir / "study.json").string();
    writeTextFile(path, nlohmann::json({{"cases", 2}}).dump());
    EXPECT_TRUE(holdsStudy(path, now));
    EXPECT_THROW(holdsStudy(path, {{"cases", 3}}), InputError);
}

}  // namespace
}  // namespace pgt
