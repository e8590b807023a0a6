// judge (verdict/regression.h): cells from the bands, per-seed means, Student's t on the log
// ratio (paired over seeds when both studies ran the same ones, two samples otherwise), each
// cell's variance moderated toward its configuration's, Benjamini-Hochberg over every cell.
#include "verdict/regression.h"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/digamma.hpp>
#include <boost/math/special_functions/polygamma.hpp>
#include <boost/math/special_functions/trigamma.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>

#include "core/error.h"
#include "core/format.h"

namespace pgt {

namespace {

using Json = nlohmann::json;

double mean(const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

// The sample variance (n - 1).
double variance(const std::vector<double>& v) {
    const double m = mean(v);
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return s / double(v.size() - 1);
}

// Student's t quantile for `df` degrees of freedom (df > 0).
double tQuantile(double df, double q) {
    return boost::math::quantile(boost::math::students_t_distribution<double>(df), q);
}

// The band of `theta`: its index among `edges` (-1 outside them); without edges, none needed.
int bandOf(double theta, const std::vector<double>& edges) {
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const bool last = i + 2 == edges.size();
        if (theta >= edges[i] && (theta < edges[i + 1] || (last && theta == edges[i + 1])))
            return int(i);
    }
    return -1;
}

// The seeds every case of `cases` has.
std::set<double> commonSeeds(const std::vector<const VerdictRows::Case*>& cases) {
    std::set<double> seeds;
    for (const auto& [seed, v] : cases.front()->bySeed) seeds.insert(seed);
    for (const auto* c : cases)
        for (auto it = seeds.begin(); it != seeds.end();)
            it = c->bySeed.count(*it) ? std::next(it) : seeds.erase(it);
    return seeds;
}

// Per seed, the mean of the cases' values.
std::vector<double> seedMeans(const std::vector<const VerdictRows::Case*>& cases,
                              const std::set<double>& seeds) {
    std::vector<double> out;
    for (double s : seeds) {
        double sum = 0;
        for (const auto* c : cases) sum += c->bySeed.at(s);
        out.push_back(sum / double(cases.size()));
    }
    return out;
}

bool finiteAt(const VerdictRows::Case& c, const std::set<double>& seeds) {
    for (double s : seeds)
        if (!c.bySeed.count(s) || !std::isfinite(c.bySeed.at(s))) return false;
    return true;
}

// A cell's log ratio: its estimate, the variance of one replicate's log value (s2) with df
// degrees of freedom, and k, with the estimate's variance s2 k.
struct CellFit {
    double est = 0, s2 = 0, df = 0, k = 0;
};

// Paired over seeds (the differences of logs), or two samples with a pooled variance.
CellFit fitCell(const std::vector<double>& o, const std::vector<double>& n, double floor,
                bool paired) {
    std::vector<double> x, y;
    for (double v : o) x.push_back(std::log(v + floor));
    for (double v : n) y.push_back(std::log(v + floor));
    CellFit f;
    if (paired) {
        std::vector<double> d;
        for (size_t i = 0; i < x.size(); ++i) d.push_back(y[i] - x[i]);
        f.est = mean(d);
        f.s2 = variance(d);
        f.df = double(d.size() - 1);
        f.k = 1 / double(d.size());
    } else {
        const double nx = double(x.size()), ny = double(y.size());
        f.est = mean(y) - mean(x);
        f.df = nx + ny - 2;
        f.s2 = ((nx - 1) * variance(x) + (ny - 1) * variance(y)) / f.df;
        f.k = 1 / nx + 1 / ny;
    }
    return f;
}

// The inverse of the trigamma function (Newton's method from 0.5 + 1/x, as Smyth's limma).
double trigammaInverse(double x) {
    if (x > 1e7) return 1 / std::sqrt(x);
    if (x < 1e-6) return 1 / x;
    double y = 0.5 + 1 / x;
    for (int i = 0; i < 50; ++i) {
        const double tri = boost::math::trigamma(y);
        const double dif = tri * (1 - tri / x) / boost::math::polygamma(2, y);
        y += dif;
        if (-dif / y < 1e-8) break;
    }
    return y;
}

// The prior of a configuration's cell variances (Smyth 2004, "Linear models and empirical
// Bayes methods for assessing differential expression"): log s2 is fitted by a scaled F
// distribution, giving a prior variance s0^2 with d0 degrees of freedom. Cells with no spread
// (s2 below 1e-12: deterministic) take no part. d0 is infinite when the cells' variances
// vary no more than sampling alone makes them.
NoisePrior fitPrior(const std::vector<CellFit>& fits) {
    std::vector<double> e, tri;
    for (const CellFit& f : fits)
        if (f.s2 > 1e-12 && f.df > 0) {
            e.push_back(std::log(f.s2) - boost::math::digamma(f.df / 2) + std::log(f.df / 2));
            tri.push_back(boost::math::trigamma(f.df / 2));
        }
    NoisePrior p;
    if (e.size() < 3) return p;  // too few to fit: every cell on its own
    const double em = mean(e);
    const double ev = variance(e) - mean(tri);
    p.d0 = ev > 0 ? 2 * trigammaInverse(ev) : kInfiniteDf;
    p.s0 = std::sqrt(std::exp(
        em + (p.d0 < kInfiniteDf ? boost::math::digamma(p.d0 / 2) - std::log(p.d0 / 2) : 0.0)));
    return p;
}

// The cell's moderated t: its variance shrunk toward the prior's, its degrees of freedom
// d0 + df; the ratio, the 95 % interval and the two-sided p into the cell.
void testCell(const CellFit& f, const NoisePrior& prior, VerdictCell& cell) {
    const double d0 = std::min(prior.d0, kInfiniteDf);
    const double s2 = (d0 * prior.s0 * prior.s0 + f.df * f.s2) / (d0 + f.df);
    const double df = std::min(d0 + f.df, kInfiniteDf);
    const double se = std::sqrt(s2 * f.k);
    cell.ratio = std::exp(f.est);
    cell.df = df;
    if (!(se > 0)) {  // no spread at all, and no prior: the ratio is exact
        cell.lo = cell.hi = cell.ratio;
        cell.p = f.est == 0 ? 1 : 0;
        return;
    }
    const double q = tQuantile(df, 0.975);
    cell.lo = std::exp(f.est - q * se), cell.hi = std::exp(f.est + q * se);
    boost::math::students_t_distribution<double> t(df);
    cell.p = std::min(1.0, 2 * boost::math::cdf(boost::math::complement(t, std::fabs(f.est / se))));
}

// Benjamini and Hochberg's step-up: the i-th smallest of m p-values times m / i, kept
// monotone from the largest down (the q-values). When nothing changed, the chance that any
// cell is flagged at level alpha is at most alpha; when some did, the share of flagged cells
// that did not is at most alpha.
void benjaminiHochberg(std::vector<VerdictCell>& cells) {
    std::vector<size_t> order(cells.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return cells[a].p < cells[b].p; });
    double running = 1;
    const size_t m = cells.size();
    for (size_t i = m; i-- > 0;) {
        running = std::min(running, double(m) / double(i + 1) * cells[order[i]].p);
        cells[order[i]].pAdjusted = running;
    }
}

struct CellKey {
    int band = 0;  // index of the band (or of the theta without edges)
    double scale = 0;
    bool operator<(const CellKey& o) const {
        return std::tie(scale, band) < std::tie(o.scale, o.band);
    }
};

// A cell's cases, OLD's and NEW's in pairs: those finite at every seed of both kept, the
// per-seed means fitted (into `fits`); false when none is left. InputError when a side has
// fewer than two seeds.
bool measureCell(const std::vector<const VerdictRows::Case*>& oldCases,
                 const std::vector<const VerdictRows::Case*>& newCases, double floor,
                 const std::string& what, VerdictCell& cell, std::vector<CellFit>& fits) {
    const std::set<double> so = commonSeeds(oldCases), sn = commonSeeds(newCases);
    std::vector<const VerdictRows::Case*> o, n;
    for (size_t i = 0; i < oldCases.size(); ++i) {
        if (finiteAt(*oldCases[i], so) && finiteAt(*newCases[i], sn))
            o.push_back(oldCases[i]), n.push_back(newCases[i]);
        else
            ++cell.leftOut;
    }
    cell.cases = int(o.size());
    cell.seedsOld = int(so.size()), cell.seedsNew = int(sn.size());
    if (so.size() < 2 || sn.size() < 2)
        throw InputError(what, "seed", std::to_string(std::min(so.size(), sn.size())),
                         "\"" + cell.labelOld + "\" at theta " + formatNumber(cell.thetaLo, 6) +
                             ", scale " + formatNumber(cell.scale, 6) + " has " +
                             std::to_string(so.size()) + " seed(s) in OLD and " +
                             std::to_string(sn.size()) +
                             " in NEW: a verdict needs the spread of at least 2 replicates "
                             "on each side; add \"replicates\": 3 to each study's sweep "
                             "block and run it (docs/studies.md, \"Replicates\")");
    if (o.empty()) return false;  // nothing finite to compare
    cell.paired = so == sn;
    const std::vector<double> om = seedMeans(o, so), nm = seedMeans(n, sn);
    cell.oldMean = mean(om), cell.newMean = mean(nm);
    fits.push_back(fitCell(om, nm, floor, cell.paired));
    return true;
}

// One pair's cells: the common cases grouped by (band, scale), each tested.
void judgePair(const VerdictRows& old, const VerdictRows& neu, const ConfigPair& pair,
               const VerdictOptions& opt, const std::string& what, Comparison& out) {
    static const std::map<std::string, VerdictRows::Case> kNone;
    const auto& oc = old.byLabel.count(pair.labelOld) ? old.byLabel.at(pair.labelOld) : kNone;
    const auto& nc = neu.byLabel.count(pair.labelNew) ? neu.byLabel.at(pair.labelNew) : kNone;
    std::vector<double> thetas;  // without edges: each theta its own band
    for (const auto& [key, c] : oc)
        if (nc.count(key)) thetas.push_back(c.theta);
    std::sort(thetas.begin(), thetas.end());
    thetas.erase(std::unique(thetas.begin(), thetas.end()), thetas.end());
    std::map<CellKey, std::pair<std::vector<const VerdictRows::Case*>,
                                std::vector<const VerdictRows::Case*>>>
        groups;
    for (const auto& [key, c] : oc) {
        if (!nc.count(key)) continue;
        const int band =
            opt.bandEdges.empty()
                ? int(std::lower_bound(thetas.begin(), thetas.end(), c.theta) - thetas.begin())
                : bandOf(c.theta, opt.bandEdges);
        if (band < 0) continue;
        groups[{band, c.scale}].first.push_back(&c);
        groups[{band, c.scale}].second.push_back(&nc.at(key));
    }
    ConfigVerdict verdict{pair.labelOld, pair.labelNew, pair.changed, Change::Unchanged, {}, {}};
    std::vector<CellFit> fits;
    for (auto& [key, group] : groups) {
        VerdictCell cell;
        cell.labelOld = pair.labelOld, cell.labelNew = pair.labelNew;
        cell.scale = key.scale;
        cell.thetaLo = opt.bandEdges.empty() ? thetas[key.band] : opt.bandEdges[key.band];
        cell.thetaHi = opt.bandEdges.empty() ? thetas[key.band] : opt.bandEdges[key.band + 1];
        if (!measureCell(group.first, group.second, opt.floor, what, cell, fits)) continue;
        verdict.cells.push_back(out.cells.size());
        out.cells.push_back(cell);
    }
    verdict.prior = fitPrior(fits);
    for (size_t i = 0; i < fits.size(); ++i)
        testCell(fits[i], verdict.prior, out.cells[verdict.cells[i]]);
    out.configs.push_back(std::move(verdict));
}

}  // namespace

