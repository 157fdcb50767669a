// The control panel left of the panes, as small ImGui functions in the order they appear. Each
// returns whether it edited what the trace shows (as ImGui's widgets return true when edited);
// control_panel() marks those edits for the restart.
#pragma once

#include <string>
#include <vector>

#include "state/viewer.h"
#include "ui/compare_panel.h"
#include "ui/panes.h"

namespace rt::view {

/// The panel's own text fields and lists.
struct PanelState {
    explicit PanelState(const std::string& path);
    char path_buf[1024];
    char save_buf[1024] = "rayview.png";
    char scene_buf[1024] = "edited.ray";
    bool save_included = false;      // also write edited materials into their included files
    int image_size[2] = {640, 480};  // "Render and save image": raytrace's default size
    int image_spp = 16;
    // "Render animation": the frame files' %d pattern, the frame count (0: the loop at the
    // timeline's fps) and the video ("" : none).
    char anim_pattern[1024] = "frame_%04d.png";
    char anim_video[1024] = "";
    int anim_frames = 0;
    int path_for = 0;                          // the scene (LoadedScene::id) path_buf shows
    int material = 0;                          // the material the panel edits
    int material_picked = -1;                  // the selection's material when last seen
    bool completing = false;                   // the path field lists matching files
    std::string completed_for;                 // the typed path the list below belongs to
    std::vector<std::string> completion_list;  // completions(completed_for)
    std::string samples_dir;                   // the sample scenes' folder ("": no list)
    std::vector<std::string> samples;          // sample_scenes(samples_dir), listed once
    ComparePanelState compare;                 // "Compare with image"
};

/// The .ray files in `dir` (not its subfolders), sorted.
std::vector<std::string> sample_scenes(const std::string& dir);

/// .ray files whose path starts with what is typed (the directory part lists its folder).
std::vector<std::string> completions(const std::string& typed);

/// The scene's path with completion, Open, Reload, the recent files, the sample scenes (the
/// ones installed with the program, or packaged with the web page), the last message, the
/// offer to open a file whose textures are missing with checker stand-ins, and which stand in.
bool file_panel(ViewerState& v, PanelState& ui);
/// The camera: frame, home, undo, redo, the half-height angle, aperture and focus distance,
/// setting the view as the scene's camera, bookmarks. Each panel edits a copy of what it shows
/// and puts it back once (yocto-gl's draw_scene_editor): the viewer sees the change.
void camera_panel(ViewerState& v, const PaneLayout& layout);
/// Layout and overlays, and the renderer's settings.
void settings_panel(ViewerState& v);
/// Every light: on or off, its colour (V0/V1) or three colours (V3: ambient, diffuse, specular),
/// a sphere light's radius, position, attenuation, direction, spot cone; add, remove.
void lights_panel(ViewerState& v);
/// The trace's progress, what the renderer left out, the error plot.
void status_panel(const ViewerState& v, const std::vector<std::string>& preview_defines,
                  double frame_s);
/// Saving the scene (camera and lights) and the traced image.
void save_panel(ViewerState& v, PanelState& ui);

/// The trace's progress along the bottom of the panes, always visible (status_text): samples per
/// pixel, rays per second, the estimated error and the time to the target error, the first
/// (coarse) and first full-resolution pass times.
void status_bar(const ViewerState& v, const PaneLayout& layout);
/// Every shortcut in a window over the panes, opened and closed with F1 or ? (Esc closes it).
void help_overlay(ViewUi& ui);
/// The animation's DOFs and loop, its fps, and "render animation" in the background.
void animation_panel(ViewerState& v, PanelState& ui);
/// The whole panel as one ImGui window, resizable and collapsible.
void control_panel(ViewerState& v, PanelState& ui, const PaneLayout& layout,
                   const std::vector<std::string>& preview_defines, double frame_s);

}  // namespace rt::view
