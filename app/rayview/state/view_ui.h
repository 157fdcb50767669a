// The viewer's own state of the window, not the scene's: what is selected, the pixel inspected,
// the image compared, the bookmarked views, the help overlay, the files dropped, a count of the
// changes the panes show, and the web page's hooks. No GL.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "state/camera_controller.h"
#include "state/compare_view.h"
#include "state/inspect_view.h"
#include "state/selection.h"

namespace rt::view {

struct ViewUi {
    Selection selection;
    InspectView inspect;  // the inspect mode and the pixel's ray tree
    CompareView compare;  // the image compared with the trace (the comparison pane)
    /// The light last edited in the panel, framed or dragged (-1: none): the preview draws its
    /// direction (a spot's cone, a directional light's arrows), the others' small markers only.
    int selected_light = -1;
    std::vector<OrbitCamera> bookmarks;  // views the user kept
    bool show_help = false;              // the shortcuts overlay
    std::vector<std::string> dropped;    // files dropped onto the window, picked up by poll_files
    /// Counts the changes of what the panes show (an edit waiting, a pick, a ray tree, undo):
    /// a view draws again when it differs from the count it drew.
    int changes = 0;

    /// What a click or the ray tree's menu picked: highlighted in the panes.
    void select(Selection s) {
        selection = std::move(s);
        ++changes;
    }
    void clear_selection() {
        selection = {};
        ++changes;  // the highlight goes
    }
    void select_light(int i) { selected_light = i; }
    /// A file dropped onto the window (or handed over by the page): poll_files() opens it.
    void drop(std::string path) { dropped.push_back(std::move(path)); }
    void set_help(bool on) { show_help = on; }
    void toggle_help() { show_help = !show_help; }
    void add_bookmark(const OrbitCamera& view) { bookmarks.push_back(view); }
    void remove_bookmark(size_t i) {
        if (i < bookmarks.size()) bookmarks.erase(bookmarks.begin() + static_cast<long>(i));
    }
};

/// What the web page does when the viewer saves or opens a file; nothing on the desktop.
struct PageHooks {
    /// Called with each file the viewer saves (a scene, a trace, a rendered image); the web
    /// page downloads it.
    std::function<void(const std::string& path)> on_saved;
    /// Called with each scene file that opens (at start, an open, a drop, a reload); the web
    /// page makes its folder the working directory.
    std::function<void(const std::string& path)> on_opened;
};

}  // namespace rt::view
