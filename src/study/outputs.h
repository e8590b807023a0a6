// Writers for `pgt render`: frame.exr (named float channels), summary.json, and the
// false-colour error maps for people. Every file is written to a temporary name and renamed.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.h"
#include "study/render.h"

namespace pgt {

// Writes DIR/frame.exr, DIR/summary.json and DIR/<label>_error.png; creates DIR.
// Throws OutputError naming the path that could not be written.
void writeRenderOutputs(const Scene& scene, const RenderResult& result, const std::string& dir);

nlohmann::json summaryJson(const Scene& scene, const RenderResult& result);
nlohmann::json toJson(const FrameStats& stats);

// EXR with one float channel per name; `channels[c]` is a W x H image, row 0 at the top.
void writeExr(const std::string& path, const std::vector<std::string>& names,
              const std::vector<const Image2D<float>*>& channels);

// Replaces `path` atomically with `text`.
void writeTextFile(const std::string& path, const std::string& text);

// The top of an error map's colour scale: the smallest 1-2-5 value (0.01 .. 5e12) at or
// above the method's p99 error, so that the top percent saturates and the rest is visible.
double errorScaleTexels(double p99Texels);

}  // namespace pgt
