// frame.exr's channel schema (frame/frame_channels.h) and the interleaving it drives.
#include "frame/frame_channels.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "frame/render.h"
#include "methods/config.h"

namespace pgt {

namespace {

// Pixel k of a band as a channel of configuration `method` sees it.
ChannelPixel pixelOf(const FrameBand& b, size_t k, size_t method, bool perMethod) {
    return {b.truth->data[k], b.fragments->data[k], b.inputs ? &b.inputs->data[k] : nullptr,
            perMethod ? &b.pixels[method]->data[k] : nullptr,
            perMethod ? b.errTexels[method]->data[k] : NAN};
}

// A channel's fill from its per-pixel value (inlined into the loop: one indirect call a
// channel and block, not a pixel).
template <bool PerMethod, auto Value>
void fillWith(const FrameBand& b, size_t begin, size_t end, size_t method, float* out,
              size_t stride) {
    for (size_t k = begin; k < end; ++k) out[k * stride] = Value(pixelOf(b, k, method, PerMethod));
}

float shadowOf(int8_t state) { return state == kShadowNone ? NAN : float(state); }
// A value where the fragment was drawn, NaN elsewhere.
float drawn(const ChannelPixel& p, double v) { return p.fragment.covered ? float(v) : NAN; }
float ofMethod(const ChannelPixel& p, double v) { return p.method->covered ? float(v) : NAN; }
float exact(const ChannelPixel& p, int c) {
    return p.fragment.covered && p.fragment.exactFrame ? float(p.fragment.viewTangentExact[c])
                                                       : NAN;
}
float vertexV(const ChannelPixel& p, int c) {
    return p.fragment.covered ? float(p.inputs->viewVertex[c]) : NAN;
}

constexpr ChannelGroup kUv = ChannelGroup::Uv, kDepth = ChannelGroup::Depth,
                       kShadow = ChannelGroup::Shadow, kInputs = ChannelGroup::Inputs;

// A frame's own channel and a method's.
template <auto Value>
FrameChannel frame(const char* name, ChannelGroup group, bool needsInputs = false) {
    return {name, group, false, needsInputs, &fillWith<false, Value>};
}
template <auto Value>
FrameChannel method(const char* suffix, ChannelGroup group) {
    return {suffix, group, true, false, &fillWith<true, Value>};
}

}  // namespace

const std::array<const char*, kChannelGroups>& channelGroupNames() {
    static const std::array<const char*, kChannelGroups> names = {"uv", "depth", "shadow",
                                                                  "inputs"};
    return names;
}

const std::vector<FrameChannel>& frameChannelSchema() {
    using P = const ChannelPixel&;
    static const std::vector<FrameChannel> schema = {
        // Where the truth's ray hits (NaN: a miss), and the rasterised base uv0.
        frame<[](P p) { return p.truth.hit ? float(p.truth.uv.x) : NAN; }>("truth.u", kUv),
        frame<[](P p) { return p.truth.hit ? float(p.truth.uv.y) : NAN; }>("truth.v", kUv),
        frame<[](P p) { return p.truth.hit ? 1.0f : 0.0f; }>("truth.hit", kUv),
        frame<[](P p) { return drawn(p, p.fragment.uv0.x); }>("base.u", kUv),
        frame<[](P p) { return drawn(p, p.fragment.uv0.y); }>("base.v", kUv),
        frame<[](P p) { return p.fragment.covered ? 1.0f : 0.0f; }>("base.hit", kUv),
        // Each method's uv' and its error in texels.
        method<[](P p) { return ofMethod(p, p.method->uv.x); }>(".u", kUv),
        method<[](P p) { return ofMethod(p, p.method->uv.y); }>(".v", kUv),
        method<[](P p) { return p.errTexels; }>(".err", kUv),
        // The depth offsets and shadow states (docs/model.md §5b, §6c), after the UV channels.
        frame<[](P p) { return float(p.truth.depth); }>("truth.depth", kDepth),
        frame<[](P p) { return shadowOf(p.truth.shadow); }>("truth.shadow", kShadow),
        method<[](P p) { return p.method->covered ? p.method->depth : NAN; }>(".depth", kDepth),
        method<[](P p) { return p.method->covered ? shadowOf(p.method->shadow) : NAN; }>(".shadow",
                                                                                         kShadow),
        // The tangent-space V every method was given (the base's frame: pgt's, the asset's or
        // MikkTSpace) and V in the exact frame of the drawn surface (docs/model.md §2).
        frame<[](P p) { return drawn(p, p.fragment.viewTangent.x); }>("base.V.x", kInputs),
        frame<[](P p) { return drawn(p, p.fragment.viewTangent.y); }>("base.V.y", kInputs),
        frame<[](P p) { return drawn(p, p.fragment.viewTangent.z); }>("base.V.z", kInputs),
        frame<[](P p) { return exact(p, 0); }>("base.Vexact.x", kInputs),
        frame<[](P p) { return exact(p, 1); }>("base.Vexact.y", kInputs),
        frame<[](P p) { return exact(p, 2); }>("base.Vexact.z", kInputs),
        // V per vertex, where a method reads FragmentInputs.
        frame<[](P p) { return vertexV(p, 0); }>("base.Vvertex.x", kInputs, true),
        frame<[](P p) { return vertexV(p, 1); }>("base.Vvertex.y", kInputs, true),
        frame<[](P p) { return vertexV(p, 2); }>("base.Vvertex.z", kInputs, true),
    };
    return schema;
}

std::vector<FrameChannelSlot> frameChannelLayout(const std::vector<std::string>& labels,
                                                 bool inputs) {
    const auto& schema = frameChannelSchema();
    std::vector<FrameChannelSlot> out;
    for (size_t i = 0; i < schema.size();) {
        if (!schema[i].perMethod) {
            if (!schema[i].needsInputs || inputs) out.push_back({&schema[i], 0, schema[i].name});
            ++i;
            continue;
        }
        size_t run = i;  // a run of per-method entries, method by method
        while (run < schema.size() && schema[run].perMethod) ++run;
        for (size_t m = 0; m < labels.size(); ++m)
            for (size_t j = i; j < run; ++j)
                out.push_back({&schema[j], m, labels[m] + schema[j].name});
        i = run;
    }
    return out;
}

size_t frameChannelCount(size_t methods, bool inputs) {
    size_t n = 0;
    for (const FrameChannel& c : frameChannelSchema())
        n += c.perMethod ? methods : (!c.needsInputs || inputs) ? 1 : 0;
    return n;
}

std::vector<FrameChannelSlot> frameChannelLayout(const std::vector<MethodConfig>& configs) {
    std::vector<std::string> labels;
    for (const MethodConfig& c : configs) labels.push_back(c.label);
    return frameChannelLayout(labels, readsFragmentInputs(configs));
}

std::vector<std::string> frameChannelNames(const std::vector<MethodConfig>& configs) {
    std::vector<std::string> names;
    for (const FrameChannelSlot& s : frameChannelLayout(configs)) names.push_back(s.name);
    return names;
}

void interleaveFrameBand(const FrameBand& b, float* rows) {
    // Labels do not matter here: the layout's slots, in row order.
    const std::vector<FrameChannelSlot> layout =
        frameChannelLayout(std::vector<std::string>(b.pixels.size()), b.inputs != nullptr);
    const size_t nc = layout.size(), n = b.truth->data.size();
    // Blocks of 512 pixels (their rows stay in the core's cache while every channel is
    // written into them), channel by channel.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const auto& r) {
        for (size_t c = 0; c < nc; ++c)
            layout[c].channel->fill(b, r.begin(), r.end(), layout[c].method, rows + c, nc);
    });
}

}  // namespace pgt