const char* toString(Change c) {
    switch (c) {
        case Change::Regression:
            return "regression";
        case Change::Improvement:
            return "improvement";
        case Change::Unchanged:
            break;
    }
    return "unchanged";
}

bool Comparison::regressed() const {
    return std::any_of(configs.begin(), configs.end(),
                       [](const ConfigVerdict& c) { return c.change == Change::Regression; });
}

Comparison judge(const VerdictRows& old, const VerdictRows& neu,
                 const std::vector<ConfigPair>& pairs, const VerdictOptions& options,
                 const std::string& what) {
    Comparison out;
    for (const ConfigPair& p : pairs) judgePair(old, neu, p, options, what, out);
    benjaminiHochberg(out.cells);
    for (VerdictCell& c : out.cells) {
        if (c.pAdjusted > options.alpha) continue;
        if (c.ratio >= 1 + options.minEffect) c.change = Change::Regression;
        if (c.ratio <= 1 / (1 + options.minEffect)) c.change = Change::Improvement;
    }
    for (ConfigVerdict& v : out.configs) {
        for (size_t i : v.cells) {
            const Change c = out.cells[i].change;
            if (c == Change::Regression) v.change = Change::Regression;
            if (c == Change::Improvement && v.change == Change::Unchanged)
                v.change = Change::Improvement;
        }
    }
    return out;
}

