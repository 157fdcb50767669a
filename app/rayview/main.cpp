// rayview: the scene's OpenGL preview beside its progressive ray trace, with camera, light and
// render controls. Shaped like Dear ImGui's GLFW + OpenGL 3 example (1.86): error callback
// before init, a 3.3 core context, shutdown in reverse order. Only this thread touches OpenGL;
// the trace runs on the Tracer's threads and every edit stops it first.
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "camera_controller.h"
#include "preview.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/format/writer.h"
#include "rt/render/camera.h"
#include "rt/render/render.h"
#include "rt/util/file_io.h"
#include "tracer.h"

namespace {

using namespace rt;

// ---- a loaded scene, and the edits made to it --------------------------------------------------

struct LoadedScene {
    std::string path;
    SceneDesc desc;  // for saving the edited scene
    RenderScene scene;
    CameraDesc file_camera;     // Home returns here
    std::vector<Light> lights;  // every light, on or off
    std::vector<char> light_on;
};

std::unique_ptr<LoadedScene> load_scene(const std::string& path, std::string* error) {
    try {
        Diagnostics diag;
        auto s = std::make_unique<LoadedScene>();
        s->path = path;
        s->desc = parse_scene_file(path, diag);
        s->scene = compile_scene(s->desc);
        if (s->desc.camera) {
            s->file_camera = *s->desc.camera;
        } else {
            const CameraPose d = default_camera(s->scene.world_bounds, 640, 480);
            s->file_camera.position = d.position;
            s->file_camera.direction = d.direction;
            s->file_camera.up = d.up;
            s->file_camera.half_height_angle_rad = d.half_height_angle_rad;
        }
        s->lights = s->scene.lights;
        s->light_on.assign(s->lights.size(), 1);
        return s;
    } catch (const std::exception& e) {
        *error = e.what();
        return nullptr;
    }
}

// The description with the viewer's camera and lights, as a .ray file (written to a temporary
// name, then renamed).
void save_scene(const LoadedScene& s, const CameraDesc& camera, const std::string& path) {
    SceneDesc desc = s.desc;
    desc.camera = camera;
    desc.lights.clear();
    for (size_t i = 0; i < s.lights.size(); ++i) {
        if (!s.light_on[i]) continue;
        desc.lights.push_back(describe_light(s.lights[i]));
    }
    write_file_atomic(path, write_scene(desc));
}

// ---- GL helpers: a texture for the trace and a framebuffer for the preview -----------------

struct GlTexture {
    GLuint id = 0;
    int w = 0, h = 0;
    ~GlTexture() {
        if (id) glDeleteTextures(1, &id);
    }
    void upload(const Image& img) {
        if (!id) glGenTextures(1, &id);
        const std::vector<uint8_t> bytes = to_bytes(img);  // as raytrace writes
        glBindTexture(GL_TEXTURE_2D, id);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, img.width, img.height, 0, GL_RGB, GL_UNSIGNED_BYTE,
                     bytes.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        w = img.width;
        h = img.height;
    }
};

struct GlFramebuffer {
    GLuint fbo = 0, color = 0, depth = 0;
    int w = 0, h = 0;
    ~GlFramebuffer() { release(); }
    void release() {
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (color) glDeleteTextures(1, &color);
        if (depth) glDeleteRenderbuffers(1, &depth);
        fbo = color = depth = 0;
    }
    void resize(int width, int height) {
        if (width == w && height == h && fbo) return;
        release();
        w = width;
        h = height;
        glGenTextures(1, &color);
        glBindTexture(GL_TEXTURE_2D, color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glGenRenderbuffers(1, &depth);
        glBindRenderbuffer(GL_RENDERBUFFER, depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
};

// Files dropped onto the window, picked up by the main loop.
std::vector<std::string> g_dropped;
void on_drop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_dropped.emplace_back(paths[i]);
}

std::filesystem::file_time_type modified(const std::string& path) {
    std::error_code ec;
    return std::filesystem::last_write_time(path, ec);
}

// .ray files whose path starts with what is typed (the directory part lists its folder).
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

// The whole window as drawn, rows flipped to top-first.
void save_window(int width, int height, const std::string& path) {
    std::vector<unsigned char> px(static_cast<size_t>(width) * height * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
    Image shot(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = (static_cast<size_t>(height - 1 - y) * width + x) * 3;
            shot.set(x, y, Vec3(px[i], px[i + 1], px[i + 2]) / 255.0);
        }
    save_image(shot, path);
}

// --script: one command a line, "FRAME COMMAND ARGS...", run at that frame (scripted input for
// tests and measurements): orbit DYAW DPITCH | open PATH | light I colour R G B |
// shadows on|off | boxes GROUP_LEVELS BVH_LEVELS | layout both|preview|trace |
// resolution SCALE | screenshot PATH.
struct ScriptLine {
    int frame = 0;
    std::string command;
    std::vector<std::string> args;
};

std::vector<ScriptLine> read_script(const std::string& path) {
    std::ifstream f(path);
    if (!f) throw std::runtime_error("cannot open script '" + path + "'");
    std::vector<ScriptLine> lines;
    std::string line;
    while (std::getline(f, line)) {
        std::istringstream ss(line);
        ScriptLine l;
        if (!(ss >> l.frame >> l.command)) continue;
        for (std::string a; ss >> a;) l.args.push_back(a);
        lines.push_back(l);
    }
    return lines;
}

void glfw_error(int code, const char* message) {
    std::fprintf(stderr, "rayview: GLFW error %d: %s\n", code, message);
}

// Without a display: the same renderer, headless, to a PNG next to the working directory.
int render_headless(const std::string& path) {
    std::string error;
    const auto s = load_scene(path, &error);
    if (!s) {
        std::cerr << error << "\n";
        return 1;
    }
    const std::string out = std::filesystem::path(path).stem().string() + ".png";
    RenderSettings settings;
    RenderState state;
    render_samples(state, s->scene, make_render_plan(s->scene, settings), settings, 16);
    try {
        save_image(state.image(), out);
    } catch (const std::exception& e) {
        std::cerr << "rayview: error: " << e.what() << "\n";
        return 1;
    }
    std::printf("rayview: rendered %s headless (16 spp) to %s\n", path.c_str(), out.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string source_dir = RT_SOURCE_DIR;
    std::string path = source_dir + "/scenes/showpiece.ray";
    int frames = 0;  // > 0: run this many frames, save the window, exit
    std::string screenshot;
    std::string script_path;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::printf(
                "usage: rayview [--frames N --screenshot OUT.png] [SCENE.ray]\n"
                "Opens the scene (default: the showpiece) in a window: OpenGL preview "
                "beside the progressive ray trace.\n"
                "--frames N --screenshot F  run N frames, save the whole window to F, exit\n");
            return 0;
        } else if (a == "--frames" && i + 1 < argc) {
            frames = std::atoi(argv[++i]);
            if (frames <= 0) {
                std::fprintf(stderr, "rayview: --frames needs a positive count\n");
                return 2;
            }
        } else if (a == "--screenshot" && i + 1 < argc) {
            screenshot = argv[++i];
        } else if (a == "--script" && i + 1 < argc) {
            script_path = argv[++i];
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "rayview: unknown option '%s' (see rayview --help)\n", a.c_str());
            return 2;
        } else {
            path = a;
        }
    }
    if (!screenshot.empty() && frames == 0) frames = 60;
    std::vector<ScriptLine> script;
    if (!script_path.empty()) {
        try {
            script = read_script(script_path);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "rayview: %s\n", e.what());
            return 2;
        }
        for (const ScriptLine& l : script) frames = std::max(frames, l.frame + 2);
    }
    int frame_index = 0;

