// frame.exr's channel schema in one place (docs/outputs.md): every channel's name, its group
// (`pgt render --channels`), whether each method has one, and what a pixel writes into it.
// The names, their order, the offsets in an interleaved row, the groups a --channels list
// keeps and the interleaving itself all come from this table; a new channel is one entry in
// frame_channels.cpp and one in docs/outputs.md (a test checks the document names it).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/samples.h"
#include "raster/raster.h"

namespace pgt {

struct FrameBand;
struct MethodConfig;

// The groups a frame.exr holds; `none` of them writes no frame.exr.
enum class ChannelGroup { Uv, Depth, Shadow, Inputs };
inline constexpr size_t kChannelGroups = 4;
// Their names as --channels takes them ("uv", "depth", "shadow", "inputs"), in enum order.
const std::array<const char*, kChannelGroups>& channelGroupNames();

// What one pixel of a band offers a channel: the truth, the rasterised fragment, V per vertex
// where a method reads it, and for a method's channel its pixel and error.
struct ChannelPixel {
    const TruthSample& truth;
    const Fragment& fragment;
    const FragmentInputs* inputs;  // null unless the frame's methods read FragmentInputs
    const MethodPixel* method;     // null for the frame's own channels
    float errTexels;               // the method's error (NaN: none)
};

// Writes one channel of pixels [begin, end) of a band into `out` (one float a pixel, `stride`
// floats apart); `method`: the configuration's index for a method's channel.
using ChannelFill = void (*)(const FrameBand& band, size_t begin, size_t end, size_t method,
                             float* out, size_t stride);

struct FrameChannel {
    // The whole name ("truth.u"), or the suffix after a method's label (".u").
    const char* name;
    ChannelGroup group;
    bool perMethod = false;
    // Only where a method reads FragmentInputs (base.Vvertex).
    bool needsInputs = false;
    ChannelFill fill = nullptr;
};

// The schema in file order. A run of per-method entries is written method by method: each
// configuration's channels of the run together, in the configurations' order.
const std::vector<FrameChannel>& frameChannelSchema();

// One channel of a frame's interleaved row: its schema entry and, for a method's, which.
struct FrameChannelSlot {
    const FrameChannel* channel;
    size_t method;  // the configuration's index (0 for the frame's own)
    std::string name;
};
// A frame's channels for `methods` configurations (with the inputs' where `inputs`), in the
// order of an interleaved row.
std::vector<FrameChannelSlot> frameChannelLayout(const std::vector<std::string>& labels,
                                                 bool inputs);
// The same for a frame of these configurations (their labels; the inputs' where one reads
// FragmentInputs).
std::vector<FrameChannelSlot> frameChannelLayout(const std::vector<MethodConfig>& configs);
// Their count without building them.
size_t frameChannelCount(size_t methods, bool inputs);
std::vector<std::string> frameChannelNames(const std::vector<MethodConfig>& configs);

// A band's pixels as frame.exr holds them: channels interleaved, row by row (NaN where a
// channel has no value), into `rows` (width x rows x channels floats).
void interleaveFrameBand(const FrameBand& band, float* rows);

}  // namespace pgt
