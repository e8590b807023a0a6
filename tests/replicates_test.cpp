// Replicates (docs/studies.md "Replicates"): "replicates": N and "seed": [..] make every case
// N cases that differ in their jitter seed alone, planned alike by parseStudy and by merge's
// planCases, and a replicate's rows are exactly those of the study run with that one seed.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "core/error.h"
#include "io/csv_table.h"
#include "study/plan.h"
#include "study/result_columns.h"
#include "study/sweep.h"
#include "test_util.h"

namespace pgt {
namespace {

nlohmann::json sceneJson() {
    return nlohmann::json::parse(R"({
      "heightmap": {"procedural": "bricks", "size": [32, 32], "bricks": [2, 4]},
      "base": {"type": "plane", "infinite": true},
      "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [24, 24],
                 "samples": "jittered", "seed": 7},
      "methods": ["parallax", "pom"],
      "truth": {"rate": 1, "uncertainty": false},
      "sweep": {"theta": [20, 60], "scale": [0.05], "replicates": 3, "timing": {"repeats": 0}}
    })");
}

Study studyOf(const nlohmann::json& j) { return parseStudy(parseScene(j, "replicates.json")); }

// results.csv's `mean` by (theta, seed, label).
std::map<std::tuple<double, double, std::string>, std::string> means(const std::string& dir) {
    std::ifstream in(dir + "/results.csv");
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    const ResultHeader head(dir + "/results.csv", text, "");
    bool torn = false;
    std::map<std::tuple<double, double, std::string>, std::string> out;
    for (const auto& row : splitCsvRecords(text, head.rowsFrom(), &torn))
        out[{std::stod(head.field(row, "theta")), std::stod(head.field(row, "seed")),
             head.field(row, "label")}] = head.field(row, "mean");
    return out;
}

TEST(Replicates, EveryCaseOncePerSeedFromTheCamerasSeed) {
    const Study st = studyOf(sceneJson());
    ASSERT_EQ(st.cases.size(), 6u);
    const double seeds[] = {7, 8, 9, 7, 8, 9};
    for (size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(st.cases[i].seed, seeds[i]) << i;
        EXPECT_EQ(st.cases[i].theta, i < 3 ? 20 : 60) << i;
    }
    EXPECT_NE(st.cases[0].key(), st.cases[1].key());
    // merge plans the cases from study.json alone: the same keys, the camera's seed included.
    const auto planned = planCases(st.resolved, "study.json");
    ASSERT_EQ(planned.size(), st.cases.size());
    for (size_t i = 0; i < planned.size(); ++i) EXPECT_EQ(planned[i].key(), st.cases[i].key());

    nlohmann::json listed = sceneJson();
    listed["sweep"].erase("replicates");
    listed["sweep"]["seed"] = {5, 2};
    const Study ls = studyOf(listed);
    ASSERT_EQ(ls.cases.size(), 4u);
    EXPECT_EQ(ls.cases[0].seed, 5);
    EXPECT_EQ(ls.cases[1].seed, 2);
}

TEST(Replicates, BadSeedsNameTheirKey) {
    auto refused = [](nlohmann::json j, const std::string& field) {
        try {
            studyOf(j);
            ADD_FAILURE() << j["sweep"].dump() << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    nlohmann::json both = sceneJson();
    both["sweep"]["seed"] = {1, 2};
    refused(both, "sweep.replicates");
    nlohmann::json centre = sceneJson();
    centre["sweep"]["samples"] = "centre";
    refused(centre, "sweep.replicates");
    nlohmann::json half = sceneJson();
    half["sweep"].erase("replicates");
    half["sweep"]["seed"] = {1.5, 2};
    refused(half, "sweep.seed");
    nlohmann::json zero = sceneJson();
    zero["sweep"]["replicates"] = 0;
    refused(zero, "sweep.replicates");
}

// The seeds move the samples (the means differ), and a replicate is the study of its seed:
// its rows equal those of the same study run with "seed": [8] alone.
TEST(Replicates, AReplicateIsTheStudyOfItsSeed) {
    const auto dir = test::tempDir("replicates_all"), one = test::tempDir("replicates_one");
    SweepOptions opt;
    opt.progress = false;
    opt.outDir = dir.string();
    const nlohmann::json j = sceneJson();
    const Scene scene = parseScene(j, "replicates.json");
    runSweep(scene, parseStudy(scene), opt);
    nlohmann::json single = sceneJson();
    single["sweep"].erase("replicates");
    single["sweep"]["seed"] = {8};
    const Scene singleScene = parseScene(single, "replicates.json");
    opt.outDir = one.string();
    runSweep(singleScene, parseStudy(singleScene), opt);
    const auto all = means(dir.string()), eight = means(one.string());
    ASSERT_EQ(all.size(), 12u);
    ASSERT_EQ(eight.size(), 4u);
    for (const auto& [key, mean] : eight) EXPECT_EQ(all.at(key), mean);
    EXPECT_NE(all.at({60, 7, "pom"}), all.at({60, 8, "pom"}));
    EXPECT_NE(all.at({60, 8, "pom"}), all.at({60, 9, "pom"}));
    std::filesystem::remove_all(dir);
    std::filesystem::remove_all(one);
}

}  // namespace
}  // namespace pgt
