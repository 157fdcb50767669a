// rayview: the scene's OpenGL preview beside its progressive ray trace, with camera, light and
// render controls. Shaped like Dear ImGui's GLFW + OpenGL 3 example (1.86): error callback
// before init, a 3.3 core context, a frame loop of calls, shutdown in reverse order. Only this
// thread touches OpenGL; the trace runs on the Tracer's threads and every edit stops it first
// (viewer.h).
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#ifdef __EMSCRIPTEN__
#include <emscripten.h>

#include "ui/web.h"
#else
#include <dlfcn.h>
#include <link.h>
#endif

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "cli.h"
#include "data_dir.h"
#include "rt/util/sanitizers.h"
#include "state/config.h"
#include "state/headless.h"
#include "state/key_queue.h"
#include "state/viewer.h"
#include "state/viewer_compare.h"
#include "ui/input.h"
#include "ui/panels.h"
#include "ui/panes.h"
#include "ui/script.h"
#include "ui/timeline_bar.h"

namespace {

// Under AddressSanitizer: the GL driver's libraries stay mapped until exit (RTLD_NODELETE), so
// LeakSanitizer can name the library of the driver's own small leak at exit and the chaos
// test can suppress it by that name (never our code). Without ASan: nothing.
void keep_gl_driver_loaded() {
#if defined(RT_ASAN) && !defined(__EMSCRIPTEN__)
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void*) {
            const std::string name = info->dlpi_name ? info->dlpi_name : "";
            for (const char* lib : {"mesa", "dri", "gallium", "LLVM", "glapi"})
                if (name.find(lib) != std::string::npos)
                    dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            return 0;
        },
        nullptr);
#endif
}

// Ctrl+C or a kill from outside closes the window as its close button does: the trace stops
// and the settings are kept (nothing is lost to a signal).
volatile std::sig_atomic_t g_quit = 0;
void on_signal(int) { g_quit = 1; }

void glfw_error(int code, const char* message) {
    std::fprintf(stderr, "rayview: GLFW error %d: %s\n", code, message);
}

// Files dropped onto the window go to the viewer, which opens them at the next frame.
void on_drop(GLFWwindow* window, int count, const char** paths) {
    auto* viewer = static_cast<rt::view::ViewerState*>(glfwGetWindowUserPointer(window));
    for (int i = 0; i < count; ++i) viewer->ui.drop(paths[i]);
}

