// Writers for `pgt render`: frame.exr (named float channels), summary.json, and the
// false-colour error maps for people. Every file is written in full to a temporary name
// (each write checked, flushed to disk), and the files of one output are renamed into place
// together, so a failure (a full disk) leaves nothing half-written and no final-looking file.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"
#include "study/render.h"

namespace pgt {

// Writes DIR/frame.exr, DIR/summary.json and DIR/<label>_error.png; creates DIR.
// Throws OutputError naming the path that could not be written.
void writeRenderOutputs(const Scene& scene, const RenderResult& result, const std::string& dir);

nlohmann::json summaryJson(const Scene& scene, const RenderResult& result);
nlohmann::json toJson(const FrameStats& stats);

// Replaces `path` atomically with `text`.
void writeTextFile(const std::string& path, const std::string& text);

// Creates `dir` (and its parents) and checks that a file can be created in it; removes the
// temporaries that killed pgt processes left there. Throws OutputError naming `dir`.
void prepareOutputDir(const std::string& dir);

// Files of one output, each written whole to a hidden temporary in `dir`, then renamed into
// place together by commit(); whatever is not committed is removed on destruction.
class StagedFiles {
  public:
    explicit StagedFiles(std::string dir);
    ~StagedFiles();
    StagedFiles(const StagedFiles&) = delete;
    StagedFiles& operator=(const StagedFiles&) = delete;
    // Writes `bytes` to a temporary for DIR/name; throws OutputError (the write, the flush
    // or the close failed, e.g. no space left) after removing it.
    void add(const std::string& name, const std::string& bytes);
    void commit();

  private:
    std::string dir_;
    std::vector<std::pair<std::string, std::string>> staged_;  // temporary, final path
};

// The encoded bytes of `buf` in the format of `name`'s extension (".exr", ".png").
std::string encodeImage(const std::string& name, const OIIO_NAMESPACE::ImageBuf& buf);

// The top of an error map's colour scale: the smallest 1-2-5 value (0.01 .. 5e12) at or
// above the method's p99 error, so that the top percent saturates and the rest is visible.
double errorScaleTexels(double p99Texels);

}  // namespace pgt
