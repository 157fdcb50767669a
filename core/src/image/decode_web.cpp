// The web page's PNG and JPEG decoders: stb_image behind our checks (decode_stb.cpp), as there is
// no libpng or libjpeg for Emscripten among Debian's packages.
#include "rt/image/decode.h"

namespace rt {

bool decode_png(std::string_view data, TextureImage* out, std::string* error) {
    return decode_png_jpeg_stb(data, out, error);
}

bool decode_jpeg(std::string_view data, TextureImage* out, std::string* error) {
    return decode_png_jpeg_stb(data, out, error);
}

}  // namespace rt
