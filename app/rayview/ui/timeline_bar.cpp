// The timeline over the bottom of the panes (an animated scene only), as Blender's: play/pause
// (space), back to the start, the time slider (scrub), the frame, loop, speed, and the
// interpolation and rotation choices of spec §14.7. The panel's "animation" section
// (panels.cpp) renders the sequence in the background.
#include "ui/timeline_bar.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "state/key_queue.h"

namespace rt::view {

namespace {

// A combo over an enum of values 0 .. n - 1, each shown by its name(E).
template <class E>
bool enum_combo(const char* label, E* value, int n, const char* (*name)(E), float width) {
    struct Names {
        const char* (*name)(E);
    } names{name};
    int i = static_cast<int>(*value);
    ImGui::SetNextItemWidth(width);
    const auto item = [](void* data, int k, const char** text) {
        *text = static_cast<Names*>(data)->name(static_cast<E>(k));
        return true;
    };
    if (!ImGui::Combo(label, &i, item, &names, n)) return false;
    *value = static_cast<E>(i);
    return true;
}

}  // namespace

bool timeline_keys(ViewerState& v) {
    const ImGuiIO& io = ImGui::GetIO();
    const double length = v.animation_length();
    if (length <= 0 || io.WantCaptureKeyboard) return false;
    const Timeline& tl = v.timeline;     // changed through its verbs
    const KeyQueue& keys = key_queue();  // every tap, also within one slow frame
    if (keys.presses(GLFW_KEY_SPACE, false, false) % 2 == 1) {
        v.timeline.toggle_play(length);  // from the end: from 0
        return true;
    }
    const int step = keys.presses(GLFW_KEY_RIGHT) - keys.presses(GLFW_KEY_LEFT);
    if (step == 0) return false;
    v.timeline.pause();
    v.seek((tl.frame() + step) / tl.fps);
    return true;
}

void timeline_bar(ViewerState& v, const PaneLayout& layout) {
    const double length = v.animation_length();
    if (length <= 0) return;
    const Timeline& tl = v.timeline;  // changed through its verbs
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const float h = ImGui::GetFrameHeightWithSpacing();
    ImGui::SetNextWindowPos(ImVec2(layout.panel_w, vp->Size.y - 2 * h - 4));
    ImGui::SetNextWindowSize(ImVec2(vp->Size.x - layout.panel_w, h + 4));
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("timeline", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
    const float em = ImGui::GetFontSize();
    if (ImGui::Button(tl.playing ? "Pause" : "Play", ImVec2(4 * em, 0)))
        v.timeline.toggle_play(length);
    ImGui::SameLine();
    if (ImGui::Button("|<")) {
        v.timeline.pause();
        v.seek(0);
    }
    ImGui::SameLine();
    const int frames = std::max(1, static_cast<int>(std::ceil(length * tl.fps - 1e-9)));
    char label[64];
    std::snprintf(label, sizeof label, "t = %.2f s  frame %d / %d", tl.time, tl.frame(), frames);
    float t = static_cast<float>(tl.time);
    const float right = 29 * em;  // loop, speed and the two choices
    ImGui::SetNextItemWidth(std::max(6 * em, ImGui::GetContentRegionAvail().x - right));
    if (ImGui::SliderFloat("##time", &t, 0.0f, static_cast<float>(length), label)) {
        v.timeline.pause();  // scrubbing pauses; the trace restarts at the time shown
        v.seek(t);
    }
    ImGui::SameLine();
    bool loop = tl.loop;
    if (ImGui::Checkbox("loop", &loop)) v.timeline.set_loop(loop);
    ImGui::SameLine();
    float speed = static_cast<float>(tl.speed);
    ImGui::SetNextItemWidth(4 * em);
    if (ImGui::DragFloat("##speed", &speed, 0.01f, 0.05f, 8.0f, "%.2fx"))
        v.timeline.set_speed(speed);
    ImGui::SameLine();
    Interpolation interpolation = tl.interpolation;
    Rotation rotation = tl.rotation;
    bool changed = enum_combo("##interpolation", &interpolation, kInterpolations,
                              interpolation_name, 8.5f * em);
    ImGui::SameLine();
    changed |= enum_combo("##rotation", &rotation, kRotations, rotation_name, 8.5f * em);
    if (changed) {  // the same time, other values: the trace restarts
        v.timeline.set_choices(interpolation, rotation);
        v.seek(tl.time);
    }
    ImGui::End();
}

}  // namespace rt::view
