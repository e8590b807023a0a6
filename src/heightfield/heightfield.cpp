// Height-field loading (OpenImageIO, through heightfield/image_reader.h), procedural
// generators, and Lengyel FGED 2's derived maps.
#include "heightfield/heightfield.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "heightfield/image_reader.h"
#include "heightfield/mipmaps.h"

namespace pgt {

std::string toString(Address a) { return a == Address::Repeat ? "repeat" : "clamp"; }

namespace {

// Largest accepted map side: 65536 texels; 8192^2 is a stress case (scenes/stress/).
constexpr int kMaxSide = 65536;
constexpr double kMaxTexels = 1 << 28;

void checkSize(const std::string& file, const std::string& field, int w, int h) {
    if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide || double(w) * h > kMaxTexels)
        throw InputError(file, field, std::to_string(w) + "x" + std::to_string(h),
                         "image size out of range (1..65536 per side, at most 2^28 texels)");
}

}  // namespace

namespace {

// Image libraries (libpng through OpenImageIO) print warnings and errors to stderr on their
// own; pgt's promise is one error line. While a decoder runs, fd 2 goes to a temporary file
// whose text is folded into pgt's own message when the decode fails.
class StderrCapture {
  public:
    StderrCapture() {
        std::fflush(stderr);
        file_ = std::tmpfile();
        saved_ = ::dup(2);
        if (file_ && saved_ >= 0) ::dup2(::fileno(file_), 2);
    }
    ~StderrCapture() { restore(); }
    // Restores fd 2 and returns what was written meanwhile, on one line.
    std::string restore() {
        if (saved_ < 0) return text_;
        std::fflush(stderr);
        ::dup2(saved_, 2);
        ::close(saved_);
        saved_ = -1;
        if (file_) {
            std::rewind(file_);
            char buf[512];
            size_t n;
            while ((n = std::fread(buf, 1, sizeof buf, file_)) > 0 && text_.size() < 2000)
                text_.append(buf, n);
            std::fclose(file_);
            file_ = nullptr;
        }
        for (char& c : text_)
            if (c == '\n' || c == '\r') c = ' ';
        while (!text_.empty() && text_.back() == ' ') text_.pop_back();
        return text_;
    }

  private:
    std::FILE* file_ = nullptr;
    int saved_ = -1;
    std::string text_;
};

// One line of why an image could not be read: OIIO's error and what the decoder printed.
std::string whyUnreadable(std::string why, const std::string& printed) {
    for (char& c : why)
        if (c == '\n' || c == '\r') c = ' ';
    if (!printed.empty() && why.find(printed) == std::string::npos)
        why += (why.empty() ? "" : "; ") + printed;
    return why;
}

std::unique_ptr<ImageFile> openHeightImage(const std::string& path, int channel,
                                           const std::string& sceneFile, const std::string& field) {
    requireRegularFile(path, sceneFile, field + ".file", "height map image");
    std::unique_ptr<ImageFile> in;
    std::string printed, why;
    {
        StderrCapture capture;
        in = openImageFile(path, why);
        printed = capture.restore();
    }
    if (!in) {
        why = whyUnreadable(why, printed);
        throw InputError(sceneFile, field + ".file", path,
                         "cannot read image" + (why.empty() ? std::string() : ": " + why));
    }
    const ImageHeader h = in->header();
    checkSize(sceneFile, field + ".file", h.width, h.height);
    if (channel < 0 || channel >= h.channels)
        throw InputError(sceneFile, field + ".channel", std::to_string(channel),
                         "image " + path + " has " + std::to_string(h.channels) + " channel(s)");
    // Decoding holds every channel as read and as doubles, then the float texture.
    double texels = double(h.width) * h.height;
    checkMemory(texels * h.channels * (8.0 + double(h.sampleBytes)) + texels * 4, sceneFile,
                field + ".file", path, "decoding this image");
    return in;
}

}  // namespace

