// Scene files: the bundled scenes parse; bad input names file, field and value.
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/data_dir.h"
#include "core/error.h"
#include "methods/shader/glsl_spec.h"
#include "test_util.h"

namespace pgt {
namespace {

std::string errorOf(const std::string& json) {
    try {
        parseScene(nlohmann::json::parse(json), "bad.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

const char* kValid = R"({"heightmap":{"procedural":"sine","size":[16,16]},
  "base":{"type":"plane"},"camera":{"type":"orthographic","theta":30,"resolution":[8,8]},
  "methods":["parallax"]})";

TEST(Scene, BundledScenesParse) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(test::sceneDir())) {
        if (e.path().extension() != ".json") continue;
        EXPECT_NO_THROW(loadScene(e.path().string())) << e.path();
        ++n;
    }
    EXPECT_GE(n, 3);
}

// "pgt:F" names a shipped shader wherever the scene file is (an installed scene, a user's);
// the shaders are found beside the binary (core/data_dir.h), not in the source tree.
TEST(Scene, ShippedShaderPrefixReadsFromTheDataFolder) {
    const std::string method =
        R"({"name": "mine", "glsl": "pgt:parallax.glsl", "function": "ParallaxMapping",
            "sampler": "heightMap"})";
    std::string json = kValid;
    json.replace(json.find(R"("parallax")"), 10, method);
    Scene s = parseScene(nlohmann::json::parse(json), "/nowhere/scene.json");
    ASSERT_TRUE(s.methods[0].shader());
    EXPECT_EQ(s.methods[0].shader()->path,
              (std::filesystem::path(dataDir()) / "shaders/parallax.glsl").lexically_normal());
    EXPECT_NE(s.methods[0].shader()->source.find("ParallaxMapping"), std::string::npos);
    json.replace(json.find("pgt:parallax"), 12, "pgt:no_such_");
    const std::string e = errorOf(json);
    EXPECT_NE(e.find("methods[0].glsl"), std::string::npos) << e;
    EXPECT_NE(e.find("shaders/no_such_.glsl"), std::string::npos) << e;
}

// The data folder of a build tree is build/share/pgt, whose entries link to the sources.
TEST(Scene, DataFolderIsFoundBesideTheBinary) {
    unsetenv("PGT_DATA_DIR");
    const std::filesystem::path dir = dataDir();
    EXPECT_EQ(dir.filename(), "pgt");
    EXPECT_EQ(dir.parent_path().filename(), "share");
    EXPECT_TRUE(std::filesystem::exists(dir / "shaders/presets/godot.glsl"));
    EXPECT_TRUE(std::filesystem::exists(dir / "analysis/report.py"));
    EXPECT_TRUE(std::filesystem::exists(dir / "scenes/default.json"));
    setenv("PGT_DATA_DIR", "/elsewhere", 1);
    EXPECT_EQ(dataDir(), "/elsewhere");
    unsetenv("PGT_DATA_DIR");
}

TEST(Scene, ValidMinimalScene) {
    Scene s = parseScene(nlohmann::json::parse(kValid), "ok.json");
    EXPECT_EQ(s.height.width, 16);
    EXPECT_EQ(s.methods.size(), 1u);
    EXPECT_DOUBLE_EQ(s.displacement.bias, -0.025);
}

TEST(Scene, UnknownKeySuggestsTheNearest) {
    auto j = nlohmann::json::parse(kValid);
    j["camera"]["thetaa"] = 10;
    j["camera"].erase("theta");
    std::string e = errorOf(j.dump());
    EXPECT_NE(e.find("bad.json"), std::string::npos) << e;
    // "theta" is required, so that is what fails first; a stray key with theta present:
    j["camera"]["theta"] = 10;
    e = errorOf(j.dump());
    EXPECT_NE(e.find("camera.thetaa"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean \"theta\""), std::string::npos) << e;
}

TEST(Scene, UnknownMethodListsTheKnownOnes) {
    auto j = nlohmann::json::parse(kValid);
    j["methods"] = {"parralax"};
    std::string e = errorOf(j.dump());
    EXPECT_NE(e.find("methods[0].name"), std::string::npos) << e;
    EXPECT_NE(e.find("tangent_plane"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean \"parallax\""), std::string::npos) << e;
    j["methods"] = nlohmann::json::array();
    EXPECT_NE(errorOf(j.dump()).find("empty"), std::string::npos);
}

TEST(Scene, OutOfRangeValuesNameTheField) {
    struct Bad {
        const char* pointer;
        nlohmann::json value;
        const char* field;
    };
    const Bad cases[] = {{"/camera/resolution", {0, 8}, "camera.resolution"},
                         {"/camera/theta", 95, "camera.theta"},
                         {"/camera/theta", "steep", "camera.theta"},
                         {"/truth", {{"rate", 0}}, "truth.rate"},
                         {"/address", "wrap", "address"},
                         {"/displacement", {{"scale", "big"}}, "displacement.scale"}};
    for (const auto& c : cases) {
        auto j = nlohmann::json::parse(kValid);
        j[nlohmann::json::json_pointer(c.pointer)] = c.value;
        std::string e = errorOf(j.dump());
        EXPECT_NE(e.find(c.field), std::string::npos) << c.pointer << ": " << e;
    }
    auto j = nlohmann::json::parse(kValid);
    j["camera"] = {{"type", "pinhole"},
                   {"eye", {0, -2, 1}},
                   {"target", {0, 0, 0}},
                   {"fov", 180},
                   {"resolution", {8, 8}}};
    EXPECT_NE(errorOf(j.dump()).find("camera.fov"), std::string::npos);
}

TEST(Scene, MalformedJsonGivesLineAndColumn) {
    auto dir = test::tempDir("badjson");
    auto path = dir / "broken.json";
    std::ofstream(path) << "{\n  \"heightmap\": {\"procedural\": \"sine\"},\n  \"base\": ,\n}\n";
    try {
        loadScene(path.string());
        FAIL();
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("broken.json"), std::string::npos) << what;
        EXPECT_NE(what.find("line 3"), std::string::npos) << what;
    }
    EXPECT_THROW(loadScene((dir / "missing.json").string()), InputError);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt
