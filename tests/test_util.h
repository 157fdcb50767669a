// Helpers shared by the tests: inline scenes, one-pixel renders.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/camera.h"
#include "rt/render/render.h"

namespace rt::test {

inline SceneDesc parse(const std::string& text, Diagnostics* diag = nullptr,
                       ParseOptions options = {}) {
    Diagnostics local;
    return parse_scene_string(text, "test.ray", diag ? *diag : local, options);
}

inline RenderScene compile(const std::string& text, ParseOptions options = {}) {
    return compile_scene(parse(text, nullptr, options));
}

/// The message of the SceneError that parsing `text` throws ("" when none).
inline std::string parse_error(const std::string& text, ParseOptions options = {}) {
    try {
        parse(text, nullptr, options);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

inline Image render(const RenderScene& scene, int w, int h, int depth = 5, double cutoff = 0.001,
                    bool shadows = true) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.max_depth = depth;
    s.cutoff = cutoff;
    s.shadows = shadows;
    s.threads = 2;
    RenderState state;
    render_samples(state, scene, make_render_plan(scene, s), s, 1);
    return state.image();
}

/// render_samples() with the plan made for this call.
inline bool render_samples(RenderState& state, const RenderScene& scene,
                           const RenderSettings& settings, int spp) {
    return rt::render_samples(state, scene, make_render_plan(scene, settings), settings, spp);
}

/// Colour along one ray through the scene, depth 5, cutoff 0.001.
inline Vec3 shade(const RenderScene& scene, const Ray& ray, int depth = 5, double cutoff = 0.001,
                  bool shadows = true) {
    RenderSettings s;
    s.max_depth = depth;
    s.cutoff = cutoff;
    s.shadows = shadows;
    RayCounters c;
    return trace_ray(scene, make_render_plan(scene, s), s, ray, depth, Vec3(1.0), c);
}

}  // namespace rt::test

#define EXPECT_VEC_NEAR(a, b, tol)           \
    do {                                     \
        const ::rt::Vec3 _a = (a), _b = (b); \
        EXPECT_NEAR(_a.x, _b.x, tol);        \
        EXPECT_NEAR(_a.y, _b.y, tol);        \
        EXPECT_NEAR(_a.z, _b.z, tol);        \
    } while (0)
