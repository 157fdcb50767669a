// libFuzzer target: file bytes -> every image decoder (rt/image/decode.h and decode_exr): the
// texture path as the programs take it (decode_texture: BMP, PNM, and PNG and JPEG through libpng
// and libjpeg), the web page's checked stb_image path, PFM and OpenEXR. Any input must end in a
// decoded image or an error (false, or a std::exception from the EXR reader): a crash, a
// sanitizer report, a hang or an image of another size than its decoder says is a bug.
//
// The image budget is lowered to 2^16 pixels, so that inputs declaring large images reach the
// budget's refusal instead of spending the run on allocations (the checks are the same at any
// budget): at 2^20, the many allocations of a few megabytes (an EXR's 16 channels of the budget)
// passing through ASan's quarantine grew the process past libFuzzer's 2 GB in 5 minutes. Seeds:
// tests/fuzz/corpus/image (every format and variant) and scenes/textures.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string_view>

#include "rt/image/decode.h"
#include "rt/image/exr.h"
#include "rt/util/limits.h"

namespace {

void check(bool ok, const rt::TextureImage& t) {
    const auto pixels = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
    if (ok ? (t.width <= 0 || t.height <= 0 || t.rgb.size() != pixels * 3) : !t.rgb.empty())
        std::abort();  // a decoder's result disagrees with its size or its answer
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    rt::set_max_image_pixels(uint64_t{1} << 16);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
    const std::string_view data(reinterpret_cast<const char*>(bytes), size);
    std::string error;
    {
        rt::TextureImage t;
        check(rt::decode_texture(data, &t, &error), t);
    }
    {
        rt::TextureImage t;
        check(rt::decode_png_jpeg_stb(data, &t, &error), t);
    }
    rt::Image image;
    if (rt::decode_pfm(data, &image, &error) &&
        image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3)
        std::abort();
    try {
        (void)rt::decode_exr(data);
    } catch (const std::exception&) {  // OpenEXR's errors, and ours
    }
    try {
        const rt::Image rgb = rt::decode_exr_rgb(data);  // what the comparisons read
        if (rgb.rgb.size() != static_cast<size_t>(rgb.width) * rgb.height * 3) std::abort();
    } catch (const std::exception&) {
    }
    return 0;
}
