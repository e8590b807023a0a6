// The comparison tallies, CsvTable, StagedFiles and ExrWriter on their own, with answers known
// by construction: a frame's statistics do not depend on how it is cut into bands; CSV written
// and read back is the same bytes; staged files appear together or not at all; an EXR read back
// by OpenEXR holds the bits written, in the compression asked for.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "compare/compare.h"
#include "compare/uncertainty.h"
#include "core/error.h"
#include "io/csv_table.h"
#include "io/image_files.h"
#include "io/staged_files.h"
#include "test_util.h"

namespace pgt {
namespace {

namespace fs = std::filesystem;

// A W x H frame whose method lands `k` texels right of the truth at pixel k (k = y W + x),
// with every fifth pixel a class of its own: truth only, raster only, non-finite, neither.
struct Frame {
    Image2D<TruthSample> truth;
    Image2D<MethodPixel> method;
    std::vector<double> errors;  // the compared pixels' errors, in texels
    int64_t truthOnly = 0, rasterOnly = 0, nonfinite = 0, neither = 0;
};

Frame makeFrame(int w, int h, int tex) {
    Frame f;
    f.truth = Image2D<TruthSample>(w, h);
    f.method = Image2D<MethodPixel>(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int k = y * w + x;
            TruthSample& t = f.truth.at(x, y);
            MethodPixel& m = f.method.at(x, y);
            t.hit = true;
            t.uv = Vec2d(0.25, 0.5);
            m.covered = true;
            m.fetches = uint32_t(k % 7);
            const double texels = 0.01 * k;  // far below half the map: no wrap
            m.uv = t.uv + Vec2d(texels / tex, 0);
            switch (k % 5) {
                case 1:
                    m.covered = false, ++f.truthOnly;
                    break;
                case 2:
                    t.hit = false, ++f.rasterOnly;
                    break;
                case 3:
                    m.uv = Vec2d(NAN, 0.5), ++f.nonfinite;
                    break;
                case 4:
                    t.hit = false, m.covered = false, ++f.neither;
                    break;
                default:
                    f.errors.push_back(texels);
            }
        }
    return f;
}

// Rows [y0, y1) of an image.
template <class T>
Image2D<T> rows(const Image2D<T>& img, int y0, int y1) {
    Image2D<T> out(img.width, y1 - y0);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < img.width; ++x) out.at(x, y - y0) = img.at(x, y);
    return out;
}

TEST(ErrorTally, CountsAndStatisticsByConstruction) {
    const int tex = 64;
    Frame f = makeFrame(9, 7, tex);
    FrameStats s = compareWithTruth(f.truth, f.method, tex, tex, Address::Clamp);
    EXPECT_EQ(s.coverage.both, int64_t(f.errors.size()) + f.nonfinite);
    EXPECT_EQ(s.coverage.truthOnly, f.truthOnly);
    EXPECT_EQ(s.coverage.rasterOnly, f.rasterOnly);
    EXPECT_EQ(s.coverage.neither, f.neither);
    EXPECT_EQ(s.nonfinite, f.nonfinite);
    ASSERT_EQ(s.error.count, int64_t(f.errors.size()));
    double sum = 0, largest = 0;
    for (double e : f.errors) sum += e, largest = std::max(largest, e);
    EXPECT_NEAR(s.error.mean, sum / double(f.errors.size()), 1e-6);
    EXPECT_NEAR(s.error.max, largest, 1e-6);
    EXPECT_DOUBLE_EQ(s.fracAbove1Texel, 0.0);  // every error here is under 0.63 texel
}

// Cut into bands of any height, a frame tallies to the same statistics as whole; in place,
// its coded image holds each pixel's error or the code of its class.
TEST(ErrorTally, BandsOfAnyHeightGiveTheWholeFramesStatistics) {
    const int tex = 32, w = 11, h = 13;
    Frame f = makeFrame(w, h, tex);
    const FrameStats whole = compareWithTruth(f.truth, f.method, tex, tex, Address::Repeat);
    std::mt19937 rng(3);
    for (int trial = 0; trial < 5; ++trial) {
        ErrorTally bands, inPlace(w, h);
        for (int y0 = 0; y0 < h;) {
            const int y1 = std::min(h, y0 + 1 + int(rng() % 5));
            const auto t = rows(f.truth, y0, y1);
            const auto m = rows(f.method, y0, y1);
            bands.add(t, m, tex, tex, Address::Repeat);
            inPlace.add(t, m, tex, tex, Address::Repeat, nullptr, y0);
            y0 = y1;
        }
        for (ErrorTally* tally : {&bands, &inPlace}) {
            const bool coded = tally == &inPlace;
            const FrameStats s = tally->finish();
            EXPECT_EQ(s.error.count, whole.error.count);
            EXPECT_DOUBLE_EQ(s.error.mean, whole.error.mean);
            EXPECT_DOUBLE_EQ(s.error.p90, whole.error.p90);
            EXPECT_EQ(s.coverage.truthOnly, whole.coverage.truthOnly);
            EXPECT_EQ(s.nonfinite, whole.nonfinite);
            EXPECT_EQ(s.fetchesMax, whole.fetchesMax);
            EXPECT_DOUBLE_EQ(s.fetchesMean, whole.fetchesMean);
            if (!coded) continue;
            const Image2D<float> codes = tally->takeCoded();
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const int k = y * w + x;
                    const float want = k % 5 == 0   ? float(0.01 * k)
                                       : k % 5 == 1 ? kCodeTruthOnly
                                       : k % 5 == 2 ? kCodeRasterOnly
                                       : k % 5 == 3 ? kCodeNonFinite
                                                    : kCodeNeither;
                    EXPECT_NEAR(codes.at(x, y), want, 1e-5f) << x << "," << y;
                }
        }
    }
}

