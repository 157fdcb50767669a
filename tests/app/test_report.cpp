// raytrace's reports of progressive rendering: the fitted slope, the time to reach an error,
// the CSV rows and the SVG plot, on hand-made passes.
#include <gtest/gtest.h>

#include "raytrace/report.h"

namespace raytrace {
namespace {

rt::PassRecord pass(double seconds, double relmse, double estimate, bool reference = true) {
    rt::PassRecord r;
    r.seconds = seconds;
    r.spp = seconds;
    r.rays = 1000;
    r.has_reference = reference;
    r.error.rmse = 0.5;
    r.error.relmse = relmse;
    r.error.off_share = 0.25;
    r.estimate.mse = 0.125;
    r.estimate.relmse = estimate;
    return r;
}

TEST(Report, LightSummaryCountsEachKindSphereLightsToo) {
    rt::SceneDesc desc;
    EXPECT_EQ(light_summary(desc), "0");
    for (const rt::LightKind k : {rt::LightKind::Sphere, rt::LightKind::Point,
                                  rt::LightKind::Sphere, rt::LightKind::Directional}) {
        rt::LightDesc l;
        l.kind = k;
        desc.lights.push_back(l);
    }
    EXPECT_EQ(light_summary(desc), "4 (directional 1, point 1, sphere 2)");
}

TEST(Report, TimeToReachInterpolatesOnLogLogAxes) {
    const std::vector<rt::PassRecord> run = {pass(1, 1, 9), pass(10, 0.01, 9)};
    EXPECT_NEAR(time_to_reach(run, 0.1), std::sqrt(10.0), 1e-12);
    EXPECT_EQ(time_to_reach(run, 2), 1.0);       // reached by the first pass
    EXPECT_EQ(time_to_reach(run, 0.001), -1.0);  // never
    // Without a reference the estimate counts.
    const std::vector<rt::PassRecord> estimated = {pass(1, 0, 1, false), pass(10, 0, 0.01, false)};
    EXPECT_NEAR(time_to_reach(estimated, 0.1), std::sqrt(10.0), 1e-12);
    EXPECT_EQ(pass_error(estimated[0]), 1.0);
}

TEST(Report, CsvHasOneRowAPassAndLeavesMissingErrorsEmpty) {
    const std::vector<ProgressRun> runs = {{"uniform", {pass(1, 0.5, 0.25)}},
                                           {"adaptive", {pass(2, 0, 0.5, false)}}};
    EXPECT_EQ(progress_csv(runs),
              "mode,seconds,spp,rays,rmse,relmse,off_share,estimate,estimate_relmse\n"
              "uniform,1.000000,1.0000,1000,0.5,0.5,0.250000,0.125,0.25\n"
              "adaptive,2.000000,2.0000,1000,,,,0.125,0.5\n");
}

TEST(Report, SvgPlotsEachSeriesWithItsSlope) {
    const std::vector<ProgressRun> runs = {
        {"uniform", {pass(0.1, 0.1, 0.2), pass(1, 0.01, 0.02), pass(10, 0.001, 0.002)}},
        {"a<b", {pass(1, 0.1, 0.1)}}};  // one pass: nothing to draw
    const std::string svg = progress_svg(runs, "Error & <time>");
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"720\"", 0), 0u);
    EXPECT_NE(svg.find(">Error &amp; &lt;time&gt;</text>"), std::string::npos);
    EXPECT_NE(svg.find(">uniform relMSE: slope -1.00</text>"), std::string::npos);
    EXPECT_NE(svg.find(">uniform estimate: slope -1.00</text>"), std::string::npos);
    EXPECT_EQ(svg.find("a&lt;b"), std::string::npos);
    size_t polylines = 0, dashed = 0;
    for (size_t at = svg.find("<polyline"); at != std::string::npos;
         at = svg.find("<polyline", at + 1))
        ++polylines;
    for (size_t at = svg.find("stroke-dasharray"); at != std::string::npos;
         at = svg.find("stroke-dasharray", at + 1))
        ++dashed;
    EXPECT_EQ(polylines, 2u);
    EXPECT_EQ(dashed, 1u);
    // Decades 1e-1 .. 1e1 on the time axis; the first point sits on the left edge of the frame.
    EXPECT_NE(svg.find(">1e-1</text>"), std::string::npos);
    EXPECT_NE(svg.find(">1e1</text>"), std::string::npos);
    EXPECT_NE(svg.find("points=\"80.0,"), std::string::npos);
    EXPECT_NE(svg.find(kRelMseFormula), std::string::npos);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

}  // namespace
}  // namespace raytrace