    glfwSetErrorCallback(glfw_error);
    if (!glfwInit()) {
        std::fprintf(stderr, "rayview: no display available; rendering headless instead\n");
        return render_headless(path);
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(1280, 720, "rayview", nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        std::fprintf(stderr, "rayview: cannot open a window; rendering headless instead\n");
        return render_headless(path);
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    glfwSetDropCallback(window, on_drop);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    int exit_code = 0;
    {
        std::string error;
        std::unique_ptr<LoadedScene> loaded = load_scene(path, &error);
        std::unique_ptr<view::Preview> preview;
        try {
            preview = std::make_unique<view::Preview>(source_dir + "/shaders");
        } catch (const std::exception& e) {
            std::fprintf(stderr, "rayview: %s\n", e.what());
            exit_code = 1;
        }
        if (exit_code == 0 && !loaded) {
            std::fprintf(stderr, "%s\n", error.c_str());  // keeps running with the message shown
        }
        view::Tracer tracer;
        GlTexture trace_tex;
        GlFramebuffer preview_fb;
        view::OrbitCamera orbit;
        RenderSettings settings;
        // The trace leaves one core to the interface thread, so frames stay smooth.
        settings.threads = std::max(1, resolve_thread_count(0) - 1);
        int target_spp = 256;
        std::vector<std::string> script_causes;  // script commands whose edits await a restart
        auto input_time = std::chrono::steady_clock::now();  // the first input since a restart
        auto served_input_time = input_time;                 // the input the running trace answers
        bool input_pending = false;
        double moving_div = 2.0;  // the preview's resolution divisor while the view moves
        std::vector<std::string> explained;         // the running trace's plan.reasons
        bool print_left_out = !screenshot.empty();  // once, for --frames runs (tests, logs)
        double frame_total_s = 0, frame_max_s = 0;
        int frame_count = 0;
        std::vector<double> frame_ms, first_pass_samples;  // for the summary of --frames runs
        std::chrono::steady_clock::time_point change_time{};
        double first_pass_ms = -1;  // camera/edit change -> first traced image on screen
        bool show_lights = true;
        int box_depth = 0;    // bounding boxes drawn over the preview: BVH levels, 0 = off
        int group_depth = 0;  // and the scene graph's group boxes, levels, 0 = off
        std::vector<view::LineVertex> group_lines;  // group_box_lines() of that scene and depth
        int group_lines_depth = -1;
        const LoadedScene* group_lines_for = nullptr;
        float resolution_scale = 0.5f;
        int trace_w = 0, trace_h = 0;
        bool dirty = true;
        char path_buf[1024];
        std::snprintf(path_buf, sizeof path_buf, "%s", path.c_str());
        char save_buf[1024] = "rayview.png";
        char scene_buf[1024] = "edited.ray";
        std::string message = loaded ? "" : error;
        Image last_trace;  // the latest trace image, for saving
        std::filesystem::file_time_type loaded_time{};
        std::vector<std::string> recent;  // most recent first
        bool completing = false;          // the path field lists matching files
        int dragged_light = -1;           // index into loaded->lights while dragged
        int layout = 0;                   // 0 both panes, 1 preview alone, 2 trace alone
        // What the preview framebuffer holds, so it is redrawn only when that changes.
        bool preview_stale = true, drawn_lights = true;
        int drawn_depth = -1, drawn_group_depth = -1, drawn_w = 0, drawn_h = 0;
        if (loaded) recent.push_back(loaded->path);
        auto on_loaded = [&]() {
            tracer.stop();
            preview->load(loaded->scene);
            orbit.set_from(loaded->file_camera, loaded->scene.world_bounds);
            loaded_time = modified(loaded->path);
            dirty = true;
        };
        if (loaded && preview) on_loaded();
        // Opens a file; on an error the message is shown and the previous scene stays.
        auto open = [&](const std::string& file, bool keep_camera) {
            std::string err;
            auto next = load_scene(file, &err);
            if (!next) {
                message = err;
                if (loaded) loaded_time = modified(loaded->path);  // do not retry every frame
                return;
            }
            const view::OrbitCamera kept = orbit;
            tracer.stop();
            loaded = std::move(next);
            message.clear();
            on_loaded();
            if (keep_camera) orbit = kept;
            std::snprintf(path_buf, sizeof path_buf, "%s", loaded->path.c_str());
            recent.erase(std::remove(recent.begin(), recent.end(), loaded->path), recent.end());
            recent.insert(recent.begin(), loaded->path);
            if (recent.size() > 8) recent.resize(8);
        };
        auto last_frame = std::chrono::steady_clock::now(), last_check = last_frame;
        std::string completed_for;  // the typed path the list below belongs to
        std::vector<std::string> completion_list;

        while (exit_code == 0 && !glfwWindowShouldClose(window)) {
            glfwPollEvents();
            const auto now = std::chrono::steady_clock::now();
            const double frame_s = std::chrono::duration<double>(now - last_frame).count();
            last_frame = now;
            if (frame_count++ > 0) {
                frame_total_s += frame_s;
                frame_max_s = std::max(frame_max_s, frame_s);
                if (frame_count > 3) frame_ms.push_back(1000 * frame_s);  // after start-up
            }
            // Dropped files open; the open file reloads when it changes on disk (camera kept).
            if (!g_dropped.empty()) {
                const std::string file = g_dropped.back();
                g_dropped.clear();
                open(file, false);
            }
            // The file's time is checked twice a second, not every frame.
            if (loaded && now - last_check > std::chrono::milliseconds(500)) {
                last_check = now;
                if (modified(loaded->path) != loaded_time) open(loaded->path, true);
            }
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            int fb_w = 0, fb_h = 0;
            glfwGetFramebufferSize(window, &fb_w, &fb_h);
            const float panel_w = 330;
            // Layout: both panes side by side, or one of them alone at full size.
            const int panes = layout == 0 ? 2 : 1;
            const float pane_w =
                std::max(64.0f, (static_cast<float>(fb_w) - panel_w) / static_cast<float>(panes));
            const float pane_h = std::max(64.0f, static_cast<float>(fb_h));

            // ---- controls ----
            ImGui::SetNextWindowPos(ImVec2(0, 0));
            ImGui::SetNextWindowSize(ImVec2(panel_w, pane_h));
            ImGui::Begin("rayview", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
            if (ImGui::InputText("scene", path_buf, sizeof path_buf)) completing = true;
            // Completion: the .ray files (and folders) that start with what is typed.
            if (completing) {
                if (completed_for != path_buf) {  // list the folder only when the text changes
                    completed_for = path_buf;
                    completion_list = completions(path_buf);
                }
                for (const std::string& c : completion_list)
                    if (ImGui::Selectable(c.c_str())) {
                        std::snprintf(path_buf, sizeof path_buf, "%s", c.c_str());
                        completing = c.back() == '/';  // a folder: keep completing inside it
                    }
            }
            if (ImGui::Button("Open")) {
                completing = false;
                open(path_buf, false);
            }
            ImGui::SameLine();
            if (ImGui::Button("Reload") && loaded) open(loaded->path, true);
            ImGui::SameLine();
            ImGui::TextDisabled("(or drop a .ray file)");
            if (recent.size() > 1 && ImGui::CollapsingHeader("recent files")) {
                for (size_t i = 1; i < recent.size(); ++i)
                    if (ImGui::Selectable(recent[i].c_str())) {
                        const std::string file = recent[i];
                        open(file, false);
                        break;
                    }
            }
            if (!message.empty())
                ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", message.c_str());
            if (loaded) {
                ImGui::Separator();
                ImGui::TextWrapped(
                    "Camera: drag orbits, shift/middle drag pans, wheel dollies, "
                    "right drag looks around, WASD/QE fly");
                if (ImGui::Button("Frame (F)") ||
                    (!io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F))) {
                    orbit.frame(loaded->scene.world_bounds,
                                static_cast<double>(pane_w) / static_cast<double>(pane_h));
                    dirty = true;
                }
                ImGui::SameLine();
                if (ImGui::Button("Home") ||
                    (!io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_HOME))) {
                    orbit.set_from(loaded->file_camera, loaded->scene.world_bounds);
                    dirty = true;
                }
                ImGui::Separator();
                ImGui::RadioButton("both", &layout, 0);
                ImGui::SameLine();
                ImGui::RadioButton("preview", &layout, 1);
                ImGui::SameLine();
                ImGui::RadioButton("trace", &layout, 2);
                dirty |= ImGui::Checkbox("shadows", &settings.shadows);
                ImGui::SameLine();
                ImGui::Checkbox("light markers", &show_lights);
                ImGui::SliderInt("group boxes (levels)", &group_depth, 0, 8);
                ImGui::SliderInt("BVH boxes (levels)", &box_depth, 0, 8);
                dirty |= ImGui::SliderInt("depth", &settings.max_depth, 1, 10);
                float cutoff = static_cast<float>(settings.cutoff);
                if (ImGui::SliderFloat("cutoff", &cutoff, 0.0f, 0.1f, "%.4f")) {
                    settings.cutoff = cutoff;
                    dirty = true;
                }
                dirty |= ImGui::SliderInt("target spp", &target_spp, 1, 4096);
                dirty |= ImGui::SliderFloat("resolution", &resolution_scale, 0.1f, 1.0f);
                dirty |= ImGui::SliderInt("threads (0 = all)", &settings.threads, 0, 64);
                float lr = static_cast<float>(settings.light_radius),
                      ap = static_cast<float>(settings.aperture),
                      ro = static_cast<float>(settings.roughness);
                if (ImGui::SliderFloat("light radius", &lr, 0.0f, 2.0f))
                    settings.light_radius = lr, dirty = true;
                if (ImGui::SliderFloat("aperture", &ap, 0.0f, 0.5f))
                    settings.aperture = ap, dirty = true;
                if (ImGui::SliderFloat("roughness", &ro, 0.0f, 1.0f))
                    settings.roughness = ro, dirty = true;

                ImGui::Separator();
                ImGui::Text("Lights");
                for (size_t i = 0; i < loaded->lights.size(); ++i) {
                    Light& l = loaded->lights[i];
                    ImGui::PushID(static_cast<int>(i));
                    bool on = loaded->light_on[i] != 0;
                    if (ImGui::Checkbox(l.kind == LightKind::Directional ? "directional"
                                        : l.kind == LightKind::Point     ? "point"
                                                                         : "spot",
                                        &on)) {
                        loaded->light_on[i] = on ? 1 : 0;
                        dirty = true;
                    }
                    float col[3] = {static_cast<float>(l.color.x), static_cast<float>(l.color.y),
                                    static_cast<float>(l.color.z)};
                    if (ImGui::ColorEdit3("colour", col,
                                          ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR))
                        l.color = Vec3(col[0], col[1], col[2]), dirty = true;
                    if (l.kind != LightKind::Directional) {
                        float p[3] = {static_cast<float>(l.position.x),
                                      static_cast<float>(l.position.y),
                                      static_cast<float>(l.position.z)};
                        if (ImGui::DragFloat3("position", p, 0.05f))
                            l.position = Vec3(p[0], p[1], p[2]), dirty = true;
                        float a[3] = {static_cast<float>(l.constant_atten),
                                      static_cast<float>(l.linear_atten),
                                      static_cast<float>(l.quadratic_atten)};
                        if (ImGui::DragFloat3("attenuation", a, 0.005f, 0.0f, 100.0f))
                            l.constant_atten = a[0], l.linear_atten = a[1],
                            l.quadratic_atten = a[2], dirty = true;
                    }
                    if (l.kind != LightKind::Point) {
                        float d[3] = {static_cast<float>(l.direction.x),
                                      static_cast<float>(l.direction.y),
                                      static_cast<float>(l.direction.z)};
                        if (ImGui::DragFloat3("direction", d, 0.01f) &&
                            glm::length(Vec3(d[0], d[1], d[2])) > 0)
                            l.direction = glm::normalize(Vec3(d[0], d[1], d[2])), dirty = true;
                    }
                    if (l.kind == LightKind::Spot) {
                        float c = static_cast<float>(l.cutoff_rad),
                              e = static_cast<float>(l.spot_exponent);
                        if (ImGui::SliderFloat("cut-off (rad)", &c, 0.0f, 3.1416f))
                            l.cutoff_rad = c, dirty = true;
                        if (ImGui::SliderFloat("drop-off exponent", &e, 0.0f, 256.0f))
                            l.spot_exponent = e, dirty = true;
                    }
                    if (ImGui::Button("remove")) {
                        loaded->lights.erase(loaded->lights.begin() + static_cast<long>(i));
                        loaded->light_on.erase(loaded->light_on.begin() + static_cast<long>(i));
                        dirty = true;
                        ImGui::PopID();
                        break;
                    }
                    ImGui::Separator();
                    ImGui::PopID();
                }
                if (ImGui::Button("add point light")) {
                    Light l;
                    l.kind = LightKind::Point;
                    l.position = orbit.desc().position;
                    loaded->lights.push_back(l);
                    loaded->light_on.push_back(1);
                    dirty = true;
                }

                ImGui::Separator();
                const view::Tracer::Status st = tracer.status();
                ImGui::Text("%d spp, %.2f Mray/s, %.1f s since the last change", st.spp,
                            st.rays_per_second / 1e6, st.seconds);
                ImGui::Text("estimated relMSE %.3g", st.estimate);
                ImGui::Text("frame %.1f ms, first traced pass %.0f ms after the last change",
                            1000 * frame_s, first_pass_ms);
                // What the renderer left out for this scene (issue 7), recomputed on each
                // restart: the lights and settings change it.
                {
                    int left = 0;
                    for (const std::string& l : explained) left += l.rfind("left out", 0) == 0;
                    std::string header = "renderer: ";
                    header += std::to_string(left);
                    header += " feature(s) left out###leftout";
                    if (ImGui::CollapsingHeader(header.c_str())) {
                        for (const std::string& l : explained) ImGui::TextWrapped("%s", l.c_str());
                        std::string shader = "preview shader:";
                        for (const std::string& d : preview->active_defines()) {
                            shader += ' ';
                            shader += d;
                        }
                        ImGui::TextWrapped("%s", shader.c_str());
                    }
                }
                const auto hist = tracer.history();
                std::vector<float> logs;
                for (const auto& [t, e] : hist) logs.push_back(std::log10(e));
                if (!logs.empty())
                    ImGui::PlotLines("log10 error", logs.data(), static_cast<int>(logs.size()), 0,
                                     nullptr, FLT_MAX, FLT_MAX, ImVec2(0, 60));
                ImGui::InputText("save as", save_buf, sizeof save_buf);
                ImGui::InputText("scene file", scene_buf, sizeof scene_buf);
                if (ImGui::Button("Save scene (camera and lights)")) {
                    try {
                        save_scene(*loaded, orbit.desc(), scene_buf);
                        message = std::string("saved ") + scene_buf;
                    } catch (const std::exception& e) {
                        message = e.what();
                    }
                }
                if (ImGui::Button("Save image (.png .pfm ...)")) {
                    try {
                        if (last_trace.width == 0) throw std::runtime_error("nothing traced yet");
                        save_image(last_trace, save_buf);
                        message = std::string("saved ") + save_buf;
                    } catch (const std::exception& e) {
                        message = e.what();
                    }
                }
            }
            ImGui::End();

            // ---- panes: preview (left) and trace (right) ----
            if (loaded && preview) {
                const int tw = std::max(16, static_cast<int>(pane_w * resolution_scale));
                const int th = std::max(16, static_cast<int>(pane_h * resolution_scale));
                if (tw != trace_w || th != trace_h) trace_w = tw, trace_h = th, dirty = true;

                ImGui::SetNextWindowPos(ImVec2(panel_w, 0));
                ImGui::SetNextWindowSize(ImVec2(static_cast<float>(panes) * pane_w, pane_h));
                ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
                ImGui::Begin("panes", nullptr,
                             ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoBringToFrontOnFocus);
                // While the view moves, the preview draws at a lower resolution (software GL
                // fills pixels slowly): half, and less while frames take longer than 30 ms, back
                // towards half below 20 ms; a quarter second after the last change, full.
                const bool moving =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - change_time)
                        .count() < 0.25;
                if (moving && frame_s > 0.030) moving_div = std::min(4.0, moving_div * 1.25);
                if (moving && frame_s < 0.020) moving_div = std::max(2.0, moving_div / 1.1);
                const double div = moving ? moving_div : 1.0;
                preview_fb.resize(static_cast<int>(static_cast<double>(pane_w) / div),
                                  static_cast<int>(static_cast<double>(pane_h) / div));
                bool over_preview = false, over_trace = false;
                if (layout != 2) {
                    ImGui::Image(
                        reinterpret_cast<ImTextureID>(static_cast<intptr_t>(preview_fb.color)),
                        ImVec2(pane_w, pane_h), ImVec2(0, 1), ImVec2(1, 0));
                    over_preview = ImGui::IsItemHovered();
                    ImGui::SameLine(0, 0);
                }
                if (layout != 1) {
                    if (trace_tex.id)
                        ImGui::Image(
                            reinterpret_cast<ImTextureID>(static_cast<intptr_t>(trace_tex.id)),
                            ImVec2(pane_w, pane_h));
                    else
                        ImGui::Dummy(ImVec2(pane_w, pane_h));
                    over_trace = ImGui::IsItemHovered();
                }
                ImGui::End();
                ImGui::PopStyleVar();

                // Lights are dragged in the preview: a click near a point or spot light's marker
                // picks it, and the drag moves it parallel to the image.
                const Camera view_cam =
                    make_camera(compile_camera(orbit.desc()), static_cast<int>(pane_w),
                                static_cast<int>(pane_h));
                auto to_pane = [&](const Vec3& p, double* depth) {
                    const Vec3 v = p - view_cam.position;
                    *depth = glm::dot(v, view_cam.forward);
                    const double x = glm::dot(v, view_cam.right) / (*depth * view_cam.tan_w);
                    const double y = glm::dot(v, view_cam.up) / (*depth * view_cam.tan_h);
                    return ImVec2(panel_w + static_cast<float>((x + 1) / 2) * pane_w,
                                  static_cast<float>((1 - y) / 2) * pane_h);
                };
                if (over_preview && show_lights && ImGui::IsMouseClicked(ImGuiMouseButton_Left) &&
                    !io.KeyShift) {
                    for (size_t i = 0; i < loaded->lights.size(); ++i) {
                        if (loaded->lights[i].kind == LightKind::Directional) continue;
                        double depth = 0;
                        const ImVec2 at = to_pane(loaded->lights[i].position, &depth);
                        const float ddx = at.x - io.MousePos.x, ddy = at.y - io.MousePos.y;
                        if (depth > 0 && ddx * ddx + ddy * ddy < 144.0f)
                            dragged_light = static_cast<int>(i);
                    }
                }
                if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) dragged_light = -1;
                if (dragged_light >= 0 && (io.MouseDelta.x != 0 || io.MouseDelta.y != 0)) {
                    Light& l = loaded->lights[static_cast<size_t>(dragged_light)];
                    double depth = 0;
                    to_pane(l.position, &depth);
                    const double per_pixel =
                        2 * depth * view_cam.tan_h / static_cast<double>(pane_h);
                    l.position +=
                        per_pixel * (static_cast<double>(io.MouseDelta.x) * view_cam.right -
                                     static_cast<double>(io.MouseDelta.y) * view_cam.up);
                    dirty = true;
                }

                // Camera input only over the panes (never what ImGui's controls want).
                if ((over_preview || over_trace) && dragged_light < 0) {
                    const double dx = static_cast<double>(io.MouseDelta.x),
                                 dy = static_cast<double>(io.MouseDelta.y);
                    const bool pan = ImGui::IsMouseDown(ImGuiMouseButton_Middle) ||
                                     (io.KeyShift && ImGui::IsMouseDown(ImGuiMouseButton_Left));
                    const double h = static_cast<double>(pane_h);
                    if (pan && (dx != 0 || dy != 0)) {
                        orbit.pan(-dx / h, dy / h);  // the scene follows the mouse
                        dirty = true;
                    } else if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && (dx != 0 || dy != 0)) {
                        orbit.orbit(dx * 0.005, -dy * 0.005);
                        dirty = true;
                    }
                    if (ImGui::IsMouseDown(ImGuiMouseButton_Right) && (dx != 0 || dy != 0)) {
                        orbit.look(dx * 0.004, -dy * 0.004);
                        dirty = true;
                    }
                    if (io.MouseWheel != 0) {
                        orbit.dolly(std::pow(0.9, static_cast<double>(io.MouseWheel)));
                        dirty = true;
                    }
                }

                // Fly: WASD along the view and sideways, Q/E down and up, at a speed scaled to
                // the scene (its diagonal per 4 seconds).
                if (!io.WantCaptureKeyboard) {
                    const Camera cam = make_camera(compile_camera(orbit.desc()), 4, 4);
                    const Bounds3& b = loaded->scene.world_bounds;
                    const double speed =
                        (b.empty() ? 1.0 : glm::length(b.diagonal())) / 4.0 * frame_s;
                    Vec3 move(0.0);
                    if (ImGui::IsKeyDown(GLFW_KEY_W)) move += cam.forward;
                    if (ImGui::IsKeyDown(GLFW_KEY_S)) move -= cam.forward;
                    if (ImGui::IsKeyDown(GLFW_KEY_D)) move += cam.right;
                    if (ImGui::IsKeyDown(GLFW_KEY_A)) move -= cam.right;
                    if (ImGui::IsKeyDown(GLFW_KEY_E)) move += Vec3(0, 1, 0);
                    if (ImGui::IsKeyDown(GLFW_KEY_Q)) move -= Vec3(0, 1, 0);
                    if (move != Vec3(0.0)) {
                        orbit.move(speed * move);
                        dirty = true;
                    }
                }
                // Continuous input (a drag) restarts the trace once its first pass is on screen
                // or 100 ms after the last restart, not every frame: otherwise no traced image
                // would appear until the input stops. The preview follows every frame.
                const bool trace_caught_up =
                    first_pass_ms >= 0 ||
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - change_time)
                            .count() > 0.1;
                if (dirty) preview_stale = true;
                if (dirty && !input_pending) {
                    input_pending = true;
                    input_time = std::chrono::steady_clock::now();
                }
                if (dirty && trace_caught_up) {
                    // Stop, edit, restart: the scene is only changed while no trace runs.
                    tracer.stop();
                    loaded->scene.camera = compile_camera(orbit.desc());
                    loaded->scene.lights.clear();
                    for (size_t i = 0; i < loaded->lights.size(); ++i)
                        if (loaded->light_on[i]) loaded->scene.lights.push_back(loaded->lights[i]);
                    settings.width = trace_w;
                    settings.height = trace_h;
                    tracer.restart(loaded->scene, settings, target_spp);
                    explained.clear();
                    for (const PlanReason& r : tracer.plan().reasons)
                        explained.push_back(reason_line(r));
                    if (print_left_out)
                        for (const std::string& l : explained)
                            if (l.rfind("left out", 0) == 0)
                                std::printf("rayview: %s\n", l.c_str());
                    print_left_out = false;
                    dirty = false;
                    input_pending = false;
                    served_input_time = input_time;
                    change_time = std::chrono::steady_clock::now();
                    first_pass_ms = -1;
                    for (const std::string& cause : script_causes)
                        std::printf("rayview: frame %d: %s: trace restarted\n", frame_index,
                                    cause.c_str());
                    script_causes.clear();
                }
                if (tracer.take_image(&last_trace)) {
                    trace_tex.upload(last_trace);
                    if (first_pass_ms < 0) {
                        // From the input, not the (possibly deferred) restart.
                        first_pass_ms = std::chrono::duration<double, std::milli>(
                                            std::chrono::steady_clock::now() - served_input_time)
                                            .count();
                        first_pass_samples.push_back(first_pass_ms);
                    }
                }

