#include "ui/panels.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "state/key_queue.h"
#include "state/run_options.h"
#include "state/viewer_output.h"
#include "ui/inspect_panel.h"

namespace rt::view {

namespace {

constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;  // typed values too

double decimal(float f) { return float_as_decimal(f); }
Vec3 decimal(const float f[3]) { return Vec3(decimal(f[0]), decimal(f[1]), decimal(f[2])); }

// A float slider over a double setting; typed values are clamped, non-finite ones refused.
bool slider(const char* label, double* value, float lo, float hi, const char* format = "%.3f") {
    float f = static_cast<float>(*value);
    if (!ImGui::SliderFloat(label, &f, lo, hi, format, kClamp) || !std::isfinite(f)) return false;
    *value = decimal(f);
    return true;
}

// An int slider; typed values are clamped.
bool slider(const char* label, int* value, int lo, int hi) {
    return ImGui::SliderInt(label, value, lo, hi, "%d", kClamp);
}

// A three-float drag over a Vec3; non-finite values are refused.
bool drag3(const char* label, Vec3* v, float speed) {
    float f[3] = {static_cast<float>(v->x), static_cast<float>(v->y), static_cast<float>(v->z)};
    if (!ImGui::DragFloat3(label, f, speed)) return false;
    if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2])) return false;
    *v = decimal(f);
    return true;
}

const char* kind_name(LightKind k) {
    switch (k) {
        case LightKind::Directional:
            return "directional";
        case LightKind::Point:
            return "point";
        case LightKind::Spot:
            return "spot";
        case LightKind::Sphere:
            break;
    }
    return "sphere";
}

// A colour picker over a Vec3 (HDR: light colours may exceed 1).
bool colour(const char* label, Vec3* v) {
    float c[3] = {static_cast<float>(v->x), static_cast<float>(v->y), static_cast<float>(v->z)};
    if (!ImGui::ColorEdit3(label, c, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR))
        return false;
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) return false;
    *v = decimal(c);
    return true;
}

// A float slider over a float setting; typed values are clamped, non-finite ones refused.
bool slider_float(const char* label, float* value, float lo, float hi, const char* format,
                  ImGuiSliderFlags flags = kClamp) {
    float f = *value;
    if (!ImGui::SliderFloat(label, &f, lo, hi, format, flags) || !std::isfinite(f)) return false;
    *value = f;
    return true;
}

// A float drag over a double setting; typed values are clamped, non-finite ones refused.
bool drag(const char* label, double* value, float speed, float lo, float hi, const char* format) {
    float f = static_cast<float>(*value);
    if (!ImGui::DragFloat(label, &f, speed, lo, hi, format, kClamp) || !std::isfinite(f))
        return false;
    *value = decimal(f);
    return true;
}

// An angle in radians, shown in degrees.
bool angle_slider(const char* label, double* rad, float lo_deg, float hi_deg) {
    float deg = static_cast<float>(*rad * 180 / kPi);
    if (!ImGui::SliderFloat(label, &deg, lo_deg, hi_deg, "%.1f deg", kClamp) || !std::isfinite(deg))
        return false;
    *rad = decimal(deg) * kPi / 180;
    return true;
}

// A V0/V1 light's one colour (its diffuse and specular).
bool one_colour(LightDesc& l) {
    Vec3 c = l.diffuse;
    if (!colour("colour", &c)) return false;
    l.set_colour(c);
    return true;
}

// A number of a light (kLightNumbers' row): dragged, or a slider where it has no step; typed
// values are clamped to its range, non-finite ones refused.
bool light_number(const LightNumber& n, LightDesc& l) {
    double& value = l.*n.field;
    if (n.step == 0.0f)
        return slider(n.label, &value, static_cast<float>(n.lo), static_cast<float>(n.hi));
    float f = static_cast<float>(value);
    if (!ImGui::DragFloat(n.label, &f, n.step, static_cast<float>(n.lo), static_cast<float>(n.hi),
                          "%.3f", kClamp) ||
        !std::isfinite(f))
        return false;
    value = std::clamp(decimal(f), n.lo, n.hi);
    return true;
}

// A direction, shown and edited made unit (as the renderer uses it); zero is refused.
bool unit_direction(const char* label, Vec3* direction) {
    const Vec3 unit = glm::normalize(*direction);
    float d[3] = {static_cast<float>(unit.x), static_cast<float>(unit.y),
                  static_cast<float>(unit.z)};
    if (!ImGui::DragFloat3(label, d, 0.01f) || !(glm::length(Vec3(d[0], d[1], d[2])) > 0))
        return false;
    *direction = glm::normalize(Vec3(d[0], d[1], d[2]));
    return true;
}

