// The viewer's state without a window: an edit reaches the traced scene only through the one
// restart path (stop, apply the edits, restart), and a saved scene holds the edited lights as
// described.
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <variant>

#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/format/writer.h"
#include "rt/render/render.h"
#include "rt/shapes/shapes.h"
#include "rt/util/file_io.h"
#include "rt/util/threads.h"
#include "state/commands.h"
#include "state/key_queue.h"
#include "state/light_edit.h"
#include "state/preview_geometry.h"
#include "state/run_options.h"
#include "state/viewer.h"
#include "state/viewer_compare.h"
#include "state/viewer_output.h"
#include "test_util.h"

namespace rt::view {
namespace {

// A spot, a point and a directional light.
const std::string kLights = RT_SOURCE_DIR "/scenes/lights.ray";

// Waits for the restart policy (it may hold an edit up to 100 ms for the running trace).
void restart(ViewerState& v) {
    for (int i = 0; i < 1000 && !v.restart_if_due(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_FALSE(v.edit_pending());
}

TEST(Viewer, EditsReachTheTracedSceneAtTheRestart) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);  // opening the file is an edit
    ASSERT_EQ(v.session.loaded->scene.lights.size(), 3u);
    EXPECT_EQ(v.settings.render.width, 32);
    EXPECT_EQ(v.settings.render.height, 24);

    v.edits.lights[0].set_colour(Vec3(0, 0, 3));
    v.edits.light_on[2] = 0;  // the directional light off
    v.edits.camera.orbit(0.3, 0.1);
    v.mark_edited();
    EXPECT_EQ(v.session.loaded->scene.lights[0].diffuse,
              Vec3(1.6, 0.3, 0.3));  // not before the restart
    restart(v);
    const RenderScene& s = v.session.loaded->scene;
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].diffuse, Vec3(0, 0, 3));
    EXPECT_EQ(s.lights[0].kind, LightKind::Spot);
    EXPECT_VEC_NEAR(s.lights[0].direction, glm::normalize(Vec3(0.3, -1, -0.2)), 1e-15);
    EXPECT_EQ(s.lights[1].kind, LightKind::Point);
    ASSERT_TRUE(s.camera);
    EXPECT_EQ(s.camera->position, v.edits.camera.desc().position);
    EXPECT_EQ(s.camera->direction, v.edits.camera.desc().direction);
}

// The timeline loops or stops at the end; the preview's scene follows every frame,
// the trace's copy only at the restart; both then hold the instances of a compile at that time.
TEST(Viewer, TheTimelineMovesThePreviewAtOnceAndTheTraceAtTheRestart) {
    Timeline tl;
    tl.playing = true;
    EXPECT_TRUE(tl.advance(0.5, 4));
    EXPECT_DOUBLE_EQ(tl.time, 0.5);
    tl.speed = 2;
    tl.advance(2, 4);  // 0.5 + 4 = 4.5: wraps to 0.5
    EXPECT_DOUBLE_EQ(tl.time, 0.5);
    tl.loop = false;
    tl.advance(3, 4);  // stops at the end
    EXPECT_DOUBLE_EQ(tl.time, 4);
    EXPECT_FALSE(tl.playing);
    tl.seek(-1, 4);
    EXPECT_EQ(tl.time, 0);
    tl.fps = 24;
    tl.seek(1.0, 4);
    EXPECT_EQ(tl.frame(), 24);

    ViewerState v(RT_SOURCE_DIR "/scenes/robot_arm.ray", false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    EXPECT_DOUBLE_EQ(v.animation_length(), 4.0);
    v.set_trace_size(32, 24);
    restart(v);
    const RenderScene& scene = v.session.loaded->scene;
    const RenderScene* traced = v.trace.traced(v.session.loaded->id);
    ASSERT_TRUE(traced);
    v.timeline.playing = true;
    v.step_animation(0.75);  // the preview's scene moves at once
    const SceneTime at = v.timeline.scene_time();
    EXPECT_DOUBLE_EQ(at.seconds, 0.75);
    ASSERT_TRUE(scene.time);
    EXPECT_EQ(*scene.time, at);
    EXPECT_NE(traced->time, scene.time);  // the trace's copy, made at the restart
    EXPECT_TRUE(v.edit_pending());
    v.timeline.playing = false;
    restart(v);
    ASSERT_TRUE(traced->time);
    EXPECT_EQ(*traced->time, at);
    const RenderScene fresh = compile_scene(v.session.loaded->desc, nullptr, at);
    ASSERT_EQ(traced->instances.size(), fresh.instances.size());
    for (size_t i = 0; i < fresh.instances.size(); ++i) {
        EXPECT_EQ(traced->instances[i].world_from_set.m, fresh.instances[i].world_from_set.m);
        EXPECT_EQ(scene.instances[i].world_from_set.m, fresh.instances[i].world_from_set.m);
    }
    EXPECT_EQ(&scene.sets[0], &traced->sets[0]);  // shared, not copied
}

// The trace pane refines at full resolution once the view is still: a change of the trace's
// size restarts the trace but is not an edit, so the refinement's own restart does not put the
// view back to "moving" (which would shrink it again).
TEST(Viewer, AResizedTraceRestartsWithoutCountingAsAnEdit) {
    TraceSession t;
    t.mark_edited();
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    const double before = t.seconds_since_edit();
    EXPECT_GE(before, 0.02);
    t.set_size(64, 48);
    EXPECT_TRUE(t.edit_pending());  // the new size restarts the trace
    EXPECT_GE(t.seconds_since_edit(), before);
    t.mark_edited();
    EXPECT_LT(t.seconds_since_edit(), before);
}

// Two taps within one slow frame both count (ImGui samples the keyboard once a frame), with the
// modifiers each had; auto-repeats only where asked; the next frame starts empty.
TEST(Viewer, KeyTapsWithinOneFrameAreQueued) {
    KeyQueue q;
    constexpr int kRight = 262, kZ = 90;
    q.press(kRight, false, false, false);
    q.press(kRight, false, false, false);
    q.press(kRight, false, false, true);  // held: an auto-repeat
    q.press(kZ, true, true, false);       // Ctrl+Shift+Z
    EXPECT_EQ(q.presses(kRight), 3);
    EXPECT_EQ(q.presses(kRight, false, false), 2);
    EXPECT_EQ(q.presses(kZ), 0);  // not without Ctrl
    EXPECT_EQ(q.presses(kZ, true), 1);
    EXPECT_TRUE(q.shifted(kZ));
    EXPECT_FALSE(q.shifted(kRight));
    q.next_frame();
    EXPECT_EQ(q.presses(kRight), 0);
}

// No writer marks an edit: a change of the edits or of a setting the trace uses is pending by
// itself, one of the display's (the exposure) restarts nothing.
TEST(Viewer, AnEditMarksItself) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);
    v.settings.exposure = 2;
    v.settings.layout = 1;
    EXPECT_FALSE(v.edit_pending());
    v.edits.set_material(0, MaterialDesc{});
    EXPECT_TRUE(v.edit_pending());
    restart(v);
    EXPECT_TRUE(v.session.loaded->scene.materials[0].diffuse == Material{}.diffuse);
    v.settings.render.shadows = !v.settings.render.shadows;
    EXPECT_TRUE(v.edit_pending());
    restart(v);
    OrbitCamera cam = v.edits.camera;
    cam.orbit(0.2, 0);
    v.edits.set_camera(cam);
    EXPECT_TRUE(v.edit_pending());
    restart(v);
    ASSERT_TRUE(v.session.loaded->scene.camera);
    EXPECT_EQ(v.session.loaded->scene.camera->direction, compile_camera(cam.desc()).direction);
}

// The lights' verbs: a copy put back (on or off), added at the eye, removed; an index out of
// range changes nothing.
TEST(Viewer, SceneEditsVerbs) {
    SceneEdits e;
    e.camera.distance = 4;
    e.add_light(LightKind::Sphere);
    ASSERT_EQ(e.lights.size(), 1u);
    EXPECT_EQ(e.lights[0].position, e.camera.eye());
    EXPECT_DOUBLE_EQ(e.lights[0].radius, 0.2);
    LightDesc l = e.lights[0];
    l.position = Vec3(1, 2, 3);
    e.set_light(0, l, false);
    EXPECT_EQ(e.lights[0].position, Vec3(1, 2, 3));
    EXPECT_EQ(e.light_on[0], 0);
    e.set_light(5, LightDesc{}, true);  // nothing there
    e.remove_light(5);
    EXPECT_EQ(e.lights.size(), 1u);
    e.frame_light(0, Bounds3{});
    EXPECT_EQ(e.camera.target, Vec3(1, 2, 3));
    e.remove_light(0);
    EXPECT_TRUE(e.lights.empty() && e.light_on.empty());
}

ScriptLine line(int frame, std::string command, std::vector<std::string> args = {}) {
    return {frame, std::move(command), std::move(args)};
}