// The truth against itself has no uncertainty; a fine frame moved by d texels has d at every
// percentile; a hit in one frame only is a mismatch, never a difference.
TEST(UncertaintyTally, KnownDifferences) {
    const int tex = 16, w = 6, h = 5;
    Image2D<TruthSample> coarse(w, h), fine(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            coarse.at(x, y).hit = fine.at(x, y).hit = true;
            coarse.at(x, y).uv = Vec2d(0.5, 0.5);
            fine.at(x, y).uv = Vec2d(0.5, 0.5 + 0.25 / tex);  // a quarter texel along v
        }
    fine.at(0, 0).hit = false;
    UncertaintyTally same;
    same.add(coarse, coarse, tex, tex, Address::Clamp);
    const TruthUncertainty zero = same.finish();
    EXPECT_EQ(zero.pixelsCompared, w * h);
    EXPECT_DOUBLE_EQ(zero.maxTexels, 0.0);
    UncertaintyTally moved;
    moved.add(rows(coarse, 0, 2), rows(fine, 0, 2), tex, tex, Address::Clamp);
    moved.add(rows(coarse, 2, h), rows(fine, 2, h), tex, tex, Address::Clamp);
    const TruthUncertainty u = moved.finish();
    EXPECT_EQ(u.pixelsCompared, w * h - 1);
    EXPECT_EQ(u.hitMismatch, 1);
    EXPECT_NEAR(u.p50Texels, 0.25, 1e-6);
    EXPECT_NEAR(u.p99Texels, 0.25, 1e-6);
    EXPECT_NEAR(u.maxTexels, 0.25, 1e-6);
    // Nothing compared: nothing measured (NaN), not zero.
    UncertaintyTally empty;
    EXPECT_TRUE(std::isnan(empty.finish().p99Texels));
}

struct CsvRow {
    std::string name, json;
    double value;
};

// Written and read back, every line is the same bytes, whatever its fields hold.
TEST(CsvTable, RoundTripsQuotesCommasAndLineBreaks) {
    const CsvTable<CsvRow> table(
        {{"name", [](const CsvRow& r) { return r.name; }},
         {"params", [](const CsvRow& r) { return r.json; }, true},
         {"value", [](const CsvRow& r) { return std::to_string(r.value); }}});
    EXPECT_EQ(table.header(), "name,params,value\n");
    const std::vector<CsvRow> input = {{"plain", "{}", 1.5},
                                       {"a,comma", R"({"k": "v, w"})", -2},
                                       {"a \"quote\"", R"({"q": "\""})", 0},
                                       {"two\nlines", "", 3}};
    std::string text = table.header();
    for (const CsvRow& r : input) text += table.line(r);
    EXPECT_NE(text.find("\"a,comma\""), std::string::npos);
    EXPECT_NE(text.find("\"a \"\"quote\"\"\""), std::string::npos);
    EXPECT_NE(text.find(",\"{}\","), std::string::npos);  // a JSON column is always quoted
    bool torn = true;
    const auto records = splitCsvRecords(text, 0, &torn);
    EXPECT_FALSE(torn);
    ASSERT_EQ(records.size(), input.size() + 1);
    EXPECT_EQ(records[4][0], "two\nlines");
    for (size_t i = 0; i < input.size(); ++i)
        EXPECT_EQ(table.line(records[i + 1]), table.line(input[i])) << i;
    // A record cut short (a killed writer) is reported, not read as whole.
    splitCsvRecords(text.substr(0, text.size() - 3), 0, &torn);
    EXPECT_TRUE(torn);
    // A reader that does not ask whether the text was torn (it once crashed on a null flag).
    EXPECT_EQ(splitCsvRecords(text, 0, nullptr).size(), records.size());
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path freshDir(const char* name) { return test::tempDir(name); }  // a name of its own