// One light's controls: a V3 light's three colours (spec §13.3), a V0/V1 light's one colour
// (its diffuse and specular), its position and direction, and the numbers its kind has
// (kLightNumbers). Directions are shown and edited made unit, as the renderer uses them.
bool light_editor(LightDesc& l, char* on, bool three_colours) {
    bool edited = false;
    bool checked = *on != 0;
    if (ImGui::Checkbox(kind_name(l.kind), &checked)) {
        *on = checked ? 1 : 0;
        edited = true;
    }
    if (three_colours) {
        edited |= colour("ambient", &l.ambient);
        edited |= colour("diffuse", &l.diffuse);
        edited |= colour("specular", &l.specular);
    } else {
        edited |= one_colour(l);
    }
    if (l.kind != LightKind::Directional) edited |= drag3("position", &l.position, 0.05f);
    if (l.kind == LightKind::Directional || l.kind == LightKind::Spot)
        edited |= unit_direction("direction", &l.direction);
    for (const LightNumber& n : kLightNumbers)
        if (n.of(l.kind)) edited |= light_number(n, l);
    return edited;
}

}  // namespace

PanelState::PanelState(const std::string& path) {
    std::snprintf(path_buf, sizeof path_buf, "%s", path.c_str());
}

std::vector<std::string> completions(const std::string& typed) {
    namespace fs = std::filesystem;
    const fs::path p(typed);
    const fs::path dir = typed.empty() || typed.back() == '/' ? fs::path(typed) : p.parent_path();
    const std::string prefix = typed.empty() || typed.back() == '/' ? "" : p.filename().string();
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        std::string ext = e.path().extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (e.is_directory(ec) || ext == ".ray")
            out.push_back((dir / name).string() + (e.is_directory(ec) ? "/" : ""));
    }
    std::sort(out.begin(), out.end());
    if (out.size() > 8) out.resize(8);
    return out;
}

std::vector<std::string> sample_scenes(const std::string& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.path().extension() == ".ray" && e.is_regular_file(ec)) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

namespace {

// The load under way: its file and time, a bar of the megabytes parsed of those read, then of
// the compile's share done, then the preview's tessellation; and Cancel.
void loading_line(ViewerState& v) {
    const char spinner[] = "|/-\\";
    const LoadStatus st = v.jobs.loader.status();
    ImGui::Text("%c loading %s (%.1f s)",
                spinner[static_cast<int>(v.jobs.loader.seconds() * 8) % 4],
                v.jobs.loader.path().c_str(), v.jobs.loader.seconds());
    char label[64];
    const auto share = [](uint64_t done, uint64_t total) {
        return total > 0 ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total))
                         : 0.0;
    };
    double fraction = share(st.parsed, st.read);
    if (st.previewing) {
        fraction = 1;
        std::snprintf(label, sizeof label, "making the preview");
    } else if (st.to_compile > 0) {
        fraction = share(st.compiled, st.to_compile);
        std::snprintf(label, sizeof label, "compiling: %.0f%%", 100 * fraction);
    } else if (st.read > 0 && st.parsed >= st.read) {
        std::snprintf(label, sizeof label, "compiling");
    } else {
        std::snprintf(label, sizeof label, "%.1f of %.1f MB parsed", st.parsed / 1e6,
                      st.read / 1e6);
    }
    ImGui::ProgressBar(static_cast<float>(fraction), ImVec2(ImGui::GetFontSize() * 16, 0), label);
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel")) v.cancel_loading();
}

// The path field and its completion: the .ray files (and folders) that start with what is
// typed. True when a file is to be opened: Enter in the field, or a file picked.
bool path_field(PanelState& ui) {
    bool open_typed = false;
    if (ImGui::InputText("scene", ui.path_buf, sizeof ui.path_buf,
                         ImGuiInputTextFlags_EnterReturnsTrue))
        open_typed = true;
    if (ImGui::IsItemEdited()) ui.completing = true;
    if (ui.completing && !open_typed) {
        if (ui.completed_for != ui.path_buf) {  // list the folder only when the text changes
            ui.completed_for = ui.path_buf;
            ui.completion_list = completions(ui.path_buf);
        }
        for (const std::string& c : ui.completion_list)
            if (ImGui::Selectable(c.c_str())) {
                std::snprintf(ui.path_buf, sizeof ui.path_buf, "%s", c.c_str());
                ui.completing = c.back() == '/';  // a folder: keep completing inside it
                open_typed = !ui.completing;      // a file: open it
                break;
            }
    }
    return open_typed;
}

