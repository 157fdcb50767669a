// The timeline over the bottom of the panes (an animated scene only): the bar and its keys
// (timeline_bar.cpp).
#pragma once

#include "state/viewer.h"
#include "ui/panes.h"

namespace rt::view {

/// The timeline above the status bar (an animated scene only): play/pause, back to the start,
/// scrub, the frame, loop, speed, the interpolation and rotation.
void timeline_bar(ViewerState& v, const PaneLayout& layout);
/// Space plays and pauses, Left and Right step a frame (an animated scene, keyboard not taken by
/// a widget). Returns whether a key did something.
bool timeline_keys(ViewerState& v);

}  // namespace rt::view