HeightImageHeader probeHeightImage(const std::string& path, int channel,
                                   const std::string& sceneFile, const std::string& field) {
    const ImageHeader h = openHeightImage(path, channel, sceneFile, field)->header();
    return {h.width, h.height, h.channels};
}

namespace {

// Every channel of every pixel, normalised as docs/model.md §1 says: 8-bit / 255, 16-bit / 65535,
// float as is. Reading the native integer type and dividing here keeps the exact quotient
// (no table lookup).
std::vector<double> decodeNormalised(ImageFile& in, const std::string& path,
                                     const std::string& sceneFile, const std::string& field) {
    const ImageHeader h = in.header();
    std::vector<double> values(size_t(h.width) * h.height * h.channels);
    bool ok = false;
    std::string why;
    StderrCapture capture;
    auto decode = [&](auto sample, double range) {
        std::vector<decltype(sample)> raw(values.size());
        ok = in.read(raw.data(), why);
        for (size_t k = 0; k < raw.size(); ++k) values[k] = raw[k] / range;
    };
    if (h.type == SampleType::UInt8)
        decode(uint8_t(0), 255.0);
    else if (h.type == SampleType::UInt16)
        decode(uint16_t(0), 65535.0);
    else
        decode(0.0f, 1.0);
    std::string printed = capture.restore();
    if (!ok)
        throw InputError(sceneFile, field + ".file", path,
                         "cannot decode image: " + whyUnreadable(why, printed));
    return values;
}

// A colour image without an explicit channel is accepted only when its colour channels
// agree (a grey image saved as RGB); otherwise the choice is ambiguous.
void checkChannelsAgree(const std::vector<double>& values, int nc, const std::string& path,
                        const std::string& sceneFile, const std::string& field) {
    int colour = nc == 2 ? 1 : std::min(nc, 3);  // grey + alpha: one colour channel
    for (size_t p = 0; p < values.size() / size_t(nc) && colour > 1; ++p)
        for (int c = 1; c < colour; ++c)
            if (values[p * nc + c] != values[p * nc])
                throw InputError(sceneFile, field + ".channel", "(missing)",
                                 "image " + path + " has " + std::to_string(nc) +
                                     " channels that differ; choose one with \"channel\"");
}

}  // namespace

Texture loadHeightImage(const std::string& path, int channel, const std::string& sceneFile,
                        const std::string& field, bool channelGiven) {
    auto in = openHeightImage(path, channel, sceneFile, field);
    const int w = in->header().width, h = in->header().height, nc = in->header().channels;
    std::vector<double> values = decodeNormalised(*in, path, sceneFile, field);
    if (!channelGiven && nc > 1) checkChannelsAgree(values, nc, path, sceneFile, field);
    Texture t;
    t.width = w;
    t.height = h;
    t.channels = 1;
    t.texels.resize(size_t(w) * h);
    for (int row = 0; row < h; ++row) {
        int j = h - 1 - row;  // file rows run top-down; v = 0 is the bottom row
        for (int i = 0; i < w; ++i) {
            double value = values[(size_t(row) * w + i) * nc + channel];
            if (!std::isfinite(value)) {
                std::ostringstream os;
                os << path << " texel (column " << i << ", row " << row << " from the top)";
                throw InputError(sceneFile, field + ".file", os.str(),
                                 "non-finite height value " + std::to_string(value));
            }
            t.texel(i, j) = float(value);
        }
    }
    return t;
}

