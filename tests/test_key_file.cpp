// The .key grammar (spec §14.1) and the binding of joints to DOFs (§14.2): every key kept, the
// errors at their file:line:col, the warnings counted per file, and the course's own files (the
// public Homework4 scenes: mine.key's non-affine and singular keys, test.key's 18-DOF figure).
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <iostream>

#include "rt/accel/intersect.h"
#include "rt/scene/scene_time.h"
#include "rt/util/sanitizers.h"
#include "test_util.h"

namespace rt {
namespace {

namespace fs = std::filesystem;

// Caps the address space of this process at `extra` bytes more than it maps now, so that an
// allocation larger than that fails at once (std::bad_alloc) instead of filling memory. Not under
// AddressSanitizer or ThreadSanitizer, whose shadow memory needs an address space without a cap.
void cap_address_space(uint64_t extra) {
#if defined(RT_ASAN) || defined(RT_TSAN)
    (void)extra;
#else
    uint64_t pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    const uint64_t limit = pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) + extra;
    const rlimit cap{limit, limit};
    setrlimit(RLIMIT_AS, &cap);
#endif
}

class KeyFiles : public ::testing::Test {
public:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("rt_key_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const fs::path p = dir / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p) << text;
        return p.string();
    }
    // The error of loading a .ray file that names `key` as its key file and has one joint "a".
    std::string error_with_key(const std::string& key) {
        write("k.key", key);
        write("t.ray", "#key_file k.key\n#joint_begin a\n#shape_sphere -1 0 0 0 1\n#joint_end\n");
        Diagnostics diag;
        try {
            parse_scene_file((dir / "t.ray").string(), diag);
        } catch (const SceneError& e) {
            const std::string prefix = dir.string() + "/";
            std::string s = e.what();
            for (size_t at; (at = s.find(prefix)) != std::string::npos;) s.erase(at, prefix.size());
            return s.substr(0, s.find('\n'));
        }
        return "";
    }
    fs::path dir;
};

const std::string kId = " 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";

TEST_F(KeyFiles, EveryKeyOfEveryBoundDofIsKept) {
    write("k.key", "// a comment\n#DOFS 2 a b #DURATION 2.5 #FRAMES 3\n" + kId + kId +
                       "\n 1 0 0 0 0 1 0 0 0 0 1 0 7 8 9 1" + kId + "\n" + kId +
                       " 2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1\n");
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(
        write("t.ray", "#key_file k.key\n#joint_begin b\n#joint_end\n#joint_begin a\n#joint_end\n"),
        diag);
    ASSERT_EQ(s.tracks.size(), 2u);  // in the order joints bind them
    EXPECT_EQ(s.tracks[0].name, "b");
    EXPECT_EQ(s.tracks[0].duration, 2.5);
    ASSERT_EQ(s.tracks[0].keys.size(), 3u);
    EXPECT_EQ(s.tracks[0].keys[2][0][0], 2.0);               // frame-major: frame 2, DOF 1
    EXPECT_EQ(Vec3(s.tracks[1].keys[1][3]), Vec3(7, 8, 9));  // column-major: 13-15 translate
    EXPECT_EQ(s.files[0].root.groups[0].track, 0);
    EXPECT_EQ(s.files[0].root.groups[1].track, 1);
    EXPECT_EQ(s.files[0].root.groups[1].matrix, Mat4(1.0));  // key 0 as read
    EXPECT_EQ(s.tracks[1].loc.line, 4);                      // the first joint bound to it
    for (const Warning& w : diag.warnings())
        if (w.kind != "no-camera") ADD_FAILURE() << w.str();
}

TEST_F(KeyFiles, BadKeyFilesAreErrorsAtTheirPlace) {
    const std::string head = "#DOFS 1 a #DURATION 1 #FRAMES 2\n";
    EXPECT_EQ(error_with_key(head + kId + "\n"),
              "k.key:3:1: error: key file has 16 numbers after #FRAMES, expected "
              "16\u00b71\u00b72 = 32");
    EXPECT_EQ(error_with_key(head + kId + kId + " 5 6\n"),
              "k.key:2:66: error: key file has 34 numbers after #FRAMES, expected "
              "16\u00b71\u00b72 = 32");
    EXPECT_EQ(error_with_key(head + kId + " 1 0 x"),
              "k.key:2:38: error: key file has 18 numbers after #FRAMES, expected "
              "16\u00b71\u00b72 = 32; then 'x'");
    EXPECT_EQ(error_with_key(head + kId + " 1 0 nan"),
              "k.key:2:38: error: non-finite number 'nan'");
    EXPECT_EQ(error_with_key("#DOFS 1 a #DURATION 0 #FRAMES 1" + kId),
              "k.key:1:21: error: #DURATION must be > 0, got 0");
    EXPECT_EQ(error_with_key("#DOFS 1 a #DURATION -2 #FRAMES 1" + kId),
              "k.key:1:21: error: #DURATION must be > 0, got -2");
    EXPECT_EQ(error_with_key("#DOFS 0 #DURATION 1 #FRAMES 1"),
              "k.key:1:7: error: #DOFS must be >= 1, got 0");
    EXPECT_EQ(error_with_key("#DOFS 1 a #DURATION 1 #FRAMES -1"),
              "k.key:1:31: error: #FRAMES must be >= 1, got -1");
    EXPECT_EQ(error_with_key("#DOFS 1 a #FRAMES 1"),
              "k.key:1:11: error: expected #DURATION, got '#FRAMES'");
    EXPECT_EQ(error_with_key("#DOFS 2 a a #DURATION 1 #FRAMES 1"),
              "k.key:1:11: error: duplicate DOF name 'a'");
    EXPECT_EQ(error_with_key(""), "k.key:1:1: error: expected #DOFS, got end of file");
    // A first token that is not printable text is not quoted (a binary file, or a secret).
    EXPECT_EQ(error_with_key(std::string("KEY=secret\0#DOFS", 17)),
              "k.key:1:1: error: 'k.key' is not a .key file: its first bytes are not printable "
              "text");
    EXPECT_EQ(error_with_key("DOFS 1"), "k.key:1:1: error: expected #DOFS, got 'DOFS'");
    // A joint naming no DOF, a missing file, a #group_end closing a joint.
    EXPECT_EQ(error_with_key("#DOFS 1 b #DURATION 1 #FRAMES 1" + kId),
              "t.ray:2:14: error: no DOF 'a' in key files k.key");
    write("m.ray", "#key_file nothere.key\n");
    Diagnostics diag;
    try {
        parse_scene_file((dir / "m.ray").string(), diag);
        ADD_FAILURE() << "a missing key file loads";
    } catch (const SceneError& e) {
        EXPECT_NE(
            std::string(e.what()).find("m.ray:1:11: error: cannot open key file 'nothere.key'"),
            std::string::npos)
            << e.what();
    }
    write("k.key", "#DOFS 1 a #DURATION 1 #FRAMES 1" + kId);
    write("g.ray", "#key_file k.key\n#joint_begin a\n#group_end\n");
    try {
        parse_scene_file((dir / "g.ray").string(), diag);
        ADD_FAILURE() << "#group_end closes a joint";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("g.ray:3:1: error: #group_end does not match "
                                             "#joint_begin at"),
                  std::string::npos)
            << e.what();
    }
}

