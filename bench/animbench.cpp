// A frame update against a full compile: animate() moves one joint over a static
// mesh of about 100k triangles by recomputing the instances under joints and rebuilding the
// top-level BVH only. Prints, for the joint holding a small part and the joint holding the mesh
// itself, with and without a camera (no camera: the default camera needs the tight bounds of
// every moved primitive), the compile time, the update time, their ratio, and whether the
// updated scene gives the same hits as a compile at that time. Asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "cli.h"
#include "rt/accel/intersect.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/scene/mesh_gen.h"
#include "rt/util/stopwatch.h"

namespace {

// A track that turns about y and slides along x over 12 keys.
rt::KeyTrack turning_track() {
    rt::KeyTrack t;
    t.name = "arm";
    t.duration = 3;
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * rt::kPi * k / 12;
        rt::Mat4 m(1.0);
        m[0] = {std::cos(a), 0, -std::sin(a), 0};
        m[2] = {std::sin(a), 0, std::cos(a), 0};
        m[3] = {0.5 * std::sin(a), 0, 0, 1};
        t.keys.push_back(m);
    }
    return t;
}

// The blob mesh with one joint: holding a sphere (mesh static), or holding the mesh itself.
rt::SceneDesc scene(bool joint_holds_mesh, bool camera) {
    rt::Diagnostics diag;
    rt::SceneDesc d =
        rt::parse_scene_string(rt::ray_text_for_mesh(rt::make_blob_mesh(100000)), "blob.ray", diag);
    if (!camera) d.camera.reset();
    d.tracks.push_back(turning_track());
    rt::GroupDesc joint;
    joint.joint = "arm";
    joint.track = 0;
    joint.matrix = d.tracks[0].keys[0];
    rt::GroupDesc& root = d.files[0].root;
    if (joint_holds_mesh) {
        std::swap(joint.shapes, root.shapes);
    } else {
        rt::ShapeDesc s;
        s.material = 0;
        s.geometry = rt::Sphere{{1.6, 0, 0}, 0.3};
        joint.shapes.push_back(s);
    }
    root.groups.push_back(std::move(joint));
    return d;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Rays from around the scene at its centre: the hits of `a` and `b` agree exactly.
int hit_mismatches(const rt::RenderScene& a, const rt::RenderScene& b, int* hits) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0;
    for (int i = 0; i < 20000; ++i) {
        const rt::Vec3 o(3 * u(rng), 3 * u(rng), 3 + u(rng));
        const rt::Vec3 target(0.8 * u(rng), 0.8 * u(rng), 0.8 * u(rng));
        const rt::Ray r{o, glm::normalize(target - o)};
        rt::Hit ha, hb;
        const bool x = rt::intersect(a, r, {1e-9, rt::kInf}, &ha);
        const bool y = rt::intersect(b, r, {1e-9, rt::kInf}, &hb);
        bad += x != y || (x && ha.t != hb.t);
        *hits += x;
    }
    return bad;
}

void row(const char* what, bool holds_mesh, bool camera) {
    const rt::SceneDesc d = scene(holds_mesh, camera);
    std::vector<double> compile_s;
    rt::RenderScene s;
    for (int k = 0; k < 5; ++k) {
        const auto t0 = rt::Clock::now();
        s = rt::compile_scene(d);
        compile_s.push_back(rt::seconds_since(t0));
    }
    std::vector<double> update_s;
    for (int k = 0; k < 101; ++k) {
        const rt::SceneTime t{0.037 * k};
        const auto t0 = rt::Clock::now();
        rt::animate(s, d, t);
        update_s.push_back(rt::seconds_since(t0));
    }
    const rt::SceneTime last{0.037 * 100};
    int hits = 0;
    const int bad = hit_mismatches(s, rt::compile_scene(d, nullptr, last), &hits);
    std::vector<double> plan_s;
    for (int k = 0; k < 11; ++k) {
        const auto t0 = rt::Clock::now();
        const rt::RenderPlan plan = rt::make_render_plan(s, rt::RenderSettings{});
        plan_s.push_back(rt::seconds_since(t0));
    }
    size_t tris = 0;
    for (const rt::GeometrySet& g : s.sets) tris += g.triangle_count();
    const double c = median(compile_s), u = median(update_s);
    char same[64];
    std::snprintf(same, sizeof same, "%s (%d of 20000 rays hit)", bad == 0 ? "same" : "DIFFERENT",
                  hits);
    std::printf("| %-32s | %7zu | %-6s | %10.2f | %9.3f | %7.3f%% | %7.3f | %s |\n", what, tris,
                camera ? "yes" : "no", 1e3 * c, 1e3 * u, 100 * u / c, 1e3 * median(plan_s), same);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Times a frame update (animate) against a full compile, one joint over a\n"
        "100k-triangle mesh and the animated scenes of scenes/ (a table)."};
    rtapp::setup_cli(app, "animbench", true);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    if (!rtapp::isa_usable("animbench")) return 2;
    std::printf("frame update (animate) against a full compile, median times\n\n");
    std::printf("| %-32s | %7s | %-6s | %10s | %9s | %8s | %7s | %s |\n", "scene", "tris", "camera",
                "compile ms", "update ms", "ratio", "plan ms", "hits vs a compile at t");
    std::printf(
        "|%s|%s|%s|%s|%s|%s|%s|%s|\n", std::string(34, '-').c_str(), std::string(9, '-').c_str(),
        std::string(8, '-').c_str(), std::string(12, '-').c_str(), std::string(11, '-').c_str(),
        std::string(10, '-').c_str(), std::string(9, '-').c_str(), std::string(24, '-').c_str());
    row("joint with a sphere, mesh still", false, true);
    row("joint with a sphere, mesh still", false, false);
    row("joint holding the mesh", true, true);
    row("joint holding the mesh", true, false);
    return 0;
}