                // The preview, with the same camera, into its framebuffer: redrawn only when
                // something it shows changed (software GL spends most of a frame on it).
                const bool overlay_changed = show_lights != drawn_lights ||
                                             box_depth != drawn_depth ||
                                             group_depth != drawn_group_depth;
                if (preview_stale || overlay_changed || preview_fb.w != drawn_w ||
                    preview_fb.h != drawn_h) {
                    glBindFramebuffer(GL_FRAMEBUFFER, preview_fb.fbo);
                    // The camera of the latest input, also while a restart waits.
                    const Camera cam =
                        make_camera(compile_camera(orbit.desc()), preview_fb.w, preview_fb.h);
                    preview->draw(loaded->scene, cam, preview_fb.w, preview_fb.h, settings.shadows);
                    std::vector<view::LineVertex> lines =
                        view::overlay_lines(loaded->scene, show_lights, box_depth);
                    if (group_depth != group_lines_depth || loaded.get() != group_lines_for) {
                        // Walked again only when the scene or the level changes.
                        group_lines = view::group_box_lines(loaded->desc, group_depth);
                        group_lines_depth = group_depth;
                        group_lines_for = loaded.get();
                    }
                    lines.insert(lines.end(), group_lines.begin(), group_lines.end());
                    preview->draw_lines(lines, loaded->scene, cam);
                    glBindFramebuffer(GL_FRAMEBUFFER, 0);
                    preview_stale = false;
                    drawn_lights = show_lights;
                    drawn_depth = box_depth;
                    drawn_group_depth = group_depth;
                    drawn_w = preview_fb.w;
                    drawn_h = preview_fb.h;
                }
            }