// The recent files and the sample scenes, each opened in the background on a click.
void file_lists(ViewerState& v, PanelState& ui) {
    const size_t first = v.session.loaded ? 1 : 0;  // the open file is recent[0]
    if (v.session.recent.size() > first && ImGui::CollapsingHeader("recent files")) {
        for (size_t i = first; i < v.session.recent.size(); ++i)
            if (ImGui::Selectable(v.session.recent[i].c_str())) {
                v.open_in_background(v.session.recent[i]);
                break;
            }
    }
    if (!ui.samples_dir.empty() && ImGui::CollapsingHeader("sample scenes")) {
        if (ui.samples.empty()) ui.samples = sample_scenes(ui.samples_dir);
        for (const std::string& path : ui.samples)
            if (ImGui::Selectable(std::filesystem::path(path).filename().c_str())) {
                v.open_in_background(path);
                break;
            }
    }
}

// Errors here, wrapped (they name files and their includes); notes go to the status bar,
// so "saved ..." never moves the panel's controls. Then a reload's conflict with the user's
// edits, the offer of checker stand-ins and the stand-ins in use. True when a file opened.
bool file_messages(ViewerState& v) {
    bool opened = false;
    if (!v.messages.text.empty() && v.messages.is_error) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::TextWrapped("%s", v.messages.text.c_str());
        ImGui::PopStyleColor();
    }
    if (!v.session.reload_conflict.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.8f, 0.3f, 1));
        ImGui::TextWrapped("%s", v.session.reload_conflict.c_str());
        ImGui::PopStyleColor();
        if (ImGui::Button("Use the file's")) v.use_file_edits();
        ImGui::SameLine();
        if (ImGui::Button("Keep mine")) v.session.keep_my_edits();
    }
    // The offer goes with its message: a newer error or note replaces both.
    v.session.withdraw_offer_after(v.messages.serial);
    if (!v.session.checker_offer.empty() &&
        ImGui::Button("open with checker stand-ins (for the rest of the session)"))
        opened |= v.open_with_checker();
    if (v.session.loaded) {
        const std::string stand_ins = stand_in_text(v.session.loaded->desc);
        if (!stand_ins.empty()) {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.8f, 0.3f, 1));
            ImGui::TextWrapped("%s", stand_ins.c_str());
            ImGui::PopStyleColor();
        }
    }
    return opened;
}

}  // namespace

bool file_panel(ViewerState& v, PanelState& ui) {
    if (v.session.loaded && v.session.loaded->id != ui.path_for) {  // a file opened: show its path
        std::snprintf(ui.path_buf, sizeof ui.path_buf, "%s", v.session.loaded->path.c_str());
        ui.path_for = v.session.loaded->id;
    }
    bool opened = false;
    // Enter in the field, Open, or a file picked from the completions.
    bool open_typed = path_field(ui);
    open_typed |= ImGui::Button("Open");
    if (open_typed) {  // in the background: the open scene stays interactive
        ui.completing = false;
        v.open_in_background(ui.path_buf);
        if (v.session
                .loaded)  // until it opens (or fails, with the error shown) the open scene's path
            std::snprintf(ui.path_buf, sizeof ui.path_buf, "%s", v.session.loaded->path.c_str());
    }
    ImGui::SameLine();
    if (ImGui::Button("Reload") && v.session.loaded) opened |= v.reload();
    ImGui::SameLine();
    ImGui::TextDisabled("(or drop a .ray file)");
    if (v.jobs.loader.busy()) loading_line(v);
    file_lists(v, ui);
    opened |= file_messages(v);
    return opened;
}

