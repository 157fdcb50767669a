#include "ui/inspect_panel.h"

#include <imgui.h>

#include <string>
#include <string_view>
#include <vector>

#include "state/overlay.h"

namespace rt::view {

namespace {

// The tree's text as lines with their depth (two spaces a level).
struct TextLine {
    std::string_view text;
    int depth = 0;
};

std::vector<TextLine> split_lines(std::string_view text) {
    std::vector<TextLine> out;
    while (!text.empty()) {
        const size_t end = text.find('\n');
        std::string_view l = text.substr(0, end);
        size_t spaces = l.find_first_not_of(' ');
        if (spaces == std::string_view::npos) spaces = l.size();
        out.push_back({l.substr(spaces), static_cast<int>(spaces / 2)});
        if (end == std::string_view::npos) break;
        text.remove_prefix(end + 1);
    }
    return out;
}

bool is_ray_line(std::string_view t) {
    for (std::string_view kind : {"camera ray,", "reflected ray,", "refracted ray,"})
        if (t.substr(0, kind.size()) == kind) return true;
    return false;
}

ImVec4 colour_of(const float* c) { return ImVec4(c[0], c[1], c[2], 1.0f); }

// Draws lines [i, end of its subtree) as tree nodes; returns the index after the subtree.
// `ray` counts the ray lines met so far: the k-th is PixelTree::rays[k] (both in the order the
// shading traced them).
size_t draw_nodes(ViewerState& v, const std::vector<TextLine>& lines, size_t i, int* ray) {
    const InspectView& in = v.ui.inspect;
    const int depth = lines[i].depth;
    while (i < lines.size() && lines[i].depth == depth) {
        const TextLine& l = lines[i];
        const bool parent = i + 1 < lines.size() && lines[i + 1].depth > depth;
        const bool ray_line = is_ray_line(l.text);
        const int ray_index = ray_line ? (*ray)++ : -1;
        ImGui::PushID(static_cast<int>(i));
        ImGuiTreeNodeFlags flags = ImGuiTreeNodeFlags_SpanAvailWidth;
        if (!parent) flags |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
        // Rays and their bounces open; a light's terms and the material's values closed.
        if (ray_line || depth == 0 || l.text.substr(0, 12) == "reflected = " ||
            l.text.substr(0, 12) == "refracted = ")
            flags |= ImGuiTreeNodeFlags_DefaultOpen;
        if (ray_line) {
            const InspectRay& r = in.tree->rays[static_cast<size_t>(ray_index)];
            ImGui::PushStyleColor(
                ImGuiCol_Text,
                colour_of(r.kind == InspectRay::Kind::Camera      ? InspectColours::camera
                          : r.kind == InspectRay::Kind::Reflected ? InspectColours::reflected
                                                                  : InspectColours::refracted));
        }
        // The node without a label, then its text wrapped at the pane's edge (a long line such as
        // a hit's normals goes on below, at the text's own indentation, instead of being cut).
        const bool open = ImGui::TreeNodeEx("node", flags, "%s", "");
        const bool hovered = ImGui::IsItemHovered();
        const bool right_clicked = ImGui::IsItemClicked(ImGuiMouseButton_Right);
        ImGui::SameLine();
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextUnformatted(l.text.data(), l.text.data() + l.text.size());
        ImGui::PopTextWrapPos();
        if (ray_line) {
            ImGui::PopStyleColor();
            if (hovered) v.ui.inspect.hover(ray_index);
            const InspectRay& r = in.tree->rays[static_cast<size_t>(ray_index)];
            if (right_clicked && r.hit)
                v.ui.select(selection_of(*v.session.loaded, r.prim.instance, r.prim.prim, r.point));
            if (hovered && r.hit)
                ImGui::SetTooltip("right click: select what it hits (F frames it)");
        }
        ++i;
        if (parent) {
            if (open) {
                i = draw_nodes(v, lines, i, ray);
                ImGui::TreePop();
            } else {  // skip the subtree, counting its rays
                while (i < lines.size() && lines[i].depth > depth)
                    *ray += is_ray_line(lines[i++].text);
            }
        }
        ImGui::PopID();
    }
    return i;
}

// The tree itself: which pixel and sample, the buttons, the collapsible lines.
void tree_list(ViewerState& v) {
    const InspectView& in = v.ui.inspect;
    const PixelTree& t = *in.tree;
    ImGui::TextWrapped("pixel %d,%d: the trace shows (%.4g %.4g %.4g) at %d spp", t.x, t.y,
                       in.traced.x, in.traced.y, in.traced.z, in.traced_spp);
    ImGui::TextWrapped("its sample %u: (%.4g %.4g %.4g)", t.sample, t.color.x, t.color.y,
                       t.color.z);
    if (ImGui::SmallButton("Clear (C)")) {
        v.ui.inspect.clear();
        return;
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("Copy as text")) ImGui::SetClipboardText(in.text.c_str());
    const std::vector<TextLine> lines = split_lines(in.text);
    // The first line says which sample; the tree starts at the camera ray.
    size_t first = 0;
    while (first < lines.size() && !is_ray_line(lines[first].text)) ++first;
    // No horizontal scrolling: every line wraps at the pane's edge.
    if (ImGui::BeginChild("tree", ImVec2(0, ImGui::GetTextLineHeightWithSpacing() * 24), true) &&
        first < lines.size()) {
        int ray = 0;
        const size_t end = draw_nodes(v, lines, first, &ray);
        ImGui::PushTextWrapPos(0.0f);
        for (size_t i = end; i < lines.size(); ++i)  // the sample's colour, the pixel's value
            ImGui::TextUnformatted(lines[i].text.data(),
                                   lines[i].text.data() + lines[i].text.size());
        ImGui::PopTextWrapPos();
    }
    ImGui::EndChild();
}

}  // namespace

void inspect_panel(ViewerState& v) {
    const InspectView& in = v.ui.inspect;  // changed through its verbs
    v.ui.inspect.hover(-1);                // set again while a ray's line is hovered
    if (v.ui.inspect.take_new_tree()) ImGui::SetNextItemOpen(true);  // a new tree: show it
    if (ImGui::CollapsingHeader("Inspect a pixel")) {
        bool mode = in.mode;
        if (ImGui::Checkbox("Inspect mode (I): a click explains a pixel", &mode))
            v.ui.inspect.set_mode(mode);
        ImGui::TextDisabled("Lines:");
        const std::pair<const char*, const float*> legend[] = {
            {"camera", InspectColours::camera},          {"reflected", InspectColours::reflected},
            {"refracted", InspectColours::refracted},    {"to a light", InspectColours::shadow_lit},
            {"blocked", InspectColours::shadow_blocked}, {"normal", InspectColours::normal}};
        for (const auto& [name, c] : legend) {
            ImGui::SameLine();
            ImGui::TextColored(colour_of(c), "%s", name);
        }
        if (in.tree)
            tree_list(v);
        else
            ImGui::TextWrapped(
                "Turn the mode on and click a pixel in either pane (script: inspect X Y).");
    }
}

}  // namespace rt::view
