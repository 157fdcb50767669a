#define GL_GLEXT_PROTOTYPES
#include "ui/panes.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "rt/scene/scene_time.h"
#include "state/viewer_compare.h"
#include "state/viewer_output.h"

namespace rt::view {

namespace {

ImTextureID texture_id(unsigned id) {
    return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(id));
}

}  // namespace

PaneLayout pane_layout(int layout, int fb_w, int fb_h, float panel_w, double aspect, bool compare) {
    PaneLayout p;
    p.panel_w = panel_w;
    p.panes = layout == 0 ? 2 : 1;
    p.preview = layout == 2 ? -1 : 0;
    p.trace = layout == 1 ? -1 : p.panes - 1;
    if (compare) p.compare = p.panes++;
    p.pane_w =
        std::max(64.0f, (static_cast<float>(fb_w) - p.panel_w) / static_cast<float>(p.panes));
    p.pane_h = std::max(64.0f, static_cast<float>(fb_h));
    const float a = static_cast<float>(aspect > 0 ? aspect : 4.0 / 3.0);
    p.image_w = std::min(p.pane_w, std::round(p.pane_h * a));
    p.image_h = std::min(p.pane_h, std::round(p.pane_w / a));
    return p;
}

Panes::Panes(const std::string& shader_dir) : m_preview(shader_dir) {
    m_preview.env_budget_ms = 12;  // environment maps over several frames, which stay smooth
}

PaneHover Panes::show(ViewerState& v, const PaneLayout& p, double frame_s) {
    const ViewSettings& s = v.settings;
    // The resolution setting serves a view that changes; half a second after the last edit the
    // trace starts again at full resolution (the status bar says which).
    const float scale = v.trace.seconds_since_edit() > 0.5 ? 1.0f : s.resolution_scale;
    v.set_trace_size(std::max(16, static_cast<int>(p.image_w * scale)),
                     std::max(16, static_cast<int>(p.image_h * scale)));

    ImGui::SetNextWindowPos(ImVec2(p.panel_w, 0));
    ImGui::SetNextWindowSize(ImVec2(static_cast<float>(p.panes) * p.pane_w, p.pane_h));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0);
    ImGui::Begin("panes", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoBringToFrontOnFocus);
    // While the view moves, the preview draws at a lower resolution (software GL fills pixels
    // slowly): half, and less while frames take longer than 30 ms, back towards half below
    // 20 ms; a quarter second after the last change, full.
    const bool moving = v.trace.moving();
    if (moving && frame_s > 0.030) m_moving_div = std::min(4.0, m_moving_div * 1.25);
    if (moving && frame_s < 0.020) m_moving_div = std::max(2.0, m_moving_div / 1.1);
    const double div = moving ? m_moving_div : 1.0;
    m_target.resize(static_cast<int>(static_cast<double>(p.image_w) / div),
                    static_cast<int>(static_cast<double>(p.image_h) / div));
    PaneHover hover;
    const ImVec2 size(p.image_w, p.image_h);
    const ImVec2 origin = ImGui::GetWindowPos();
    if (p.preview >= 0) {
        ImGui::SetCursorScreenPos(ImVec2(p.image_x(p.preview), origin.y + p.image_y()));
        ImGui::Image(texture_id(m_target.color.id()), size, ImVec2(0, 1), ImVec2(1, 0));
        hover.preview = ImGui::IsItemHovered();
    }
    if (p.trace >= 0) {
        ImGui::SetCursorScreenPos(ImVec2(p.image_x(p.trace), origin.y + p.image_y()));
        if (m_trace.texture)
            ImGui::Image(texture_id(m_trace.texture.id()), size);
        else
            ImGui::Dummy(size);
        hover.trace = ImGui::IsItemHovered();
    }
    if (p.compare >= 0) {
        ImGui::SetCursorScreenPos(ImVec2(p.image_x(p.compare), origin.y + p.image_y()));
        if (m_compare.texture)
            ImGui::Image(texture_id(m_compare.texture.id()), size);
        else
            ImGui::Dummy(size);
        hover.compare = ImGui::IsItemHovered();
        show_compare(v, p, hover.compare);
    }
    // The pane's toolbar: the inspect mode's toggle (I), lit while it is on.
    const int tool_pane = p.trace >= 0 ? p.trace : p.preview;
    ImGui::SetCursorScreenPos(ImVec2(p.image_x(tool_pane) + 6, origin.y + p.image_y() + 6));
    const bool inspecting = v.ui.inspect.mode;
    if (inspecting) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.9f, 0.45f, 0.1f, 0.9f));
    if (ImGui::SmallButton(inspecting ? "Inspect: on (I)" : "Inspect (I)"))
        v.ui.inspect.set_mode(!inspecting);
    if (inspecting) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "A click in any pane explains that pixel of the trace:\n"
            "its ray tree, drawn in the preview and listed in the panel");
    // Say why a pane is blank: nothing to draw, or nothing that lights it.
    const char* blank = nullptr;
    if (v.session.loaded->scene.instances.empty() || v.session.loaded->scene.world_bounds.empty())
        blank = "the scene is empty: it has no shapes";
    else if (v.edits.lights.empty() && !v.settings.headlight)
        blank = "the scene has no lights (turn the headlight on in the panel)";
    if (blank)
        for (int i : {p.preview, p.trace}) {
            if (i < 0) continue;
            const ImVec2 text = ImGui::CalcTextSize(blank);
            ImGui::SetCursorScreenPos(
                ImVec2(p.image_x(i) + 0.5f * (p.image_w - text.x), origin.y + 0.5f * p.pane_h));
            ImGui::TextUnformatted(blank);
        }
    ImGui::End();
    ImGui::PopStyleVar(2);
    return hover;
}

