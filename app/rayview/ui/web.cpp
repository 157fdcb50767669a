#include "ui/web.h"

#include <GLFW/glfw3.h>
#include <emscripten.h>
#include <emscripten/html5.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rt/render/render.h"
#include "state/viewer.h"

namespace rt::view {
namespace {

ViewerState* g_viewer = nullptr;

// The page's functions (app/web/page.js) on the Module object.
EM_JS(void, page_download, (const char* path), { Module.rvDownload(UTF8ToString(path)); });
EM_JS(void, page_finished, (int code), { Module.rvFinished(code); });
EM_JS(double, page_pixel_ratio, (), { return window.devicePixelRatio || 1; });

// A JSON string literal.
std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

}  // namespace

void web_start(ViewerState* viewer) {
    g_viewer = viewer;
    viewer->hooks.on_saved = [](const std::string& path) { page_download(path.c_str()); };
    const auto go_to_folder = [](const std::string& path) {
        const std::filesystem::path dir = std::filesystem::path(path).parent_path();
        std::error_code ec;  // a folder that is gone: relative saves stay where they were
        if (!dir.empty()) std::filesystem::current_path(dir, ec);
    };
    // After the desktop's hook (main.cpp: the scene opened is said on stdout).
    viewer->hooks.on_opened = [said = viewer->hooks.on_opened,
                               go_to_folder](const std::string& path) {
        if (said) said(path);
        go_to_folder(path);
    };
    if (viewer->session.loaded)
        go_to_folder(viewer->session.loaded->path);  // opened before this call
}

void web_fit_canvas(GLFWwindow* window) {
    double css_w = 0, css_h = 0;
    if (emscripten_get_element_css_size("#canvas", &css_w, &css_h) != EMSCRIPTEN_RESULT_SUCCESS)
        return;
    const double ratio = web_pixel_ratio();
    const int w = static_cast<int>(std::lround(css_w * ratio));
    const int h = static_cast<int>(std::lround(css_h * ratio));
    int cur_w = 0, cur_h = 0;
    glfwGetWindowSize(window, &cur_w, &cur_h);
    if (w > 0 && h > 0 && (w != cur_w || h != cur_h)) glfwSetWindowSize(window, w, h);
}

void web_finished(int exit_code) { page_finished(exit_code); }

double web_pixel_ratio() { return page_pixel_ratio(); }

}  // namespace rt::view

// Called by the page (Module.ccall).
extern "C" {

/// Opens a file of the page's file system (picked or dropped files, a sample), as a file
/// dropped onto the desktop window: at the next frame, in the background.
EMSCRIPTEN_KEEPALIVE void rv_open(const char* path) {
    if (rt::view::g_viewer) rt::view::g_viewer->ui.drop(path);
}

/// The viewer's state as JSON: the open scene, the message line, the comparison's figures,
/// the trace's progress.
EMSCRIPTEN_KEEPALIVE const char* rv_status() {
    using rt::view::quoted;
    static std::string json;
    const rt::view::ViewerState* v = rt::view::g_viewer;
    if (!v) return "{}";
    const rt::view::Tracer::Status st = v->trace.tracer.status();
    char numbers[256];
    std::snprintf(
        numbers, sizeof numbers,
        "\"spp\":%d,\"seconds\":%.3f,\"rays_per_second\":%.0f,\"threads\":%d,"
        "\"threaded\":%s,\"loading\":%s",
        st.spp, st.seconds, st.rays_per_second,
        v->trace.tracer.threaded() ? rt::resolve_thread_count(v->settings.render.threads) : 1,
        v->trace.tracer.threaded() ? "true" : "false", v->jobs.loader.busy() ? "true" : "false");
    json = "{\"scene\":" + quoted(v->session.loaded ? v->session.loaded->path : "") +
           ",\"message\":" + quoted(v->messages.text) +
           ",\"error\":" + (v->messages.is_error ? "true" : "false") + ",\"compare\":" +
           quoted(v->ui.compare.active() ? rt::view::compare_status(v->ui.compare) : "") + "," +
           numbers + "}";
    return json.c_str();
}

}  // extern "C"
