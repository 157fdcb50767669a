// The diagnosis scored and timed on a labelled class: images made by another renderer
// with known mistakes (tests/diagnose/make_class.py writes them and manifest.csv), each compared
// with our reference as raycompare compares it, and each that fails diagnosed as
// `raycompare --diagnose` diagnoses it. Prints, per scene, how many images fail, how often the
// first-ranked explanation is the image's mistake and how often it is among the first three,
// the correct images given a diagnosis (should be none), the mutant renders and the seconds;
// then the images whose first explanation was wrong. Asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "cli.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/image/compare.h"
#include "rt/image/diagnose.h"
#include "rt/render/mistakes.h"
#include "rt/render/plan.h"
#include "rt/util/stopwatch.h"
#include "rt/util/threads.h"

namespace {

struct Labelled {
    std::string scene, image;
    std::vector<std::string> mistakes;  // empty: a correct image
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string part; std::getline(in, part, sep);) out.push_back(part);
    return out;
}

// manifest.csv: scene, image, mistakes ("a+b", "none"), designed_for, ...; rows of images the
// scene was not designed for are left out.
std::vector<Labelled> read_manifest(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    std::vector<Labelled> out;
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
        const std::vector<std::string> f = split(line, ',');
        if (f.size() < 4 || f[3] != "1") continue;
        Labelled l{f[0], f[1], {}};
        if (f[2] != "none") l.mistakes = split(f[2], '+');
        out.push_back(std::move(l));
    }
    return out;
}

// The explanation names the image's mistakes (in any order).
bool names(const rt::Explanation& e, std::vector<std::string> truth) {
    std::vector<std::string> got = e.mistakes;
    std::sort(got.begin(), got.end());
    std::sort(truth.begin(), truth.end());
    return got == truth;
}

struct Score {
    int images = 0, failing = 0, first = 0, top3 = 0, correct_diagnosed = 0, passed_mistaken = 0;
    int correct_failing = 0;
    size_t renders = 0;
    double seconds = 0;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Scores and times the diagnosis on a labelled class of images made by another\n"
        "renderer (tests/diagnose/make_class.py writes them and their manifest.csv)."};
    rtapp::setup_cli(app, "diagbench", true);
    std::string dir, scenes;
    int threads = 0;
    app.add_option("class", dir, "the class folder (its manifest.csv)")->required();
    app.add_option("scenes", scenes, "the folder of its .ray scenes")->required();
    app.add_option("--threads", threads, "render threads (0: all cores)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    if (!rtapp::isa_usable("diagbench")) return 2;

    const std::vector<Labelled> all = read_manifest(dir + "/manifest.csv");
    std::vector<std::string> catalogue;
    for (const rt::MistakeInfo& m : rt::mistake_catalogue()) catalogue.push_back(m.name);
    std::map<std::string, Score> scores;
    std::vector<std::string> misses;
    std::vector<std::string> order;
    for (const Labelled& l : all)
        if (std::find(order.begin(), order.end(), l.scene) == order.end()) order.push_back(l.scene);
    for (const std::string& name : order) {
        Score& s = scores[name];
        const rt::Clock::time_point t0 = rt::Clock::now();
        rt::Diagnostics diag;
        const rt::SceneDesc desc = rt::parse_scene_file(scenes + "/" + name + ".ray", diag);
        const rt::RenderScene scene = rt::compile_scene(desc);
        std::optional<rt::MutantRenders> renders;
        rt::Image reference;
        for (const Labelled& l : all) {
            if (l.scene != name) continue;
            const rt::Image image = rt::load_image(dir + "/" + l.image);
            if (!renders) {  // one size per scene in a class
                rt::RenderSettings settings;
                settings.width = image.width;
                settings.height = image.height;
                settings.threads = rt::resolve_thread_count(threads);
                const rt::RenderPlan plan = rt::make_render_plan(scene, settings);
                renders.emplace([&scene, settings, plan](const std::vector<std::string>& m) {
                    return rt::render_written(scene, plan, settings, rt::parse_mistakes(m), 1);
                });
                reference = renders->get({});
            }
            ++s.images;
            rt::CompareSettings cs;
            const rt::ImageComparison c = rt::compare_images(image, reference, cs);
            if (c.share_off <= 0.005) {
                s.passed_mistaken += !l.mistakes.empty();
                continue;
            }
            ++s.failing;
            rt::DiagnoseSettings ds;
            ds.half_angle = scene.camera ? scene.camera->half_height_angle_rad : 0.0;
            const rt::Diagnosis d = rt::diagnose(image, *renders, catalogue, ds);
            if (l.mistakes.empty()) {
                ++s.correct_failing;
                s.correct_diagnosed += !d.ranked.empty();
                continue;
            }
            const bool first = !d.ranked.empty() && names(d.ranked[0], l.mistakes);
            bool top3 = false;
            for (size_t i = 0; i < d.ranked.size() && i < 3; ++i)
                top3 = top3 || names(d.ranked[i], l.mistakes);
            s.first += first;
            s.top3 += top3;
            if (!first) misses.push_back(l.image + ": " + d.summary());
        }
        s.renders = renders ? renders->renders() : 0;
        s.seconds = rt::seconds_since(t0);
    }
    std::printf(
        "the diagnosis on %s (first: the first-ranked explanation names the image's "
        "mistakes; of the failing mistaken images)\n",
        dir.c_str());
    std::printf("%-10s %6s %7s %8s %8s %14s %13s %8s %8s\n", "scene", "images", "failing", "first",
                "top 3", "correct named", "mistake pass", "renders", "seconds");
    Score t;
    for (const std::string& name : order) {
        const Score& s = scores[name];
        std::printf("%-10s %6d %7d %8d %8d %14d %13d %8zu %8.2f\n", name.c_str(), s.images,
                    s.failing, s.first, s.top3, s.correct_diagnosed, s.passed_mistaken, s.renders,
                    s.seconds);
        t.images += s.images, t.failing += s.failing, t.first += s.first, t.top3 += s.top3;
        t.correct_diagnosed += s.correct_diagnosed, t.passed_mistaken += s.passed_mistaken;
        t.renders += s.renders, t.seconds += s.seconds, t.correct_failing += s.correct_failing;
    }
    std::printf("%-10s %6d %7d %8d %8d %14d %13d %8zu %8.2f\n", "all", t.images, t.failing, t.first,
                t.top3, t.correct_diagnosed, t.passed_mistaken, t.renders, t.seconds);
    const int mistaken = t.failing - t.correct_failing;
    if (mistaken > 0)
        std::printf(
            "\nof %d failing mistaken images: first right %.0f%%, in the first three "
            "%.0f%%; %d correct images failed the comparison\n",
            mistaken, 100.0 * t.first / mistaken, 100.0 * t.top3 / mistaken, t.correct_failing);
    std::printf("\nfirst explanation wrong:\n");
    for (const std::string& m : misses) std::printf("  %s\n", m.c_str());
    return 0;
}
