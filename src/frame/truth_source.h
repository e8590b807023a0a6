// Where a frame's truth comes from, band by band (frame/render.cpp's band pipeline): the
// frame's surfaces traced per band, frames traced block by block beforehand, or a prepared
// view's bands.
#pragma once

#include <optional>

#include "core/image.h"
#include "frame/render.h"
#include "scene/camera.h"
#include "truth/builder.h"

namespace pgt {

// The source's interface: SurfacesTruth, FramesTruth, PreparedTruth (whose bands also hold
// the fragments).
class TruthSource {
  public:
    virtual ~TruthSource() = default;
    // The band's truth samples: traced or copied into `own`, or the source's own image.
    virtual const Image2D<TruthSample>& band(const Camera& camera, PixelRect rect,
                                             Image2D<TruthSample>& own) const = 0;
    virtual bool haveFine() const = 0;
    // The 2x-rate twin's band (only where haveFine()).
    virtual void fineBand(const Camera& camera, PixelRect rect,
                          Image2D<TruthSample>& out) const = 0;
    // What summary.json records of the truth's build.
    virtual void describe(RenderResult& r) const = 0;
    // A prepared view (its fragments and depths made beforehand); null otherwise.
    virtual const PreparedView* prepared() const { return nullptr; }
};

class SurfacesTruth : public TruthSource {
  public:
    // `light`: the view's (scene.h lightToward), whose shadow rays the surfaces trace.
    SurfacesTruth(const TruthPair& t, std::optional<Vec3d> light) : t_(t), light_(light) {}
    const Image2D<TruthSample>& band(const Camera& camera, PixelRect rect,
                                     Image2D<TruthSample>& own) const override {
        t_.truth->traceRect(camera, rect, own, TraceMode::Coherent, light_);
        return own;
    }
    bool haveFine() const override { return bool(t_.fine); }
    void fineBand(const Camera& camera, PixelRect rect, Image2D<TruthSample>& out) const override {
        t_.fine->traceRect(camera, rect, out, TraceMode::Coherent, light_);
    }
    void describe(RenderResult& r) const override {
        r.truthBuild = t_.truth->stats();
        if (t_.fine) r.truthBuildFine = t_.fine->stats();
    }

  private:
    const TruthPair& t_;
    std::optional<Vec3d> light_;
};

class FramesTruth : public TruthSource {
  public:
    explicit FramesTruth(const TruthFrames& f) : f_(f) {}
    const Image2D<TruthSample>& band(const Camera&, PixelRect rect,
                                     Image2D<TruthSample>& own) const override {
        own = rowsOf(f_.truth, rect);
        return own;
    }
    bool haveFine() const override { return f_.haveFine; }
    void fineBand(const Camera&, PixelRect rect, Image2D<TruthSample>& out) const override {
        out = rowsOf(f_.fine, rect);
    }
    void describe(RenderResult& r) const override {
        r.truthBuild = f_.build;
        r.truthBuildFine = f_.buildFine;
        r.truthBlocks = f_.blocks;
    }

  private:
    const TruthFrames& f_;
};

class PreparedTruth : public TruthSource {
  public:
    explicit PreparedTruth(const PreparedView& v) : v_(v) {}
    // Its depths were set when it was prepared.
    const Image2D<TruthSample>& band(const Camera&, PixelRect rect,
                                     Image2D<TruthSample>&) const override {
        return v_.bands[size_t(rect.y0 / bandRows(rect.width()))].truth;
    }
    bool haveFine() const override { return false; }
    void fineBand(const Camera&, PixelRect, Image2D<TruthSample>&) const override {}
    void describe(RenderResult& r) const override { r.truthBuild = v_.build; }
    const PreparedView* prepared() const override { return &v_; }

  private:
    const PreparedView& v_;
};

}  // namespace pgt
