// raytrace's options: every value lands in its field of Options (the library's RenderSettings
// extended), the defaults are the library's, and usage errors throw UsageError.
#include <gtest/gtest.h>

#include "frames.h"
#include "raytrace/options.h"
#include "raytrace/output.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"

namespace raytrace {
namespace {

Options parse(std::vector<std::string> args) { return parse_options(args); }

TEST(Options, DefaultsAreTheLibrarysSettings) {
    const Options o = parse({"a.ray"});
    const rt::RenderSettings s;
    EXPECT_EQ(o.scene, "a.ray");
    EXPECT_EQ(o.output, "out.png");
    EXPECT_EQ(o.width, s.width);
    EXPECT_EQ(o.height, s.height);
    EXPECT_EQ(o.max_depth, s.max_depth);
    EXPECT_EQ(o.cutoff, s.cutoff);
    EXPECT_EQ(o.shadows, s.shadows);
    EXPECT_EQ(o.specialize, s.specialize);
    EXPECT_EQ(o.spp, 1);
    EXPECT_EQ(o.light_samples, s.light_samples);
    EXPECT_EQ(o.light_samples, 64);
    EXPECT_FALSE(o.progressive.enabled);
    EXPECT_EQ(o.progressive.spp_limit, 0);
    EXPECT_EQ(o.progressive.reference_spp, 256);
    EXPECT_FALSE(o.dialect);
}

TEST(Options, EveryOptionSetsItsField) {
    const Options o = parse({"--width",   "20",          "--height",     "10",
                             "--depth",   "3",           "--cutoff",     "0.5",
                             "--spp",     "4",           "--seed",       "9",
                             "--threads", "2",           "--no-shadows", "--dialect",
                             "V0",        "--stats",     "--explain",    "--no-specialize",
                             "-q",        "-o",          "x.pfm",        "--light-radius",
                             "0.25",      "--aperture",  "0.125",        "--focus-distance",
                             "3",         "--roughness", "0.5",          "--light-samples",
                             "9",         "s.ray"});
    EXPECT_EQ(o.scene, "s.ray");
    EXPECT_EQ(o.output, "x.pfm");
    EXPECT_EQ(o.width, 20);
    EXPECT_EQ(o.height, 10);
    EXPECT_EQ(o.max_depth, 3);
    EXPECT_EQ(o.cutoff, 0.5);
    EXPECT_EQ(o.spp, 4);
    EXPECT_EQ(o.seed, 9u);
    EXPECT_EQ(o.threads, 2);
    EXPECT_FALSE(o.shadows);
    EXPECT_EQ(o.dialect, rt::Dialect::V0);
    EXPECT_TRUE(o.stats && o.explain && o.quiet);
    EXPECT_FALSE(o.specialize);
    EXPECT_EQ(o.light_radius, 0.25);
    EXPECT_EQ(o.aperture, 0.125);
    EXPECT_EQ(o.focus_distance, 3);
    EXPECT_EQ(o.roughness, 0.5);
    EXPECT_EQ(o.light_samples, 9);
    EXPECT_EQ(o.progressive.spp_limit, 0);  // not progressive
}

TEST(Options, ARepeatedOptionTakesItsLastValue) {
    // scripts/run.sh passes -o and then the user's own arguments, which may repeat it.
    const Options o =
        parse({"a.ray", "-o", "x.png", "--width", "20", "-o", "y.png", "--width", "30"});
    EXPECT_EQ(o.output, "y.png");
    EXPECT_EQ(o.width, 30);
}

TEST(Options, ProgressiveLimitsAreTheLibrarysSettings) {
    const Options o =
        parse({"s.ray", "--progressive", "--spp", "8", "--time", "2.5", "--adaptive", "--reference",
               "auto", "--reference-spp", "64", "--report", "r.csv", "--plot", "p.svg"});
    EXPECT_TRUE(o.progressive.enabled);
    EXPECT_EQ(o.progressive.spp_limit, 8);
    EXPECT_EQ(o.progressive.time_limit_s, 2.5);
    EXPECT_TRUE(o.progressive.adaptive);
    EXPECT_EQ(o.progressive.reference, "auto");
    EXPECT_EQ(o.progressive.reference_spp, 64);
    EXPECT_EQ(o.progressive.report, "r.csv");
    EXPECT_EQ(o.progressive.plot, "p.svg");
    EXPECT_EQ(parse({"s.ray", "--progressive", "--time", "1"}).progressive.spp_limit, 0);
}

TEST(Options, UsageErrorsThrow) {
    const std::vector<std::vector<std::string>> bad = {
        {},
        {"a.ray", "b.ray"},
        {"a.ray", "--bogus"},
        {"a.ray", "--width"},
        {"a.ray", "--width", "abc"},
        {"a.ray", "--width", "0"},
        {"a.ray", "--height", "40000"},
        {"a.ray", "--depth", "0"},
        {"a.ray", "--depth", "257"},
        {"a.ray", "--cutoff", "-1"},
        {"a.ray", "--spp", "0"},
        {"a.ray", "--light-samples", "0"},
        {"a.ray", "--light-samples", "-4"},
        {"a.ray", "--light-samples", "2.5"},
        {"a.ray", "--light-samples", "2000000"},
        {"a.ray", "--threads", "257"},
        {"a.ray", "--seed", "-1"},
        {"a.ray", "--dialect", "v7"},
        {"a.ray", "--aperture", "-1"},
        {"a.ray", "--roughness", "inf"},
        {"a.ray", "--time", "2"},
        {"a.ray", "--target-error", "1e-3"},
        {"a.ray", "--progressive", "--target-error", "-1"},
        {"a.ray", "--progressive", "--target-error", "nan"},
        {"a.ray", "--report", "r.csv"},
        {"a.ray", "--progressive"},
        {"a.ray", "--progressive", "--spp", "4", "--reference", "r.png"},
        {"a.ray", "--progressive", "--spp", "4", "--reference-spp", "1"},
        {"a.ray", "-o", "x.tiff"}};
    for (const auto& args : bad) {
        std::string line;
        for (const std::string& a : args) line += a + " ";
        EXPECT_THROW(parse(args), UsageError) << line;
    }
    // The messages name the problem.
    try {
        parse({"a.ray", "--progressive"});
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "--progressive needs --time S, --spp N or --target-error E");
    }
    EXPECT_EQ(parse({"a.ray", "--progressive", "--target-error", "2e-4"}).progressive.target_relmse,
              2e-4);
    try {
        parse({"a.ray", "--light-samples", "0"});
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "--light-samples must be between 1 and 1048576");
    }
    EXPECT_EQ(parse({"a.ray", "--light-samples", "1"}).light_samples, 1);
}