namespace {

// Tileable value noise: lattice values on a period-`cells` grid, smooth (quintic) blend.
double valueNoise(const std::vector<double>& lattice, int cells, double x, double y) {
    int xi = int(std::floor(x)), yi = int(std::floor(y));
    double fx = x - xi, fy = y - yi;
    auto at = [&](int i, int j) {
        i = ((i % cells) + cells) % cells;
        j = ((j % cells) + cells) % cells;
        return lattice[size_t(j) * cells + i];
    };
    auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    double sx = fade(fx), sy = fade(fy);
    double a = at(xi, yi) + (at(xi + 1, yi) - at(xi, yi)) * sx;
    double b = at(xi, yi + 1) + (at(xi + 1, yi + 1) - at(xi, yi + 1)) * sx;
    return a + (b - a) * sy;
}

double smoothstep01(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

// What every generator may use besides its own fields: the map's size and the seed.
struct GeneratorArgs {
    int width = 0, height = 0;
    unsigned seed = 1;
};
// Height as a function of the texel centre (u, v) in [0,1)^2.
using HeightFn = std::function<double(double, double)>;

HeightFn generateConstant(JsonFields& f, const GeneratorArgs&) {
    double value = f.number("value", 0.5, -1e6, 1e6);
    return [=](double, double) { return value; };
}

HeightFn generateRamp(JsonFields& f, const GeneratorArgs&) {
    // h = offset + slope_u * u + slope_v * v at texel centres (exact under bilinear).
    std::vector<double> slope =
        f.has("slope") ? f.numbers("slope", 2, -1e6, 1e6) : std::vector<double>{1.0, 0.0};
    double offset = f.number("offset", 0.0, -1e6, 1e6);
    return [=](double u, double v) { return offset + slope[0] * u + slope[1] * v; };
}

HeightFn generateSine(JsonFields& f, const GeneratorArgs&) {
    // h = 0.5 + amplitude * prod over axes with frequency > 0 of sin(2 pi f x).
    std::vector<double> freq =
        f.has("frequency") ? f.numbers("frequency", 2, 0, 1e4) : std::vector<double>{4, 4};
    double amplitude = f.number("amplitude", 0.5, -1e6, 1e6);
    return [=](double u, double v) {
        double p = 1.0;
        if (freq[0] > 0) p *= std::sin(2 * kPi * freq[0] * u);
        if (freq[1] > 0) p *= std::sin(2 * kPi * freq[1] * v);
        return 0.5 + amplitude * p;
    };
}

HeightFn generateBricks(JsonFields& f, const GeneratorArgs& g) {
    // Running bond: `bricks` = [columns, rows] per repeat, odd rows shifted by half a
    // brick; mortar width and bevel as fractions of a brick's height; h = 1 on bricks.
    std::vector<int> count =
        f.has("bricks") ? f.integers("bricks", 2, 1, 4096) : std::vector<int>{4, 8};
    double mortar = f.number("mortar", 0.1, 0.0, 0.9);
    double bevel = f.number("bevel", 0.15, 0.0, 1.0);
    double mortarHeight = f.number("mortar_height", 0.0, -1e6, 1e6);
    double jitter = f.number("jitter", 0.0, 0.0, 1.0);
    std::mt19937 rng(g.seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<double> brickHeight(static_cast<size_t>(count[0]) * count[1]);
    for (auto& b : brickHeight) b = 1.0 - jitter * uni(rng);
    return [=](double u, double v) {
        double rowF = v * count[1];
        int row = std::min(int(rowF), count[1] - 1);
        double colF = u * count[0] + (row % 2 ? 0.5 : 0.0);
        int col = int(std::floor(colF)) % count[0];
        // Distances to the brick's edges in units of brick height.
        double aspect = double(count[1]) / count[0];  // brick width / height in UV
        double dy = std::min(rowF - row, row + 1 - rowF);
        double dx = std::min(colF - std::floor(colF), std::ceil(colF) - colF) / aspect;
        double inside = std::min(dx, dy) - mortar / 2;
        if (inside <= 0) return mortarHeight;
        double top = brickHeight[size_t(row) * count[0] + col];
        double t = bevel > 0 ? smoothstep01(inside / bevel) : 1.0;
        return mortarHeight + (top - mortarHeight) * t;
    };
}

HeightFn generateSteps(JsonFields& f, const GeneratorArgs&) {
    // A staircase along u: `levels` flat treads from 0 to 1 with jumps between them.
    int levels = f.integer("levels", 4, 2, 65536);
    return [=](double u, double) { return std::floor(u * levels) / (levels - 1); };
}

HeightFn generateChecker(JsonFields& f, const GeneratorArgs&) {
    std::vector<int> cells =
        f.has("cells") ? f.integers("cells", 2, 1, kMaxSide) : std::vector<int>{8, 8};
    return [=](double u, double v) { return double((int(u * cells[0]) + int(v * cells[1])) % 2); };
}

HeightFn generateSpike(JsonFields& f, const GeneratorArgs& g) {
    // One texel at `texel` = [column, row from the bottom] has `value`, all others 0.
    std::vector<int> at = f.has("texel") ? f.integers("texel", 2, 0, kMaxSide - 1)
                                         : std::vector<int>{g.width / 2, g.height / 2};
    double value = f.number("value", 1.0, -1e6, 1e6);
    if (at[0] >= g.width || at[1] >= g.height) f.fail("texel", "outside the map");
    return [at, value, w = g.width, h = g.height](double u, double v) {
        return int(u * w) == at[0] && int(v * h) == at[1] ? value : 0.0;
    };
}

HeightFn generateNoise(JsonFields& f, const GeneratorArgs& g) {
    int cells = f.integer("frequency", 4, 1, 4096);
    int octaves = f.integer("octaves", 4, 1, 12);
    double gain = f.number("gain", 0.5, 0.0, 1.0);
    // The lattices hold (frequency * 2^octave)^2 doubles each: refuse before allocating.
    double latticeBytes = 0;
    for (int o = 0; o < octaves; ++o) latticeBytes += std::pow(double(cells) * (1 << o), 2) * 8;
    checkMemory(latticeBytes, f.file(), f.fieldPath("octaves"), std::to_string(octaves),
                "noise with frequency " + std::to_string(cells) + " and " +
                    std::to_string(octaves) + " octaves (its value lattices)");
    std::mt19937 rng(g.seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<std::vector<double>> lattices;
    for (int o = 0; o < octaves; ++o) {
        int c = cells << o;
        std::vector<double> lat(size_t(c) * c);
        for (auto& x : lat) x = uni(rng);
        lattices.push_back(std::move(lat));
    }
    double norm = 0, amp = 1;
    for (int o = 0; o < octaves; ++o) norm += amp, amp *= gain;
    // Moved into the generator, not copied: the lattices are the bulk of its memory.
    return [lattices = std::move(lattices), cells, octaves, gain, norm](double u, double v) {
        double sum = 0, a = 1;
        for (int o = 0; o < octaves; ++o) {
            int c = cells << o;
            sum += a * valueNoise(lattices[o], c, u * c, v * c);
            a *= gain;
        }
        return sum / norm;
    };
}

// The generators by name: each reads its own fields and returns h(u, v) at texel centres.
using GeneratorFn = HeightFn (*)(JsonFields& f, const GeneratorArgs& g);
const std::pair<const char*, GeneratorFn> kGenerators[] = {
    {"constant", generateConstant}, {"ramp", generateRamp},   {"sine", generateSine},
    {"bricks", generateBricks},     {"steps", generateSteps}, {"checker", generateChecker},
    {"spike", generateSpike},       {"noise", generateNoise},
};

}  // namespace

Texture makeProceduralHeight(const Json& params, const std::string& sceneFile,
                             const std::string& field) {
    JsonFields f(params, sceneFile, field);
    std::vector<std::string> kinds;
    for (const auto& generator : kGenerators) kinds.push_back(generator.first);
    std::string kind = f.choice("procedural", kinds, "");
    std::vector<int> size =
        f.has("size") ? f.integers("size", 2, 1, kMaxSide) : std::vector<int>{256, 256};
    checkSize(sceneFile, field + ".size", size[0], size[1]);
    int w = size[0], h = size[1];
    unsigned seed = unsigned(f.integer("seed", 1, 0, 2147483647));
    // Store the map as an 8- or 16-bit image would (h rounded to k/255 or k/65535 after
    // clamping to [0, 1]): the same surface at two quantisations.
    int quantize = f.integer("quantize", 0, 0, 16);
    if (quantize != 0 && quantize != 8 && quantize != 16)
        f.fail("quantize", "expected 8 or 16 (bits), or 0 for float");
    f.has("channel");  // allowed and meaningless for procedural maps
    f.has("mipmaps");  // read by the scene (scene/scene.cpp)

    GeneratorArgs args{w, h, seed};
    HeightFn fn;
    for (const auto& [name, generate] : kGenerators)
        if (kind == name) fn = generate(f, args);
    f.finish();

    // The map's floats (and its mip chain's third more), refused before they are made.
    checkMemory(double(w) * h * sizeof(float) * 4 / 3, f.file(), f.fieldPath("size"),
                std::to_string(w) + "x" + std::to_string(h),
                "a " + std::to_string(w) + "x" + std::to_string(h) + " procedural height map");
    Texture t;
    t.width = w;
    t.height = h;
    // Row by row into reserved memory (a gigabyte's zero fill alone takes seconds), polling
    // the cancel flag: Ctrl-C in Python stops a 16384^2 map here.
    t.texels.reserve(size_t(w) * h);
    const double levels = quantize == 8 ? 255.0 : 65535.0;
    for (int j = 0; j < h; ++j) {
        throwIfCancelled();
        for (int i = 0; i < w; ++i) {
            double v = fn((i + 0.5) / w, (j + 0.5) / h);
            if (quantize) v = std::round(std::clamp(v, 0.0, 1.0) * levels) / levels;
            t.texels.push_back(float(v));
        }
    }
    return t;
}

DerivedMaps makeDerivedMaps(const Texture& height, double scaleUv, double biasUv) {
    const int w = height.width, h = height.height;
    DerivedMaps maps;
    maps.normal.width = maps.parallax.width = w;
    maps.normal.height = maps.parallax.height = h;
    maps.normal.channels = 3;
    maps.normal.address = maps.parallax.address = height.address;
    maps.normal.texels.resize(size_t(w) * h * 3);
    maps.parallax.texels.resize(size_t(w) * h);
    // Neighbour index: wrapped for repeat, clamped for clamp (Lengyel FGED 2 after Eq. 7.41).
    auto nb = [&](int k, int n) {
        if (height.address == Address::Repeat) return (k + n) % n;
        return std::clamp(k, 0, n - 1);
    };
    for (int j = 0; j < h; ++j) {
        throwIfCancelled();
        for (int i = 0; i < w; ++i) {
            // Lengyel FGED 2 Eq. 7.41 with s in texel units = s_uv * W (resp. H).
            double dx = scaleUv * w / 2 *
                        (double(height.texel(nb(i + 1, w), j)) - height.texel(nb(i - 1, w), j));
            double dy = scaleUv * h / 2 *
                        (double(height.texel(i, nb(j + 1, h))) - height.texel(i, nb(j - 1, h)));
            // Lengyel FGED 2 Eq. 7.43.
            double len = std::sqrt(dx * dx + dy * dy + 1.0);
            double mz = 1.0 / len;
            maps.normal.texel(i, j, 0) = float(-dx / len);
            maps.normal.texel(i, j, 1) = float(-dy / len);
            maps.normal.texel(i, j, 2) = float(mz);
            maps.parallax.texel(i, j) = float(mz * (scaleUv * height.texel(i, j) + biasUv));
        }
    }
    if (height.mips) {  // a mipmapped height map's derived maps get chains of their own
        addMipmaps(maps.normal);
        addMipmaps(maps.parallax);
    }
    return maps;
}

}  // namespace pgt
