#include "ui/input.h"

#include <GLFW/glfw3.h>

#include <cmath>

#include "rt/render/camera.h"
#include "state/key_queue.h"
#include "state/viewer_compare.h"

namespace rt::view {

namespace {

// Lights are dragged in the preview: a click near a point or spot light's marker picks it, and
// the drag moves it parallel to the image.
bool drag_lights(ViewerState& v, InputState& input, const ImGuiIO& io, const PaneLayout& p,
                 bool over_preview) {
    const std::vector<LightDesc>& lights = v.edits.lights;
    const Camera view_cam =
        v.edits.camera.camera(static_cast<int>(p.image_w), static_cast<int>(p.image_h));
    auto to_pane = [&](const Vec3& pos, double* depth) {
        const Vec3 d = pos - view_cam.position;
        *depth = glm::dot(d, view_cam.forward);
        const double x = glm::dot(d, view_cam.right) / (*depth * view_cam.tan_w);
        const double y = glm::dot(d, view_cam.up) / (*depth * view_cam.tan_h);
        return ImVec2(p.image_x(0) + static_cast<float>((x + 1) / 2) * p.image_w,
                      p.image_y() + static_cast<float>((1 - y) / 2) * p.image_h);
    };
    if (over_preview && v.settings.show_lights && ImGui::IsMouseClicked(ImGuiMouseButton_Left) &&
        !io.KeyShift) {
        for (size_t i = 0; i < lights.size(); ++i) {
            if (lights[i].kind == LightKind::Directional) continue;
            double depth = 0;
            const ImVec2 at = to_pane(lights[i].position, &depth);
            const float ddx = at.x - io.MousePos.x, ddy = at.y - io.MousePos.y;
            if (depth > 0 && ddx * ddx + ddy * ddy < 144.0f) {
                input.dragged_light = static_cast<int>(i);
                v.ui.select_light(static_cast<int>(i));
                input.dragged_scene = v.session.loaded->id;
            }
        }
    }
    // A release ends the drag; so does a reload or a removed light under it.
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) || input.dragged_scene != v.session.loaded->id ||
        input.dragged_light >= static_cast<int>(lights.size()))
        input.dragged_light = -1;
    if (input.dragged_light < 0 || (io.MouseDelta.x == 0 && io.MouseDelta.y == 0)) return false;
    const size_t i = static_cast<size_t>(input.dragged_light);
    LightDesc l = lights[i];  // a copy, put back once
    double depth = 0;
    to_pane(l.position, &depth);
    const double per_pixel = 2 * depth * view_cam.tan_h / static_cast<double>(p.image_h);
    l.position += per_pixel * (static_cast<double>(io.MouseDelta.x) * view_cam.right -
                               static_cast<double>(io.MouseDelta.y) * view_cam.up);
    v.edits.set_light(i, l, v.edits.light_on[i] != 0);
    return true;
}

// Drag orbits, shift or middle drag pans, right drag looks around, the wheel dollies.
bool mouse_camera(OrbitCamera& orbit, const ImGuiIO& io, const PaneLayout& p) {
    bool edited = false;
    const double dx = static_cast<double>(io.MouseDelta.x),
                 dy = static_cast<double>(io.MouseDelta.y);
    const bool pan = ImGui::IsMouseDown(ImGuiMouseButton_Middle) ||
                     (io.KeyShift && ImGui::IsMouseDown(ImGuiMouseButton_Left));
    const double h = static_cast<double>(p.image_h);
    if (pan && (dx != 0 || dy != 0)) {
        orbit.pan(-dx / h, dy / h);  // the scene follows the mouse
        edited = true;
    } else if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && (dx != 0 || dy != 0)) {
        orbit.orbit(dx * 0.005, -dy * 0.005);
        edited = true;
    }
    if (ImGui::IsMouseDown(ImGuiMouseButton_Right) && (dx != 0 || dy != 0)) {
        orbit.look(dx * 0.004, -dy * 0.004);
        edited = true;
    }
    if (io.MouseWheel != 0) {
        orbit.dolly(std::pow(0.9, static_cast<double>(io.MouseWheel)));
        edited = true;
    }
    return edited;
}

