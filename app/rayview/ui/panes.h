// The panes right of the control panel: the GL preview (left) and the trace (right), or one of
// them alone, and while comparing with an image the comparison pane right of them. Owns the
// viewer's GL objects: the Preview, its framebuffer and the trace's and comparison's textures. The
// preview is redrawn only when something it shows changed (software GL spends most of a frame on
// it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gl/gl_util.h"
#include "gl/preview.h"
#include "state/overlay.h"
#include "state/viewer.h"

namespace rt::view {

/// Where things go in the window (pixels): the control panel, then the panes. Each pane shows
/// its image at the render's aspect ratio, letterboxed: what raytrace would write.
struct PaneLayout {
    float panel_w = 330;
    int panes = 2;  // shown side by side
    /// Which pane shows what, from the left (-1: not shown).
    int preview = 0, trace = 1, compare = -1;
    float pane_w = 0, pane_h = 0;
    float image_w = 0, image_h = 0;  // the image in each pane
    /// The image's top left corner in pane `i` (0 the left one), in window pixels.
    float image_x(int i) const {
        return panel_w + static_cast<float>(i) * pane_w + 0.5f * (pane_w - image_w);
    }
    float image_y() const { return 0.5f * (pane_h - image_h); }
};
/// Both panes side by side, or one of them alone at full size (`layout`: ViewSettings::layout),
/// right of a panel `panel_w` wide, with images of aspect `aspect` (width / height); `compare`:
/// the comparison pane too, rightmost.
PaneLayout pane_layout(int layout, int fb_w, int fb_h, float panel_w, double aspect,
                       bool compare = false);

/// Which pane the mouse is over (never true while it is over the control panel).
struct PaneHover {
    bool preview = false, trace = false, compare = false;
    bool any() const { return preview || trace || compare; }
};

class Panes {
public:
    /// Compiles the preview's shaders from `shader_dir`; throws std::runtime_error naming the file.
    explicit Panes(const std::string& shader_dir);

    /// Sizes the trace and the preview's framebuffer for this frame and shows both panes.
    PaneHover show(ViewerState& v, const PaneLayout& layout, double frame_s);
    /// Uploads a new trace image, and redraws the preview when what it shows changed.
    void draw(ViewerState& v);
    /// The preview has a change to draw: the viewer's (ViewUi::changes), new materials, or its
    /// environment maps still being made.
    bool preview_stale(const ViewerState& v) const {
        return m_preview_stale || v.ui.changes != m_drawn_changes;
    }
    /// The preview shader's defines (for the status panel).
    const std::vector<std::string>& preview_defines() const { return m_preview.active_defines(); }

private:
    // The steps of draw().
    void upload_compare(const ViewerState& v);
    void upload_trace(ViewerState& v);
    void upload_scene(LoadedScene& loaded);
    void draw_preview(ViewerState& v, const LoadedScene& loaded);

    /// The comparison pane's toolbar, scale bar and the pixel under the mouse.
    void show_compare(ViewerState& v, const PaneLayout& p, bool hovered);
    Preview m_preview;
    ImageTexture m_trace;
    ImageTexture m_compare;      // the comparison pane's view (CompareView::show)
    int m_compare_version = -1;  // what m_compare holds: CompareView::version, show, display
    CompareShow m_compare_show = CompareShow::Difference;
    float m_compare_exposure = 0;
    Tonemap m_compare_tonemap = Tonemap::Clamp;
    RenderTarget m_target;       // the preview is drawn here, shown as an image
    double m_moving_div = 2.0;   // the preview's resolution divisor while the view moves
    float m_shown_exposure = 0;  // what m_trace was uploaded with
    Tonemap m_shown_tonemap = Tonemap::Clamp;
    int m_loaded_id = 0;  // the scene m_preview holds (LoadedScene::id)
    // What m_target holds, so it is redrawn only when that changes.
    bool m_drawn_lights = true, m_drawn_directions = false;
    int m_drawn_selected = -1;
    bool m_preview_stale = true;  // new materials, or the environment maps being made
    int m_drawn_changes = -1;     // ViewUi::changes drawn
    int m_drawn_inspect = -1, m_drawn_hovered = -1;  // InspectView::version and hovered drawn
    std::vector<Material> m_drawn_materials;  // the materials the preview's maps were made for
    float m_drawn_exposure = 0;               // the display transform the preview was drawn with
    Tonemap m_drawn_tonemap = Tonemap::Clamp;
    int m_drawn_depth = -1, m_drawn_group_depth = -1, m_drawn_w = 0, m_drawn_h = 0;
    std::vector<LineVertex> m_group_lines;  // group_box_lines() of that scene and depth
    int m_group_lines_depth = -1, m_group_lines_for = 0;
    std::optional<SceneTime> m_group_lines_time;  // the joints' time the group boxes show
};

}  // namespace rt::view