MeanInterval meanInterval(const std::vector<double>& values) {
    if (values.empty()) return {NAN, NAN};
    if (values.size() < 2) return {values[0], NAN};
    const double se = std::sqrt(variance(values) / double(values.size()));
    return {mean(values), se > 0 ? tQuantile(double(values.size() - 1), 0.975) * se : 0.0};
}

std::vector<std::string> parameterChanges(const std::string& oldParams,
                                          const std::string& newParams) {
    if (oldParams == newParams) return {};
    const Json a = Json::parse(oldParams, nullptr, false),
               b = Json::parse(newParams, nullptr, false);
    if (a.is_discarded() || b.is_discarded()) return {oldParams + " → " + newParams};
    const Json fa = a.flatten(), fb = b.flatten();
    std::vector<std::string> out;
    auto name = [](std::string k) {
        if (!k.empty() && k[0] == '/') k.erase(0, 1);
        std::replace(k.begin(), k.end(), '/', '.');
        return k;
    };
    for (auto it = fa.begin(); it != fa.end(); ++it) {
        const std::string was = it.value().dump();
        const std::string now = fb.contains(it.key()) ? fb.at(it.key()).dump() : "(none)";
        if (was != now) out.push_back(name(it.key()) + " " + was + " → " + now);
    }
    for (auto it = fb.begin(); it != fb.end(); ++it)
        if (!fa.contains(it.key()))
            out.push_back(name(it.key()) + " (none) → " + it.value().dump());
    return out;
}

}  // namespace pgt
