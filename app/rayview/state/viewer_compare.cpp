#include "state/viewer_compare.h"

#include <algorithm>
#include <filesystem>

#include "rt/util/threads.h"

namespace rt::view {

namespace {

void start_compare(ViewerState& v, const std::string& path, Image theirs) {
    CompareView& c = v.ui.compare;
    c.path = path;
    c.theirs = std::move(theirs);
    c.settings.linear = holds_linear(image_format_from_path(path));
    c.reference = Image();
    c.current = false;
    c.probe_x = c.probe_y = -1;
    c.recompare();
    v.settings.image_w = c.theirs.width;  // both panes keep its aspect
    v.settings.image_h = c.theirs.height;
    if (v.session.loaded)
        v.edits.camera.set_from(v.session.loaded->file_camera,
                                v.session.loaded->scene.world_bounds);
    v.trace.set_size(c.theirs.width, c.theirs.height);
    v.mark_edited();
    v.messages.note("comparing with " + std::filesystem::path(path).filename().string() + " (" +
                    std::to_string(c.theirs.width) + "x" + std::to_string(c.theirs.height) +
                    "): the trace renders the reference at its size from the file's camera, " +
                    std::to_string(c.spp) + " spp as raytrace renders it");
}

}  // namespace

bool compare_with(ViewerState& v, const std::string& path) {
    Image theirs;
    try {
        theirs = read_compare_image(path);
    } catch (const std::exception& e) {
        v.messages.fail("cannot compare with " + path + ": " + e.what());
        return false;  // the previous comparison, if any, stays
    }
    start_compare(v, path, std::move(theirs));
    return true;
}

void compare_in_background(ViewerState& v, const std::string& path) {
    v.jobs.compare.start(path);
    v.messages.note("reading " + path + " to compare with ...");
    if (!have_threads()) take_compare_image(v);  // read at once: taken now; else in poll_files()
}

void take_compare_image(ViewerState& v) {
    std::string path, error;
    Image theirs;
    if (!v.jobs.compare.take(&path, &theirs, &error)) return;
    if (!error.empty())
        v.messages.fail("cannot compare with " + path + ": " + error);  // the previous one stays
    else
        start_compare(v, path, std::move(theirs));
}

void stop_compare(ViewerState& v) {
    if (!v.ui.compare.active()) return;
    const int version = v.ui.compare.version;  // counts on: the pane uploads the next one
    v.ui.compare = CompareView();
    v.ui.compare.version = version + 1;
    v.mark_edited();  // the progressive trace again, of the pane's size
}

bool take_trace(ViewerState& v) {
    if (!v.trace.take_image()) return false;
    CompareView& c = v.ui.compare;
    const Image& t = v.trace.last_trace;
    if (c.active() && !v.edit_pending() && t.width == c.theirs.width &&
        t.height == c.theirs.height && v.trace.last_spp >= c.spp) {
        c.reference = t;
        c.current = true;
        c.recompare();
    }
    return true;
}

void probe_compare(ViewerState& v, int x, int y) {
    CompareView& c = v.ui.compare;
    c.probe_x = x;
    c.probe_y = y;
    v.inspect((x + 0.5) / c.theirs.width, (y + 0.5) / c.theirs.height);
}

void set_compare_spp(ViewerState& v, int spp) {
    v.ui.compare.spp = std::clamp(spp, 1, 1 << 16);
    v.mark_edited();  // rendered again
}

}  // namespace rt::view
