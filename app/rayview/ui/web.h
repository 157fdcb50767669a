// rayview's side of the web page (Emscripten builds only; the page is app/web): the canvas that
// fills the page, the files the page hands over (picked, dropped onto it), downloads of what
// the viewer saves, and the state the page and its test read (rv_status).
#pragma once

struct GLFWwindow;

namespace rt::view {

struct ViewerState;

/// Where the page's files are: the shaders and the sample scenes, packaged with the page.
inline constexpr const char* kWebDataDir = "/data";

/// Before the first frame: the viewer the page's calls go to; what it saves is downloaded. The
/// working directory follows the open scene, so that relative paths (the panel's "edited.ray",
/// a script's) name files beside it: a scene saved there refers to its included files and
/// textures as the original does, and downloaded, it works beside them on the user's disk.
void web_start(ViewerState* viewer);
/// Once a frame: the window takes the canvas's size on the page (CSS pixels times the
/// device's pixel ratio).
void web_fit_canvas(GLFWwindow* window);
/// The page's device pixel ratio (CSS pixels to the canvas's).
double web_pixel_ratio();
/// A --frames run is over (its statistics printed): tells the page, with the exit code.
void web_finished(int exit_code);

}  // namespace rt::view
