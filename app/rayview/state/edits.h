// What the user edits, on the description side: the camera and the lights (SceneEdits), the
// renderer's settings and the viewer's own knobs (ViewSettings), and UndoState, what undo and
// redo restore. No GL.
#pragma once

#include <vector>

#include "rt/compile/compile.h"
#include "rt/image/image.h"
#include "rt/render/render.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"
#include "state/camera_controller.h"

namespace rt::view {

/// The user's edits, on the description side: the camera and every light, on or off; and the
/// materials as their files describe them (a texture is its file's index), one per
/// RenderScene::materials (material_descs: set whole only from the scene's, when it opens or
/// reloads). The restart compiles them (apply_edits), and the scene saves them as they are.
/// The panels, the keys and the script edit it through the same verbs; the viewer sees every
/// change itself (ViewerState::edit_pending), so no writer marks an edit.
struct SceneEdits {
    OrbitCamera camera;
    std::vector<LightDesc> lights;
    std::vector<char> light_on;
    std::vector<MaterialDesc> materials;

    /// The view becomes `view` (a copy edited by a panel, the mouse or the keys, put back).
    void set_camera(const OrbitCamera& view) { camera = view; }
    /// Light i becomes `l` (on or off); nothing for a light that is not there.
    void set_light(size_t i, const LightDesc& l, bool on);
    /// A new light of `kind` at the eye, along the view (a spot's cone 0.5 rad, a sphere's
    /// radius 5% of the distance to the target).
    void add_light(LightKind kind);
    void remove_light(size_t i);
    /// Keeps the headlight as a light of the scene (saved with it).
    void keep_headlight();
    /// Turns the view to light i: a point, spot or sphere light at the centre of the view, a
    /// directional light's direction as the view direction (`world`: the scene's bounds).
    void frame_light(size_t i, const Bounds3& world);
    /// Material i becomes `m`; nothing for a material that is not there.
    void set_material(size_t i, const MaterialDesc& m);
};

/// What the user sets: the renderer's settings and the viewer's own knobs.
struct ViewSettings {
    RenderSettings render;
    int target_spp = 256;
    float target_error = 1e-4f;     // the trace stops at this estimated relMSE too (0: never)
    float resolution_scale = 0.5f;  // trace pixels per pane pixel
    bool show_lights = true;        // light markers over the preview
    bool light_directions = false;  // every light's cone or arrows, not the selected one's only
    int box_depth = 0;              // BVH levels drawn over the preview, 0 = off
    int group_depth = 0;            // scene graph group levels drawn over it, 0 = off
    int layout = 0;                 // 0 both panes, 1 preview alone, 2 trace alone
    bool show_panel = true;         // the control panel left of the panes
    float panel_w = 380;            // its width in pixels (the user resizes it; 0: collapsed)
    float ui_scale = 1;             // fonts and panel, times the monitor's content scale
    bool headlight = true;          // a scene without lights is lit along the view (never saved)
    // How the trace is shown and saved to 8-bit files (display only: no re-render).
    float exposure = 0;  // stops
    Tonemap tonemap = Tonemap::Clamp;
    // The render's size, as raytrace's --width and --height: both panes keep its aspect.
    int image_w = 640, image_h = 480;
    double aspect() const { return static_cast<double>(image_w) / static_cast<double>(image_h); }
    bool operator==(const ViewSettings&) const = default;
};

/// What undo and redo restore: every edit of the camera, the lights and the settings.
struct UndoState {
    SceneEdits edits;
    ViewSettings settings;
};

/// The same camera, lights (and which are on) and materials, locations aside: what undo and
/// the trace's restart both compare.
bool same_edits(const SceneEdits& a, const SceneEdits& b);
/// Two lists of lights alike but for where they were read (a reload moves lines).
bool same_lights(const std::vector<LightDesc>& a, const std::vector<LightDesc>& b);
/// Two lists of materials alike in every term (and texture; not where they were read).
bool same_materials(const std::vector<Material>& a, const std::vector<Material>& b);
bool same_materials(const std::vector<MaterialDesc>& a, const std::vector<MaterialDesc>& b);

/// The settings that follow the window, not the user's edits (undo keeps them as they are): the
/// trace's size, which follows the pane, and the panel's width, visibility and scale, from
/// `window` into `*s`.
void keep_window_settings(ViewSettings* s, const ViewSettings& window);

/// The double a float widget's value stands for: the shortest decimal that reads back as the
/// float (0.3f gives 0.3, not 0.30000001192092896), so a saved scene holds the numbers shown.
double float_as_decimal(float f);

/// The edits into the compiled scene: the camera, the lights that are on (and the headlight)
/// and the materials (compiled from their descriptions as compile_scene compiles them, `origins`
/// being material_origins()), and the trace's size.
void apply_edits(const SceneEdits& edits, const std::vector<MaterialOrigin>& origins,
                 bool headlight, int trace_w, int trace_h, RenderScene* scene,
                 RenderSettings* settings);

/// The headlight: a white directional light along the view of `camera`.
LightDesc headlight_desc(const OrbitCamera& camera);

}  // namespace rt::view