// The script's commands run headless on the state, through the verbs the panels use: each
// edit is pending by itself, a bad argument or a failed command throws naming it, the window's
// own commands are not the state's.
// Every number of kLightNumbers is the script's to set (clamped to its range) on a light whose
// kind has it, and refused on one whose kind has not; the restart takes it to the scene.
TEST(Viewer, ScriptSetsEveryLightNumberOfTheTable) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);
    for (const char* kind : {"point", "spot", "directional", "sphere"})
        run_command(v, line(1, "add-light", {kind}));
    const size_t first = v.edits.lights.size() - 4;
    int set = 0;
    for (const LightNumber& n : kLightNumbers)
        for (size_t i = first; i < v.edits.lights.size(); ++i) {
            const std::string index = std::to_string(i);
            if (!n.of(v.edits.lights[i].kind)) {
                EXPECT_THROW(run_command(v, line(2, "light", {index, n.name, "0.5"})),
                             std::runtime_error)
                    << n.name;
                continue;
            }
            run_command(v, line(2, "light", {index, n.name, "-1"}));
            EXPECT_EQ(v.edits.lights[i].*n.field, n.lo) << n.name;
            run_command(v, line(2, "light", {index, n.name, "0.5"}));
            EXPECT_EQ(v.edits.lights[i].*n.field, 0.5) << n.name;
            ++set;
        }
    EXPECT_EQ(set, 1 + 3 * 3 + 2);  // a sphere's radius; three kinds' attenuation; a spot's two
    restart(v);
    ASSERT_EQ(v.session.loaded->scene.lights.size(), v.edits.lights.size());
    for (const LightNumber& n : kLightNumbers)
        for (size_t i = first; i < v.edits.lights.size(); ++i)
            EXPECT_EQ(v.session.loaded->scene.lights[i].*n.field, v.edits.lights[i].*n.field);
}

TEST(Viewer, ScriptCommandsRunOnTheState) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);
    const OrbitCamera before = v.edits.camera;
    EXPECT_EQ(run_command(v, line(1, "orbit", {"0.4", "0.1"})), "");
    EXPECT_FALSE(v.edits.camera == before);
    EXPECT_TRUE(v.edit_pending());
    restart(v);
    ASSERT_TRUE(run_command(v, line(2, "shadows", {"off"})));
    EXPECT_FALSE(v.settings.render.shadows);
    EXPECT_TRUE(v.edit_pending());
    run_command(v, line(2, "light", {"1", "position", "1", "2", "3"}));
    EXPECT_EQ(v.edits.lights[1].position, Vec3(1, 2, 3));
    run_command(v, line(2, "material", {"0", "diffuse", "0.25", "0.5", "0.75"}));
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.lights[1].position, Vec3(1, 2, 3));
    EXPECT_EQ(v.session.loaded->scene.materials[0].diffuse, Vec3(0.25, 0.5, 0.75));
    EXPECT_FALSE(v.session.loaded->scene.lights.empty());
    // The display's settings restart nothing.
    run_command(v, line(3, "exposure", {"1.5"}));
    EXPECT_FLOAT_EQ(v.settings.exposure, 1.5f);
    EXPECT_FALSE(v.edit_pending());
    // What a command says, with its frame.
    const std::optional<std::string> picked = run_command(v, line(4, "pick", {"0.5", "0.5"}));
    ASSERT_TRUE(picked);
    EXPECT_EQ(picked->rfind("rayview: frame 4: picked ", 0), 0u) << *picked;
    EXPECT_EQ(run_command(v, line(5, "status"))->rfind("rayview: frame 5: status: ", 0), 0u);
    // Errors name the command; nothing changes.
    try {
        run_command(v, line(6, "light", {"9", "position", "0", "0", "0"}));
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "light: the scene has no light 9");
    }
    EXPECT_THROW(run_command(v, line(6, "depth", {"nan"})), std::runtime_error);
    EXPECT_THROW(run_command(v, line(6, "compare", {"tolerance", "3"})), std::runtime_error);
    EXPECT_FALSE(v.edit_pending());
    // Undo takes back the last step (the edits above, one step as no gesture held them).
    v.track_history(false);
    ASSERT_TRUE(run_command(v, line(7, "undo")));
    EXPECT_TRUE(v.settings.render.shadows);
    // The runner's own commands.
    EXPECT_FALSE(run_command(v, line(8, "wait-spp", {"4"})));
    EXPECT_FALSE(run_command(v, line(8, "screenshot", {"x.png"})));
    EXPECT_FALSE(run_command(v, line(8, "no-such-command")));
}

TEST(Viewer, SavedSceneHoldsTheEditedLightsAndCamera) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.edits.lights[1].position = Vec3(1, 2, 3);
    v.edits.light_on[0] = 0;              // the spot off: not saved
    v.edits.add_light(LightKind::Point);  // at the eye
    const Vec3 eye = v.edits.camera.desc().position;
    v.edits.camera.orbit(0.5, 0);
    const std::string path = ::testing::TempDir() + "rt_viewer_saved.ray";
    save_scene(v, path);
    Diagnostics diag;
    const SceneDesc d = parse_scene_file(path, diag);
    ASSERT_EQ(d.lights.size(), 3u);
    EXPECT_EQ(d.lights[0].kind, LightKind::Point);
    EXPECT_VEC_NEAR(d.lights[0].position, Vec3(1, 2, 3), 1e-9);
    EXPECT_VEC_NEAR(d.lights[0].diffuse, Vec3(0.3, 1.4, 0.4), 1e-9);
    EXPECT_EQ(d.lights[1].kind, LightKind::Directional);
    EXPECT_EQ(d.lights[2].kind, LightKind::Point);
    EXPECT_VEC_NEAR(d.lights[2].position, eye, 1e-6);
    ASSERT_TRUE(d.camera);
    EXPECT_VEC_NEAR(d.camera->position, v.edits.camera.desc().position, 1e-6);
}

TEST(Viewer, AFailedOpenKeepsTheSceneAndSaysWhy) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const int id = v.session.loaded->id;
    EXPECT_FALSE(v.open(RT_SOURCE_DIR "/scenes/no_such_file.ray", false));
    EXPECT_EQ(v.session.loaded->id, id);
    EXPECT_NE(v.messages.text.find("no_such_file.ray"), std::string::npos) << v.messages.text;
    EXPECT_TRUE(v.open(kLights, true));
    EXPECT_GT(v.session.loaded->id, id);
    EXPECT_TRUE(v.messages.text.empty());
    EXPECT_EQ(v.session.recent.size(), 1u);  // the same file once
}

// A FIFO (or a device) opened, dropped or loaded in the background is an error that says what it
// is, and the open scene stays: nothing waits on the FIFO, which has no writer.
TEST(Viewer, AFifoIsAnErrorAndTheSceneStays) {
    const std::string fifo = ::testing::TempDir() + "rt_viewer_fifo.ray";
    std::filesystem::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const int id = v.session.loaded->id;
    EXPECT_EQ(v.messages.failures, 0);
    EXPECT_FALSE(v.open(fifo, false));
    EXPECT_EQ(v.session.loaded->id, id);
    EXPECT_TRUE(v.messages.is_error);
    EXPECT_NE(v.messages.text.find("'" + fifo + "' is a FIFO, not a regular file"),
              std::string::npos)
        << v.messages.text;
    EXPECT_EQ(v.messages.failures, 1);  // a scripted run exits 1
    v.ui.dropped.push_back(fifo);
    v.poll_files();  // the drop loads in the background
    // No time limit of its own (ctest's timeout ends a hang): a slow, loaded machine is no failure.
    while (v.jobs.loader.busy()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        v.poll_files();
    }
    EXPECT_EQ(v.session.loaded->id, id);
    EXPECT_EQ(v.messages.failures, 2);
    EXPECT_NE(v.messages.text.find("is a FIFO"), std::string::npos) << v.messages.text;
    std::filesystem::remove(fifo);
}

// The script's light command: one colour (V0/V1: ambient 0, diffuse = specular), each of a V3
// light's three colours, a sphere light's radius; anything else leaves the light as it was.
TEST(Viewer, ScriptEditsOneOrThreeLightColoursAndTheRadius) {
    LightDesc l;
    l.ambient = Vec3(0.1);
    ASSERT_TRUE(edit_light("colour", 1, 2, 3, &l));
    EXPECT_EQ(l.ambient, Vec3(0.0));
    EXPECT_EQ(l.diffuse, Vec3(1, 2, 3));
    EXPECT_EQ(l.specular, Vec3(1, 2, 3));
    EXPECT_TRUE(l.one_colour());
    ASSERT_TRUE(edit_light("ambient", 0.5, 0, 0, &l));
    ASSERT_TRUE(edit_light("specular", 0, 0, 1, &l));
    EXPECT_EQ(l.ambient, Vec3(0.5, 0, 0));
    EXPECT_EQ(l.diffuse, Vec3(1, 2, 3));
    EXPECT_EQ(l.specular, Vec3(0, 0, 1));
    ASSERT_TRUE(edit_light("diffuse", 0, 1, 0, &l));
    EXPECT_EQ(l.diffuse, Vec3(0, 1, 0));
    const LightDesc before = l;
    EXPECT_FALSE(edit_light("radius", 2, 0, 0, &l));  // a point light has none
    EXPECT_FALSE(edit_light("shininess", 2, 0, 0, &l));
    EXPECT_EQ(l.radius, before.radius);
    EXPECT_EQ(l.diffuse, before.diffuse);
    l.kind = LightKind::Sphere;
    ASSERT_TRUE(edit_light("radius", 0.75, 0, 0, &l));
    EXPECT_EQ(l.radius, 0.75);
    ASSERT_TRUE(edit_light("radius", -1, 0, 0, &l));
    EXPECT_EQ(l.radius, 0.0);
}