void Panes::show_compare(ViewerState& v, const PaneLayout& p, bool hovered) {
    const CompareView& c = v.ui.compare;  // changed through its verbs
    const ImVec2 origin = ImGui::GetWindowPos();
    const float x0 = p.image_x(p.compare), y0 = origin.y + p.image_y();
    // The toolbar: the views (B flips theirs and ours, V cycles), and the end of the comparison.
    ImGui::SetCursorScreenPos(ImVec2(x0 + 6, y0 + 6));
    for (CompareShow s : {CompareShow::Theirs, CompareShow::Ours, CompareShow::Difference,
                          CompareShow::Threshold}) {
        const bool on = c.show == s;
        if (on) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.9f, 0.45f, 0.1f, 0.9f));
        if (ImGui::SmallButton(compare_show_name(s))) v.ui.compare.set_show(s);
        if (on) ImGui::PopStyleColor();
        ImGui::SameLine();
    }
    if (ImGui::SmallButton("x")) {
        stop_compare(v);
        return;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Stop comparing");
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const std::string name = std::filesystem::path(c.path).filename().string();
    const char* what = c.show == CompareShow::Theirs       ? "theirs (B: ours)"
                       : c.show == CompareShow::Ours       ? "ours: the reference (B: theirs)"
                       : c.show == CompareShow::Difference ? "difference, 8-bit steps"
                                                           : "off by more than the tolerance (red)";
    const std::string label = name + ": " + what;
    draw->AddText(ImVec2(x0 + 8, y0 + 30), IM_COL32(255, 255, 255, 230), label.c_str());
    if (!c.result) {
        const char* wait = "rendering the reference...";
        const ImVec2 t = ImGui::CalcTextSize(wait);
        draw->AddText(ImVec2(x0 + 0.5f * (p.image_w - t.x), y0 + 0.5f * p.image_h),
                      IM_COL32(255, 255, 255, 255), wait);
    } else if (c.show == CompareShow::Difference) {  // the scale bar, 0 to the largest
        const float bw = std::min(220.0f, p.image_w - 90), bh = 12;
        const float bx = x0 + 10, by = y0 + p.image_h - bh - 10;
        constexpr int kSteps = 32;
        for (int i = 0; i < kSteps; ++i) {
            const Vec3 col = heat_colour((i + 0.5) / kSteps);
            auto u8 = [](double x) { return static_cast<int>(std::clamp(x, 0.0, 1.0) * 255); };
            draw->AddRectFilled(ImVec2(bx + bw * static_cast<float>(i) / kSteps, by),
                                ImVec2(bx + bw * static_cast<float>(i + 1) / kSteps, by + bh),
                                IM_COL32(u8(col.x), u8(col.y), u8(col.z), 255));
        }
        char hi[32];
        std::snprintf(hi, sizeof hi, "%.0f", std::max(1.0, c.result->max_diff));
        draw->AddText(ImVec2(bx, by - 16), IM_COL32(255, 255, 255, 230), "0");
        draw->AddText(ImVec2(bx + bw - ImGui::CalcTextSize(hi).x, by - 16),
                      IM_COL32(255, 255, 255, 230), hi);
    }
    if (c.probe_x >= 0) {  // the pixel clicked, marked
        const float px = x0 + (static_cast<float>(c.probe_x) + 0.5f) * p.image_w /
                                  static_cast<float>(c.theirs.width);
        const float py = y0 + (static_cast<float>(c.probe_y) + 0.5f) * p.image_h /
                                  static_cast<float>(c.theirs.height);
        draw->AddCircle(ImVec2(px, py), 6, IM_COL32(0, 255, 255, 255), 12, 2);
    }
    if (hovered && c.result) {  // both values under the mouse
        const ImVec2 m = ImGui::GetIO().MousePos;
        const int x = static_cast<int>((m.x - x0) / p.image_w * static_cast<float>(c.theirs.width));
        const int y =
            static_cast<int>((m.y - y0) / p.image_h * static_cast<float>(c.theirs.height));
        const std::string text = compare_probe_text(c, x, y);
        if (!text.empty()) ImGui::SetTooltip("%s\nclick: its ray tree", text.c_str());
    }
}

