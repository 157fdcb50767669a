// rayview's command line (app/rayview/state/run_options.h): raytrace's render flags become the
// viewer's initial settings; bad values are usage errors (2); --help and --version exit 0.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "state/run_options.h"

namespace rt::view {
namespace {

// A command line's words.
std::vector<std::string> words(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

// parse_run_options on the arguments (argv[0] added); the exit code, or -1 to run.
int parse(std::vector<std::string> args, RunOptions* out) {
    std::string name = "rayview";
    std::vector<char*> argv{name.data()};
    for (std::string& a : args) argv.push_back(a.data());
    return parse_run_options(static_cast<int>(argv.size()), argv.data(), "default.ray", out);
}

TEST(RunOptions, RenderFlagsBecomeTheInitialSettings) {
    RunOptions opt;
    ASSERT_EQ(parse(words("scene.ray --width 400 --height 100 --spp 8 --depth 3 --cutoff 0.01 "
                          "--threads 1 --seed 7 --no-shadows --light-radius 0.2 --aperture 0.05 "
                          "--focus-distance 4 --roughness 0.3 --light-samples 16 "
                          "--target-error 0.002 --no-specialize --missing-textures checker "
                          "--dialect v0 --layout trace --panel off"),
                    &opt),
              -1);
    EXPECT_EQ(opt.scene, "scene.ray");
    EXPECT_EQ(opt.render.missing_textures, MissingTextures::Checker);
    EXPECT_EQ(opt.render.dialect, Dialect::V0);
    EXPECT_TRUE(opt.spp_given);
    ViewSettings vs;
    vs.render.width = 321;  // the trace's own size (the pane's) is kept
    vs.render.centre_first_sample = false;
    apply_run_options(opt, &vs);
    EXPECT_EQ(vs.image_w, 400);
    EXPECT_EQ(vs.image_h, 100);
    EXPECT_DOUBLE_EQ(vs.aspect(), 4.0);
    EXPECT_EQ(vs.target_spp, 8);
    EXPECT_FLOAT_EQ(vs.target_error, 0.002f);
    EXPECT_EQ(vs.render.width, 321);
    EXPECT_FALSE(vs.render.centre_first_sample);
    EXPECT_EQ(vs.render.max_depth, 3);
    EXPECT_DOUBLE_EQ(vs.render.cutoff, 0.01);
    EXPECT_EQ(vs.render.threads, 1);
    EXPECT_EQ(vs.render.seed, 7u);
    EXPECT_FALSE(vs.render.shadows);
    EXPECT_DOUBLE_EQ(vs.render.light_radius, 0.2);
    EXPECT_DOUBLE_EQ(vs.render.aperture, 0.05);
    EXPECT_DOUBLE_EQ(vs.render.focus_distance, 4.0);
    EXPECT_DOUBLE_EQ(vs.render.roughness, 0.3);
    EXPECT_EQ(vs.render.light_samples, 16);
    EXPECT_FALSE(vs.render.specialize);
    EXPECT_EQ(vs.layout, 2);  // the trace alone
    EXPECT_FALSE(vs.show_panel);
}

TEST(RunOptions, WithoutFlagsTheViewersDefaults) {
    RunOptions opt;
    ASSERT_EQ(parse({}, &opt), -1);
    EXPECT_EQ(opt.scene, "default.ray");
    EXPECT_FALSE(opt.spp_given);
    const ViewSettings defaults;
    ViewSettings vs;
    apply_run_options(opt, &vs);
    EXPECT_EQ(vs.target_spp, defaults.target_spp);
    EXPECT_FLOAT_EQ(vs.target_error, defaults.target_error);
    EXPECT_EQ(vs.image_w, defaults.image_w);
    EXPECT_EQ(vs.image_h, defaults.image_h);
    EXPECT_EQ(vs.render.max_depth, defaults.render.max_depth);
    EXPECT_TRUE(vs.render.shadows);
    EXPECT_EQ(vs.render.threads, resolve_thread_count(0));  // 0: every core
}

TEST(RunOptions, BadValuesAreUsageErrors) {
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"--width", "0"},
                                                {"--spp", "0"},
                                                {"--depth", "0"},
                                                {"--depth", "30000"},
                                                {"--threads", "300"},
                                                {"--light-radius", "-1"},
                                                {"--target-error", "nan"},
                                                {"--seed", "-1"},
                                                {"--width", "wide"},
                                                {"--dialect", "v2"},
                                                {"--no-such-flag"},
                                                {"--missing-textures", "maybe"},
                                                {"--size", "10x10"}}) {
        RunOptions opt;
        EXPECT_EQ(parse(bad, &opt), 2) << bad[0];
    }
    RunOptions opt;
    EXPECT_EQ(parse({"--version"}, &opt), 0);
    EXPECT_EQ(parse({"--help"}, &opt), 0);
}

}  // namespace
}  // namespace rt::view