// The camera (a copy, put back once when edited), the lens, the selection and the bookmarks.
void camera_panel(ViewerState& v, const PaneLayout& layout) {
    bool edited = false;
    const bool keys = !ImGui::GetIO().WantCaptureKeyboard;
    OrbitCamera cam = v.edits.camera;
    ImGui::Separator();
    ImGui::TextWrapped(
        "Camera: drag orbits, shift/middle drag pans, wheel dollies, "
        "right drag looks around, WASD/QE fly (F1: every shortcut)");
    if (ImGui::Button("Frame (F)") || (keys && key_queue().presses(GLFW_KEY_F) > 0)) {
        // The selection, or else the whole scene.
        cam.frame(v.ui.selection.instance >= 0 ? v.ui.selection.bounds
                                               : v.session.loaded->scene.world_bounds,
                  static_cast<double>(layout.image_w) / static_cast<double>(layout.image_h));
        edited = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Home") || (keys && key_queue().presses(GLFW_KEY_HOME) > 0)) {
        cam.set_from(v.session.loaded->file_camera, v.session.loaded->scene.world_bounds);
        edited = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Help (F1)")) v.ui.toggle_help();
    if (ImGui::Button("Undo")) v.undo();
    ImGui::SameLine();
    if (ImGui::Button("Redo")) v.redo();
    // The field of view as the spec's half-height angle, shown in degrees.
    edited |= angle_slider("half-height angle", &cam.half_height, 1.0f, 85.0f);
    ViewSettings s = v.settings;
    RenderSettings& r = s.render;
    edited |= slider("aperture", &r.aperture, 0.0f, 0.5f);
    const bool focus_set = static_cast<float>(r.focus_distance) > 0;
    edited |= drag("focus distance", &r.focus_distance, 0.05f, 0.0f, 1e6f,
                   focus_set ? "%.3f" : "scene centre");
    if (v.ui.selection.instance >= 0) {  // what a click in a pane picked
        const Selection& sel = v.ui.selection;
        ImGui::TextWrapped("selected: %s, %s\n%s\nin %s\nat (%.3g, %.3g, %.3g)", sel.shape.c_str(),
                           sel.material.c_str(), sel.where.c_str(), sel.groups.c_str(), sel.point.x,
                           sel.point.y, sel.point.z);
        if (ImGui::SmallButton("clear selection")) v.ui.clear_selection();
    } else {
        ImGui::TextDisabled("click a shape in a pane to select it");
    }
    if (ImGui::Button("Set as the scene's camera")) v.set_file_camera();
    ImGui::SameLine();
    if (ImGui::Button("Bookmark")) v.ui.add_bookmark(cam);
    for (size_t i = 0; i < v.ui.bookmarks.size(); ++i) {
        ImGui::PushID(static_cast<int>(i));
        if (ImGui::Button(("view " + std::to_string(i + 1)).c_str())) {
            cam = v.ui.bookmarks[i];
            edited = true;
        }
        ImGui::SameLine();
        if (ImGui::SmallButton("x")) {
            v.ui.remove_bookmark(i);
            ImGui::PopID();
            break;
        }
        if (i + 1 < v.ui.bookmarks.size() && (i + 1) % 4 != 0) ImGui::SameLine();
        ImGui::PopID();
    }
    if (!edited) return;
    v.edits.set_camera(cam);  // the viewer sees the change: the trace restarts
    v.settings = s;
}

// The renderer's settings and the panes' (a copy, put back once): the viewer restarts the trace
// for those the trace uses.
void settings_panel(ViewerState& v) {
    ViewSettings s = v.settings;
    RenderSettings& r = s.render;
    ImGui::Separator();
    ImGui::RadioButton("both", &s.layout, 0);
    ImGui::SameLine();
    ImGui::RadioButton("preview", &s.layout, 1);
    ImGui::SameLine();
    ImGui::RadioButton("trace", &s.layout, 2);
    ImGui::Checkbox("shadows", &r.shadows);
    ImGui::SameLine();
    ImGui::Checkbox("light markers", &s.show_lights);
    if (s.show_lights) {
        ImGui::SameLine();
        ImGui::Checkbox("all directions", &s.light_directions);
    }
    slider("group box levels", &s.group_depth, 0, 8);
    slider("BVH box levels", &s.box_depth, 0, 8);
    slider("depth", &r.max_depth, 1, 10);
    slider("cutoff", &r.cutoff, 0.0f, 0.1f, "%.4f");
    slider("target spp", &s.target_spp, 1, 4096);
    // The trace also stops at an estimated error (relMSE), as raytrace --target-error.
    slider_float("target error", &s.target_error, 0.0f, 0.01f, s.target_error > 0 ? "%.1e" : "off",
                 kClamp | ImGuiSliderFlags_Logarithmic);
    slider_float("resolution", &s.resolution_scale, 0.1f, 1.0f, "%.3f");
    slider("threads (0 = all)", &r.threads, 0, 64);
    slider("light radius", &r.light_radius, 0.0f, 2.0f);
    slider("roughness", &r.roughness, 0.0f, 1.0f);
    // Display only: the trace is not rendered again.
    float exposure = s.exposure;
    if (ImGui::SliderFloat("exposure", &exposure, -8.0f, 8.0f, "%+.1f stops", kClamp) &&
        std::isfinite(exposure))
        s.exposure = static_cast<float>(decimal(exposure));
    int tonemap = static_cast<int>(s.tonemap);
    if (ImGui::Combo("tonemap", &tonemap, "clamp (as raytrace)\0Reinhard\0ACES filmic\0"))
        s.tonemap = static_cast<Tonemap>(tonemap);
    slider_float("UI scale", &s.ui_scale, 0.75f, 2.5f, "%.2f");  // the window's, not an edit
    if (!(s == v.settings)) v.settings = s;
}

// Each light (a copy, put back once when edited), its framing and removal; new lights; the
// headlight of a scene without lights.
void lights_panel(ViewerState& v) {
    ImGui::Separator();
    ImGui::Text("Lights");
    const bool three_colours = v.session.loaded->desc.dialect == Dialect::V3;
    for (size_t i = 0; i < v.edits.lights.size(); ++i) {
        ImGui::PushID(static_cast<int>(i));
        // The light being edited shows its direction in the preview.
        LightDesc light = v.edits.lights[i];
        char on = v.edits.light_on[i];
        if (light_editor(light, &on, three_colours)) {
            v.edits.set_light(i, light, on != 0);
            v.ui.select_light(static_cast<int>(i));
        }
        if (ImGui::Button("frame")) {  // find a light outside the view
            v.edits.frame_light(i, v.session.loaded->scene.world_bounds);
            v.ui.select_light(static_cast<int>(i));
        }
        ImGui::SameLine();
        if (ImGui::Button("remove")) {
            v.edits.remove_light(i);
            ImGui::PopID();
            break;
        }
        ImGui::Separator();
        ImGui::PopID();
    }
    // New lights at the eye, along the view; V3 scenes may have sphere lights too.
    ImGui::TextUnformatted("add");
    const LightKind kinds[] = {LightKind::Point, LightKind::Spot, LightKind::Directional,
                               LightKind::Sphere};
    const int count = three_colours ? 4 : 3;
    for (int k = 0; k < count; ++k) {
        ImGui::SameLine();
        if (ImGui::Button(kind_name(kinds[k]))) v.edits.add_light(kinds[k]);
    }
    if (v.edits.lights.empty()) {
        ViewSettings s = v.settings;
        if (ImGui::Checkbox("headlight (the scene has no lights)", &s.headlight)) v.settings = s;
        if (s.headlight && ImGui::Button("keep the headlight as a light")) v.edits.keep_headlight();
    }
}

void status_panel(const ViewerState& v, const std::vector<std::string>& preview_defines,
                  double frame_s) {
    ImGui::Separator();
    const Tracer::Status st = v.trace.tracer.status();
    ImGui::Text("%.1f s since the last change; frame %.1f ms", st.seconds, 1000 * frame_s);
    // What the renderer left out for this scene, recomputed on each restart: the lights and
    // settings change it.
    int left = 0;
    for (const std::string& l : v.trace.explained) left += l.rfind("left out", 0) == 0;
    std::string header = "renderer: ";
    header += std::to_string(left);
    header += " feature(s) left out###leftout";
    if (ImGui::CollapsingHeader(header.c_str())) {
        for (const std::string& l : v.trace.explained) ImGui::TextWrapped("%s", l.c_str());
        std::string shader = "preview shader:";
        for (const std::string& d : preview_defines) {
            shader += ' ';
            shader += d;
        }
        ImGui::TextWrapped("%s", shader.c_str());
    }
    // The estimated error of each pass on a log scale, its axes labelled: the relMSE at the top
    // and the bottom, the passes and their time along the bottom.
    std::vector<float> logs;
    const std::vector<std::pair<float, float>> history = v.trace.tracer.history();
    for (const auto& [t, e] : history) logs.push_back(std::log10(e));
    if (!logs.empty()) {
        const auto [lo_it, hi_it] = std::minmax_element(logs.begin(), logs.end());
        const float lo = std::floor(*lo_it), hi = std::max(std::ceil(*hi_it), lo + 1);
        ImGui::PlotLines("##error", logs.data(), static_cast<int>(logs.size()), 0, nullptr, lo, hi,
                         ImVec2(0, 70));
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        ImDrawList* draw = ImGui::GetWindowDrawList();
        const ImU32 grey = ImGui::GetColorU32(ImGuiCol_TextDisabled);
        char label[48];
        std::snprintf(label, sizeof label, "1e%+.0f", static_cast<double>(hi));
        draw->AddText(ImVec2(a.x + 3, a.y + 1), grey, label);
        std::snprintf(label, sizeof label, "1e%+.0f", static_cast<double>(lo));
        draw->AddText(ImVec2(a.x + 3, b.y - ImGui::GetTextLineHeight() - 1), grey, label);
        ImGui::TextDisabled("relMSE (log) by pass: 1 .. %zu, 0 .. %.1f s", logs.size(),
                            static_cast<double>(history.back().first));
    }
}

namespace {

// A material's texture: none or one of its own file's (the file's #texture lines; textures
// modulate K_D, or every term in V3: spec §7.3, §13.9).
bool texture_combo(const LoadedScene& s, size_t material, int* texture) {
    const SceneDesc& desc = s.desc;
    const MaterialOrigin o = s.origin(material);
    if (o.textures == 0) return false;
    const auto& files = desc.files[static_cast<size_t>(o.file)].textures;
    auto name = [&](int t) {  // the file's texture t
        if (t < 0 || t >= o.textures) return std::string("none");
        return std::filesystem::path(files[static_cast<size_t>(t)].path).filename().string() +
               " (texture " + std::to_string(t) + ")";
    };
    bool edited = false;
    if (ImGui::BeginCombo("texture", name(*texture).c_str())) {
        for (int t = -1; t < o.textures; ++t)
            if (ImGui::Selectable(name(t).c_str(), t == *texture) && t != *texture) {
                *texture = t;
                edited = true;
            }
        ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(desc.dialect == Dialect::V3 ? "modulates every term (spec §13.9)"
                                                      : "modulates K_D (spec §7.3)");
    return edited;
}

}  // namespace

// One material's terms (spec §7, §13.9): its colours (HDR), the exponent, the transparency
// and the refraction index, edited as a copy put back once into SceneEdits::materials (undo,
// both panes at the restart, saved with the scene). The material follows the last pick, or
// the list.
void materials_panel(ViewerState& v, PanelState& ui) {
    const std::vector<MaterialDesc>& materials = v.edits.materials;
    if (materials.empty() || !ImGui::CollapsingHeader("Materials")) return;
    const LoadedScene& s = *v.session.loaded;
    const int picked = v.ui.selection.instance >= 0 ? v.ui.selection.material_index : -1;
    if (picked >= 0 && picked != ui.material_picked) ui.material = picked;
    ui.material_picked = picked;
    ui.material = std::clamp(ui.material, 0, static_cast<int>(materials.size()) - 1);
    auto name = [&](int i) {
        const size_t k = static_cast<size_t>(i);
        const std::string n = k < s.material_names.size() ? s.material_names[k] : "";
        return (n.empty() ? "" : "!" + n + "! ") + "(material " + std::to_string(i) + ")";
    };
    if (ImGui::BeginCombo("material", name(ui.material).c_str())) {
        for (int i = 0; i < static_cast<int>(materials.size()); ++i)
            if (ImGui::Selectable(name(i).c_str(), i == ui.material)) ui.material = i;
        ImGui::EndCombo();
    }
    MaterialDesc m = materials[static_cast<size_t>(ui.material)];  // a copy, put back once
    bool edited = false;
    edited |= colour("emissive", &m.emissive);
    edited |= colour("ambient", &m.ambient);
    edited |= colour("diffuse", &m.diffuse);
    edited |= colour("specular", &m.specular);
    edited |= colour("transparent", &m.transparent);
    edited |= slider("exponent", &m.specular_exponent, 0.0f, 1000.0f);
    edited |= slider("refraction index", &m.refractive_index, 0.1f, 4.0f);
    edited |= texture_combo(s, static_cast<size_t>(ui.material), &m.texture);
    // An included file's material is saved into that file when asked (the Save section); the
    // built-in default is in no file.
    const MaterialOrigin origin = s.origin(static_cast<size_t>(ui.material));
    if (origin.file != 0) {
        const std::string where =
            origin.file < 0
                ? std::string("the built-in default: edited for this session, not saved")
                : "from " +
                      std::filesystem::path(s.desc.files[static_cast<size_t>(origin.file)].path)
                          .filename()
                          .string() +
                      ": saved into it when asked under Save";
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
        ImGui::TextWrapped("%s", where.c_str());
        ImGui::PopStyleColor();
    }
    if (ImGui::Button("Revert this material")) {
        m = s.file_materials[static_cast<size_t>(ui.material)];
        edited = true;
    }
    if (edited) v.edits.set_material(static_cast<size_t>(ui.material), m);
}

void save_panel(ViewerState& v, PanelState& ui) {
    ImGui::InputText("save as", ui.save_buf, sizeof ui.save_buf);
    ImGui::InputText("scene file", ui.scene_buf, sizeof ui.scene_buf);
    // Materials of included files live in those files: written there (each edited #material
    // line replaced, the rest kept) only when asked.
    const std::vector<std::string> parts = edited_included_files(v);
    std::string names;
    for (const std::string& p : parts)
        names += (names.empty() ? "" : ", ") + std::filesystem::path(p).filename().string();
    if (!parts.empty())
        ImGui::Checkbox(("also write the edited materials into " + names).c_str(),
                        &ui.save_included);
    if (ImGui::Button("Save scene (camera, lights, materials)")) {
        const bool included = ui.save_included && !parts.empty();
        try {
            save_scene(v, ui.scene_buf, included);
            v.messages.note(std::string("saved ") + ui.scene_buf +
                            (included ? " and the materials of " + names : ""));
        } catch (const std::exception& e) {
            v.messages.fail(e.what());
        }
    }
    // Back to the file's camera and lights whatever was kept or edited (one undo step).
    ImGui::SameLine();
    if (ImGui::Button("Revert to the file")) {
        v.use_file_edits();
        v.messages.note("the file's camera and lights");
    }
    // The image: rendered again at a size and sample count of the user's choice, in the
    // background, or the pane's trace as it is.
    ImGui::InputInt2("image size", ui.image_size);
    ui.image_size[0] = std::clamp(ui.image_size[0], 1, 32768);
    ui.image_size[1] = std::clamp(ui.image_size[1], 1, 32768);
    ImGui::InputInt("samples per pixel", &ui.image_spp);
    ui.image_spp = std::clamp(ui.image_spp, 1, 1 << 16);
    if (v.jobs.image.running()) {
        ImGui::ProgressBar(static_cast<float>(v.jobs.image.progress()), ImVec2(-80, 0));
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            v.jobs.image.cancel();
            v.messages.note("the image was cancelled; nothing written");
        }
    } else if (ImGui::Button("Render and save image (.png .pfm ...)")) {
        render_image(v, ui.save_buf, ui.image_size[0], ui.image_size[1], ui.image_spp);
    }
    if (ImGui::Button("Save the pane's trace as it is")) {
        try {
            save_trace(v, ui.save_buf);
            v.messages.note(std::string("saved ") + ui.save_buf);
        } catch (const std::exception& e) {
            v.messages.fail(e.what());
        }
    }
}

namespace {

void help_window(bool* open) {
    const ImGuiIO& io = ImGui::GetIO();
    const KeyQueue& keys = key_queue();
    // F1 or ? (shifted /) toggles it, each tap (two in one frame cancel out).
    const int taps =
        keys.presses(GLFW_KEY_F1, false, false) +
        (keys.shifted(GLFW_KEY_SLASH) ? keys.presses(GLFW_KEY_SLASH, false, false) : 0);
    if (!io.WantTextInput && taps % 2 == 1) *open = !*open;
    if (!*open) return;
    if (keys.presses(GLFW_KEY_ESCAPE, false, false) > 0) *open = false;
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(vp->Size.x * 0.5f, vp->Size.y * 0.5f), ImGuiCond_Always,
                            ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.92f);
    if (!ImGui::Begin("Shortcuts (F1 or ? to close)", open,
                      ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        ImGui::End();
        return;
    }
    static const char* const kRows[][2] = {
        {"left drag", "orbit about the target"},
        {"shift + left drag, middle drag", "pan"},
        {"right drag", "look around (the eye stays)"},
        {"wheel", "dolly towards the target"},
        {"W A S D, Q E", "fly forward, left, back, right, down, up"},
        {"F", "frame the selection, or the scene"},
        {"I", "inspect mode: a click explains a pixel (its ray tree)"},
        {"C", "clear the ray tree"},
        {"Home", "back to the scene's camera"},
        {"click a light's marker, drag", "move the light (preview pane)"},
        {"Space", "play or pause the animation"},
        {"Left, Right", "previous, next frame of the animation"},
        {"Ctrl+Z", "undo"},
        {"Ctrl+Shift+Z, Ctrl+Y", "redo"},
        {"F1, ?", "this help; Esc closes it"},
        {"drop a .ray file", "open it"},
        {"drop an image (PNG, PFM, ...)", "compare it with the reference (comparison pane)"},
        {"B", "comparing: flip between theirs and ours"},
        {"V", "comparing: the next view (theirs, ours, difference, threshold)"},
        {"click in the comparison pane", "both values there and the reference's ray tree"},
    };
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
        for (const auto& row : kRows) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(row[0]);
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(row[1]);
        }
        ImGui::EndTable();
    }
    if (ImGui::CollapsingHeader("Script commands (rayview --script FILE)",
                                ImGuiTreeNodeFlags_DefaultOpen))
        ImGui::TextUnformatted(script_commands_help());
    ImGui::TextDisabled("Every flag: rayview --help.");
    ImGui::End();
}

}  // namespace

