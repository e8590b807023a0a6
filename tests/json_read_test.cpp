// core/json_read.h: the bounded JSON reader's refusals, each at its exact boundary and with
// the field path an error must name.
#include "core/json_read.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "methods/config.h"

namespace pgt {
namespace {

std::string nested(int depth) {
    return std::string(size_t(depth), '[') + std::string(size_t(depth), ']');
}

// The InputError's field for `text`, or "accepted".
std::string refusalField(const std::string& text) {
    try {
        parseJsonText(text, "t.json");
    } catch (const InputError& e) {
        return e.field();
    }
    return "accepted";
}

TEST(JsonRead, DepthIsBoundedExactlyAtTheLimit) {
    EXPECT_EQ(refusalField(nested(kMaxJsonDepth)), "accepted");
    EXPECT_NE(refusalField(nested(kMaxJsonDepth + 1)), "accepted");
    // Far past the limit (a recursive reader would overflow its stack here).
    EXPECT_NE(refusalField(nested(1000000)), "accepted");
}

TEST(JsonRead, DuplicateKeysAreNamedByTheirPath) {
    EXPECT_EQ(refusalField(R"({"a": 1, "a": 2})"), "a");
    EXPECT_EQ(refusalField(R"({"methods": [{"name": "x"}, {"name": "y", "name": "z"}]})"),
              "methods[1].name");
    EXPECT_EQ(refusalField(R"({"a": {"b": 1}, "c": {"b": 1}})"), "accepted");  // other objects
}

TEST(JsonRead, NumbersBeyondDoubleAreNamedByTheirPath) {
    EXPECT_EQ(refusalField(R"({"camera": {"theta": 1e400}})"), "camera.theta");
    EXPECT_EQ(refusalField(R"({"sweep": {"scale": [0.1, -1e999]}})"), "sweep.scale[1]");
    EXPECT_EQ(refusalField(R"({"x": 1e308})"), "accepted");
}

TEST(JsonRead, MalformedJsonGivesLineAndColumn) {
    EXPECT_EQ(refusalField("{\n  \"a\": ,\n}"), "line 2, column 8");
}

TEST(JsonRead, ParsedValuesEqualNlohmanns) {
    const std::string text = R"({"a": [1, 2.5, "x", null, true, {"b": []}], "c": {}})";
    EXPECT_EQ(parseJsonText(text, "t.json"), nlohmann::json::parse(text));
}

TEST(Errors, EchoedKeysAndValuesArePrintableAndShort) {
    InputError e("f.json", std::string("a\0b", 3) + std::string(100000, 'k'), "", "unknown key");
    std::string line = e.what();
    EXPECT_EQ(line.find('\0'), std::string::npos);
    EXPECT_NE(line.find("a\\u0000b"), std::string::npos) << line;
    EXPECT_LT(line.size(), 400u) << line;
}

TEST(Labels, UserLabelsAreUniqueAndGeneratedOnesNeverCollide) {
    using Json = nlohmann::json;
    EXPECT_THROW(parseMethods(Json::parse(R"([{"name": "parallax", "label": "a"},
                                              {"name": "pom", "label": "a"}])"),
                              "f", "methods"),
                 InputError);
    for (const char* bad : {"a,b", "a\"b", "a b", "../x", ""})
        EXPECT_THROW(
            parseMethods(Json::array({{{"name", "parallax"}, {"label", bad}}}), "f", "methods"),
            InputError)
            << bad;
    EXPECT_THROW(
        parseMethods(
            Json::array({{{"name", "parallax"}, {"label", std::string(kMaxLabelLength + 1, 'x')}}}),
            "f", "methods"),
        InputError);
    auto list = parseMethods(
        Json::parse(R"(["parallax", {"name": "parallax", "label": "parallax_2"}, "parallax"])"),
        "f", "methods");
    ASSERT_EQ(list.size(), 3u);
    EXPECT_EQ(list[1].label, "parallax_2");
    EXPECT_NE(list[0].label, list[2].label);
    EXPECT_NE(list[2].label, "parallax_2");
}

}  // namespace
}  // namespace pgt
