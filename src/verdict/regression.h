// The regression verdict between two studies' rows (`pgt compare`, docs/studies.md "Gating a
// shader change"): each configuration judged per cell (a band of view angles at one scale),
// its error ratio NEW / OLD paired over the cases and given a 95 % interval from the spread of
// the replicate seeds; a cell changed when that ratio is significant after Benjamini and
// Hochberg's correction over every cell of the comparison and passes the minimum effect. Each
// cell's variance is moderated toward its configuration's (Smyth's empirical Bayes t): a few
// replicates then borrow strength from the other cells without trusting any one cell's few seeds.
// Pure: no files.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace pgt {

// One study's rows, as compare needs them: per configuration label, per case (its key without
// the seed), per seed, the metric's value.
struct VerdictRows {
    struct Case {
        double theta = 0, scale = 0;
        std::map<double, double> bySeed;  // seed -> the metric (NaN where not finite)
    };
    std::map<std::string, std::map<std::string, Case>> byLabel;  // label -> case key -> case
};

struct VerdictOptions {
    // Band edges in degrees, ascending: [e0, e1), [e1, e2), ..., [e(n-2), e(n-1)]; empty: every
    // theta of the cases its own band.
    std::vector<double> bandEdges;
    double alpha = 0.01;      // the false-alarm level (Benjamini-Hochberg over every cell)
    double minEffect = 0.05;  // a change is at least this relative (ratio >= 1.05 or <= 1/1.05)
    double floor = 1e-4;      // texels added to every mean before its ratio (0 vs 0 is 1)
};

enum class Change { Unchanged, Regression, Improvement };
const char* toString(Change c);

// One configuration in one band of angles at one scale.
struct VerdictCell {
    std::string labelOld, labelNew;
    double thetaLo = 0, thetaHi = 0;  // the band [lo, hi] of the cases' theta
    double scale = 0;
    int cases = 0;    // the cases compared (finite in both studies at every seed)
    int leftOut = 0;  // cases left out: a non-finite value, or a seed missing
    int seedsOld = 0, seedsNew = 0;
    bool paired = false;               // both studies ran the same seeds: ratios paired per seed
    double oldMean = 0, newMean = 0;   // the metric's mean over cases and seeds
    double ratio = 1, lo = 1, hi = 1;  // (new + floor) / (old + floor), its 95 % interval
    double p = 1, pAdjusted = 1;       // two-sided, and its q-value (Benjamini-Hochberg)
    double df = 0;                     // the moderated t's degrees of freedom
    Change change = Change::Unchanged;
};

// A configuration's prior of its cells' seed noise: the log ratio's per-replicate standard
// deviation s0 with d0 degrees of freedom (infinite: one variance for every cell; 0: none, each
// cell on its own).
constexpr double kInfiniteDf = 1e6;
struct NoisePrior {
    double s0 = 0, d0 = 0;
};

struct ConfigVerdict {
    std::string labelOld, labelNew;
    std::vector<std::string> changed;   // "min_layers 8 → 4": what differs in its parameters
    Change change = Change::Unchanged;  // Regression when any cell regressed
    std::vector<size_t> cells;          // its cells in Comparison::cells
    NoisePrior prior;
};

struct Comparison {
    std::vector<VerdictCell> cells;
    std::vector<ConfigVerdict> configs;
    bool regressed() const;
};

// A pair of configurations to judge: OLD's label, NEW's label, and what changed between them.
struct ConfigPair {
    std::string labelOld, labelNew;
    std::vector<std::string> changed;
};

// Judges every pair over the cases both studies have. InputError (naming `what`) when a
// cell has fewer than two seeds on a side (no noise floor can be taken: the message says how
// to run replicates).
Comparison judge(const VerdictRows& old, const VerdictRows& neu,
                 const std::vector<ConfigPair>& pairs, const VerdictOptions& options,
                 const std::string& what);

// The mean of `values` and the half-width of its 95 % interval (Student's t over the values;
// NaN with fewer than two).
struct MeanInterval {
    double mean = 0, halfWidth = 0;
};
MeanInterval meanInterval(const std::vector<double>& values);

// `item` added to the list `to`, after `separator` when the list is not empty.
inline void appendListed(std::string& to, const std::string& item, const char* separator) {
    if (!to.empty()) to += separator;
    to += item;
}

// "key a → b" for every leaf where two JSON texts differ (objects flattened with dots);
// each side's whole text when either is not JSON.
std::vector<std::string> parameterChanges(const std::string& oldParams,
                                          const std::string& newParams);

}  // namespace pgt
