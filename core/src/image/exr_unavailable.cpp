// The web page's build has no OpenEXR (no WebAssembly build of it in Debian): .exr is refused
// with a message, as any format this build cannot write.
#include <stdexcept>

#include "rt/image/exr.h"

namespace rt {

namespace {
[[noreturn]] void unavailable(const std::string& path) {
    throw std::runtime_error("cannot use '" + path +
                             "': this build has no OpenEXR (save .png, .ppm or .pfm instead)");
}
}  // namespace

void save_exr(const Image&, const std::vector<ExrChannel>&, bool, const std::string& path) {
    unavailable(path);
}

ExrImage load_exr(const std::string& path) { unavailable(path); }

ExrImage decode_exr(std::string_view) { unavailable("memory"); }

Image load_exr_rgb(const std::string& path) { unavailable(path); }

Image decode_exr_rgb(std::string_view) { unavailable("memory"); }

}  // namespace rt