void help_overlay(ViewUi& ui) {
    bool open = ui.show_help;
    help_window(&open);
    ui.set_help(open);
}

void status_bar(const ViewerState& v, const PaneLayout& layout) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const float h = ImGui::GetFrameHeightWithSpacing();
    ImGui::SetNextWindowPos(ImVec2(layout.panel_w, vp->Size.y - h));
    ImGui::SetNextWindowSize(ImVec2(vp->Size.x - layout.panel_w, h));
    ImGui::SetNextWindowBgAlpha(0.7f);
    ImGui::Begin("status", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
    const std::string status = status_text(v);
    ImGui::Text("%s", status.c_str());
    if (!v.messages.text.empty() && !v.messages.is_error) {  // the last note
        ImGui::SameLine();
        ImGui::TextDisabled("| %s", v.messages.text.c_str());
    }
    // A narrow window cuts the line: the whole of it, and the last message with its paths in
    // full, on hover.
    if (ImGui::IsWindowHovered()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 45.0f);
        ImGui::TextUnformatted(status.c_str());
        if (!v.messages.text.empty()) {
            ImGui::Separator();
            ImGui::TextUnformatted(v.messages.text.c_str());
        }
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
    ImGui::End();
}

void animation_panel(ViewerState& v, PanelState& ui) {
    const double length = v.animation_length();
    if (length <= 0 || !ImGui::CollapsingHeader("animation", ImGuiTreeNodeFlags_DefaultOpen))
        return;
    const Timeline& tl = v.timeline;
    ImGui::Text("%zu DOFs, %.3g s loop; t = %.3f s (%s, %s)", v.session.loaded->desc.tracks.size(),
                length, tl.time, interpolation_name(tl.interpolation), rotation_name(tl.rotation));
    float fps = static_cast<float>(v.timeline.fps);
    if (ImGui::InputFloat("frames per second", &fps, 1, 5, "%.3g")) v.timeline.set_fps(fps);
    if (ui.anim_frames <= 0) ui.anim_frames = static_cast<int>(std::ceil(length * v.timeline.fps));
    ImGui::InputInt("frames", &ui.anim_frames);
    ui.anim_frames = std::clamp(ui.anim_frames, 1, 100000);
    ImGui::InputText("frame files", ui.anim_pattern, sizeof ui.anim_pattern);
    ImGui::InputText("video (ffmpeg)", ui.anim_video, sizeof ui.anim_video);
    if (v.jobs.image.running()) {
        ImGui::ProgressBar(static_cast<float>(v.jobs.image.progress()), ImVec2(-80, 0));
        ImGui::SameLine();
        if (ImGui::Button("Cancel##animation")) {
            v.jobs.image.cancel();
            v.messages.note("render cancelled; the frames written so far stay");
        }
    } else if (ImGui::Button("Render animation")) {
        render_animation(v, ui.anim_pattern, ui.anim_frames, ui.image_size[0], ui.image_size[1],
                         ui.image_spp, ui.anim_video);
    }
    ImGui::TextDisabled("at the image size and samples of \"save\" below");
}

