// Mouse and keys -> the viewer's edits: orbit, pan, dolly, look and fly move the camera, and a
// light's marker in the preview is picked and dragged. Mouse input counts only over the panes
// (the panes are ImGui windows too, so ImGui's WantCaptureMouse is set over them: the gate is
// the pane image's hover); keys only when ImGui does not want the keyboard.
#pragma once

#include <imgui.h>

#include "state/viewer.h"
#include "ui/panes.h"

namespace rt::view {

/// What input remembers between frames.
struct InputState {
    int dragged_light = -1;  // index into ViewerState::edits.lights while dragged
    int dragged_scene = -1;  // LoadedScene::id of the scene whose light is dragged
};

/// Applies this frame's input; marks the edit and returns true when something moved.
bool handle_input(ViewerState& v, InputState& input, const ImGuiIO& io, const PaneLayout& layout,
                  const PaneHover& hover, double frame_s);

}  // namespace rt::view