// Three-colour edits reach the traced scene through the restart path.
TEST(Viewer, ThreeColourEditsReachTheTracedScene) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(16, 12);
    restart(v);
    v.edits.lights[1].ambient = Vec3(0.2, 0.3, 0.4);
    v.edits.lights[1].specular = Vec3(0, 1, 0);
    v.mark_edited();
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.lights[1].ambient, Vec3(0.2, 0.3, 0.4));
    EXPECT_EQ(v.session.loaded->scene.lights[1].specular, Vec3(0, 1, 0));
}

// A scene whose texture cannot be opened: the error, then the offer to open it with a checker
// standing in, and the panel's note on the stand-in; --missing-textures checker opens it at once.
TEST(Viewer, MissingTexturesOpenWithCheckerStandIns) {
    const std::string path = ::testing::TempDir() + "rt_viewer_missing_texture.ray";
    write_file_atomic(path,
                      "#texture no_such_texture.png\n"
                      "#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  0 !m!\n"
                      "#light_dir 1 1 1  0 -1 0\n#shape_sphere 0 0 0 0 1\n");
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    EXPECT_TRUE(v.session.checker_offer.empty());
    EXPECT_FALSE(v.open(path, false));
    EXPECT_NE(v.messages.text.find("no_such_texture.png"), std::string::npos) << v.messages.text;
    EXPECT_EQ(v.session.checker_offer, path);
    EXPECT_EQ(v.session.loaded->path, kLights);  // the previous scene stays
    EXPECT_EQ(stand_in_text(v.session.loaded->desc), "");
    ASSERT_TRUE(v.open_with_checker()) << v.messages.text;
    EXPECT_EQ(v.session.loaded->path, path);
    EXPECT_TRUE(v.session.checker_offer.empty());
    EXPECT_EQ(v.session.loaded->missing_textures, MissingTextures::Checker);
    ASSERT_EQ(v.session.loaded->desc.missing_textures,
              std::vector<std::string>{"no_such_texture.png"});
    EXPECT_NE(stand_in_text(v.session.loaded->desc).find("no_such_texture.png"), std::string::npos);
    // The choice is asked once a session: the file opens with stand-ins again, no question.
    ASSERT_TRUE(v.open(kLights, false)) << v.messages.text;
    EXPECT_TRUE(v.open(path, false)) << v.messages.text;
    EXPECT_TRUE(v.session.checker_offer.empty());
    // Another failure (not a texture) makes no offer.
    EXPECT_FALSE(v.open(RT_SOURCE_DIR "/scenes/no_such_file.ray", false));
    EXPECT_TRUE(v.session.checker_offer.empty());

    ViewerState direct(path, false, MissingTextures::Checker);
    ASSERT_TRUE(direct.session.loaded) << direct.messages.text;
    EXPECT_EQ(direct.session.loaded->desc.missing_textures.size(), 1u);
    ViewerState refused(path, false);
    EXPECT_FALSE(refused.session.loaded);
    EXPECT_EQ(refused.session.checker_offer, path);
    // The offer belongs to its message: a newer one (here a note) outdates it.
    EXPECT_EQ(refused.session.checker_offer_message, refused.messages.serial);
    refused.messages.note("something else");
    EXPECT_NE(refused.session.checker_offer_message, refused.messages.serial);
}

// A V3 scene saves as V3 (the writer's syntax), with the viewer's three-colour and radius edits.
TEST(Viewer, AV3SceneSavesAsV3WithItsEdits) {
    const std::string path = ::testing::TempDir() + "rt_viewer_v3.ray";
    write_file_atomic(
        path,
        "#camera 0 2 6  0 -0.3 -1  0 1 0  0.5\n"
        "#light_sphere 0.1 0.1 0.1  1 1 1  1 1 1  2 3 3  0.5  1 0 0\n"
        "#material 0 0 0  0.5 0.5 0.5  0.6 0.5 0.4  0.3 0.3 0.3  20  0 0 0  1  -1 !!\n"
        "#shape_torus 0  0 0 0  0.4 1.2\n");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    ASSERT_EQ(v.session.loaded->desc.dialect, Dialect::V3);
    LightDesc& l = v.edits.lights[0];
    ASSERT_EQ(l.kind, LightKind::Sphere);
    l.ambient = Vec3(0.2, 0.3, 0.4);
    l.specular = Vec3(0, 1, 0);
    l.radius = 0.8;
    const std::string saved = ::testing::TempDir() + "rt_viewer_v3_saved.ray";
    save_scene(v, saved);
    Diagnostics diag;
    const SceneDesc d = parse_scene_file(saved, diag);
    EXPECT_EQ(d.dialect, Dialect::V3);
    ASSERT_EQ(d.lights.size(), 1u);
    EXPECT_EQ(d.lights[0].kind, LightKind::Sphere);
    EXPECT_VEC_NEAR(d.lights[0].ambient, Vec3(0.2, 0.3, 0.4), 1e-12);
    EXPECT_VEC_NEAR(d.lights[0].diffuse, Vec3(1.0), 1e-12);
    EXPECT_VEC_NEAR(d.lights[0].specular, Vec3(0, 1, 0), 1e-12);
    EXPECT_NEAR(d.lights[0].radius, 0.8, 1e-12);
    ASSERT_EQ(d.files[0].root.shapes.size(), 1u);
    EXPECT_TRUE(std::holds_alternative<Torus>(d.files[0].root.shapes[0].geometry));
}

// Reloading keeps the user's edits (once: a plain touch discarded the panel's light and camera
// edits). A file of one point light and a sphere, written to a temporary place.
std::string small_scene(const std::string& name, const std::string& light_colour) {
    const std::string path = ::testing::TempDir() + name;
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#light_point " +
                          light_colour +
                          "  0 3 3  1 0 0\n"
                          "#material 0 0 0  0 0 0  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !!\n"
                          "#shape_sphere 0  0 0 0  1\n");
    return path;
}

TEST(Viewer, OnOpenedHearsEveryOpenAndReloadButNotAFailure) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    std::vector<std::string> heard;
    v.hooks.on_opened = [&](const std::string& path) { heard.push_back(path); };
    const std::string other = small_scene("rt_viewer_opened.ray", "1 1 1");
    EXPECT_TRUE(v.open(other, false));
    EXPECT_FALSE(v.open(RT_SOURCE_DIR "/scenes/no_such_file.ray", false));
    EXPECT_TRUE(v.reload());
    EXPECT_EQ(heard, (std::vector<std::string>{other, other}));
}

TEST(Viewer, ReloadKeepsTheEditsOfAnUnchangedFile) {
    const std::string path = small_scene("rt_viewer_touch.ray", "1 1 1");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.edits.lights[0].set_colour(Vec3(0, 0, 3));
    v.edits.camera.orbit(0.4, 0.2);
    const CameraDesc edited = v.edits.camera.desc();
    const int id = v.session.loaded->id;
    ASSERT_TRUE(v.reload());
    EXPECT_GT(v.session.loaded->id, id);
    EXPECT_EQ(v.edits.lights[0].diffuse, Vec3(0, 0, 3));
    EXPECT_EQ(v.edits.camera.desc().position, edited.position);
    EXPECT_TRUE(v.session.reload_conflict.empty()) << v.session.reload_conflict;
    EXPECT_NE(v.messages.text.find("your edits are kept"), std::string::npos) << v.messages.text;
    EXPECT_FALSE(v.messages.is_error);
}

TEST(Viewer, ReloadOfAChangedFileKeepsTheEditsAndOffersTheFile) {
    const std::string path = small_scene("rt_viewer_changed.ray", "1 1 1");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.edits.lights[0].set_colour(Vec3(0, 0, 3));
    small_scene("rt_viewer_changed.ray", "0.5 0.5 0.5");  // the file's light changes too
    ASSERT_TRUE(v.reload());
    EXPECT_EQ(v.edits.lights[0].diffuse, Vec3(0, 0, 3));
    EXPECT_NE(v.session.reload_conflict.find("lights"), std::string::npos)
        << v.session.reload_conflict;
    EXPECT_EQ(v.session.reload_conflict.find("camera"), std::string::npos)
        << v.session.reload_conflict;
    v.use_file_edits();  // the user's choice: the file's
    EXPECT_EQ(v.edits.lights[0].diffuse, Vec3(0.5));
    EXPECT_TRUE(v.session.reload_conflict.empty());
}

TEST(Viewer, ReloadWithoutEditsTakesTheFile) {
    const std::string path = small_scene("rt_viewer_plain.ray", "1 1 1");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    small_scene("rt_viewer_plain.ray", "0.25 0.5 1");
    ASSERT_TRUE(v.reload());
    EXPECT_EQ(v.edits.lights[0].diffuse, Vec3(0.25, 0.5, 1));
    EXPECT_TRUE(v.session.reload_conflict.empty());
    EXPECT_TRUE(v.messages.text.empty()) << v.messages.text;
}

TEST(Viewer, ATouchReloadsAndKeepsTheEdits) {
    const std::string path = small_scene("rt_viewer_poll.ray", "1 1 1");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.edits.light_on[0] = 0;
    const int id = v.session.loaded->id;
    std::filesystem::last_write_time(
        path, std::filesystem::last_write_time(path) + std::chrono::seconds(2));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // polled twice a second
    v.poll_files();  // starts the reload in the background
    EXPECT_EQ(v.session.loaded->id, id);
    for (int i = 0; i < 2000 && v.session.loaded->id == id; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        v.poll_files();
    }
    EXPECT_GT(v.session.loaded->id, id);
    EXPECT_EQ(v.edits.light_on[0], 0);
}

