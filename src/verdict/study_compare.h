// `pgt compare OLD NEW... --out DIR`: study directories (study.json + results.csv) read, their
// scenes checked to be one surface, configurations paired by label (or --pair), each NEW
// judged against OLD (verdict/regression.h), and DIR/compare.csv, history.csv, compare.json
// and compare.md written (docs/outputs.md "pgt compare"); figures by a front end's script.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "verdict/regression.h"

namespace pgt {

struct CompareOptions {
    std::vector<std::string> dirs;  // OLD, then one or more NEW (a history, oldest first)
    std::string outDir;
    std::string metric = "mean";  // a results.csv error column (compareMetrics())
    VerdictOptions verdict;
    std::vector<std::pair<std::string, std::string>> pairs;  // --pair OLD_LABEL=NEW_LABEL
    bool anyScene = false;  // compare studies of different scenes (the differences noted)
};

// Draws the figures of a compare directory (compare.csv, history.csv): the files made, or
// none with `why` set.
using CompareFigures =
    std::function<std::vector<std::string>(const std::string& outDir, std::string* why)>;

struct CompareSummary {
    Comparison last;                 // the last NEW against OLD: what the exit status says
    std::vector<std::string> notes;  // labels only on one side, incomplete studies
    std::string markdownPath, figuresWhy;
};

// InputError (exit 2) on a directory that is not a study, a scene that differs without
// anyScene, labels on both sides with no match and no --pair, a cell with fewer than two
// seeds; OutputError when DIR cannot be written.
CompareSummary compareStudies(const CompareOptions& options, const CompareFigures& figures = {});

// The results.csv columns a comparison can judge: the error statistics in texels (mean,
// rms, p50, ...), from results.csv's schema.
std::vector<std::string> compareMetrics();

// "OLD=NEW" as a pair; InputError naming --pair otherwise.
std::pair<std::string, std::string> parseLabelPair(const std::string& text);
// "0,30,60,90" as ascending band edges; InputError naming --bands otherwise.
std::vector<double> parseBandEdges(const std::string& text);

}  // namespace pgt
