// Animated scenes (spec §14): a frame at time t renders like the static scene whose joints hold
// J(t) (scene_at_time), animate() gives what a compile at that time gives, joints singular at a
// time are left out with a warning, and the default camera follows the animation.
#include <filesystem>
#include <fstream>

#include "rt/accel/intersect.h"
#include "rt/scene/scene_time.h"
#include "test_util.h"

namespace rt {
namespace {

class Animate : public ::testing::Test {
public:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() /
              ("rt_animate_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const auto p = dir / name;
        std::ofstream(p) << text;
        return p.string();
    }
    SceneDesc load(const std::string& name, Diagnostics* diag = nullptr) {
        Diagnostics local;
        return parse_scene_file((dir / name).string(), diag ? *diag : local);
    }
    std::filesystem::path dir;
};

// Two DOFs over four keys (column-major blocks): "arm" turns about z and moves, "hand" turns
// about x; a sub file instanced inside the hand.
constexpr const char* kKey =
    "#DOFS 2 arm hand #DURATION 2 #FRAMES 4\n"
    "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1     1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
    "0 1 0 0  -1 0 0 0  0 0 1 0  1 0 0 1    1 0 0 0  0 0 1 0  0 -1 0 0  0 0 0 1\n"
    "-1 0 0 0  0 -1 0 0  0 0 1 0  1 1 0 1   1 0 0 0  0 -1 0 0  0 0 -1 0  0 0 0 1\n"
    "0 -1 0 0  1 0 0 0  0 0 1 0  0 1 0 1    1 0 0 0  0 0 -1 0  0 1 0 0  0 0 0 1\n";

constexpr const char* kMaterials =
    "#material_num 2\n"
    "#material 0 0 0  .2 .2 .2  .7 .3 .2  .3 .3 .3  30  0 0 0  1 -1 !red!\n"
    "#material 0 0 0  .1 .1 .1  .2 .6 .8  0 0 0  1  0 0 0  1 -1 !blue!\n";

std::string figure(bool camera) {
    std::string s = camera ? "#camera 0 1 9  0 0 -1  0 1 0  0.6\n" : "";
    s += std::string(
             "#background .1 .1 .1\n#ambient .2 .2 .2\n#light_num 1\n"
             "#light_point 1 1 1  4 6 8  1 0 0\n") +
         kMaterials +
         "#vertex_num 3\n#vertex -5 -2 -5 0 0 0 0 0\n#vertex 5 -2 -5 0 0 0 0 0\n"
         "#vertex 0 -2 5 0 0 0 0 0\n"
         "#ray_file_num 1\n#ray_file sub.ray\n#key_file_num 1\n#key_file fig.key\n"
         "#shape_triangle 1 0 1 2\n"
         "#joint_begin arm\n"
         "  #shape_box 0  1 0 0  2 .4 .4\n"
         "  #group_begin 1 0 0 2  0 1 0 .3  0 0 1 0  0 0 0 1\n"
         "    #joint_begin hand\n"
         "      #shape_sphere 1  0 0 0  .5\n"
         "      #group_begin 1 0 0 0  0 1 0 .8  0 0 1 0  0 0 0 1\n"
         "        #ray_file_instance 0\n"
         "      #group_end\n"
         "    #joint_end\n"
         "  #group_end\n"
         "#joint_end\n";
    return s;
}

constexpr const char* kSub =
    "#material_num 1\n#material 0 0 0  .1 .1 .1  .9 .9 .2  0 0 0  1  0 0 0  1 -1 !!\n"
    "#shape_cylinder 0  0 0 0  .2 .6\n";

void write_figure(Animate& t, bool camera = true) {
    t.write("fig.key", kKey);
    t.write("sub.ray", kSub);
    t.write("fig.ray", figure(camera));
}

Image image_of(const RenderScene& scene) { return test::render(scene, 48, 36); }

// The mean over pixels of the largest channel difference, and the count of pixels that differ
// in some channel.
std::pair<double, int> compare(const Image& a, const Image& b) {
    double sum = 0;
    int differ = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const Vec3 d = glm::abs(a.at(x, y) - b.at(x, y));
            sum += max_component(d);
            differ += max_component(d) > 0;
        }
    return {sum / (a.width * a.height), differ};
}

TEST_F(Animate, AFrameRendersLikeTheStaticSceneOfItsJointValues) {
    write_figure(*this);
    const SceneDesc desc = load("fig.ray");
    ASSERT_EQ(desc.tracks.size(), 2u);
    for (double t : {0.0, 0.3, 1.1, 2.75, -0.4}) {
        for (Interpolation in : {Interpolation::Linear, Interpolation::CatmullRom}) {
            const SceneTime time{t, in, Rotation::Quaternion};
            const RenderScene frame = compile_scene(desc, nullptr, time);
            const SceneDesc still = scene_at_time(desc, time);
            EXPECT_TRUE(still.tracks.empty());
            const RenderScene reference = compile_scene(still);
            // Same surfaces: the joints are instances in one, flattened groups in the other, so
            // hit distances agree to rounding; the pictures are the same, pixel for pixel.
            int hits = 0;
            for (int i = 0; i < 400; ++i) {
                const double x = -4 + 8 * (i % 20) / 19.0, y = -2.5 + 5 * (i / 20) / 19.0;
                const Ray r{{0, 1, 9}, glm::normalize(Vec3(x, y, 0) - Vec3(0, 1, 9))};
                Hit a, b;
                const bool ha = intersect(frame, r, {1e-9, kInf}, &a);
                const bool hb = intersect(reference, r, {1e-9, kInf}, &b);
                ASSERT_EQ(ha, hb) << "t " << t << " ray " << i;
                if (!ha) continue;
                EXPECT_NEAR(a.t, b.t, 1e-9 * b.t);
                ++hits;
            }
            EXPECT_GT(hits, 60);
            const auto [mean, differ] = compare(image_of(frame), image_of(reference));
            EXPECT_EQ(differ, 0) << "t " << t << ", mean difference " << mean;
        }
    }
}

TEST_F(Animate, AnimateGivesWhatACompileAtThatTimeGives) {
    write_figure(*this, false);  // no camera: the default camera frames each frame's bounds
    const SceneDesc desc = load("fig.ray");
    RenderScene scene = compile_scene(desc);
    const size_t sets = scene.sets.size();
    const void* static_nodes = scene.sets[0].bvh.nodes.data();
    for (double t : {0.5, 1.25, 3.9, 0.5}) {
        const SceneTime time{t, Interpolation::CatmullRom, Rotation::Quaternion};
        animate(scene, desc, time);
        const RenderScene fresh = compile_scene(desc, nullptr, time);
        EXPECT_EQ(scene.sets.size(), sets);
        EXPECT_EQ(scene.sets[0].bvh.nodes.data(), static_nodes);  // no set was built again
        ASSERT_EQ(scene.instances.size(), fresh.instances.size());
        for (size_t i = 0; i < fresh.instances.size(); ++i)
            EXPECT_EQ(scene.instances[i].world_from_set.m, fresh.instances[i].world_from_set.m);
        EXPECT_EQ(scene.world_bounds.lo, fresh.world_bounds.lo);
        EXPECT_EQ(scene.world_bounds.hi, fresh.world_bounds.hi);
        const auto [mean, differ] = compare(image_of(scene), image_of(fresh));
        EXPECT_EQ(differ, 0) << "t " << t;
    }
    // The frames differ from each other: the figure moves.
    RenderScene other = compile_scene(desc, nullptr, SceneTime{1.0});
    EXPECT_GT(compare(image_of(scene), image_of(other)).second, 20);
    // Without a time again: key 0 as read, as the static compile.
    animate(scene, desc, std::nullopt);
    EXPECT_EQ(compare(image_of(scene), image_of(compile_scene(desc))).second, 0);
}

TEST_F(Animate, TheDefaultCameraFollowsTheAnimation) {
    write_figure(*this, false);
    const SceneDesc desc = load("fig.ray");
    RenderScene scene = compile_scene(desc);
    const Bounds3 at0 = scene.world_bounds;
    animate(scene, desc, SceneTime{1.0, Interpolation::Nearest});  // key 2: the arm points to -x
    EXPECT_LT(scene.world_bounds.lo.x, at0.lo.x + 1e-9);
    EXPECT_NE(scene.world_bounds.hi.y, at0.hi.y);
    // Tight: the bounds of the static compile at that time.
    const RenderScene fresh =
        compile_scene(scene_at_time(desc, SceneTime{1.0, Interpolation::Nearest}));
    EXPECT_VEC_NEAR(scene.world_bounds.lo, fresh.world_bounds.lo, 1e-12);
    EXPECT_VEC_NEAR(scene.world_bounds.hi, fresh.world_bounds.hi, 1e-12);
}

TEST_F(Animate, AJointSingularAtATimeIsLeftOutWithAWarning) {
    // Spec §14.6: with `matrix`, halfway between R_z(0) and R_z(180) the 3x3 is singular.
    write("s.key",
          "#DOFS 1 arm #DURATION 2 #FRAMES 2\n"
          "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1   -1 0 0 0  0 -1 0 0  0 0 1 0  0 0 0 1\n");
    write("s.ray", std::string("#camera 0 0 9  0 0 -1  0 1 0  0.6\n#light_num 0\n") + kMaterials +
                       "#key_file s.key\n#shape_sphere 1  3 0 0 1\n"
                       "#joint_begin arm\n#shape_sphere 0  0 0 0 1\n#joint_end\n");
    const SceneDesc desc = load("s.ray");
    const SceneTime half{0.5, Interpolation::Linear, Rotation::Matrix};
    Diagnostics diag;
    RenderScene scene = compile_scene(desc, nullptr, half, &diag);
    ASSERT_EQ(diag.warnings().size(), 1u);
    EXPECT_EQ(diag.warnings()[0].str(), (dir / "s.ray").string() +
                                            ":8:14: warning: joint 'arm' is singular at t = "
                                            "0.5; its shapes are omitted");
    Hit h;
    EXPECT_FALSE(intersect(scene, {{0, 0, 9}, {0, 0, -1}}, {0, kInf}, &h));  // the arm is gone
    EXPECT_TRUE(intersect(scene, {{3, 0, 9}, {0, 0, -1}}, {0, kInf}, &h));   // the rest is not
    Diagnostics later;
    animate(scene, desc, SceneTime{0.25, Interpolation::Linear, Rotation::Matrix}, &later);
    EXPECT_TRUE(later.warnings().empty());
    EXPECT_TRUE(intersect(scene, {{0, 0, 9}, {0, 0, -1}}, {0, kInf}, &h));
    // The static scene of that time has an empty group there.
    EXPECT_FALSE(intersect(compile_scene(scene_at_time(desc, half)), {{0, 0, 9}, {0, 0, -1}},
                           {0, kInf}, &h));
}

TEST_F(Animate, JointsSharingADofMoveTogether) {
    write("k.key",
          "#DOFS 1 slide #DURATION 1 #FRAMES 2\n"
          "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1   1 0 0 0  0 1 0 0  0 0 1 0  0 4 0 1\n");
    write("t.ray", std::string("#camera 0 0 9  0 0 -1  0 1 0  0.6\n") + kMaterials +
                       "#key_file k.key\n"
                       "#joint_begin slide\n#shape_sphere 0  -2 0 0 .5\n#joint_end\n"
                       "#joint_begin slide\n#shape_sphere 1  2 0 0 .5\n#joint_end\n");
    const SceneDesc desc = load("t.ray");
    EXPECT_EQ(desc.tracks.size(), 1u);
    const RenderScene s = compile_scene(desc, nullptr, SceneTime{0.5, Interpolation::Linear});
    Hit h;
    for (double x : {-2.0, 2.0}) {
        EXPECT_TRUE(intersect(s, {{x, 4, 9}, {0, 0, -1}}, {0, kInf}, &h)) << x;
        EXPECT_FALSE(intersect(s, {{x, 0, 9}, {0, 0, -1}}, {0, kInf}, &h)) << x;
    }
}

TEST_F(Animate, AJointInsideACsgNodeIsCompiledAtEachTime) {
    write("k.key",
          "#DOFS 1 cut #DURATION 1 #FRAMES 2\n"
          "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1   1 0 0 0  0 1 0 0  0 0 1 0  3 0 0 1\n");
    write("c.ray",
          "#camera 0 0 9  0 0 -1  0 1 0  0.6\n"
          "#material 0 0 0  .2 .2 .2  .7 .3 .2  0 0 0  1  0 0 0  1  -1 !!\n"
          "#key_file k.key\n"
          "#shape_difference #shape_box 0  0 0 0  2 2 2\n"
          "  #dynamic_affine cut #shape_sphere 0  0 0 1  1.3\n");
    const SceneDesc desc = load("c.ray");
    RenderScene scene = compile_scene(desc);
    EXPECT_TRUE(scene.rig.recompile);
    Hit h;
    // Key 0: the sphere bites the front of the box; the ray meets the bite's wall at z = -0.3.
    ASSERT_TRUE(intersect(scene, {{0, 0, 9}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_NEAR(h.t, 9.3, 1e-9);
    scene.lights.push_back(Light{});  // what the caller set stays, as without CSG
    scene.camera->position = Vec3(0, 0, 7);
    ASSERT_EQ(scene.materials.size(), 2u);       // the file's, then the V0 default
    scene.materials[0].diffuse = Vec3(0, 1, 0);  // edited, as the viewer does at its restart
    animate(scene, desc, SceneTime{0.5, Interpolation::Nearest});  // key 1: moved away
    ASSERT_TRUE(intersect(scene, {{0, 0, 9}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_NEAR(h.t, 8.0, 1e-9);
    EXPECT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.camera->position, Vec3(0, 0, 7));
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[0].diffuse, Vec3(0, 1, 0));
}

}  // namespace
}  // namespace rt
