// The panel's "Compare with image" section: the image's path and Compare (or a drop of the file
// onto the window), the views, the tolerance, the 3x3 neighbourhood, the reference's samples
// per pixel, the figures (as raycompare prints them) and the pixel clicked in the pane: both
// values there; its ray tree is the inspect section's.
#pragma once

#include <string>

#include "state/viewer.h"

namespace rt::view {

struct ComparePanelState {
    char path[1024] = "";
};

void compare_panel(ViewerState& v, ComparePanelState& ui);

}  // namespace rt::view
