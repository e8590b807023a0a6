// `pgt stress`: the stiff suite. Renders each scene, counts non-finite and
// diverged pixels per method, and checks the truth's float hits against a double-precision
// re-intersection, into DIR/stress.csv.
#pragma once

#include <string>
#include <vector>

namespace pgt {

struct StressOptions {
    std::string outDir;
    int resolution = 0;  // > 0: override every scene's resolution (square)
    int precisionSamples = 4096;
    bool progress = true;
};

// Scene files, or folders whose *.json files are taken in name order. Returns the number of
// scenes run. Bad scenes throw InputError (naming the file) before anything is written.
int runStress(const std::vector<std::string>& paths, const StressOptions& options);

// stress.csv columns, in order (docs/studies.md "Stiff cases").
const std::vector<std::string>& stressColumns();

}  // namespace pgt