TEST(Viewer, AFileThatFailsAtStartUpIsWatched) {
    const std::string path = ::testing::TempDir() + "rt_viewer_broken.ray";
    write_file_atomic(path, "#shape_sphere 0  0 0 0  1\n");  // material 0 does not exist
    ViewerState v(path, false);
    ASSERT_FALSE(v.session.loaded);
    EXPECT_TRUE(v.messages.is_error);
    EXPECT_NE(v.messages.text.find("rt_viewer_broken.ray:1:"), std::string::npos)
        << v.messages.text;
    small_scene("rt_viewer_broken.ray", "1 1 1");  // fixed in an editor
    std::filesystem::last_write_time(
        path, std::filesystem::last_write_time(path) + std::chrono::seconds(2));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    v.poll_files();
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    EXPECT_EQ(v.session.loaded->desc.lights.size(), 1u);
}

// A scene without lights is lit by a headlight along the view, which is never saved unless the
// user keeps it (once: such scenes showed black panes and no word why).
TEST(Viewer, ASceneWithoutLightsGetsAHeadlightThatIsNotSaved) {
    const std::string path = ::testing::TempDir() + "rt_viewer_dark.ray";
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#material 0 0 0  0 0 0  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !!\n"
                      "#shape_sphere 0  0 0 0  1\n");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    EXPECT_TRUE(v.headlight_on());
    v.set_trace_size(16, 12);
    v.edits.camera.orbit(0.3, 0.2);
    v.mark_edited();
    restart(v);
    ASSERT_EQ(v.session.loaded->scene.lights.size(), 1u);
    EXPECT_EQ(v.session.loaded->scene.lights[0].kind, LightKind::Directional);
    EXPECT_VEC_NEAR(v.session.loaded->scene.lights[0].direction, v.edits.camera.forward(), 1e-12);
    const std::string saved = ::testing::TempDir() + "rt_viewer_dark_saved.ray";
    save_scene(v, saved);
    Diagnostics diag;
    EXPECT_TRUE(parse_scene_file(saved, diag).lights.empty());
    v.settings.headlight = false;  // off: dark, as the file says
    v.mark_edited();
    restart(v);
    EXPECT_TRUE(v.session.loaded->scene.lights.empty());
    v.settings.headlight = true;
    v.edits.keep_headlight();  // asked: now a light of the scene
    EXPECT_FALSE(v.headlight_on());
    save_scene(v, saved);
    EXPECT_EQ(parse_scene_file(saved, diag).lights.size(), 1u);
}

TEST(Viewer, NewLightsOfEveryKindStartAtTheEyeAlongTheView) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const size_t before = v.edits.lights.size();
    for (LightKind k : {LightKind::Point, LightKind::Spot, LightKind::Directional})
        v.edits.add_light(k);
    ASSERT_EQ(v.edits.lights.size(), before + 3);
    for (size_t i = before; i < v.edits.lights.size(); ++i) {
        EXPECT_VEC_NEAR(v.edits.lights[i].position, v.edits.camera.eye(), 1e-12);
        EXPECT_VEC_NEAR(v.edits.lights[i].direction, v.edits.camera.forward(), 1e-12);
    }
    EXPECT_EQ(v.edits.lights[before + 1].kind, LightKind::Spot);
    EXPECT_EQ(v.edits.lights[before + 2].kind, LightKind::Directional);
    v.set_trace_size(16, 12);
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.lights.size(), before + 3);
}

// Saved scenes hold the numbers the panel showed (once: 0.30000001192092896).
TEST(Viewer, FloatWidgetValuesAreTheirShortestDecimal) {
    EXPECT_EQ(float_as_decimal(0.3f), 0.3);
    EXPECT_EQ(float_as_decimal(1.15f), 1.15);
    EXPECT_EQ(float_as_decimal(-2.5f), -2.5);
    EXPECT_EQ(float_as_decimal(1e-7f), 1e-7);
    EXPECT_EQ(static_cast<float>(float_as_decimal(0.1234567f)), 0.1234567f);
    LightDesc l;
    l.position = Vec3(float_as_decimal(0.3f), 0, 0);
    SceneDesc d;
    d.files.emplace_back();
    d.lights.push_back(l);
    EXPECT_NE(write_scene(d).find(" 0.3 0 0"), std::string::npos) << write_scene(d);
}

// A material edited in the panel reaches the preview's scene and the trace's copy at the
// restart, is one undo step, and is saved with the scene in its #material line.
TEST(Viewer, MaterialEditsReachBothPanesUndoAndSave) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);
    ASSERT_FALSE(v.edits.materials.empty());
    EXPECT_EQ(v.edits.materials[0].diffuse, Vec3(0.85));  // lights.ray's !white!
    v.track_history(false);
    v.edits.materials[0].diffuse = Vec3(0.25, 0.5, 0.75);
    v.edits.materials[0].specular_exponent = 12;
    v.track_history(false);
    EXPECT_EQ(v.history.undo_steps(), 1u);
    v.mark_edited();
    EXPECT_EQ(v.session.loaded->scene.materials[0].diffuse, Vec3(0.85));  // not before it
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.materials[0].diffuse, Vec3(0.25, 0.5, 0.75));
    ASSERT_TRUE(v.trace.traced(v.session.loaded->id));
    EXPECT_EQ(v.trace.traced(v.session.loaded->id)->materials[0].specular_exponent, 12.0);
    const std::string path = ::testing::TempDir() + "rt_viewer_material.ray";
    save_scene(v, path);
    std::string text;
    ASSERT_TRUE(read_file(path, &text));
    EXPECT_NE(text.find("0.25 0.5 0.75"), std::string::npos) << text;
    ASSERT_TRUE(v.undo());
    EXPECT_EQ(v.edits.materials[0].diffuse, Vec3(0.85));
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.materials[0].diffuse, Vec3(0.85));
}

// Each material of the compiled scene knows its file, its index there and the textures it may
// use (its file's): materials.ray's five, then its floor's (parts/floor.ray, one texture),
// then the V0 default.
TEST(Viewer, MaterialsKnowTheirFileAndItsTextures) {
    Diagnostics diag;
    const SceneDesc d = parse_scene_file(RT_SOURCE_DIR "/scenes/materials.ray", diag);
    ASSERT_EQ(d.files.size(), 2u);
    const std::vector<MaterialOrigin> origins = material_origins(d);
    ASSERT_EQ(origins.size(), 7u);
    EXPECT_EQ(origins[6].file, -1);  // the built-in default, material 6, is in no file
    const MaterialOrigin glass = origins[1];
    EXPECT_EQ(glass.file, 0);
    EXPECT_EQ(glass.index, 1);
    EXPECT_EQ(glass.textures, 0);
    const MaterialOrigin floor = origins[5];
    EXPECT_EQ(floor.file, 1);
    EXPECT_EQ(floor.index, 0);
    EXPECT_EQ(floor.first_texture, 0);
    EXPECT_EQ(floor.textures, 1);
    const RenderScene scene = compile_scene(d);
    EXPECT_EQ(scene.materials[5].texture, floor.first_texture + d.files[1].materials[0].texture);
}

// A material's texture edited in the panel (another of its file's, or none) reaches the traced
// scene and is saved as the file's texture index in its #material line.
TEST(Viewer, TextureEditsReachTheSceneAndAreSaved) {
    ViewerState v(RT_SOURCE_DIR "/scenes/textures.ray", false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(32, 24);
    restart(v);
    ASSERT_EQ(v.edits.materials[0].texture, 0);
    v.edits.materials[0].texture = 3;   // checker -> grid
    v.edits.materials[1].texture = -1;  // wood -> none
    v.track_history(false);
    v.mark_edited();
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.materials[0].texture, 3);
    EXPECT_EQ(v.trace.traced(v.session.loaded->id)->materials[1].texture, -1);
    const std::string path = ::testing::TempDir() + "rt_viewer_texture.ray";
    save_scene(v, path);
    Diagnostics diag;
    const SceneDesc saved = parse_scene_file(path, diag);
    ASSERT_EQ(saved.files[0].materials.size(), 4u);
    EXPECT_EQ(saved.files[0].materials[0].texture, 3);
    EXPECT_EQ(saved.files[0].materials[1].texture, -1);
    EXPECT_EQ(saved.files[0].materials[2].texture, 2);  // not edited
    ASSERT_TRUE(v.undo());
    EXPECT_EQ(v.edits.materials[0].texture, 0);
}

