// What made an output (docs/outputs.md "Provenance"): pgt's version and commit, how it was
// built, the libraries it was built against, the machine (CPU, the Embree kernel in use, the
// GL when GLSL methods ran), the date and the command. Every output records it: summary.json,
// frame.exr's header, a study's provenance.json (one entry per run), fit.json, compare.json.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pgt {

// The command that is running, as the front end names it ("pgt render a.json --out o", or
// "python: pgt.render(...)"): recorded in every provenance block. Set once at start.
void setCommandLine(const std::vector<std::string>& argv);
void setCommandLine(const std::string& text);

// "pgt 0.1.0 (commit 1a2b3c4d5e6f, Release, GNU 12.2.0)" and the libraries, for --version.
std::string versionText();

// The provenance block of an output made now; `sceneSha1`, when given, the SHA-1 of the
// canonical (resolved) scene it measured.
nlohmann::json provenance(const std::string& sceneSha1 = "");

// The SHA-1 of a scene's canonical form (resolvedSceneJson as compact JSON): what an output
// records of the scene it measured.
std::string sceneSha1(const Scene& scene);

// A study directory's provenance.json: {"runs": [...]}, one entry per sweep or merge that wrote
// it. beginRun appends this run's provenance (`fresh`: the earlier runs dropped with the
// study's rows) and returns its index; endRun adds what it did to that entry. Both replace
// the file whole; a file that is not such JSON is started again.
int beginRun(const std::string& dir, const nlohmann::json& entry, bool fresh);
void endRun(const std::string& dir, int run, const nlohmann::json& done);
// The runs recorded in DIR/provenance.json (none when it is missing or unreadable).
nlohmann::json studyRuns(const std::string& dir);

// The Embree kernel pgt's traces use: PGT_EMBREE_ISA's when set, else the best this CPU runs
// ("avx2 (auto)").
std::string embreeKernel();

}  // namespace pgt