// Fly: WASD along the view and sideways, Q/E down and up, at a speed scaled to the scene (its
// diagonal per 4 seconds).
bool fly_camera(OrbitCamera& orbit, const Bounds3& world, double frame_s) {
    const Camera cam = orbit.camera(4, 4);
    const double speed = (world.empty() ? 1.0 : glm::length(world.diagonal())) / 4.0 * frame_s;
    Vec3 move(0.0);
    if (ImGui::IsKeyDown(GLFW_KEY_W)) move += cam.forward;
    if (ImGui::IsKeyDown(GLFW_KEY_S)) move -= cam.forward;
    if (ImGui::IsKeyDown(GLFW_KEY_D)) move += cam.right;
    if (ImGui::IsKeyDown(GLFW_KEY_A)) move -= cam.right;
    if (ImGui::IsKeyDown(GLFW_KEY_E)) move += Vec3(0, 1, 0);
    if (ImGui::IsKeyDown(GLFW_KEY_Q)) move -= Vec3(0, 1, 0);
    if (move == Vec3(0.0)) return false;
    orbit.move(speed * move);
    return true;
}

}  // namespace

// A click (released without dragging) in the preview or the trace picks what is under it, or in
// the inspect mode explains that pixel of the trace (its ray tree); in the comparison pane it
// marks the pixel (both values in the panel) and explains the reference's pixel there.
void click_to_pick(ViewerState& v, const ImGuiIO& io, const PaneLayout& p, const PaneHover& hover,
                   const InputState& input) {
    if (!hover.any() || input.dragged_light >= 0) return;
    if (!ImGui::IsMouseReleased(ImGuiMouseButton_Left) || io.KeyShift) return;
    const ImVec2 drag = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left, 0.0f);
    if (drag.x * drag.x + drag.y * drag.y > 9.0f) return;  // that was an orbit
    const int pane = hover.preview ? p.preview : hover.trace ? p.trace : p.compare;
    const double x = (io.MousePos.x - p.image_x(pane)) / p.image_w;
    const double y = (io.MousePos.y - p.image_y()) / p.image_h;
    if (x < 0 || x >= 1 || y < 0 || y >= 1) return;
    if (hover.compare) {
        const CompareView& c = v.ui.compare;
        v.ui.inspect.set_mode(true);  // the tree is why the reference's pixel is what it is
        probe_compare(v, static_cast<int>(x * c.theirs.width),
                      static_cast<int>(y * c.theirs.height));
    } else if (v.ui.inspect.mode)
        v.inspect(x, y);
    else
        v.pick(x, y);
}

bool handle_input(ViewerState& v, InputState& input, const ImGuiIO& io, const PaneLayout& layout,
                  const PaneHover& hover, double frame_s) {
    click_to_pick(v, io, layout, hover, input);
    bool edited = drag_lights(v, input, io, layout, hover.preview);
    // Camera input only over the preview and the trace (never what ImGui's controls want; the
    // comparison pane takes clicks only); on a copy, put back once.
    OrbitCamera cam = v.edits.camera;
    bool moved = false;
    if ((hover.preview || hover.trace) && input.dragged_light < 0)
        moved |= mouse_camera(cam, io, layout);
    if (!io.WantCaptureKeyboard)
        moved |= fly_camera(cam, v.session.loaded->scene.world_bounds, frame_s);
    if (moved) v.edits.set_camera(cam);
    edited |= moved;
    // Undo and redo (text fields keep their own): Ctrl+Z, Ctrl+Shift+Z or Ctrl+Y.
    // Every press counts, also several within one slow frame (key_queue.h).
    if (!io.WantTextInput) {
        const KeyQueue& keys = key_queue();
        for (int i = keys.presses(GLFW_KEY_Z, true, false); i > 0; --i)
            keys.shifted(GLFW_KEY_Z) ? v.redo() : v.undo();
        for (int i = keys.presses(GLFW_KEY_Y, true, false); i > 0; --i) v.redo();
    }
    // The inspect mode: I turns it on and off, C clears the tree.
    if (!io.WantCaptureKeyboard) {
        const KeyQueue& keys = key_queue();
        if (keys.presses(GLFW_KEY_I, false, false) % 2 == 1)
            v.ui.inspect.set_mode(!v.ui.inspect.mode);
        if (keys.presses(GLFW_KEY_C, false, false) > 0 && v.ui.inspect.tree) v.ui.inspect.clear();
        // Comparing: B flips theirs and ours, V cycles the views.
        if (v.ui.compare.active() && keys.presses(GLFW_KEY_B, false, false) % 2 == 1)
            v.ui.compare.flip();
        if (v.ui.compare.active())
            for (int i = keys.presses(GLFW_KEY_V, false, false); i > 0; --i)
                v.ui.compare.next_view();
    }
    return edited;
}

}  // namespace rt::view