// An included file's material (materials.ray's floor, from parts/floor.ray) is written into
// that file only when asked, as its one #material line, the rest of the file kept; a file
// changed since it was read is an error and nothing is written.
TEST(Viewer, IncludedMaterialsAreSavedIntoTheirFileWhenAsked) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(::testing::TempDir()) / "rt_viewer_included";
    fs::remove_all(dir);
    fs::create_directories(dir / "parts");
    fs::create_directories(dir / "textures");
    fs::copy_file(RT_SOURCE_DIR "/scenes/materials.ray", dir / "materials.ray");
    fs::copy_file(RT_SOURCE_DIR "/scenes/parts/floor.ray", dir / "parts/floor.ray");
    fs::copy_file(RT_SOURCE_DIR "/scenes/textures/checker.bmp", dir / "textures/checker.bmp");
    std::string floor_before;
    ASSERT_TRUE(read_file((dir / "parts/floor.ray").string(), &floor_before));
    ViewerState v((dir / "materials.ray").string(), false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    EXPECT_TRUE(edited_included_files(v).empty());
    ASSERT_EQ(v.session.loaded->origin(5).file, 1);   // the table made with the scene
    EXPECT_EQ(v.session.loaded->origin(6).file, -1);  // the built-in default
    // The floor's texture is its own file's first: the edit holds the file's number, the
    // compiled scene the scene's (the restart compiles it); the built-in default has none.
    EXPECT_EQ(v.edits.materials[5].texture, 0);
    v.set_trace_size(16, 12);
    restart(v);
    EXPECT_EQ(v.session.loaded->scene.materials[5].texture,
              v.session.loaded->origin(5).first_texture + 0);
    EXPECT_EQ(v.session.loaded->scene.materials[6].texture, -1);
    v.edits.materials[5].diffuse = Vec3(0.25, 0.5, 0.75);
    ASSERT_EQ(edited_included_files(v).size(), 1u);
    EXPECT_EQ(fs::path(edited_included_files(v)[0]).filename(), "floor.ray");

    const std::string saved = (dir / "saved.ray").string();
    save_scene(v, saved);  // not asked: the part stays as it was
    std::string floor;
    ASSERT_TRUE(read_file((dir / "parts/floor.ray").string(), &floor));
    EXPECT_EQ(floor, floor_before);

    save_scene(v, saved, true);
    ASSERT_TRUE(read_file((dir / "parts/floor.ray").string(), &floor));
    EXPECT_NE(floor, floor_before);
    EXPECT_EQ(floor.substr(0, floor.find('\n')), floor_before.substr(0, floor_before.find('\n')));
    EXPECT_NE(floor.find("0.25 0.5 0.75"), std::string::npos) << floor;
    Diagnostics diag;
    const RenderScene back = compile_scene(parse_scene_file(saved, diag));
    EXPECT_EQ(back.materials[5].diffuse, Vec3(0.25, 0.5, 0.75));
    EXPECT_EQ(back.materials[5].texture, 0);

    // The part changed on disk since it was read: an error, and neither file is written.
    write_file_atomic((dir / "parts/floor.ray").string(), "// moved down\n" + floor_before);
    v.edits.materials[5].diffuse = Vec3(0.5);
    v.edits.camera.orbit(0.3, 0);
    const std::string other = (dir / "other.ray").string();
    EXPECT_THROW(save_scene(v, other, true), SceneError);
    EXPECT_FALSE(fs::exists(other));
    ASSERT_TRUE(read_file((dir / "parts/floor.ray").string(), &floor));
    EXPECT_EQ(floor, "// moved down\n" + floor_before);
}

// A big mesh's coarse version for the moving view: about the target's triangles, no triangle
// collapsed, each of one of the source's materials, its bounds within a cell of the source's.
TEST(Viewer, BigMeshesGetACoarseVersionNearTheirShape) {
    Sphere ball;
    ball.centre = Vec3(1, 2, 3);
    ball.radius = 2;
    PreviewMesh mesh = tessellate(ball, 500);  // about 250k triangles
    mesh.materials.assign(mesh.triangle_count(), 0);
    Box box;
    box.centre = Vec3(4, 2, 3);
    box.half = Vec3(0.5);
    PreviewMesh cube = tessellate(box);
    cube.materials.assign(cube.triangle_count(), 1);
    mesh.append(cube);
    ASSERT_GT(mesh.triangle_count(), 200000u);
    const PreviewMesh coarse = decimate(mesh, 20000);
    EXPECT_LE(coarse.triangle_count(), 20000u);
    EXPECT_GT(coarse.triangle_count(), 10000u);
    ASSERT_EQ(coarse.materials.size(), coarse.triangle_count());
    ASSERT_EQ(coarse.normals.size(), coarse.positions.size());
    Bounds3 a, b;
    for (const Vec3& p : mesh.positions) a.extend(p);
    for (const Vec3& p : coarse.positions) b.extend(p);
    const double cell = 5.0 / std::sqrt(20000.0);  // the grid's first guess, along 5 units
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.lo[k], b.lo[k], cell) << k;
        EXPECT_NEAR(a.hi[k], b.hi[k], cell) << k;
    }
    bool both = false;
    for (size_t t = 0; t < coarse.triangle_count(); ++t) {
        const uint32_t* i = &coarse.indices[3 * t];
        ASSERT_TRUE(i[0] != i[1] && i[1] != i[2] && i[0] != i[2]) << t;
        ASSERT_TRUE(coarse.materials[t] == 0 || coarse.materials[t] == 1);
        both |= coarse.materials[t] == 1;
    }
    EXPECT_TRUE(both);  // the small box is still there
    for (const Vec3& n : coarse.normals) EXPECT_NEAR(glm::length(n), 1.0, 1e-9);
    // Small meshes come back as they are; prepare_preview makes coarse versions of big sets only.
    EXPECT_EQ(decimate(cube, 20000).triangle_count(), cube.triangle_count());
}

// A load cancelled while its preview is made stops there (its thread is not kept for seconds
// by a big mesh's tessellation and clustering).
TEST(Viewer, MakingThePreviewStopsWhenCancelled) {
    Sphere ball;
    ball.radius = 2;
    PreviewMesh mesh = tessellate(ball, 500);
    mesh.materials.assign(mesh.triangle_count(), 0);
    std::atomic<bool> cancel{true};
    EXPECT_THROW(decimate(mesh, 20000, &cancel), std::runtime_error);
    cancel = false;
    EXPECT_LE(decimate(mesh, 20000, &cancel).triangle_count(), 20000u);

    const RenderScene scene =
        compile_scene(test::parse("#camera 0 0 5 0 0 -1 0 1 0 0.5\n"
                                  "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 "
                                  "0 1 -1 !!\n#shape_sphere 0 0 0 0 1\n"));
    cancel = true;
    try {
        prepare_preview(scene, 48, &cancel);
        ADD_FAILURE() << "a cancelled preview was made";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "loading cancelled");
    }
    cancel = false;
    EXPECT_GT(prepare_preview(scene, 48, &cancel).sets.at(0).mesh.triangle_count(), 0u);
}

// Clustering a bumpy mesh folds some triangles over; each is wound back so that it faces along
// its normals where its source did (else the two-sided rule draws it dark: black specks).
TEST(Viewer, CoarseTrianglesFaceAlongTheirNormals) {
    PreviewMesh mesh;
    const int n = 400;  // a sphere with bumps, n x n quads
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const double th = M_PI * i / n, ph = 2 * M_PI * j / n;
            const Vec3 d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            mesh.positions.push_back(d * (1 + 0.08 * std::sin(23 * th) * std::sin(19 * ph)));
            mesh.normals.push_back(d);
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const uint32_t a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
            for (uint32_t v : {a, b, c, b, d, c}) mesh.indices.push_back(v);
        }
    mesh.materials.assign(mesh.triangle_count(), 0);
    const auto folded = [](const PreviewMesh& m) {
        size_t count = 0;
        for (size_t t = 0; t < m.triangle_count(); ++t) {
            const uint32_t* v = &m.indices[3 * t];
            const Vec3 e = glm::cross(m.positions[v[1]] - m.positions[v[0]],
                                      m.positions[v[2]] - m.positions[v[0]]);
            count += glm::dot(e, m.normals[v[0]] + m.normals[v[1]] + m.normals[v[2]]) < 0;
        }
        return count;
    };
    const size_t source = folded(mesh);
    const PreviewMesh coarse = decimate(mesh, 20000);
    ASSERT_GT(coarse.triangle_count(), 5000u);
    std::printf("folded: %zu of %zu source, %zu of %zu coarse\n", source, mesh.triangle_count(),
                folded(coarse), coarse.triangle_count());
    EXPECT_LE(folded(coarse), source);  // 974 of 16630 without the rewinding
}

// Undo and redo of the camera, a light and a setting; a gesture is one step; a new edit drops
// the redo steps; opening a file starts a new history.
TEST(Viewer, UndoAndRedoEveryEdit) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const UndoState start{v.edits, v.settings};
    EXPECT_FALSE(v.undo());
    v.edits.camera.orbit(0.2, 0);  // a drag over three frames: one step
    v.track_history(true);
    v.edits.camera.orbit(0.2, 0);
    v.track_history(true);
    v.track_history(false);
    const OrbitCamera turned = v.edits.camera;
    v.edits.lights[0].set_colour(Vec3(0, 0, 3));
    v.track_history(false);
    v.settings.render.max_depth = 2;
    v.settings.render.width = 99;  // the trace's size follows the pane: not an edit
    v.track_history(false);
    EXPECT_EQ(v.history.undo_steps(), 3u);

    ASSERT_TRUE(v.undo());  // the depth
    EXPECT_EQ(v.settings.render.max_depth, 5);
    EXPECT_EQ(v.settings.render.width, 99);
    EXPECT_TRUE(v.edit_pending());
    ASSERT_TRUE(v.undo());  // the colour
    EXPECT_EQ(v.edits.lights[0].diffuse, start.edits.lights[0].diffuse);
    EXPECT_EQ(v.edits.camera, turned);
    ASSERT_TRUE(v.undo());  // the whole drag
    EXPECT_EQ(v.edits.camera, start.edits.camera);
    EXPECT_FALSE(v.undo());

    ASSERT_TRUE(v.redo());
    EXPECT_EQ(v.edits.camera, turned);
    ASSERT_TRUE(v.redo());
    EXPECT_EQ(v.edits.lights[0].diffuse, Vec3(0, 0, 3));
    v.edits.light_on[1] = 0;  // a new edit: the depth's redo is gone
    v.track_history(false);
    EXPECT_FALSE(v.redo());
    ASSERT_TRUE(v.undo());
    EXPECT_EQ(v.edits.light_on[1], 1);

    ASSERT_TRUE(v.open(kLights, false));
    EXPECT_EQ(v.history.undo_steps(), 0u);
    EXPECT_FALSE(v.undo());
}