// A 3.3 core context (#version 330 core) with vsync; nullptr (and glfwTerminate) without a
// display or a window.
GLFWwindow* open_window(int width, int height) {
    if (!glfwInit()) {
        std::fprintf(stderr, "rayview: no display available; rendering headless instead\n");
        return nullptr;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(width, height, "rayview", nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        std::fprintf(stderr, "rayview: cannot open a window; rendering headless instead\n");
        return nullptr;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    keep_gl_driver_loaded();
    return window;
}

// The panes and their GL objects; nullptr after printing why the shaders did not compile.
std::unique_ptr<rt::view::Panes> make_panes(const std::string& shader_dir) {
    try {
        return std::make_unique<rt::view::Panes>(shader_dir);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rayview: %s\n", e.what());
        return nullptr;
    }
}

// Every key press into the frame's queue (key_queue.h). Installed before ImGui's back end,
// which calls it after its own.
void on_key(GLFWwindow*, int key, int, int action, int mods) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        rt::view::key_queue().press(key, (mods & GLFW_MOD_CONTROL) != 0,
                                    (mods & GLFW_MOD_SHIFT) != 0, action == GLFW_REPEAT);
}

// Dear ImGui: context, style, and the GLFW and OpenGL 3 back ends.
ImGuiIO& init_imgui(GLFWwindow* window) {
    glfwSetKeyCallback(window, on_key);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init(rt::view::kGlslEs ? "#version 300 es" : "#version 330 core");
    return io;
}

// The frame's ImGui draw data over a cleared window.
void render_frame(int fb_w, int fb_h) {
    ImGui::Render();
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

// The shaders and the sample scenes, beside the executable (installed or in the build tree);
// "" and *error when they are not there.
std::string find_data(std::string* error) {
    try {
        return rtapp::find_data_dir("shaders/preview.vert").string();
    } catch (const std::exception& e) {
        *error = e.what();
        return "";
    }
}

// "showpiece.ray - rayview", or "rayview" with no scene open.
std::string window_title(const rt::view::ViewerState& viewer) {
    if (!viewer.session.loaded) return "rayview";
    return std::filesystem::path(viewer.session.loaded->path).filename().string() + " - rayview";
}

// In reverse order of initialisation.
void shutdown(GLFWwindow* window) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
}

#ifdef __EMSCRIPTEN__
constexpr bool kInPage = true;  // the web page (app/web): the browser paces the frames
#else
constexpr bool kInPage = false;
#endif

// The monitor's content scale (the page's device pixel ratio).
float content_scale(GLFWwindow* window) {
#ifdef __EMSCRIPTEN__
    (void)window;
    return static_cast<float>(rt::view::web_pixel_ratio());
#else
    float x = 1, y = 1;
    glfwGetWindowContentScale(window, &x, &y);
    return x;
#endif
}

// What the frames share: the window, the viewer and its panes, and the interface's state.
struct Session {
    GLFWwindow* window;
    ImGuiIO& io;
    rt::view::ViewerState& viewer;
    rt::view::Panes& panes;
    rt::view::PanelState ui;
    rt::view::InputState input;
    rt::view::ScriptRun script;
    rt::view::FrameStats stats;
    std::string title;
    int exit_code = 0;
};

// One frame: events, the panel and the panes, input, the trace restarted when due, drawing.
// False once the window is to close.
bool frame(Session& s) {
    using namespace rt::view;
    ViewerState& viewer = s.viewer;
    if (glfwWindowShouldClose(s.window)) return false;
    // The title names the open scene, as a desktop program's does.
    if (const std::string t = window_title(viewer); t != s.title)
        glfwSetWindowTitle(s.window, (s.title = t).c_str());
    // Events; dropped files open, the open file reloads when it changed on disk. With nothing
    // to redraw at once the loop waits for an event or 1/30 s (new trace images), so it leaves
    // the cores to the trace (in the page, the browser paces the frames).
    const bool busy =
        viewer.edit_pending() || s.panes.preview_stale(viewer) || viewer.timeline.playing;
    rt::view::key_queue().next_frame();  // the last frame read its presses
    if (busy || kInPage)
        glfwPollEvents();
    else
        glfwWaitEventsTimeout(1.0 / 30);
    const double frame_s = s.stats.tick();
    viewer.poll_files();
    // Without threads the trace runs here, between frames, for part of one (the page's
    // single-thread build); with threads this does nothing.
    viewer.trace.tracer.pump(1.0 / 40);
    // Start the Dear ImGui frame; the control panel, the panes, input, restart, draw. Fonts
    // follow the monitor's content scale and the user's UI scale.
    s.io.FontGlobalScale = viewer.settings.ui_scale * std::max(1.0f, content_scale(s.window));
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(s.window, &fb_w, &fb_h);
    const ViewSettings& vs = viewer.settings;
    const PaneLayout layout = pane_layout(vs.layout, fb_w, fb_h, vs.show_panel ? vs.panel_w : 0,
                                          vs.aspect(), viewer.ui.compare.active());
    if (vs.show_panel) control_panel(viewer, s.ui, layout, s.panes.preview_defines(), frame_s);
    if (vs.show_panel && viewer.session.loaded) status_bar(viewer, layout);
    if (vs.show_panel && viewer.session.loaded) timeline_bar(viewer, layout);
    help_overlay(viewer.ui);
    if (viewer.session.loaded) {
        const PaneHover hover = s.panes.show(viewer, layout, frame_s);
        handle_input(viewer, s.input, s.io, layout, hover, frame_s);
        timeline_keys(viewer);
        viewer.step_animation(frame_s);
        // A drag or a widget in use is one undo step when it ends.
        viewer.track_history(ImGui::IsAnyItemActive() || ImGui::IsAnyMouseDown());
        if (viewer.restart_if_due()) s.script.restarted();
        s.panes.draw(viewer);
    }
    // Rendering
    render_frame(fb_w, fb_h);
    // Scripted input for this frame (after drawing, so screenshots show the frame).
    bool done =
        s.script.end_frame(viewer, fb_w, fb_h, !s.panes.preview_stale(viewer), &s.exit_code) ||
        g_quit;
    glfwSwapBuffers(s.window);
    return !done;
}

#ifdef __EMSCRIPTEN__
void web_frame(void* arg) {
    Session& s = *static_cast<Session*>(arg);
    rt::view::web_fit_canvas(s.window);
    if (frame(s)) return;
    // A --frames run (or a script) is over: its statistics, then the page stays as it is.
    if (s.stats.count() > 1) s.stats.print(s.viewer);
    rt::view::web_finished(s.exit_code);
    emscripten_cancel_main_loop();
}
#endif

// The command line into *opt. Returns -1 to run, else the exit code of a run that ends here:
// --help or a bad option, a processor without the build's instructions, no scene at all.
int read_options(int argc, char** argv, const std::string& data_dir, const std::string& data_error,
                 rt::view::RunOptions* opt) {
    const int rc = rt::view::parse_run_options(
        argc, argv, data_dir.empty() ? "" : data_dir + "/scenes/showpiece.ray", opt);
    if (rc >= 0) return rc;
    if (!rtapp::isa_usable("rayview")) return 2;
    if (opt->scene.empty()) {  // no scene named, and no default one
        std::fprintf(stderr, "rayview: no scene given, and the default one is missing: %s\n",
                     data_error.c_str());
        return 1;
    }
    return -1;
}

// What the last run kept: the window's size, the UI scale, the recent files. A file that cannot
// be read is a warning, and the defaults.
rt::view::UserConfig read_user_config(const std::string& config_file) {
    std::string problem;
    rt::view::UserConfig config = rt::view::read_config(config_file, &problem);
    if (!problem.empty())
        std::fprintf(stderr, "rayview: warning: the settings were not read: %s\n", problem.c_str());
    return config;
}

// A scripted run at a --size of its own (tests, screenshots) leaves the window size the user's
// interactive runs keep.
bool keeps_saved_size(const rt::view::RunOptions& opt) {
    return opt.window_w != 0 && (opt.frames > 0 || !opt.script.empty() || !opt.screenshot.empty());
}

// Ctrl+C and a kill close the window (on_signal); GLFW's errors are printed.
void install_handlers() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    glfwSetErrorCallback(glfw_error);
}