TEST(Options, HelpListsEveryOptionWithItsDefault) {
    EXPECT_TRUE(parse({"--help"}).help);
    EXPECT_TRUE(parse({"a.ray", "--bogus", "-h"}).help);
    const std::string help = usage_text();
    for (const char* opt : {"-o,--output FILE=out.png",
                            "--width N=640",
                            "--height N=480",
                            "--depth N=5",
                            "--cutoff X=0.001",
                            "--spp N=1",
                            "--light-samples N=64",
                            "--seed N=0",
                            "--threads N=0",
                            "--no-shadows",
                            "--dialect D",
                            "--stats",
                            "--explain",
                            "--no-specialize",
                            "--progressive",
                            "--time S=0",
                            "--reference R",
                            "--reference-spp N=256",
                            "--report F.csv",
                            "--plot F.svg",
                            "--adaptive",
                            "--light-radius R=0",
                            "--aperture A=0",
                            "--focus-distance F=0",
                            "--roughness X=0",
                            "-q,--quiet",
                            "-h,--help"})
        EXPECT_NE(help.find(opt), std::string::npos) << opt;
    EXPECT_NE(help.find("exit status: 0 success"), std::string::npos);
}

TEST(Options, AnimationTimesAndChoices) {
    const Options none = parse({"a.ray"});
    EXPECT_FALSE(none.animation.time());  // key 0 as read
    const Options at =
        parse({"a.ray", "--at", "-1.25", "--interpolation", "bspline", "--rotation", "log"});
    ASSERT_TRUE(at.animation.time());
    EXPECT_EQ(at.animation.time()->seconds, -1.25);
    EXPECT_EQ(at.animation.time()->interpolation, rt::Interpolation::BSpline);
    EXPECT_EQ(at.animation.time()->rotation, rt::Rotation::Log);
    EXPECT_TRUE(at.warnings.empty());
    const Options seq =
        parse({"a.ray", "--frames", "10", "--fps", "4", "--start", "2", "-o", "f_%03d.png"});
    EXPECT_EQ(seq.animation.time(0)->seconds, 2.0);
    EXPECT_EQ(seq.animation.time(3)->seconds, 2.75);
    EXPECT_EQ(seq.animation.time(3)->interpolation, rt::Interpolation::CatmullRom);  // defaults
    EXPECT_EQ(seq.animation.time(3)->rotation, rt::Rotation::Quaternion);
    EXPECT_EQ(parse({"a.ray", "--rotation", "euler"}).warnings.size(), 1u);
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"a.ray", "--at", "inf"},
          {"a.ray", "--interpolation", "Linear2"},
          {"a.ray", "--frames", "2", "-o", "f.png"},
          {"a.ray", "--frames", "2", "-o", "f_%s.png"},
          {"a.ray", "--frames", "2", "-o", "f_%d_%d.png"},
          {"a.ray", "--frames", "-1"},
          {"a.ray", "--frames", "2", "--fps", "-3", "-o", "f%d.png"},
          {"a.ray", "--frames", "2", "--progressive", "--spp", "4", "-o", "f%d.png"},
          {"a.ray", "--video", "v.mp4"}})
        EXPECT_THROW(parse(bad), UsageError) << bad[1];
}