// Exposure and tonemap change what is shown and what 8-bit files hold, never the trace nor a
// PFM or EXR (linear), and they are no edit for the trace.
TEST(Viewer, ExposureAndTonemapAreForDisplayAndEightBitFiles) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.trace.last_trace = Image(2, 1);
    v.trace.last_trace.set(0, 0, Vec3(0.25, 0.5, 1.0));
    v.trace.last_trace.set(1, 0, Vec3(2.0, 0.0, 0.1));
    v.settings.exposure = 1;
    v.settings.tonemap = Tonemap::Reinhard;
    const std::string png = ::testing::TempDir() + "rt_viewer_exposed.png";
    const std::string pfm = ::testing::TempDir() + "rt_viewer_exposed.pfm";
    save_trace(v, png);
    save_trace(v, pfm);
    TextureImage shown;
    std::string error;
    ASSERT_TRUE(load_texture_image(png, &shown, &error)) << error;
    EXPECT_EQ(shown.rgb[0], to_byte(0.5 / 1.5));  // 0.25 * 2, then x / (1 + x)
    EXPECT_EQ(shown.rgb[3], to_byte(4.0 / 5.0));
    const std::string exr = ::testing::TempDir() + "rt_viewer_exposed.exr";
    save_trace(v, exr);
    const Image linear = load_pfm(pfm), half = load_image(exr);
    ASSERT_EQ(linear.rgb.size(), v.trace.last_trace.rgb.size());
    ASSERT_EQ(half.rgb.size(), v.trace.last_trace.rgb.size());
    for (size_t i = 0; i < linear.rgb.size(); ++i) {
        EXPECT_FLOAT_EQ(static_cast<float>(linear.rgb[i]),
                        static_cast<float>(v.trace.last_trace.rgb[i]));
        // Half keeps 11 significant bits; the tonemapped value would be far off (0.1 -> 0.17).
        EXPECT_NEAR(half.rgb[i], v.trace.last_trace.rgb[i],
                    std::abs(v.trace.last_trace.rgb[i]) * 0x1p-10);
    }
    v.track_history(false);  // a display setting is an undo step, not a restart
    EXPECT_EQ(v.history.undo_steps(), 1u);
}

// A click picks the primitive under it: its shape, its material's name and the file:line of
// its directive; nothing off the scene; frame_light turns the view to a light.
TEST(Viewer, PickNamesTheShapeItsMaterialAndItsDirective) {
    const std::string path = ::testing::TempDir() + "rt_viewer_pick.ray";
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#light_point 1 1 1  0 3 3  1 0 0\n"
                      "#material 0 0 0  0 0 0  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !chalk!\n"
                      "#shape_sphere 0  -1 0 0  0.5\n"
                      "#group_begin\n1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
                      "#shape_box 0  1 0 0  1 1 1\n"
                      "#group_end\n");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(64, 48);
    // x = -1 at depth 5 with tan(0.5) * 4/3: image fraction 0.5 - 1 / (2 * 5 * 0.7284) = 0.363
    ASSERT_TRUE(v.pick(0.363, 0.5));
    EXPECT_EQ(v.ui.selection.shape, "sphere");
    EXPECT_EQ(v.ui.selection.material, "!chalk! (material 0)");
    EXPECT_NE(v.ui.selection.where.find("rt_viewer_pick.ray:4:"), std::string::npos)
        << v.ui.selection.where;
    EXPECT_NEAR(glm::length(v.ui.selection.point - Vec3(-1, 0, 0)), 0.5, 1e-9);  // on it
    EXPECT_NEAR(v.ui.selection.bounds.centre().x, -1, 1e-9);
    EXPECT_EQ(v.ui.selection.groups, "rt_viewer_pick.ray");
    ASSERT_TRUE(v.pick(0.637, 0.5));
    EXPECT_EQ(v.ui.selection.shape, "box");
    EXPECT_NE(v.ui.selection.where.find("rt_viewer_pick.ray:7:"), std::string::npos);
    EXPECT_EQ(v.ui.selection.groups, "rt_viewer_pick.ray > group at line 5");
    EXPECT_FALSE(v.pick(0.5, 0.02));  // the background
    EXPECT_EQ(v.ui.selection.instance, -1);
    v.edits.frame_light(0, v.session.loaded->scene.world_bounds);
    EXPECT_VEC_NEAR(v.edits.camera.target, Vec3(0, 3, 3), 1e-12);
}

// The inspect mode: the tree of the trace's pixel under a click, with the trace's settings;
// its text names the directive; clearing drops it; a new scene drops it too.
TEST(Viewer, InspectExplainsTheTracesPixel) {
    const std::string path = ::testing::TempDir() + "rt_viewer_inspect.ray";
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#light_point 1 1 1  0 3 3  1 0 0\n"
                      "#material 0 0 0  0 0 0  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !chalk!\n"
                      "#shape_sphere 0  0 0 0  1\n");
    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(64, 48);
    v.settings.render.max_depth = 3;
    v.restart_if_due();
    const int version = v.ui.inspect.version;
    ASSERT_TRUE(v.inspect(0.5, 0.5));
    ASSERT_TRUE(v.ui.inspect.tree);
    const PixelTree& t = *v.ui.inspect.tree;
    EXPECT_EQ(t.x, 32);
    EXPECT_EQ(t.y, 24);
    EXPECT_TRUE(t.random);  // the trace's progressive samples are jittered
    ASSERT_TRUE(t.rays.at(0).hit);
    EXPECT_EQ(t.rays[0].depth, 3);  // the trace's settings
    EXPECT_NEAR(glm::length(t.rays[0].point), 1.0, 1e-9);
    EXPECT_NE(v.ui.inspect.text.find("rt_viewer_inspect.ray:4:1"), std::string::npos)
        << v.ui.inspect.text;
    EXPECT_NE(v.ui.inspect.text.find("!chalk!"), std::string::npos);
    EXPECT_GT(v.ui.inspect.version, version);
    EXPECT_FALSE(v.inspect(0.5, 0.02) && v.ui.inspect.tree->rays[0].hit);  // the background
    v.ui.inspect.clear();
    EXPECT_FALSE(v.ui.inspect.tree);
    ASSERT_TRUE(v.inspect(0.5, 0.5));
    ASSERT_TRUE(v.open(path, false));
    EXPECT_FALSE(v.ui.inspect.tree);
}

// Waits until the comparison has the running trace's reference (take_trace(), as the panes do
// every frame).
bool wait_compared(ViewerState& v) {
    for (int i = 0; i < 5000; ++i) {
        v.restart_if_due();
        take_trace(v);
        if (!v.edit_pending() && v.ui.compare.current && v.ui.compare.result) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
}

// The comparison pane: an image raytrace rendered compares equal; one with a changed patch is
// off there, and only there; a file that cannot be read says so and keeps the comparison.
TEST(Viewer, ComparesAnImageWithTheReferenceAtItsSizeAndCamera) {
    const std::string path = ::testing::TempDir() + "rt_viewer_compare.ray";
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#light_point 1 1 1  0 3 3  1 0 0\n"
                      "#material .1 .1 .1  0 0 0  .8 .5 .2  .5 .5 .5  20  0 0 0  1  -1 !!\n"
                      "#shape_sphere 0  0 0 0  1\n");
    // raytrace's image at 48x36 (its defaults: 1 spp, the pixel centre).
    Diagnostics diag;
    const RenderScene scene = compile_scene(parse_scene_file(path, diag));
    RenderSettings rs;
    rs.width = 48;
    rs.height = 36;
    RenderState state;
    ASSERT_TRUE(render_samples(state, scene, make_render_plan(scene, rs), rs, 1));
    const std::string theirs = ::testing::TempDir() + "rt_viewer_theirs.png";
    save_image(state.image(), theirs);

    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(200, 100);
    v.edits.camera.orbit(0.5, 0.2);  // a view away from the file's camera
    v.mark_edited();
    restart(v);
    ASSERT_TRUE(compare_with(v, theirs));
    EXPECT_NE(v.messages.text.find("(48x36)"), std::string::npos) << v.messages.text;
    v.set_trace_size(200, 100);  // the pane's size no longer counts
    EXPECT_EQ(v.trace.width(), 48);
    EXPECT_EQ(v.trace.height(), 36);
    EXPECT_EQ(v.settings.image_w, 48);  // the panes take the image's aspect
    ASSERT_TRUE(wait_compared(v));
    const ImageComparison& r = *v.ui.compare.result;
    EXPECT_EQ(r.mean(), 0.0) << compare_status(v.ui.compare);
    EXPECT_EQ(r.share_off, 0.0);
    EXPECT_NE(status_text(v).find("mean |diff| 0.00"), std::string::npos) << status_text(v);

    // A patch of their image changed: off there only, the largest difference in it.
    Image changed = load_image(theirs);
    for (int y = 10; y < 14; ++y)
        for (int x = 20; x < 24; ++x) changed.set(x, y, changed.at(x, y) + Vec3(0.2, 0.0, 0.0));
    const std::string patched = ::testing::TempDir() + "rt_viewer_patched.png";
    save_image(changed, patched);
    ASSERT_TRUE(compare_with(v, patched));
    ASSERT_TRUE(wait_compared(v));
    const ImageComparison& p = *v.ui.compare.result;
    EXPECT_NEAR(p.share_off, 16.0 / (48 * 36), 1e-9);
    EXPECT_GE(p.max_x, 20);
    EXPECT_LT(p.max_x, 24);
    EXPECT_GE(p.max_y, 10);
    EXPECT_LT(p.max_y, 14);
    EXPECT_NEAR(p.max_diff, 51, 1.01);  // 0.2 x 255, to the byte
    const Image heat = compare_pane_image(v.ui.compare, 0, Tonemap::Clamp);
    EXPECT_GT(heat.at(21, 11).x, heat.at(5, 5).x);  // hot where it differs
    EXPECT_NE(compare_probe_text(v.ui.compare, 21, 11).find("off by 5"), std::string::npos)
        << compare_probe_text(v.ui.compare, 21, 11);
    // The reference's ray tree there: the pixel centre (raytrace's sample 0).
    ASSERT_TRUE(v.inspect(21.5 / 48, 11.5 / 36));
    EXPECT_FALSE(v.ui.inspect.tree->random);

    // Not an image: said, and the comparison stays.
    EXPECT_FALSE(compare_with(v, path));
    EXPECT_TRUE(v.messages.is_error);
    EXPECT_NE(v.messages.text.find("cannot compare with " + path), std::string::npos)
        << v.messages.text;
    EXPECT_FALSE(compare_with(v, ::testing::TempDir() + "rt_no_such_image.png"));
    EXPECT_EQ(v.ui.compare.path, patched);

    const int version = v.ui.compare.version;
    stop_compare(v);
    EXPECT_FALSE(v.ui.compare.active());
    EXPECT_GT(v.ui.compare.version, version) << "the pane would keep the old image";
    v.set_trace_size(200, 100);
    EXPECT_EQ(v.trace.width(), 200);
}

