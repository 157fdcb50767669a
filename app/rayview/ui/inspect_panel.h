// The panel's "Inspect a pixel" section: the inspect mode's toggle, the colours of the tree's
// lines, and the tree of the pixel inspected last as a collapsible list, every term with its
// formula (the core's inspect_text, one node a line). Hovering a ray highlights its lines in
// the preview; a click on a ray that hits selects its primitive (F then frames it).
#pragma once

#include "state/viewer.h"

namespace rt::view {

void inspect_panel(ViewerState& v);

}  // namespace rt::view
