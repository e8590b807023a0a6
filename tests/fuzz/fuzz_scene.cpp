// libFuzzer target: the bounded JSON reader (core/json_read.h) and the scene parser on
// arbitrary bytes. Bad input must end in InputError, never a crash, hang or sanitizer report.
#include <cstdint>
#include <string>

#include "core/error.h"
#include "core/json_read.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    nlohmann::json json;
    try {
        json = pgt::parseJsonText(text, "/nonexistent/fuzz.json");
    } catch (const pgt::InputError&) {
        return 0;
    }
    // Keep each input cheap: the parser accepts maps up to 2^28 texels and files anywhere,
    // which a fuzzer would turn into gigabyte allocations and reads of /dev/*.
    if (json.is_object() && json.contains("heightmap") && json["heightmap"].is_object()) {
        auto& hm = json["heightmap"];
        if (hm.contains("file")) return 0;
        if (hm.contains("size") && hm["size"].is_array() && hm["size"].size() == 2 &&
            hm["size"][0].is_number() && hm["size"][1].is_number() &&
            hm["size"][0].get<double>() * hm["size"][1].get<double>() > 65536.0)
            return 0;
    }
    if (json.is_object() && json.contains("base") && json["base"].is_object() &&
        json["base"].contains("file"))
        return 0;
    try {
        pgt::Scene s = pgt::parseScene(json, "/nonexistent/fuzz.json");
        (void)pgt::makeCamera(s);
    } catch (const pgt::InputError&) {
    }
    return 0;
}