void Panes::draw(ViewerState& v) {
    upload_compare(v);
    upload_trace(v);
    LoadedScene& loaded = *v.session.loaded;
    upload_scene(loaded);
    draw_preview(v, loaded);
}

// The comparison pane's view: a new comparison, another view or display transform.
void Panes::upload_compare(const ViewerState& v) {
    const CompareView& c = v.ui.compare;
    if (c.active() &&
        (c.version != m_compare_version || c.show != m_compare_show ||
         v.settings.exposure != m_compare_exposure || v.settings.tonemap != m_compare_tonemap)) {
        const Image shown = compare_pane_image(c, v.settings.exposure, v.settings.tonemap);
        if (shown.width > 0)
            m_compare.upload(shown);
        else
            m_compare = ImageTexture();  // blank until the reference is done
        m_compare_version = c.version;
        m_compare_show = c.show;
        m_compare_exposure = v.settings.exposure;
        m_compare_tonemap = v.settings.tonemap;
    }
}

// A new trace, or another exposure or tonemap of the last one (display only).
void Panes::upload_trace(ViewerState& v) {
    const bool new_trace = take_trace(v);
    if (new_trace || v.settings.exposure != m_shown_exposure ||
        v.settings.tonemap != m_shown_tonemap) {
        const bool as_is = v.settings.exposure == 0 && v.settings.tonemap == Tonemap::Clamp;
        if (v.trace.last_trace.width > 0 && as_is)
            m_trace.upload(v.trace.last_trace);  // no copy of every pass when nothing changes it
        else if (v.trace.last_trace.width > 0)
            m_trace.upload(displayed_trace(v));
        m_shown_exposure = v.settings.exposure;
        m_shown_tonemap = v.settings.tonemap;
    }
}

// A scene opened (tessellated with it, off this thread), or its materials edited in the panel.
void Panes::upload_scene(LoadedScene& loaded) {
    if (loaded.id != m_loaded_id) {  // tessellated with the scene, off this thread
        m_preview.load(loaded.scene, loaded.preview);
        loaded.preview = {};
        m_loaded_id = loaded.id;
        m_drawn_materials = loaded.scene.materials;
    }
    if (!same_materials(loaded.scene.materials, m_drawn_materials)) {  // edited in the panel
        // A texture put on a material: its image and the set's texture coordinates.
        if (m_preview.needs_upload(loaded.scene))
            m_preview.load(loaded.scene, prepare_preview(loaded.scene, m_preview.detail()));
        m_preview.materials_changed(loaded.scene);
        m_drawn_materials = loaded.scene.materials;
        m_preview_stale = true;
    }
}