TEST(Options, ExrPrecisionAndAovs) {
    const Options plain = parse({"a.ray", "-o", "x.exr"});
    EXPECT_FALSE(plain.exr.full_float);
    EXPECT_FALSE(plain.exr.aovs.any());
    const Options o = parse({"a.ray", "-o", "x.EXR", "--exr-float", "--aov", "depth,albedo"});
    EXPECT_TRUE(o.exr.full_float);
    EXPECT_TRUE(o.exr.aovs.albedo && o.exr.aovs.depth);
    EXPECT_FALSE(o.exr.aovs.normal || o.exr.aovs.samples || o.exr.aovs.variance);
    const Options all =
        parse({"a.ray", "-o", "x.exr", "--aov", "albedo,normal,depth,samples,variance"});
    EXPECT_TRUE(all.exr.aovs.albedo && all.exr.aovs.normal && all.exr.aovs.depth &&
                all.exr.aovs.samples && all.exr.aovs.variance);
    EXPECT_EQ(parse({"a.ray", "-o", "x.exr", "--aov", "normal", "--aov", "samples"}).exr.aovs,
              (rt::AovSet{false, false, false, true, false}));  // the last one, as for any option
    // Sequences and progressive renders write them too.
    EXPECT_TRUE(
        parse({"a.ray", "--frames", "3", "-o", "f_%02d.exr", "--aov", "depth"}).exr.aovs.depth);
    EXPECT_TRUE(parse({"a.ray", "--progressive", "--spp", "8", "-o", "p.exr", "--aov", "variance"})
                    .exr.aovs.variance);
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"a.ray", "--aov", "depth"},  // out.png
          {"a.ray", "--exr-float"},
          {"a.ray", "-o", "x.pfm", "--aov", "albedo"},
          {"a.ray", "-o", "x.part", "--aov", "albedo"},  // a part holds sums, no AOVs
          {"a.ray", "-o", "x.exr", "--aov", "albedo,shadow"},
          {"a.ray", "-o", "x.exr", "--aov", "Albedo"},
          {"a.ray", "-o", "x.exr", "--aov", ""},
          {"a.ray", "-o", "x.exr", "--aov", "albedo,"},
          {"a.ray", "-o", "x.exr", "--aov", ",albedo"},
          {"a.ray", "-o", "x.exr", "--aov", "albedo,,depth"},
          {"a.ray", "-o", "x.exr", "--aov"}})
        EXPECT_THROW(parse(bad), UsageError) << bad.back();
    try {
        parse({"a.ray", "-o", "x.exr", "--aov", "albedo,shadow"});
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown AOV 'shadow' (accepted: albedo, normal, "
                                             "depth, samples, variance"),
                  std::string::npos)
            << e.what();
    }
    try {
        parse({"a.ray", "-o", "x.png", "--aov", "albedo"});
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(),
                     "--aov and --exr-float need an OpenEXR output (-o FILE.exr), not 'x.png'");
    }
    const std::string help = usage_text();
    for (const char* opt : {"--exr-float", "--aov LIST", ".exr (OpenEXR"})
        EXPECT_NE(help.find(opt), std::string::npos) << opt;
}

