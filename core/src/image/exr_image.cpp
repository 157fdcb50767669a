// ExrImage's lookups, in every build (the web page's too, which has no OpenEXR).
#include <stdexcept>

#include "rt/image/exr.h"

namespace rt {

const ExrChannel* ExrImage::find(const std::string& name) const {
    for (const ExrChannel& c : channels)
        if (c.name == name) return &c;
    return nullptr;
}

Image ExrImage::rgb() const {
    Image image(width, height);
    const char* names[3] = {"R", "G", "B"};
    for (size_t k = 0; k < 3; ++k) {
        const ExrChannel* c = find(names[k]);
        if (!c) throw std::runtime_error(std::string("the EXR image has no channel ") + names[k]);
        for (size_t i = 0; i < c->values.size(); ++i) image.rgb[i * 3 + k] = c->values[i];
    }
    return image;
}

}  // namespace rt
