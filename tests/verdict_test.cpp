// The regression verdict (verdict/regression.h) against closed forms (Student's t,
// Benjamini-Hochberg) and against seeded synthetic studies whose seed noise is shared by every case
// of a replicate, as a jitter seed's is (docs/studies.md "Gating a shader change"). The same checks
// on real studies: tests/analysis/test_compare.py.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <random>

#include "core/error.h"
#include "verdict/regression.h"

namespace pgt {
namespace {

// A study of `labels` over thetas x scales, `seeds` replicates: each seed scales every case by
// one shared factor exp(seedNoise z) and each case by its own exp(caseNoise z'); `factor`
// multiplies a case's true error (theta, scale, label) -> factor.
VerdictRows synthetic(const std::vector<std::string>& labels, const std::vector<double>& seeds,
                      uint32_t rngSeed, double seedNoise, double caseNoise,
                      const std::function<double(double, double, const std::string&)>& factor) {
    std::mt19937 rng(rngSeed);
    std::normal_distribution<double> z(0, 1);
    VerdictRows rows;
    const std::vector<double> thetas = {0, 10, 20, 30, 40, 50, 60, 70, 80, 85};
    const std::vector<double> scales = {0.02, 0.05, 0.1, 0.15, 0.2};
    for (const auto& label : labels)
        for (double seed : seeds) {
            const double shared = std::exp(seedNoise * z(rng));
            for (double t : thetas)
                for (double s : scales) {
                    auto& c = rows.byLabel[label][std::to_string(t) + ";" + std::to_string(s)];
                    c.theta = t, c.scale = s;
                    const double truth = s * 10 * (1 + std::tan(t * M_PI / 180));
                    c.bySeed[seed] =
                        truth * factor(t, s, label) * shared * std::exp(caseNoise * z(rng));
                }
        }
    return rows;
}

const std::vector<std::string> kLabels = {"pom", "relief"};
std::vector<ConfigPair> samePairs() { return {{"pom", "pom", {}}, {"relief", "relief", {}}}; }
std::vector<double> seedRange(double first, int n) {
    std::vector<double> s;
    for (int i = 0; i < n; ++i) s.push_back(first + i);
    return s;
}
auto unchanged = [](double, double, const std::string&) { return 1.0; };

TEST(Verdict, MeanIntervalIsStudentsT) {
    // {1, 2, 3}: mean 2, standard error 1/sqrt(3), t(0.975, 2) = 4.302653.
    const MeanInterval m = meanInterval({1, 2, 3});
    EXPECT_DOUBLE_EQ(m.mean, 2);
    EXPECT_NEAR(m.halfWidth, 4.302653 / std::sqrt(3.0), 1e-6);
    EXPECT_TRUE(std::isnan(meanInterval({5}).halfWidth));
}

// One case, three seeds, paired: log ratios 0.1, 0.2, 0.3 give t = 0.2 / (0.1 / sqrt 3) with
// 2 degrees of freedom, whose two-sided p is 1 - t / sqrt(t^2 + 2) = 0.074180; 0.3, 0.4, 0.5
// give t = 6.9282, p = 0.020204. Benjamini-Hochberg over the two: the smaller doubled, the
// larger as it is.
TEST(Verdict, PairedTestAndBenjaminiHochbergMatchClosedForms) {
    VerdictRows old, neu;
    const std::map<std::string, std::vector<double>> d = {{"a", {0.1, 0.2, 0.3}},
                                                          {"b", {0.3, 0.4, 0.5}}};
    for (const auto& [label, logs] : d)
        for (int r = 0; r < 3; ++r) {
            auto& o = old.byLabel[label]["k"];
            auto& n = neu.byLabel[label]["k"];
            o.theta = n.theta = 30, o.scale = n.scale = 0.1;
            o.bySeed[r + 1] = 2.0;
            n.bySeed[r + 1] = 2.0 * std::exp(logs[r]);
        }
    VerdictOptions opt;
    opt.floor = 0;
    const Comparison c = judge(old, neu, {{"a", "a", {}}, {"b", "b", {}}}, opt, "test");
    ASSERT_EQ(c.cells.size(), 2u);
    const VerdictCell& cell = c.cells[0];
    EXPECT_TRUE(cell.paired);
    EXPECT_NEAR(cell.ratio, std::exp(0.2), 1e-12);
    EXPECT_NEAR(cell.p, 0.074180, 1e-5);
    EXPECT_NEAR(cell.lo, std::exp(0.2 - 4.302653 * 0.1 / std::sqrt(3.0)), 1e-6);
    EXPECT_NEAR(cell.pAdjusted, cell.p, 1e-12);
    EXPECT_NEAR(c.cells[1].p, 1 - 6.9282032 / std::sqrt(6.9282032 * 6.9282032 + 2), 1e-6);
    EXPECT_NEAR(c.cells[1].pAdjusted, 2 * c.cells[1].p, 1e-12);
    EXPECT_EQ(cell.change, Change::Unchanged);  // not significant at 0.01
}

// A study against itself under other jitter seeds (unpaired) flags nothing, over 50 seed
// pairs, 3 seeds a side, seed noise 5 % and case noise 3 %.
TEST(Verdict, AnotherSeedFlagsNothing) {
    int flagged = 0;
    for (uint32_t k = 0; k < 50; ++k) {
        const VerdictRows old = synthetic(kLabels, seedRange(1, 3), 100 + k, 0.05, 0.03, unchanged);
        const VerdictRows neu = synthetic(kLabels, seedRange(4, 3), 900 + k, 0.05, 0.03, unchanged);
        const Comparison c = judge(old, neu, samePairs(), {}, "test");
        for (const auto& cell : c.cells) flagged += cell.change != Change::Unchanged;
        EXPECT_FALSE(c.regressed()) << "seed pair " << k;
    }
    EXPECT_EQ(flagged, 0);
}

// 1.3x worse at theta 40 only, 10 seeds a side (unpaired): that band is a regression at every
// scale, and no other band is.
TEST(Verdict, OneBandWorseIsFlaggedThere) {
    auto worse = [](double t, double, const std::string& l) {
        return l == "pom" && t == 40 ? 1.3 : 1.0;
    };
    const VerdictRows old = synthetic(kLabels, seedRange(1, 10), 7, 0.05, 0.03, unchanged);
    const VerdictRows neu = synthetic(kLabels, seedRange(11, 10), 8, 0.05, 0.03, worse);
    const Comparison c = judge(old, neu, samePairs(), {}, "test");
    EXPECT_TRUE(c.regressed());
    for (const auto& cell : c.cells) {
        const bool there = cell.labelOld == "pom" && cell.thetaLo == 40;
        EXPECT_EQ(cell.change, there ? Change::Regression : Change::Unchanged)
            << cell.labelOld << " theta " << cell.thetaLo << " s " << cell.scale << " ratio "
            << cell.ratio << " q " << cell.pAdjusted;
    }
    EXPECT_EQ(c.configs[1].change, Change::Unchanged);
}

// One case out of 50 twice as bad, the same seeds on both sides (paired): flagged in its cell
// alone; bands given as edges still find it.
TEST(Verdict, OneCaseOutOfFiftyIsFlagged) {
    auto one = [](double t, double s, const std::string& l) {
        return l == "relief" && t == 70 && s == 0.05 ? 2.0 : 1.0;
    };
    const VerdictRows old = synthetic(kLabels, seedRange(1, 3), 11, 0.05, 0.03, unchanged);
    // The same seeds: the same shared noise (same rng stream), the method's change alone.
    const VerdictRows neu = synthetic(kLabels, seedRange(1, 3), 11, 0.05, 0.03, one);
    const Comparison c = judge(old, neu, samePairs(), {}, "test");
    int regressions = 0;
    for (const auto& cell : c.cells)
        if (cell.change == Change::Regression) {
            ++regressions;
            EXPECT_EQ(cell.labelOld, "relief");
            EXPECT_EQ(cell.thetaLo, 70);
            EXPECT_EQ(cell.scale, 0.05);
            EXPECT_NEAR(cell.ratio, 2.0, 0.01);
        }
    EXPECT_EQ(regressions, 1);
    VerdictOptions bands;
    bands.bandEdges = {0, 45, 90};
    const Comparison b = judge(old, neu, samePairs(), bands, "test");
    EXPECT_TRUE(b.regressed());
}

// Better by any factor, paired or not, is never a regression.
TEST(Verdict, AnImprovementIsNeverARegression) {
    for (double f : {0.5, 0.8, 0.95}) {
        auto better = [f](double, double, const std::string&) { return f; };
        const VerdictRows old = synthetic(kLabels, seedRange(1, 4), 21, 0.05, 0.03, unchanged);
        const VerdictRows neu = synthetic(kLabels, seedRange(5, 4), 22, 0.05, 0.03, better);
        const Comparison c = judge(old, neu, samePairs(), {}, "test");
        EXPECT_FALSE(c.regressed()) << f;
        for (const auto& cell : c.cells) EXPECT_NE(cell.change, Change::Regression);
        if (f == 0.5) {
            EXPECT_EQ(c.configs[0].change, Change::Improvement);
        }
    }
}

TEST(Verdict, OneSeedIsRefusedWithTheWayOut) {
    const VerdictRows one = synthetic(kLabels, {1}, 1, 0.05, 0.03, unchanged);
    try {
        judge(one, one, samePairs(), {}, "OLD vs NEW");
        FAIL() << "one seed judged";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("replicates"), std::string::npos) << e.what();
    }
}

TEST(Verdict, ParameterChangesAreNamed) {
    const auto c =
        parameterChanges(R"({"method":"pom","params":{"min_layers":8,"max_layers":32}})",
                         R"({"method":"pom","params":{"min_layers":2,"max_layers":32}})");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0], "params.min_layers 8 → 2");
    EXPECT_TRUE(parameterChanges("{}", "{}").empty());
}

}  // namespace
}  // namespace pgt
