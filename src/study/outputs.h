// Writers for `pgt render`: frame.exr (named float channels), summary.json, and the
// false-colour error maps for people. All go through staged files (study/staged_files.h):
// written whole to temporaries, renamed into place together.
#pragma once

#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "study/render.h"

namespace pgt {

class ExrWriter;
class StagedFiles;
class StagedStream;

// The channel groups frame.exr holds (docs/outputs.md; `pgt render --channels`): "uv" (the
// truth's, the base's and each method's u, v and hit or err), "depth", "shadow" and "inputs"
// (base.V, base.Vexact, base.Vvertex); none of them: no frame.exr (and no rows interleaved).
// A group left out is dropped from the interleaved rows before the encoder sees them.
struct FrameChannelSet {
    bool uv = true, depth = true, shadow = true, inputs = true;
    bool any() const { return uv || depth || shadow || inputs; }
    // Whether the channel named `name` (frameChannelNames) is in the set.
    bool holds(const std::string& name) const;
};
// "all", "none" or a comma-separated list of the groups; anything else throws InputError
// naming `field`.
FrameChannelSet parseFrameChannels(const std::string& list, const std::string& field);

// The files of one rendered view, written as its bands arrive (a FrameSink): frame.exr row
// by row. finish() draws the error maps from the result's coded errors (their colour scale
// needs the whole frame's p99; render with FrameOptions::keepCodedErrors), one per core,
// writes summary.json and renames every file into place. Throws OutputError
// naming the path that could not be written; nothing is left behind then.
class RenderWriter : public FrameSink {
  public:
    // Creates DIR and opens DIR/frame.exr for a width x height frame of these methods, with
    // OpenEXR's `exrCompression` ("piz", "zip" or "none"; docs/outputs.md).
    RenderWriter(const Scene& scene, const std::string& dir, int width, int height,
                 const std::vector<MethodConfig>& configs,
                 const std::string& exrCompression = "piz", const FrameChannelSet& channels = {});
    ~RenderWriter() override;
    void band(const RenderResult& frame, const FrameBand& band) override;
    void finish(const RenderResult& result);

  private:
    void waitForRows();  // the band being encoded is done (throws OutputError if it failed)
    const Scene& scene_;
    int width_, height_;
    std::string dir_;
    bool createdDir_ = false, committed_ = false;
    size_t channels_ = 0;       // every channel interleaveFrameBand writes
    std::vector<size_t> keep_;  // those the file holds (FrameChannelSet), in order
    std::unique_ptr<StagedFiles> files_;
    StagedStream* exrFile_ = nullptr;
    std::unique_ptr<ExrWriter> exr_;
    std::vector<float> rows_[2];  // bands, channels interleaved: one filled, one encoded
    // The last band's rows being encoded; declared after what it reads, so that a writer
    // dropped mid-frame (an error, a cancel) waits for it before they go.
    std::future<void> encoding_;
    int nextRows_ = 0;
    size_t methods_ = 0;
};

// Writes DIR/frame.exr, DIR/summary.json and DIR/<label>_error.png of a result that kept its
// images (one band: the whole frame through RenderWriter); creates DIR.
void writeRenderOutputs(const Scene& scene, const RenderResult& result, const std::string& dir);

// A share of counts, NaN when the whole is 0.
double share(int64_t part, int64_t whole);
// frame.exr's channels, in order: truth.u, truth.v, truth.hit, base.u, base.v, base.hit, then
// LABEL.u, LABEL.v, LABEL.err per method, then truth.depth, truth.shadow and LABEL.depth,
// LABEL.shadow per method, then base.V.x/y/z and base.Vexact.x/y/z (docs/outputs.md):
// kFrameChannels + 5 per method, then base.Vvertex.x/y/z where a method reads FragmentInputs.
constexpr size_t kFrameChannels = 14;
// With `inputs` (FrameBand::inputs: a method reads FragmentInputs), base.Vvertex.x/y/z last.
constexpr size_t frameChannelCount(size_t methods, bool inputs) {
    return kFrameChannels + 5 * methods + (inputs ? 3 : 0);
}
std::vector<std::string> frameChannelNames(const std::vector<MethodConfig>& configs);
// A band's pixels as frame.exr holds them: channels interleaved, row by row (NaN where a
// channel has no value), into `rows` (width x rows x channels floats).
void interleaveFrameBand(const FrameBand& band, float* rows);
// The whole frame of a result that kept its images, as one band.
FrameBand wholeFrameBand(const RenderResult& result);

nlohmann::json summaryJson(const Scene& scene, const RenderResult& result);
// A frame's statistics as summary.json has them; the keys that results.csv's columns say come
// from their definitions (study/result_columns.h).
nlohmann::json toJson(const FrameStats& stats);

// The top of an error map's colour scale: the smallest 1-2-5 value (0.01 .. 5e12) at or
// above the method's p99 error, so that the top percent saturates and the rest is visible.
double errorScaleTexels(double p99Texels);

}  // namespace pgt
