// The comparison of the trace with an image (a student's render): the trace renders the
// reference at the image's size from the file's camera, as raytrace does, and compares once it
// is done. Functions over the viewer's state (ui.compare); no GL.
#pragma once

#include <string>

#include "state/viewer.h"

namespace rt::view {

/// Compares the trace with the image at `path`: the trace switches to the image's size and the
/// file's camera and renders the reference there as raytrace does (ui.compare.spp samples, the
/// spec's sampling); take_trace() compares once it is done. On an error (a file that cannot be
/// read) the message is shown and the previous comparison stays.
bool compare_with(ViewerState& v, const std::string& path);
/// The same with the image read off the interface thread (CompareLoader): the comparison
/// starts in poll_files() (take_compare_image()) once it is read, or its error is shown. The
/// panel and a dropped image go this way; compare_with() serves the command line and scripts,
/// which wait.
void compare_in_background(ViewerState& v, const std::string& path);
/// Takes the image read in the background, if any, and starts comparing with it.
void take_compare_image(ViewerState& v);
/// Back to the progressive trace of the pane's size.
void stop_compare(ViewerState& v);
/// Marks pixel (x, y) of the compared image (both values in the panel) and explains the
/// reference's pixel there (its ray tree, ViewerState::inspect).
void probe_compare(ViewerState& v, int x, int y);
/// The reference's samples per pixel (clamped to 1 .. 65536): rendered again.
void set_compare_spp(ViewerState& v, int spp);
/// Takes the trace's latest image (TraceSession::take_image) and, while comparing, compares
/// the reference with the image once it is done. False when there is no new image.
bool take_trace(ViewerState& v);

}  // namespace rt::view