// "Render and save image": the scene as edited at the chosen size and samples, in the
// background, written when done; a cancelled job writes nothing.
TEST(Viewer, ImagesRenderInTheBackgroundAtTheChosenSize) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.edits.light_on[0] = v.edits.light_on[1] = v.edits.light_on[2] = 0;  // all dark
    v.settings.headlight = false;
    const std::string path = ::testing::TempDir() + "rt_viewer_job.png";
    std::filesystem::remove(path);
    render_image(v, path, 48, 36, 2);
    for (int i = 0; i < 2000 && v.jobs.image.running(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    v.poll_files();  // takes the result
    EXPECT_NE(v.messages.text.find("saved " + path + " (48x36, 2 spp"), std::string::npos)
        << v.messages.text;
    TextureImage im;
    std::string error;
    ASSERT_TRUE(load_texture_image(path, &im, &error)) << error;
    EXPECT_EQ(im.width, 48);
    EXPECT_EQ(im.height, 36);
    // The edits reached it: no light is on, so only the ambient term lights it (dim).
    int bright = 0;
    for (uint8_t c : im.rgb) bright += c > 200;
    EXPECT_EQ(bright, 0);

    const std::string big = ::testing::TempDir() + "rt_viewer_cancelled.png";
    std::filesystem::remove(big);
    render_image(v, big, 4000, 3000, 64);
    v.jobs.image.cancel();
    EXPECT_FALSE(v.jobs.image.running());
    EXPECT_FALSE(std::filesystem::exists(big));
}

// The panel and a dropped image read the image to compare with off the interface thread: the
// call returns before the image is read, and poll_files() starts the comparison once it is. A
// directory is named as one (it was "no such file").
TEST(Viewer, ImagesToCompareWithAreReadInTheBackground) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const std::string theirs = ::testing::TempDir() + "rt_viewer_bg_theirs.png";
    Image img(40, 30);
    save_image(img, theirs);
    compare_in_background(v, theirs);
    if (have_threads()) {
        EXPECT_FALSE(v.ui.compare.active());  // not yet: it is being read
        EXPECT_NE(v.messages.text.find("reading " + theirs), std::string::npos) << v.messages.text;
    }
    for (int i = 0; i < 2000 && v.jobs.compare.busy(); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        v.poll_files();
    }
    ASSERT_TRUE(v.ui.compare.active()) << v.messages.text;
    EXPECT_EQ(v.trace.width(), 40);
    EXPECT_NE(v.messages.text.find("comparing with rt_viewer_bg_theirs.png (40x30)"),
              std::string::npos)
        << v.messages.text;

    const std::string dir = ::testing::TempDir() + "rt_viewer_bg_dir";
    std::filesystem::create_directories(dir);
    compare_in_background(v, dir);
    for (int i = 0; i < 2000 && v.jobs.compare.busy(); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        v.poll_files();
    }
    EXPECT_EQ(v.messages.text,
              "cannot compare with " + dir + ": '" + dir + "' is a directory, not a regular file");
    EXPECT_EQ(v.ui.compare.path, theirs);  // the comparison stays
    EXPECT_FALSE(compare_with(v, dir));
    EXPECT_EQ(v.messages.text,
              "cannot compare with " + dir + ": '" + dir + "' is a directory, not a regular file");
}

// An image over --max-pixels is refused with the budget's message, as raytrace refuses it, before
// a job starts or a pixel is allocated (32768x32768 ended in a bare std::bad_alloc).
TEST(Viewer, ImagesOverTheBudgetAreRefused) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const std::string path = ::testing::TempDir() + "rt_viewer_huge.png";
    std::filesystem::remove(path);
    render_image(v, path, 32768, 32768, 1);
    EXPECT_FALSE(v.jobs.image.running());
    EXPECT_NE(v.messages.text.find("cannot render " + path +
                                   ": an image of 32768x32768 pixels (1073741824) is larger than "
                                   "the budget of 67108864 pixels (8192x8192); --max-pixels "
                                   "raises it"),
              std::string::npos)
        << v.messages.text;
    render_animation(v, ::testing::TempDir() + "rt_viewer_huge_%04d.png", 2, 16384, 16384, 1, "");
    EXPECT_FALSE(v.jobs.image.running());
    EXPECT_NE(v.messages.text.find("an image of 16384x16384 pixels"), std::string::npos)
        << v.messages.text;
    EXPECT_FALSE(std::filesystem::exists(path));
}

// Opening in the background: the open scene stays until the new one is read; a cancelled load
// leaves it; a failed one says why and leaves it too.
TEST(Viewer, FilesOpenInTheBackgroundAndCanBeCancelled) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    const int id = v.session.loaded->id;
    auto wait = [&] {
        for (int i = 0; i < 2000 && v.jobs.loader.busy(); ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            v.poll_files();
        }
    };
    v.open_in_background(RT_SOURCE_DIR "/scenes/shapes.ray");
    EXPECT_EQ(v.session.loaded->id, id);  // still the open scene, interactive
    wait();
    EXPECT_FALSE(v.jobs.loader.busy());
    EXPECT_GT(v.session.loaded->id, id);
    EXPECT_NE(v.session.loaded->path.find("shapes.ray"), std::string::npos);

    const int shapes = v.session.loaded->id;
    v.open_in_background(kLights);
    v.cancel_loading();
    EXPECT_FALSE(v.jobs.loader.busy());
    for (int i = 0; i < 100; ++i) {  // the abandoned load's result never arrives
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        v.poll_files();
    }
    EXPECT_EQ(v.session.loaded->id, shapes);
    EXPECT_NE(v.messages.text.find("cancelled"), std::string::npos) << v.messages.text;

    v.open_in_background(RT_SOURCE_DIR "/scenes/no_such_file.ray");
    wait();
    EXPECT_EQ(v.session.loaded->id, shapes);
    EXPECT_TRUE(v.messages.is_error);
    EXPECT_NE(v.messages.text.find("no_such_file.ray"), std::string::npos) << v.messages.text;
}

// A mesh of n triangles written to a temporary file; its path.
std::string write_mesh(const std::string& name, int n) {
    std::string text =
        "#camera 0 0 5 0 0 -1 0 1 0 0.5\n"
        "#material 0 0 0 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 1 0 0 0 1 -1 !m!\n";
    for (int k = 0; k < n + 2; ++k)
        text += "#vertex " + std::to_string(k / 2) + " " + std::to_string(k % 2) + " 0 0 0 1 0 0\n";
    for (int k = 0; k < n; ++k)
        text += "#shape_triangle 0 " + std::to_string(k) + " " + std::to_string(k + 1) + " " +
                std::to_string(k + 2) + "\n";
    const std::string path = ::testing::TempDir() + name;
    write_file_atomic(path, text);
    return path;
}