// 100,000 DOFs, and 20,000 joints bound to them (half only when case is ignored): each name is a
// look-up, where scanning every name before it took minutes (46 s for the DOFs alone, 2 to 5 ms
// per joint by case). A duplicate among them is still found.
TEST_F(KeyFiles, ManyDofsAndJointsBindByName) {
    constexpr int kDofs = 100000, kJoints = 20000;
    std::string key = "#DOFS " + std::to_string(kDofs);
    for (int i = 0; i < kDofs; ++i) key += " d" + std::to_string(i);
    key += "\n#DURATION 1 #FRAMES 1\n";
    for (int i = 0; i < kDofs; ++i) key += kId + "\n";
    write("k.key", key);
    std::string ray = "#key_file k.key\n";
    for (int j = 0; j < kJoints; ++j)
        ray += "#joint_begin " + std::string(j % 2 ? "D" : "d") +
               std::to_string(kDofs - 1 - 5 * j) + "\n#joint_end\n";
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(write("t.ray", ray), diag);
    ASSERT_EQ(s.tracks.size(), static_cast<size_t>(kJoints));
    EXPECT_EQ(s.tracks[0].name, "d99999");
    EXPECT_EQ(s.tracks[1].name, "d99994");  // joint D99994, bound by case
    EXPECT_EQ(s.tracks.back().name, "d4");
    EXPECT_EQ(s.files[0].root.groups.back().track, kJoints - 1);
    int by_case = 0;
    for (const Warning& w : diag.warnings())
        if (w.kind == "joint-case") by_case = w.count;
    EXPECT_EQ(by_case, kJoints / 2);

    const size_t last = key.find(" d99999");
    EXPECT_EQ(error_with_key(key.replace(last, 7, " d12345")),
              "k.key:1:688897: error: duplicate DOF name 'd12345'");
}

// A #FRAMES far beyond what the file holds is the shortfall at its end, with no allocation for
// the frames it declares: here in a process that cannot map 1 GiB more (10 million frames of
// one DOF filled 2.5 GB before; 2^27 frames ended in a bare std::bad_alloc).
TEST_F(KeyFiles, AFrameCountBeyondTheFileAllocatesNothing) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");  // a child of its own, not a fork
    for (const std::string frames : {"10000000", "134217728"}) {
        const std::string key = "#DOFS 1 a #DURATION 1 #FRAMES " + frames + "\n" + kId + "\n";
        const std::string numbers = std::to_string(16LL * std::stoll(frames));
        EXPECT_EXIT(
            {
                cap_address_space(uint64_t{1} << 30);
                std::cerr << error_with_key(key) << "\n";
                std::exit(0);
            },
            testing::ExitedWithCode(0),
            "k.key:3:1: error: key file has 16 numbers after #FRAMES, expected 16\u00b71\u00b7" +
                frames + " = " + numbers);
    }
}

