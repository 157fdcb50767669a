#include "ui/compare_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "state/viewer_compare.h"

namespace rt::view {

void compare_panel(ViewerState& v, ComparePanelState& ui) {
    const CompareView& c = v.ui.compare;  // changed through its verbs
    const ImGuiTreeNodeFlags open = c.active() ? ImGuiTreeNodeFlags_DefaultOpen : 0;
    if (!ImGui::CollapsingHeader("Compare with image", open)) return;
    if (c.active() && ui.path[0] == '\0')  // --compare, a drop or a script: show its path
        std::snprintf(ui.path, sizeof ui.path, "%s", c.path.c_str());
    const bool enter =
        ImGui::InputText("image", ui.path, sizeof ui.path, ImGuiInputTextFlags_EnterReturnsTrue);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "A render of this scene (PNG, BMP, PPM, JPEG, PFM, EXR), e.g. a student's;\n"
            "or drop the file onto the window");
    if (ImGui::Button("Compare") || enter) compare_in_background(v, ui.path);
    if (!c.active()) {
        ImGui::TextWrapped(
            "The trace renders the reference at the image's size from the scene's camera, as "
            "raytrace does, and the pane right of it shows where and how much the image "
            "differs.");
        return;
    }
    ImGui::SameLine();
    if (ImGui::Button("Stop comparing")) {
        stop_compare(v);
        return;
    }
    int show = static_cast<int>(c.show);
    ImGui::RadioButton("theirs", &show, 0);
    ImGui::SameLine();
    ImGui::RadioButton("ours", &show, 1);
    ImGui::SameLine();
    ImGui::RadioButton("difference", &show, 2);
    ImGui::SameLine();
    ImGui::RadioButton("threshold", &show, 3);
    v.ui.compare.set_show(static_cast<CompareShow>(show));
    ImGui::TextDisabled("B flips theirs and ours, V cycles the views");
    float tolerance = static_cast<float>(c.settings.tolerance);
    if (ImGui::SliderFloat("tolerance", &tolerance, 0, 64, "%.0f / 255"))
        v.ui.compare.set_tolerance(tolerance);
    bool neighbourhood = c.settings.neighbourhood;
    if (ImGui::Checkbox("3x3 neighbourhood", &neighbourhood))
        v.ui.compare.set_neighbourhood(neighbourhood);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Each pixel's difference is the smallest over the reference's 3x3 neighbourhood:\n"
            "an edge shifted by a pixel is not an error (what graders allow)");
    int spp = c.spp;
    if (ImGui::InputInt("reference spp", &spp)) set_compare_spp(v, spp);  // rendered again
    if (c.result) {
        const ImageComparison& r = *c.result;
        ImGui::Text("mean |difference|  %.2f  (%.2f %.2f %.2f)", r.mean(), r.mean_abs.x,
                    r.mean_abs.y, r.mean_abs.z);
        ImGui::Text("off by > %.0f/255   %.2f%% of the pixels", c.settings.tolerance,
                    100.0 * r.share_off);
        ImGui::Text("largest            %.0f at %d,%d", r.max_diff, r.max_x, r.max_y);
        if (!c.current) ImGui::TextDisabled("(rendering the reference again)");
    } else {
        ImGui::TextDisabled("rendering the reference...");
    }
    if (c.probe_x >= 0) {
        ImGui::TextWrapped("%s", compare_probe_text(c, c.probe_x, c.probe_y).c_str());
        ImGui::TextDisabled("its ray tree: the Inspect section");
    } else {
        ImGui::TextDisabled("a click in the pane: both values and the pixel's ray tree");
    }
}

}  // namespace rt::view