// The preview, its overlay lines and the inspected ray tree, redrawn when what they show changed.
void Panes::draw_preview(ViewerState& v, const LoadedScene& loaded) {
    const ViewSettings& s = v.settings;
    const bool overlay_changed =
        s.show_lights != m_drawn_lights || s.box_depth != m_drawn_depth ||
        s.light_directions != m_drawn_directions || v.ui.selected_light != m_drawn_selected ||
        s.exposure != m_drawn_exposure || s.tonemap != m_drawn_tonemap ||
        s.group_depth != m_drawn_group_depth || v.ui.inspect.version != m_drawn_inspect ||
        v.ui.inspect.hovered != m_drawn_hovered;
    if (!preview_stale(v) && !overlay_changed && m_target.w == m_drawn_w && m_target.h == m_drawn_h)
        return;
    glBindFramebuffer(GL_FRAMEBUFFER, m_target.fbo.id());
    // The camera of the latest input, also while a restart waits.
    const Camera cam = v.edits.camera.camera(m_target.w, m_target.h);
    // The joints at the timeline's time, every frame; the lights of the last restart.
    const RenderScene& scene = loaded.scene;
    m_preview.moving = v.trace.moving();
    m_preview.draw(scene, v.trace.tracer.plan(), cam, m_target.w, m_target.h, s.render.max_depth,
                   {s.exposure, s.tonemap});
    std::vector<LineVertex> lines =
        overlay_lines(scene, {s.show_lights, v.ui.selected_light, s.light_directions}, s.box_depth);
    if (s.group_depth != m_group_lines_depth || loaded.id != m_group_lines_for ||
        (s.group_depth > 0 && scene.time != m_group_lines_time)) {
        // Walked again only when the scene, the level or (with the boxes on) the joints' time
        // changes: an animated scene's groups are those of its static scene at that time.
        m_group_lines =
            loaded.desc.tracks.empty() || s.group_depth == 0
                ? group_box_lines(loaded.desc, s.group_depth)
                : group_box_lines(scene_at_time(loaded.desc, scene.time), s.group_depth);
        m_group_lines_depth = s.group_depth;
        m_group_lines_for = loaded.id;
        m_group_lines_time = scene.time;
    }
    lines.insert(lines.end(), m_group_lines.begin(), m_group_lines.end());
    if (v.ui.selection.instance >= 0) {  // the picked primitive, highlighted
        const std::vector<LineVertex> sel = box_lines(v.ui.selection.bounds, Vec3(1.0, 0.6, 0.1));
        lines.insert(lines.end(), sel.begin(), sel.end());
    }
    m_preview.draw_lines(lines, scene, cam);
    if (v.ui.inspect.tree) {  // the pixel's ray tree, over everything
        const Bounds3& wb = scene.world_bounds;
        const double size = wb.empty() ? 1.0 : glm::length(wb.diagonal());
        m_preview.draw_lines(
            inspect_lines(*v.ui.inspect.tree, 0.04 * size, size, v.ui.inspect.hovered), scene, cam,
            true);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    m_preview_stale = m_preview.environment_pending();  // drawn again until the maps are done
    m_drawn_changes = v.ui.changes;
    m_drawn_lights = s.show_lights;
    m_drawn_directions = s.light_directions;
    m_drawn_selected = v.ui.selected_light;
    m_drawn_inspect = v.ui.inspect.version;
    m_drawn_hovered = v.ui.inspect.hovered;
    m_drawn_exposure = s.exposure;
    m_drawn_tonemap = s.tonemap;
    m_drawn_depth = s.box_depth;
    m_drawn_group_depth = s.group_depth;
    m_drawn_w = m_target.w;
    m_drawn_h = m_target.h;
}

}  // namespace rt::view
