// The viewer's background work: a scene loading (or reloading), an image or animation rendering
// and an image to compare with being read, each on a thread of its own while the window stays
// interactive. No GL.
#pragma once

#include <string>

#include "state/compare_view.h"
#include "state/image_job.h"
#include "state/loader.h"

namespace rt::view {

struct Jobs {
    SceneLoader loader;
    bool reloading = false;  // the loader's job is a reload of the open file
    ImageJob image;
    std::string image_path;  // the image the render job writes ("" for an animation)
    CompareLoader compare;   // the image to compare with, being read
};

}  // namespace rt::view