// What raytrace writes for --aov: the first-hit pass traces the render's own camera rays, also
// those of --progressive's passes. Lit by ambient light alone (K_A = K_D, ambient 1, black
// background), every sample's colour is its first hit's albedo, so the image is the albedo AOV
// exactly when both place the samples alike (the spheres' edges show where they differ).
TEST(Options, TheAovsTraceTheRendersCameraRays) {
    rt::Diagnostics diag;
    const rt::RenderScene scene = rt::compile_scene(rt::parse_scene_string(
        "#camera 0 0 5  0 0 -1  0 1 0  0.5\n#background 0 0 0\n#ambient 1 1 1\n"
        "#material 0 0 0  .8 .3 .4  .8 .3 .4  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_sphere 0  0 0 0  1\n#shape_sphere 0  1.2 0.8 -1  0.4\n",
        "aov.ray", diag));
    for (const char* mode : {"--spp", "--progressive"}) {
        std::vector<std::string> args = {"a.ray",  "--width", "24", "--height", "18",
                                         "--seed", "3",       "-o", "a.exr",    "--aov",
                                         "albedo", "--spp",   "5"};
        if (std::string(mode) == "--progressive") args.push_back(mode);
        const Options o = parse(args);
        const rt::RenderPlan plan = rt::make_render_plan(scene, o);
        rt::RenderState state;
        if (o.progressive.enabled)
            rt::run_progressive(state, scene, plan, o, o.progressive, nullptr);
        else
            rt::render_samples(state, scene, plan, o, o.spp);
        EXPECT_EQ(state.samples[0], 5u) << mode;
        const ExrOutput exr = exr_output(o, state, scene, plan);
        ASSERT_EQ(exr.channels.size(), 3u);
        EXPECT_EQ(exr.channels[1].name, "Albedo.G");
        const rt::Image img = state.image();
        double max_diff = 0;
        int edges = 0;  // pixels the spheres partly cover
        for (size_t p = 0; p < state.samples.size(); ++p)
            for (size_t c = 0; c < 3; ++c) {
                max_diff =
                    std::max(max_diff, std::abs(exr.channels[c].values[p] - img.rgb[p * 3 + c]));
                edges += c == 1 && img.rgb[p * 3 + c] > 0.01 && img.rgb[p * 3 + c] < 0.29;
            }
        EXPECT_LT(max_diff, 1e-12) << mode;
        EXPECT_GT(edges, 10) << mode;
    }
}

TEST(Options, FramePatterns) {
    EXPECT_EQ(rtapp::frame_path("frame_%04d.png", 7), "frame_0007.png");
    EXPECT_EQ(rtapp::frame_path("f%d.png", 12345), "f12345.png");
    EXPECT_EQ(rtapp::frame_path("100%%_%3d.ppm", 5), "100%_  5.ppm");
    EXPECT_EQ(rtapp::frame_path("a%02d.png", 123), "a123.png");  // wider numbers are kept whole
    EXPECT_THROW(rtapp::frame_path("a%x.png", 1), std::invalid_argument);
    EXPECT_THROW(rtapp::frame_path("plain.png", 1), std::invalid_argument);
}

}  // namespace
}  // namespace raytrace