// A load shows the bytes it has parsed of those it read, and a cancelled one stops parsing.
TEST(Viewer, ALoadCountsItsBytesAndACancelledOneStops) {
    const std::string path = write_mesh("rt_viewer_progress.ray", 100000);
    const uint64_t size = std::filesystem::file_size(path);
    SceneLoader loader;
    LoadRequest request;
    request.path = path;
    request.for_preview = false;
    loader.start(request);
    std::pair<uint64_t, uint64_t> seen{0, 0};
    LoadResult result;
    std::string taken;
    for (int i = 0; i < 20000 && !loader.take(&result, &taken); ++i) {
        const LoadStatus st = loader.status();
        EXPECT_LE(st.parsed, st.read);
        EXPECT_LE(st.compiled, st.to_compile);
        if (st.read > 0) seen = {st.parsed, st.read};
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    ASSERT_TRUE(result.scene) << result.error;
    EXPECT_EQ(seen.second, size);  // the total is known from the start

    // Cancelled while parsing: load_scene's parse stops with "loading cancelled".
    LoadProgress progress;
    std::thread load([&] { result = load_scene(request, &progress); });
    while (progress.parse.done.load() == 0) std::this_thread::yield();
    progress.cancel();
    load.join();
    EXPECT_FALSE(result.scene);
    EXPECT_NE(result.error.find("loading cancelled"), std::string::npos) << result.error;
    EXPECT_LT(progress.parse.done.load(), size);
    EXPECT_EQ(progress.compile.total.load(), 0u);  // no compile started

    // Loaded to the end: the compile's share is all done.
    LoadProgress whole;
    result = load_scene(request, &whole);
    ASSERT_TRUE(result.scene) << result.error;
    EXPECT_EQ(whole.parse.done.load(), size);
    EXPECT_GE(whole.compile.total.load(), 3u * 100000);
    EXPECT_EQ(whole.compile.done.load(), whole.compile.total.load());
    std::filesystem::remove(path);
}

// The one restart path under load: the trace restarted 1000 times with an edit each time while
// it runs (the ThreadSanitizer run of scripts/test.sh checks this for races).
TEST(Viewer, ATraceRestartedAThousandTimesWithEdits) {
    ViewerState v(kLights, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(24, 18);
    int restarts = 0;
    for (int i = 0; i < 1000; ++i) {
        v.edits.camera.orbit(0.01, 0.0);
        v.edits.lights[0].position.x += 0.001;
        v.settings.render.shadows = i % 3 != 0;
        v.mark_edited();
        for (int k = 0; k < 5000 && !v.restart_if_due(); ++k) {  // up to 1 s
            v.trace.take_image();  // what the interface thread does meanwhile
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        restarts += !v.edit_pending();
        if (i % 100 == 0) (void)v.trace.tracer.status();
    }
    EXPECT_EQ(restarts, 1000);
    EXPECT_EQ(v.session.loaded->scene.lights[0].position.x, v.edits.lights[0].position.x);
}

// load_scene alone, no ViewerState: a file that does not parse gives no scene and an error
// naming the file, line and column; a texture that cannot be opened says that checker
// stand-ins would open it; the scene that opens comes with its preview geometry on request.
TEST(ViewerLoad, LoadSceneReturnsTheSceneOrTheErrorAtItsPlace) {
    const auto load = [](const std::string& path, bool for_preview = true) {
        LoadRequest request;
        request.path = path;
        request.for_preview = for_preview;
        return load_scene(request);
    };
    const std::string bad = ::testing::TempDir() + "rt_viewer_load_bad.ray";
    write_file_atomic(bad, "#light_dir 1 1 1  0 -1 0\n\n#shape_sphere 0 0 0 0 oops\n");
    const LoadResult failed = load(bad);
    EXPECT_FALSE(failed.scene);
    EXPECT_FALSE(failed.textures_missing);
    EXPECT_NE(failed.error.find("rt_viewer_load_bad.ray:3:"), std::string::npos) << failed.error;

    const std::string texture = ::testing::TempDir() + "rt_viewer_load_texture.ray";
    write_file_atomic(texture,
                      "#texture no_such_texture.png\n"
                      "#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  0 !m!\n"
                      "#light_dir 1 1 1  0 -1 0\n#shape_sphere 0 0 0 0 1\n");
    const LoadResult refused = load(texture);
    EXPECT_FALSE(refused.scene);
    EXPECT_TRUE(refused.textures_missing);
    EXPECT_NE(refused.error.find("no_such_texture.png"), std::string::npos) << refused.error;

    const LoadResult opened = load(kLights, false);
    ASSERT_TRUE(opened.scene) << opened.error;
    EXPECT_EQ(opened.error, "");
    EXPECT_EQ(opened.scene->path, kLights);
    EXPECT_EQ(opened.scene->desc.lights.size(), 3u);
    EXPECT_FALSE(opened.scene->scene.instances.empty());
}

// History alone, without a viewer: an edit becomes a step once no gesture is under way, the
// window's settings are not an edit, and undo and redo walk the steps.
TEST(ViewerHistory, StepsAfterTheGestureUndoAndRedo) {
    History h;
    SceneEdits edits;
    ViewSettings settings;
    h.reset({edits, settings});
    settings.target_spp = 64;
    h.track(edits, settings, true);  // a drag under way: not yet a step
    EXPECT_EQ(h.undo_steps(), 0u);
    h.track(edits, settings, false);
    EXPECT_EQ(h.undo_steps(), 1u);
    settings.render.width = 99;  // follows the pane: no step
    settings.panel_w = 200;
    h.track(edits, settings, false);
    EXPECT_EQ(h.undo_steps(), 1u);

    UndoState back;
    ASSERT_TRUE(h.undo({edits, settings}, &back));
    EXPECT_EQ(back.settings.target_spp, 256);
    EXPECT_EQ(h.undo_steps(), 0u);
    EXPECT_EQ(h.redo_steps(), 1u);
    EXPECT_FALSE(h.undo(back, &back));  // nothing more to undo
    h.settle(back);
    UndoState forward;
    ASSERT_TRUE(h.redo(back, &forward));
    EXPECT_EQ(forward.settings.target_spp, 64);
    EXPECT_EQ(h.redo_steps(), 0u);
    EXPECT_EQ(h.undo_steps(), 1u);
    // A new edit after an undo drops what redo held.
    ASSERT_TRUE(h.undo(forward, &back));
    h.settle(back);
    edits.camera.distance = 7;
    h.track(edits, back.settings, false);
    EXPECT_EQ(h.redo_steps(), 0u);
    EXPECT_EQ(h.undo_steps(), 1u);
}

// The script's inspect and compare probe take the same coordinates: the pixel X, Y of the trace
// (column, row from the top), whole numbers; a fraction is an error that says so, not pixel 0,0.
TEST(Viewer, ScriptInspectAndCompareProbeTakeTheSamePixels) {
    const std::string path = ::testing::TempDir() + "rt_viewer_probe.ray";
    write_file_atomic(path,
                      "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
                      "#light_point 1 1 1  0 3 3  1 0 0\n"
                      "#material .1 .1 .1  0 0 0  .8 .5 .2  .5 .5 .5  20  0 0 0  1  -1 !!\n"
                      "#shape_sphere 0  0 0 0  1\n");
    Diagnostics diag;
    const RenderScene scene = compile_scene(parse_scene_file(path, diag));
    RenderSettings rs;
    rs.width = 48;
    rs.height = 36;
    RenderState state;
    ASSERT_TRUE(render_samples(state, scene, make_render_plan(scene, rs), rs, 1));
    const std::string theirs = ::testing::TempDir() + "rt_viewer_probe.png";
    save_image(state.image(), theirs);

    ViewerState v(path, false);
    ASSERT_TRUE(v.session.loaded) << v.messages.text;
    v.set_trace_size(48, 36);
    restart(v);
    const std::optional<std::string> said = run_command(v, line(1, "inspect", {"30", "20"}));
    ASSERT_TRUE(said);
    EXPECT_NE(said->find("inspected pixel 30,20\npixel 30,20, sample 0"), std::string::npos)
        << *said;
    ASSERT_TRUE(v.ui.inspect.tree);
    EXPECT_EQ(v.ui.inspect.tree->x, 30);
    EXPECT_EQ(v.ui.inspect.tree->y, 20);
    // A fraction is refused, naming it (before: an image fraction, so 0.5 0.5 was the centre
    // and 30 20 out of range; compare probe took 0.5 as pixel 0).
    v.ui.inspect.clear();
    try {
        run_command(v, line(2, "inspect", {"0.5", "0.5"}));
        ADD_FAILURE() << "inspect 0.5 0.5 was taken";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "inspect: '0.5' is not a whole number (from 0 to 47)");
    }
    EXPECT_FALSE(v.ui.inspect.tree);
    EXPECT_THROW(run_command(v, line(2, "inspect", {"48", "0"})), std::runtime_error);
    EXPECT_THROW(run_command(v, line(2, "inspect", {"0", "36"})), std::runtime_error);

    ASSERT_TRUE(compare_with(v, theirs));
    ASSERT_TRUE(wait_compared(v));
    const std::optional<std::string> probed =
        run_command(v, line(3, "compare", {"probe", "30", "20"}));
    ASSERT_TRUE(probed);
    EXPECT_NE(probed->find("compare pixel 30,20: theirs"), std::string::npos) << *probed;
    ASSERT_TRUE(v.ui.inspect.tree);
    EXPECT_EQ(v.ui.inspect.tree->x, 30);  // the same pixel as inspect 30 20
    EXPECT_EQ(v.ui.inspect.tree->y, 20);
    try {
        run_command(v, line(4, "compare", {"probe", "0.5", "0.5"}));
        ADD_FAILURE() << "compare probe 0.5 0.5 was taken";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "compare: '0.5' is not a whole number (from 0 to 47)");
    }
    EXPECT_EQ(v.ui.compare.probe_x, 30);  // unchanged
}

// rayview --help lists the compare commands of a script beside inspect's.
TEST(Viewer, HelpListsTheCompareScriptCommands) {
    const std::string help = script_commands_help();
    for (const char* c : {"compare PATH", "compare view", "compare flip", "compare tolerance K",
                          "compare neighbourhood on|off", "compare spp N", "compare probe X Y",
                          "compare off", "wait-compare", "inspect X Y"})
        EXPECT_NE(help.find(c), std::string::npos) << c;
}

}  // namespace
}  // namespace rt::view
