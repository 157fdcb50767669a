// The inspect mode: a click in either pane explains that pixel of the trace with its ray tree
// (rt/render/inspect.h, made by the renderer's own shading code), which the preview draws as 3D
// lines (overlay.h: inspect_lines) and the panel lists term by term. No GL.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rt/render/inspect.h"

namespace rt::view {

/// What the inspect mode shows.
struct InspectView {
    bool mode = false;              // a click inspects (else it picks)
    std::optional<PixelTree> tree;  // the pixel inspected last
    std::string text;               // its tree as text (inspect_text)
    Vec3 traced{0.0};               // the trace's pixel there when inspected (its mean so far)
    int traced_spp = 0;             // of that many samples
    int hovered = -1;               // the ray (index into tree->rays) the panel hovers; -1: none
    int version = 0;                // counts changes, so the preview knows when to draw again
    int panel_version = -1;         // the version the panel opened its section for
    void set_mode(bool on) { mode = on; }
    /// The ray the panel hovers (-1: none).
    void hover(int ray) { hovered = ray; }
    /// True once for each new tree: the panel opens its section to show it.
    bool take_new_tree() {
        if (!tree || panel_version == version) return false;
        panel_version = version;
        return true;
    }
    /// Drops the tree (its lines and the panel's list).
    void clear() {
        tree.reset();
        text.clear();
        hovered = -1;
        ++version;
    }
};

}  // namespace rt::view