// No window: the image rendered as raytrace would, 16 samples per pixel unless --spp says (1
// comparing).
int render_without_window(const rt::view::RunOptions& opt) {
    const int spp = opt.spp_given ? opt.render.spp : opt.compare.empty() ? 16 : 1;
    return rt::view::render_headless(opt.scene, opt.render.missing_textures, opt.render, spp,
                                     opt.render.dialect, opt.compare);
}

// The viewer's first settings: the command line's over the last run's UI scale; the recent
// files; the --compare image (an error fails a scripted run). Every scene that opens is said on
// stdout, the one opened at start too.
void start_viewer(rt::view::ViewerState& viewer, const rt::view::RunOptions& opt,
                  const rt::view::UserConfig& config) {
    viewer.hooks.on_opened = [](const std::string& path) {
        std::printf("rayview: opened %s\n", path.c_str());
    };
    if (viewer.session.loaded) viewer.hooks.on_opened(viewer.session.loaded->path);
    rt::view::ViewSettings initial = viewer.settings;
    rt::view::apply_run_options(opt, &initial);
    initial.ui_scale = config.ui_scale;
    viewer.start_with(initial);
    viewer.session.remember_recent(config.recent);
    if (!opt.compare.empty() && viewer.session.loaded) {
        rt::view::set_compare_spp(viewer, opt.spp_given ? opt.render.spp : 1);
        if (rt::view::compare_with(viewer, opt.compare))
            std::printf("rayview: %s\n", viewer.messages.text.c_str());
    }
}