            ImGui::Render();
            glViewport(0, 0, fb_w, fb_h);
            glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            // Scripted input for this frame (after drawing, so screenshots show the frame).
            for (const ScriptLine& l : script) {
                if (l.frame != frame_index || !loaded) continue;
                auto arg = [&](size_t i) {
                    return i < l.args.size() ? std::atof(l.args[i].c_str()) : 0.0;
                };
                if (l.command == "orbit") {
                    orbit.orbit(arg(0), arg(1));
                    dirty = true;
                } else if (l.command == "open" && !l.args.empty()) {
                    open(l.args[0], false);
                } else if (l.command == "light" && l.args.size() >= 5) {
                    const size_t i = static_cast<size_t>(std::atoi(l.args[0].c_str()));
                    if (i < loaded->lights.size())
                        loaded->lights[i].color = Vec3(arg(2), arg(3), arg(4));
                    dirty = true;
                } else if (l.command == "shadows" && !l.args.empty()) {
                    settings.shadows = l.args[0] == "on";
                    dirty = true;
                } else if (l.command == "boxes" && l.args.size() >= 2) {
                    group_depth = std::atoi(l.args[0].c_str());
                    box_depth = std::atoi(l.args[1].c_str());
                } else if (l.command == "layout" && !l.args.empty()) {
                    layout = l.args[0] == "preview" ? 1 : l.args[0] == "trace" ? 2 : 0;
                } else if (l.command == "resolution" && !l.args.empty()) {
                    resolution_scale = static_cast<float>(arg(0));
                } else if (l.command == "screenshot" && !l.args.empty()) {
                    save_window(fb_w, fb_h, l.args[0]);
                    const view::Tracer::Status st = tracer.status();
                    std::printf("rayview: frame %d: %s (trace at %d spp)\n", frame_index,
                                l.args[0].c_str(), st.spp);
                }
                if (dirty) script_causes.push_back(l.command);  // reported at the restart
            }
            ++frame_index;
            if (frames > 0 && --frames == 0) {
                if (!screenshot.empty()) {
                    try {
                        save_window(fb_w, fb_h, screenshot);
                        std::printf("rayview: saved %s\n", screenshot.c_str());
                    } catch (const std::exception& e) {
                        std::fprintf(stderr, "rayview: %s\n", e.what());
                        exit_code = 1;
                    }
                }
                glfwSetWindowShouldClose(window, 1);
            }
            glfwSwapBuffers(window);
        }
        tracer.stop();
        if (frame_count > 1 && !screenshot.empty()) {
            std::printf(
                "rayview: %d frames, mean %.1f ms, max %.1f ms; first traced pass %.0f ms "
                "after the last change\n",
                frame_count, 1000 * frame_total_s / (frame_count - 1), 1000 * frame_max_s,
                first_pass_ms);
            auto quantile = [](std::vector<double> v, double q) {
                std::sort(v.begin(), v.end());
                return v.empty() ? 0.0
                                 : v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))];
            };
            std::printf(
                "rayview: frames after start-up: median %.1f ms, p95 %.1f ms; first "
                "traced pass after a change: median %.0f ms, p95 %.0f ms (%zu changes)\n",
                quantile(frame_ms, 0.5), quantile(frame_ms, 0.95),
                quantile(first_pass_samples, 0.5), quantile(first_pass_samples, 0.95),
                first_pass_samples.size());
        }
    }
    // Shutdown in reverse order of initialisation (GL objects above died with their scope).
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return exit_code;
}