void control_panel(ViewerState& v, PanelState& ui, const PaneLayout& layout,
                   const std::vector<std::string>& preview_defines, double frame_s) {
    // Resizable in width (the panes follow next frame) and collapsible.
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(layout.panel_w > 0 ? layout.panel_w : 380, vp->Size.y),
                             ImGuiCond_Once);
    ImGui::SetNextWindowSizeConstraints(ImVec2(220, vp->Size.y),
                                        ImVec2(std::max(220.0f, 0.7f * vp->Size.x), vp->Size.y));
    const bool open = ImGui::Begin("rayview", nullptr, ImGuiWindowFlags_NoMove);
    v.settings.panel_w = ImGui::IsWindowCollapsed() ? 0 : ImGui::GetWindowWidth();
    if (!open) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 10);  // room for the labels
    file_panel(v, ui);                                 // opening a file marks its own edit
    if (v.session.loaded) {
        // Each edits a copy and puts it back: the viewer sees what changed.
        camera_panel(v, layout);
        inspect_panel(v);
        compare_panel(v, ui.compare);
        settings_panel(v);
        lights_panel(v);
        materials_panel(v, ui);
        status_panel(v, preview_defines, frame_s);
        animation_panel(v, ui);
        save_panel(v, ui);
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

}  // namespace rt::view
