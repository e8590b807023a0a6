// pgt_image.so: OpenImageIO behind heightfield/image_reader.h, loaded when an image is read.
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

#include "heightfield/image_reader.h"

namespace {

class OiioImage : public pgt::ImageFile {
  public:
    explicit OiioImage(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {}
    pgt::ImageHeader header() const override {
        const OIIO::ImageSpec& spec = in_->spec();
        pgt::ImageHeader h{spec.width, spec.height, spec.nchannels, pgt::SampleType::Float,
                           spec.format.size()};
        if (spec.format == OIIO::TypeDesc::UINT8) h.type = pgt::SampleType::UInt8;
        if (spec.format == OIIO::TypeDesc::UINT16) h.type = pgt::SampleType::UInt16;
        return h;
    }
    bool read(void* out, std::string& why) override {
        const OIIO::ImageSpec& spec = in_->spec();
        const pgt::SampleType t = header().type;
        const OIIO::TypeDesc as = t == pgt::SampleType::UInt8    ? OIIO::TypeDesc::UINT8
                                  : t == pgt::SampleType::UInt16 ? OIIO::TypeDesc::UINT16
                                                                 : OIIO::TypeDesc::FLOAT;
        const bool ok = in_->read_image(0, 0, 0, spec.nchannels, as, out);
        if (!ok) why = in_->geterror();
        return ok;
    }

  private:
    std::unique_ptr<OIIO::ImageInput> in_;
};

}  // namespace

extern "C" __attribute__((visibility("default"))) pgt::ImageFile* pgt_open_image(const char* path,
                                                                                 std::string* why) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        *why = OIIO::geterror();
        return nullptr;
    }
    return new OiioImage(std::move(in));
}
