// libFuzzer target: the height-map loader on arbitrary bytes written as an image file (the
// first byte picks the extension, i.e. the OpenImageIO reader). Bad images must end in
// InputError, never a crash or a silent NaN.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "heightfield/heightfield.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* ext[] = {".png", ".exr", ".tga", ".hdr", ".pnm", ".bmp", ".tif", ".jpg"};
    std::string path = "/tmp/pgt_fuzz_image_" + std::to_string(getpid()) + ext[data[0] % 8];
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
    try {
        pgt::Texture t = pgt::loadHeightImage(path, 0, "fuzz.json", "heightmap", true);
        for (float v : t.texels)
            if (!std::isfinite(v)) __builtin_trap();  // the loader promised finite texels
    } catch (const pgt::InputError&) {
    }
    std::remove(path.c_str());
    return 0;
}
