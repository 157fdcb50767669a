// raytrace's reports of progressive rendering: the fitted slope, the time to reach an error,
// the CSV rows and the SVG plot, on hand-made passes. raycompare's report: the students' names,
// the columns a name takes, the summary, the --inspect command and Gradescope's results.
#include <gtest/gtest.h>

#include "raycompare/report.h"
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

namespace raycompare {
namespace {

Row row(const std::string& path, bool pass, const std::string& error = "") {
    Row r;
    r.path = path;
    r.name = student_names({path})[0];
    r.pass = pass;
    r.error = error;
    r.width = error.empty() ? 160 : 0;
    r.height = error.empty() ? 120 : 0;
    r.unreadable = !error.empty();
    r.c.share_off = pass ? 0.001 : 0.25;
    r.c.max_diff = 72;
    r.c.max_x = 3;
    r.c.max_y = 4;
    return r;
}

TEST(CompareReport, NamesAreStemsOrFoldersNeverPaths) {
    EXPECT_EQ(student_names({"/home/ta/in/ann.png", "bo.jpg"}),
              (std::vector<std::string>{"ann", "bo"}));
    EXPECT_EQ(student_names({"class/ann/scene.png", "class/李明/scene.png", "/abs/bo/scene.png"}),
              (std::vector<std::string>{"ann", "李明", "bo"}));
    // Folders that repeat too: folder/stem.
    EXPECT_EQ(student_names({"a/x/s.png", "b/x/s.png", "b/x/t.png"}),
              (std::vector<std::string>{"x/s", "x/s", "x/t"}));
    EXPECT_EQ(student_names({"s.png", "s.ppm"}), (std::vector<std::string>{"s", "s"}));
}

TEST(CompareReport, DisplayWidthCountsColumnsNotBytes) {
    EXPECT_EQ(display_width("ann"), 3u);
    EXPECT_EQ(display_width("chloé"), 5u);      // é: 2 bytes, 1 column
    EXPECT_EQ(display_width("李明"), 4u);       // wide: 2 columns each
    EXPECT_EQ(display_width("e\xcc\x81"), 1u);  // e and a combining acute
    EXPECT_EQ(display_width("\\x0d"), 4u);      // an escaped byte as shown
    std::vector<Row> rows = {row("c/ann/s.png", true), row("c/李明/s.png", false)};
    rows[0].name = "ann";
    rows[1].name = "李明";
    const std::string table = table_text(rows, {});
    // Both rows' sizes start in the same column: "ann" padded by 4 more than "李明" (4 columns).
    EXPECT_NE(table.find("\nann      160x120"), std::string::npos) << table;
    EXPECT_NE(table.find("\n李明     160x120"), std::string::npos) << table;
}

TEST(CompareReport, SummaryCountsPassFailAndUnreadable) {
    const std::vector<Row> rows = {row("a.png", true), row("b.png", false),
                                   row("c.png", false, "cannot read 'c.png': empty file")};
    EXPECT_EQ(summary_text(rows), "3 images: 1 pass, 1 fail, 1 cannot be read");
    Limits limits;
    limits.width = 160;
    limits.height = 120;
    EXPECT_EQ(rule_text(limits),
              "a pixel is off when a channel differs by more than 8 of 255; an image passes with "
              "at most 0.5% of its pixels off; JPEG files under the lossy rule (3x3 means); every "
              "image 160x120");
    EXPECT_EQ(inspect_command("my scene.ray", rows[1]),
              "raytrace 'my scene.ray' --width 160 --height 120 --inspect 3,4");
    EXPECT_EQ(inspect_command("it's.ray", rows[1]),
              "raytrace 'it'\\''s.ray' --width 160 --height 120 --inspect 3,4");
    EXPECT_EQ(inspect_command("s.ray", rows[2]), "");
}

TEST(CompareReport, GradescopeHasOneTestPerImageWithItsReason) {
    std::vector<Row> rows = {row("a.png", true), row("b\"q.png", false),
                             row("c.png", false, "cannot read 'c.png': empty file")};
    rows[1].diagnosis = "shadows missing";
    const std::string j = gradescope_json("s.ray", rows, {});
    EXPECT_EQ(j.rfind("{\n  \"score\": 1,\n  \"max_score\": 3,\n", 0), 0u) << j;
    EXPECT_NE(j.find("{\"name\": \"a\", \"score\": 1, \"max_score\": 1, \"status\": \"passed\", "
                     "\"output\": \"PASS: 0.100% of pixels off (at most 0.5%)\"}"),
              std::string::npos)
        << j;
    EXPECT_NE(j.find("{\"name\": \"b\\\"q\", \"score\": 0, \"max_score\": 1, \"status\": "
                     "\"failed\", \"output\": \"FAIL: 25.000% of pixels off by more than 8 (at "
                     "most 0.5%); the largest difference 72.0 at (3,4)\\nthe worst pixel, "
                     "explained: raytrace s.ray --width 160 --height 120 --inspect 3,4\\nshadows "
                     "missing\"}"),
              std::string::npos)
        << j;
    EXPECT_NE(j.find("\"output\": \"FAIL: cannot read 'c.png': empty file\"}"), std::string::npos);
    EXPECT_NE(j.find("\"output\": \"s.ray: 3 images: 1 pass, 1 fail, 1 cannot be read\\nrule: "),
              std::string::npos);
}

// A diagnosis of several lines (raycompare --diagnose): one line each under its row in the table,
// on lines of the page, joined by "; " in the CSV's last column; a control byte in it escaped.
TEST(CompareReport, ADiagnosisShowsOneExplanationALine) {
    std::vector<Row> rows = {row("a.png", true), row("b.png", false)};
    rows[1].diagnosis = "1. no-shadows (explains 97%)\n2. gamma (exponent 2.2) (explains 70%\x1b)";
    const std::string table = table_text(rows, {});
    EXPECT_NE(table.find("FAIL\n    1. no-shadows (explains 97%)\n    2. gamma (exponent 2.2) "
                         "(explains 70%\\x1b)\n"),
              std::string::npos)
        << table;
    const std::string csv = csv_text(rows);
    EXPECT_NE(csv.find(",error,diagnosis\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",pass,exact,,\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",fail,exact,,1. no-shadows (explains 97%); 2. gamma (exponent 2.2) "
                       "(explains 70%\\x1b)\n"),
              std::string::npos)
        << csv;
}

}  // namespace
}  // namespace raycompare