TEST_F(KeyFiles, NonAffineAndSingularKeysAreCountedWarnings) {
    // The course's own mine.key (spec §14.1's example): frames 1-4 and 6-9 of ROOT_NATURAL are
    // not affine, frame 2 is singular. mine.ray instances an empty c.ray.
    const fs::path src = fs::path(RT_PUBLIC_SCENES_DIR) / "szhang37__Homework4";
    fs::copy(src / "mine.ray", dir / "mine.ray");
    fs::copy(src / "mine.key", dir / "mine.key");
    fs::copy(src / "c.ray", dir / "c.ray");
    Diagnostics diag;
    const SceneDesc s = parse_scene_file((dir / "mine.ray").string(), diag);
    std::vector<std::string> got;
    for (const Warning& w : diag.warnings())
        if (w.kind.rfind("key-", 0) == 0) got.push_back(w.message);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0], "key file: 8 key matrices are not affine; their bottom row is ignored");
    EXPECT_EQ(got[1],
              "key file: 1 key matrix is singular; a joint is left out wherever its matrix is "
              "singular");
    ASSERT_EQ(s.tracks.size(), 2u);
    EXPECT_EQ(s.tracks[0].keys[1][0][3], 0.0);  // the bottom row is ignored: (0, 0, 0, 1)
    EXPECT_EQ(s.tracks[0].keys[1][3][3], 1.0);
    // It renders at every time, the singular key only where the matrix interpolates to one.
    for (double t = 0; t < 12; t += 0.75) {
        Diagnostics d;
        EXPECT_NO_THROW(compile_scene(s, nullptr, SceneTime{t}, &d)) << t;
    }
    Diagnostics at_key2;
    compile_scene(s, nullptr, SceneTime{12.0 * 2 / 11, Interpolation::Nearest, Rotation::Matrix},
                  &at_key2);
    EXPECT_TRUE(at_key2.has("joint-singular"));
}

TEST_F(KeyFiles, V3IgnoresTheBottomRowWithoutAWarning) {
    write("k.key", "#DOFS 1 Arm #DURATION 1 #FRAMES 1\n1 0 0 5 0 1 0 5 0 0 1 5 1 2 3 7\n");
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(
        write("v.ray",
              "#material 0 0 0 .2 .2 .2 .8 .6 .4 0 0 0 1 0 0 0 1 -1 !!\n#key_file k.key\n"
              "#dynamic_affine Arm #shape_sphere 0 0 0 0 1\n"),
        diag);
    ASSERT_EQ(s.dialect, Dialect::V3);
    EXPECT_EQ(s.tracks[0].keys[0], glm::translate(Mat4(1.0), Vec3(1, 2, 3)));
    EXPECT_FALSE(diag.has("key-not-affine"));
}

// The course's 18-DOF stick figure (test.ray with its test.key), its body parts made here.
TEST_F(KeyFiles, TheCoursesStickFigureMovesThroughItsKeys) {
    const fs::path src = fs::path(RT_PUBLIC_SCENES_DIR) / "szhang37__Homework4";
    fs::create_directories(dir / "scene");
    fs::copy(src / "test.ray", dir / "scene" / "test.ray");
    fs::create_directories(dir / "key");
    fs::copy(src / "test.key", dir / "key" / "smoke.key");
    for (const char* part : {"pelvis", "upper_leg", "lower_leg", "foot", "chest", "left_shoulder",
                             "upper_arm", "lower_arm", "hand", "right_shoulder", "neck", "head"})
        write(std::string("ray/stick.") + part + ".ray",
              "#material 0 0 0 .2 .2 .2 .8 .6 .4 0 0 0 1 0 0 0 1 -1 !!\n"
              "#shape_sphere 0 0 0 0 .08\n");
    Diagnostics diag;
    const SceneDesc s = parse_scene_file((dir / "scene" / "test.ray").string(), diag);
    ASSERT_EQ(s.tracks.size(), 18u);
    EXPECT_EQ(s.tracks[0].keys.size(), 20u);
    RenderScene scene = compile_scene(s);
    const size_t instances = scene.instances.size();
    EXPECT_EQ(instances, 18u);
    Bounds3 previous = scene.world_bounds;
    int moved = 0;
    for (double t = 0.25; t < 10; t += 0.5) {
        animate(scene, s, SceneTime{t});
        EXPECT_EQ(scene.instances.size(), instances);
        moved += scene.world_bounds.lo != previous.lo || scene.world_bounds.hi != previous.hi;
        previous = scene.world_bounds;
    }
    EXPECT_GE(moved, 15);  // the figure moves from frame to frame
}

}  // namespace
}  // namespace rt