// The window's frames until it closes (or the script ends); the run's exit code, 1 when the
// shaders did not compile.
int run_frames(GLFWwindow* window, ImGuiIO& io, rt::view::ViewerState& viewer,
               const rt::view::RunOptions& opt, const std::string& data_dir) {
    using namespace rt::view;
    glfwSetWindowUserPointer(window, &viewer);
    glfwSetDropCallback(window, on_drop);
    const std::unique_ptr<Panes> panes = make_panes(data_dir + "/shaders");
    if (!panes) return 1;
    if (!viewer.session.loaded) std::fprintf(stderr, "%s\n", viewer.messages.text.c_str());
    Session session{window,         io, viewer, *panes, PanelState(opt.scene), {},
                    ScriptRun(opt), {}, {},     0};
    session.ui.samples_dir = data_dir + "/scenes";
#ifdef __EMSCRIPTEN__
    // The browser runs the frames: this does not return, and the session lives on (in this
    // function's frame, with the viewer in main's).
    web_start(&viewer);
    emscripten_set_main_loop_arg(web_frame, &session, 0, true);
#endif
    while (frame(session)) {
    }
    const int exit_code = session.exit_code;
    session.script.print_summary(session.stats, viewer);
    return exit_code;
}

// What the next run starts from: the window's size (unless this run's script chose it), the UI
// scale, the recent files. Not written: a warning.
void save_user_config(const std::string& config_file, rt::view::UserConfig config,
                      GLFWwindow* window, const rt::view::ViewerState& viewer,
                      bool keep_saved_size) {
    if (!keep_saved_size) glfwGetWindowSize(window, &config.window_w, &config.window_h);
    config.ui_scale = viewer.settings.ui_scale;
    config.recent = viewer.session.recent;
    if (!rt::view::write_config(config_file, config))
        std::fprintf(stderr, "rayview: cannot write the settings to '%s'\n", config_file.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    using namespace rt::view;
#ifdef __EMSCRIPTEN__
    setenv("RAYTRACER_DATA_DIR", kWebDataDir, 0);  // the page's files (app/web)
#endif
    std::string data_error;
    const std::string data_dir = find_data(&data_error);
    RunOptions opt;
    if (const int rc = read_options(argc, argv, data_dir, data_error, &opt); rc >= 0) return rc;
    const std::string config_file = config_path();
    const UserConfig config = read_user_config(config_file);
    const bool keep_saved_size = keeps_saved_size(opt);
    if (opt.window_w == 0) opt.window_w = config.window_w, opt.window_h = config.window_h;

    install_handlers();
    GLFWwindow* window = open_window(opt.window_w, opt.window_h);
    if (!window) return render_without_window(opt);
    if (data_dir.empty()) {
        std::fprintf(stderr, "rayview: %s\n", data_error.c_str());
        glfwDestroyWindow(window);
        glfwTerminate();
        return 1;
    }
    ImGuiIO& io = init_imgui(window);
    int exit_code = 0;
    {  // the viewer and its GL objects die before the context; the trace stops with the viewer
        ViewerState viewer(opt.scene, !opt.screenshot.empty(), opt.render.missing_textures,
                           opt.render.dialect);
        start_viewer(viewer, opt, config);
        exit_code = run_frames(window, io, viewer, opt, data_dir);
        save_user_config(config_file, config, window, viewer, keep_saved_size);
    }
    shutdown(window);
    return exit_code;
}