// Staged files appear together on commit, with their bytes; none shows before; dropped
// uncommitted, they leave nothing behind, not even a temporary.
TEST(StagedFiles, AllTogetherOnCommitOrNothing) {
    const fs::path dir = freshDir("pgt_staged_test");
    {
        StagedFiles files(dir.string());
        files.add("a.txt", "first\n");
        StagedStream& s = files.stream("b.bin");
        const char bytes[] = {1, 2, 3};
        EXPECT_EQ(s.write(bytes, 3), 3u);
        s.finish();
        EXPECT_FALSE(fs::exists(dir / "a.txt"));
        EXPECT_FALSE(fs::exists(dir / "b.bin"));
        files.commit();
    }
    EXPECT_EQ(readAll(dir / "a.txt"), "first\n");
    EXPECT_EQ(readAll(dir / "b.bin"), std::string("\1\2\3"));
    {
        StagedFiles dropped(dir.string());
        dropped.add("c.txt", "never\n");
    }
    int entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
    EXPECT_EQ(entries, 2);  // a.txt and b.bin: no c.txt, no temporary
    fs::remove_all(dir);
}

// A directory that cannot take the file is an OutputError naming the file, not a crash.
TEST(StagedFiles, AnUnwritableDirectoryIsAnOutputError) {
    const fs::path dir = freshDir("pgt_staged_gone");
    StagedFiles files(dir.string());
    fs::remove_all(dir);
    try {
        files.add("x.txt", "bytes");
        FAIL() << "no error";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find("x.txt"), std::string::npos) << e.what();
    }
}

// "auto" compresses a row of fewer than kPizRowValues values (width x channels) with zip at level 1
// and a wider one with PIZ (the level is the encoder's, not recorded in the file); "piz", "zip"
// and "none" are taken as said; every one holds the bits written (NaN, infinities, denormals,
// seeded random floats), read back by OpenEXR.
TEST(ExrWriter, AutoChoosesByTheRowsWidthAndEveryChoiceIsLossless) {
    const fs::path dir = freshDir("pgt_exr_writer");
    struct Case {
        const char* compression;
        int width;
        Imf::Compression want;
    };
    const int edge = int(kPizRowValues / 20);  // the narrowest PIZ row of 20 channels
    const Case cases[] = {{"auto", edge - 1, Imf::ZIP_COMPRESSION},
                          {"auto", edge, Imf::PIZ_COMPRESSION},
                          {"piz", 16, Imf::PIZ_COMPRESSION},
                          {"zip", 2000, Imf::ZIP_COMPRESSION},
                          {"none", 16, Imf::NO_COMPRESSION}};
    const int height = 5;
    std::vector<std::string> channels;
    for (int c = 0; c < 20; ++c) channels.push_back(std::string(1, char('a' + c)));
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<float> value(-3, 3);
    for (const Case& c : cases) {
        const std::string name = std::string(c.compression) + std::to_string(c.width) + ".exr";
        std::vector<float> rows(size_t(c.width) * height * channels.size());
        for (float& v : rows) v = value(rng);
        rows[0] = NAN, rows[1] = INFINITY, rows[2] = -INFINITY, rows[3] = 1e-42f;
        {
            StagedFiles files(dir.string());
            StagedStream& out = files.stream(name);
            ExrWriter exr(out, name, c.width, height, channels, c.compression);
            const size_t perRow = size_t(c.width) * channels.size();
            exr.writeRows(0, 2, rows.data());
            exr.writeRows(2, height, rows.data() + 2 * perRow);
            exr.close();
            files.commit();
        }
        Imf::InputFile in((dir / name).string().c_str());
        EXPECT_EQ(in.header().compression(), c.want) << name;
        std::vector<float> back(rows.size());
        const size_t nc = channels.size();
        Imf::FrameBuffer fb;
        for (size_t k = 0; k < nc; ++k)
            fb.insert(channels[k],
                      Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(back.data() + k),
                                 nc * sizeof(float), size_t(c.width) * nc * sizeof(float)));
        in.setFrameBuffer(fb);
        in.readPixels(0, height - 1);
        EXPECT_EQ(std::memcmp(back.data(), rows.data(), rows.size() * sizeof(float)), 0) << name;
    }
    StagedFiles files(dir.string());
    StagedStream& out = files.stream("x.exr");
    EXPECT_THROW(ExrWriter(out, "x.exr", 4, 4, channels, "lzma"), InputError);
}

}  // namespace
}  // namespace pgt
