// Writers for `pgt render`: frame.exr (named float channels), summary.json, and the
// false-colour error maps for people. All go through staged files (io/staged_files.h):
// written whole to temporaries, renamed into place together.
#pragma once

#include <array>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "frame/frame_channels.h"
#include "frame/render.h"
#include "scene/scene.h"

namespace pgt {

class ExrWriter;
class StagedFiles;
class StagedStream;

// The channel groups (frame/frame_channels.h) a frame.exr holds (docs/outputs.md; `pgt render
// --channels`); none of them: no frame.exr (and no rows interleaved). A group left out is
// dropped from the interleaved rows before the encoder sees them.
struct FrameChannelSet {
    std::array<bool, kChannelGroups> groups{true, true, true, true};
    bool holds(ChannelGroup g) const { return groups[size_t(g)]; }
};
// "all", "none" or a comma-separated list of the groups; anything else throws InputError
// naming `field`.
FrameChannelSet parseFrameChannels(const std::string& list, const std::string& field);

// The files of one rendered view, written as its bands arrive (a FrameSink): frame.exr row
// by row. finish() draws the error maps from the result's coded errors (their colour scale
// needs the whole frame's p99; render with FrameOptions::keepCodedErrors), one per core,
// writes summary.json (and returns what it wrote) and renames every file into place. Throws
// OutputError
// naming the path that could not be written; nothing is left behind then.
class RenderWriter : public FrameSink {
  public:
    // Creates DIR and opens DIR/frame.exr for a width x height frame of these methods, with
    // OpenEXR's `exrCompression` ("auto", "piz", "zip" or "none"; docs/outputs.md).
    RenderWriter(const Scene& scene, const std::string& dir, int width, int height,
                 const std::vector<MethodConfig>& configs,
                 const std::string& exrCompression = "auto", const FrameChannelSet& channels = {});
    ~RenderWriter() override;
    void band(const RenderResult& frame, const FrameBand& band) override;
    nlohmann::json finish(const RenderResult& result);

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
// images (one band: the whole frame through RenderWriter); creates DIR. Returns the summary.
nlohmann::json writeRenderOutputs(const Scene& scene, const RenderResult& result,
                                  const std::string& dir);

// A share of counts, NaN when the whole is 0.
double share(int64_t part, int64_t whole);
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
