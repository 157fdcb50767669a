// The preview drawn by OpenGL in an off-screen OSMesa context against the tracer: the coverage
// masks agree (intersection over union >= 0.98) and, where no shadow, reflection or refraction
// is involved, so do the colours.
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/osmesa.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <type_traits>
#include <variant>

#include "gl/gl_util.h"
#include "gl/preview.h"
#include "rt/render/inspect.h"
#include "rt/util/file_io.h"
#include "state/overlay.h"
#include "test_util.h"

namespace rt {
namespace {

constexpr int kW = 160, kH = 120;

// The plan the viewer draws the preview with: the trace's, at the preview's size.
RenderPlan plan_for(const RenderScene& scene, bool shadows = false) {
    RenderSettings settings;
    settings.width = kW;
    settings.height = kH;
    settings.shadows = shadows;
    return make_render_plan(scene, settings);
}

struct Offscreen {
    OSMesaContext ctx = nullptr;
    std::vector<unsigned char> rgba = std::vector<unsigned char>(kW * kH * 4);
    Offscreen() {
        const int attribs[] = {OSMESA_FORMAT,
                               OSMESA_RGBA,
                               OSMESA_DEPTH_BITS,
                               24,
                               OSMESA_PROFILE,
                               OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION,
                               3,
                               OSMESA_CONTEXT_MINOR_VERSION,
                               3,
                               0};
        ctx = OSMesaCreateContextAttribs(attribs, nullptr);
        if (ctx) OSMesaMakeCurrent(ctx, rgba.data(), GL_UNSIGNED_BYTE, kW, kH);
    }
    ~Offscreen() {
        if (ctx) OSMesaDestroyContext(ctx);
    }
    // Pixel (x, y) with y counted from the top, as the tracer does.
    Vec3 at(int x, int y) const {
        const size_t i = (static_cast<size_t>(kH - 1 - y) * kW + x) * 4;
        return Vec3(rgba[i], rgba[i + 1], rgba[i + 2]);
    }
};

struct Comparison {
    double iou = 0;
    double colour_match = 0;  // share of commonly covered pixels within 3/255 per channel
    int covered = 0;          // pixels the trace covers
};

// `scene` in the preview and the trace. Coverage is told from a magenta background (a black
// object on V3's black background would count as uncovered).
Comparison compare(RenderScene scene) {
    scene.background = Vec3(1, 0, 1);
    Offscreen gl;
    EXPECT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 96);
    const Camera cam = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene), cam, kW, kH);
    glFinish();
    const Image traced = test::render(scene, kW, kH, 1, 0.001, false);  // local shading only
    int both = 0, either = 0, close = 0, covered = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            Hit h;
            const bool hit = intersect(scene, cam.generate(x, y, 0.5, 0.5), {0, kInf}, &h);
            const Vec3 g = gl.at(x, y);
            Vec3 bg;
            for (int k = 0; k < 3; ++k) bg[k] = to_byte(scene.background[k]);
            const bool drawn = g != bg;
            both += hit && drawn;
            either += hit || drawn;
            covered += hit;
            if (hit && drawn) {
                Vec3 t;
                for (int k = 0; k < 3; ++k) t[k] = to_byte(traced.at(x, y)[k]);
                close += glm::all(glm::lessThanEqual(glm::abs(g - t), Vec3(3.0)));
            }
        }
    return {either ? static_cast<double>(both) / either : 1.0,
            both ? static_cast<double>(close) / both : 1.0, covered};
}

Comparison compare(const std::string& text) { return compare(test::compile(text)); }

const char* kMaterials =
    "#material 0 0 0  .1 .1 .1  .7 .3 .2  .4 .4 .4  30  0 0 0  1  -1 !a!\n"
    "#material .05 .05 .1  .1 .1 .1  .2 .5 .8  0 0 0  1  0 0 0  1  -1 !b!\n";

// A shape's description (a box's full sizes; triangles are not made here).
ShapeDesc shape(const Shape& s) {
    ShapeDesc d;
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, Box>)
                d.geometry = BoxDesc{v.centre, 2.0 * v.half};
            else if constexpr (!std::is_same_v<T, Triangle>)
                d.geometry = v;
        },
        s);
    return d;
}

TEST(GlPreview, ShapesUnderTransformsAgreeWithTheTrace) {
    const Comparison c = compare(
        std::string("#camera 0 1 9  0 -0.1 -1  0 1 0  0.4\n#background 0.1 0.1 0.1\n"
                    "#ambient .3 .3 .3\n#light_point 1 1 1  3 4 5  1 0 0.01\n"
                    "#light_dir .4 .4 .4  -1 -1 -1\n"
                    "#light_spot .8 .8 .8  -2 4 2  0.3 -1 -0.3  1 0 0  0.6 4\n") +
        kMaterials +
        "#vertex -3 -1 -2 0 0 0 0 0\n#vertex 3 -1 -2 0 0 0 1 0\n#vertex 0 3 -2 0 0 0 0.5 1\n"
        "#shape_triangle 1 0 1 2\n"
        "#group_begin 0.8 0.3 0 -2  -0.2 1.2 0 0.5  0 0 0.6 0  0 0 0 1\n"
        "#shape_sphere 0 0 0 0 1\n#group_end\n"
        "#group_begin 0.7071 0 0.7071 0  0 1 0 0  -0.7071 0 0.7071 0  0 0 0 1\n"
        "#shape_box 0 0 0 1 1 1.5 1\n#group_end\n"
        "#group_begin 1 0 0 2  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#shape_cylinder 1 0 0 0 0.6 1.5\n#shape_cone 0 0 1.5 0 0.5 1\n#group_end\n");
    EXPECT_GE(c.iou, 0.98);
    // Interpolated normals on the tessellation differ slightly from the exact ones.
    EXPECT_GE(c.colour_match, 0.90);
}

// The trace pane's exposure and tonemap apply to the preview too (background included): the
// panes show the same display transform.
TEST(GlPreview, ExposureAndTonemapMatchTheTracePane) {
    const RenderScene scene = test::compile(
        std::string("#camera 0 1 9  0 -0.1 -1  0 1 0  0.4\n#background 0.3 0.2 0.1\n"
                    "#ambient .3 .3 .3\n#light_point 1 1 1  3 4 5  1 0 0.01\n") +
        kMaterials + "#shape_sphere 0 -1.5 0 0 1.5\n#shape_box 1 1.5 0 0 1.5 1.5 1.5\n");
    const Image traced = test::render(scene, kW, kH, 1, 0.001, false);
    const Camera cam = make_camera(scene, kW, kH);
    for (const view::DisplaySettings d :
         {view::DisplaySettings{1.0, Tonemap::Reinhard}, view::DisplaySettings{-1.0, Tonemap::Aces},
          view::DisplaySettings{0.5, Tonemap::Clamp}}) {
        Offscreen gl;
        ASSERT_NE(gl.ctx, nullptr);
        view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
        preview.load(scene, 96);
        preview.draw(scene, plan_for(scene), cam, kW, kH, 1, d);
        glFinish();
        const Image shown = display_transform(traced, d.exposure_stops, d.tonemap);
        int close = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                Vec3 t;
                for (int k = 0; k < 3; ++k) t[k] = to_byte(shown.at(x, y)[k]);
                close += glm::all(glm::lessThanEqual(glm::abs(gl.at(x, y) - t), Vec3(3.0)));
            }
        // Silhouettes and interpolated normals differ a little, as in the tests above.
        EXPECT_GE(close, kW * kH * 9 / 10) << d.exposure_stops;
    }
}

// The two-sided rule (spec §5) takes the side from the geometric normal, the winding: vertex
// normals against it face away from the eye, and the light in front of the triangle does not
// light it (ambient only), in the trace and in the preview; also under a mirroring group.
TEST(GlPreview, NormalsAgainstTheWindingAreDarkAsInTheTrace) {
    const std::string head =
        std::string(
            "#camera 0 0 9  0 0 -1  0 1 0  0.4\n#background 0.1 0.1 0.1\n"
            "#ambient .2 .2 .2\n#light_point 1 1 1  0 0 6  1 0 0\n") +
        kMaterials +
        "#vertex -3 -2 -2 0 0 -1 0 0\n#vertex 0 -2 -2 0 0 -1 1 0\n#vertex -1.5 2 -2 0 0 -1 0 1\n";
    for (const bool mirrored : {false, true}) {
        const std::string body = mirrored ? "#group_begin -1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
                                            "#shape_triangle 0 0 1 2\n#group_end\n"
                                          : "#shape_triangle 0 0 1 2\n";
        const RenderScene scene = test::compile(head + body);
        const Comparison c = compare(scene);
        EXPECT_GT(c.covered, kW * kH / 20) << mirrored;
        EXPECT_GE(c.iou, 0.98) << mirrored;
        EXPECT_GE(c.colour_match, 0.95) << mirrored;
        // The trace is dark there: ambient only.
        const Image traced = test::render(scene, kW, kH, 1, 0.001, false);
        EXPECT_LT(traced.at(mirrored ? kW / 2 + 20 : kW / 2 - 20, kH / 2).x, 0.1) << mirrored;
    }
}

// Tori (spec §13.7; no file names one until the V3 parser: built as a description), plain,
// thin, spindle (r > R) and under a rotating, shearing transform.
TEST(GlPreview, ToriAgreeWithTheTrace) {
    SceneDesc desc = test::parse(std::string("#camera 0 2 11  0 -0.2 -1  0 1 0  0.45\n"
                                             "#background 0.1 0.1 0.1\n#ambient .3 .3 .3\n"
                                             "#light_point 1 1 1  3 4 5  1 0 0.01\n"
                                             "#light_dir .4 .4 .4  -1 -1 -1\n") +
                                 kMaterials);
    GroupDesc& root = desc.files[0].root;
    root.shapes.push_back(shape(Torus{Vec3(-2.5, 1, 0), 0.5, 1.5}));
    root.shapes.push_back(shape(Torus{Vec3(2.5, 1.5, 0), 0.08, 1.2}));
    root.shapes.push_back(shape(Torus{Vec3(0, -2.2, 0), 1.0, 0.6}));
    GroupDesc tilted;
    tilted.matrix = Mat4(0.8, 0.3, 0, 0, -0.2, 0.9, 0.4, 0, 0, -0.4, 0.9, 0, 2.5, -1.5, 0, 1);
    tilted.shapes.push_back(shape(Torus{Vec3(0.0), 0.35, 1.0}));
    tilted.shapes.back().material = 1;
    root.groups.push_back(tilted);
    const Comparison c = compare(compile_scene(desc));
    EXPECT_GT(c.covered, kW * kH / 20);  // the tori are there
    EXPECT_GE(c.iou, 0.98);
    EXPECT_GE(c.colour_match, 0.85);
}

GroupDesc list_of(std::vector<Shape> shapes, int material = 0) {
    GroupDesc g;
    for (const Shape& s : shapes) {
        g.shapes.push_back(shape(s));
        g.shapes.back().material = material;
    }
    return g;
}

CsgDesc csg_node(CsgOp op, std::vector<GroupDesc> operands) {
    CsgDesc c;
    c.op = op;
    c.operands = std::move(operands);
    return c;
}

// CSG (spec §13.8) in the preview against the trace: the lens of _lens.ray (two spheres and a
// cylinder intersected), a ring (a cylinder minus a thinner, taller one: B's inner wall shows),
// a box minus a sphere (a spherical dent), a union of two boxes and a sphere under a transform.
TEST(GlPreview, CsgAgreesWithTheTrace) {
    SceneDesc desc = test::parse(std::string("#camera 0 3.2 5.5  0 -0.5 -1  0 1 0  0.5\n"
                                             "#background 0.1 0.1 0.1\n#ambient .3 .3 .3\n"
                                             "#light_point 1 1 1  3 4 5  1 0 0.01\n"
                                             "#light_dir .4 .4 .4  -1 -1 -1\n") +
                                 kMaterials);
    desc.dialect = Dialect::V3;
    GroupDesc& root = desc.files[0].root;
    // Operands: one child each, a list of one shape.
    auto one = [](const Shape& s, int m = 0) { return list_of({s}, m); };
    root.csgs.push_back(csg_node(CsgOp::Intersection, {one(Sphere{Vec3(0, -0.95, 0), 1.5}),
                                                       one(Sphere{Vec3(0, 0.95, 0), 1.5}),
                                                       one(Cylinder{Vec3(0.0), 1.0, 2.0})}));
    root.csgs.push_back(csg_node(CsgOp::Difference, {one(Cylinder{Vec3(0.0), 1.4, 0.3}, 1),
                                                     one(Cylinder{Vec3(0.0), 1.1, 1.0}, 1)}));
    root.csgs.push_back(csg_node(CsgOp::Difference, {one(Box{Vec3(-2.6, 0, 0), Vec3(0.6)}, 1),
                                                     one(Sphere{Vec3(-2.6, 0.6, 0.6), 0.7})}));
    GroupDesc moved = one(Sphere{Vec3(0.0), 0.6});
    moved.matrix[3] = glm::dvec4(2.6, 0.4, 0, 1);
    GroupDesc wrapped;
    wrapped.groups.push_back(moved);
    root.csgs.push_back(
        csg_node(CsgOp::Union, {one(Box{Vec3(2.6, -0.3, 0), Vec3(0.5, 0.3, 0.7)}, 1), wrapped}));
    const RenderScene scene = compile_scene(desc);
    const Comparison c = compare(scene);
    EXPECT_GE(c.iou, 0.98);
    EXPECT_GE(c.colour_match, 0.85);
    EXPECT_GT(c.covered, kW * kH / 10);  // the trace draws the CSG nodes
}

TEST(GlPreview, PublicAndOwnScenesAgreeWithTheTrace) {
    for (const char* name : {"shapes.ray", "groups.ray", "lights.ray", "textures.ray"}) {
        const std::string path = std::string(RT_SOURCE_DIR) + "/scenes/" + name;
        Diagnostics diag;
        const SceneDesc desc = parse_scene_file(path, diag);
        Offscreen gl;
        ASSERT_NE(gl.ctx, nullptr);
        const RenderScene scene = compile_scene(desc);
        view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
        preview.load(scene, 96);
        const Camera cam = make_camera(scene, kW, kH);
        preview.draw(scene, plan_for(scene), cam, kW, kH);
        glFinish();
        int both = 0, either = 0;
        Vec3 bg;
        for (int k = 0; k < 3; ++k) bg[k] = to_byte(scene.background[k]);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                Hit h;
                const bool hit = intersect(scene, cam.generate(x, y, 0.5, 0.5), {0, kInf}, &h);
                const bool drawn = gl.at(x, y) != bg;
                both += hit && drawn;
                either += hit || drawn;
            }
        EXPECT_GE(static_cast<double>(both) / either, 0.98) << name;
    }
}

// Public V3 scenes (tori, three-colour lights, shape lists, transforms; textures they name but
// do not ship stand in as checkers): the preview covers what the trace covers.
TEST(GlPreview, PublicV3ScenesAgreeWithTheTrace) {
    const std::string dir = "/work/shared/public-scenes/aarxa__RayForge-CPP-Ray-Tracing-Engine/";
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is not here";
    for (const char* name : {"test.directional.torus.ray", "_torus.ray", "test.point.ray",
                             "test.spot.ray", "test.directional.cone.ray"}) {
        Diagnostics diag;
        ParseOptions options;
        options.missing_textures = MissingTextures::Checker;
        const SceneDesc desc = parse_scene_file(dir + name, diag, options);
        EXPECT_EQ(desc.dialect, Dialect::V3) << name;
        const Comparison c = compare(compile_scene(desc));
        EXPECT_GT(c.covered, kW * kH / 50) << name;
        EXPECT_GE(c.iou, 0.98) << name;
    }
}

// Drawn: the overlay's lines (state/overlay.h, tested in tests/app/test_overlay.cpp) change
// pixels of the preview.
TEST(GlPreview, OverlayLinesAreDrawn) {
    const RenderScene scene = test::compile(
        "#light_point 1 1 1  0 2 0  1 0 0\n#light_spot 1 0 0  0 3 0  0 -1 0  1 0 0  0.5 2\n"
        "#light_dir 1 1 1  0 -1 0\n"
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere 0 0 0 0 1\n"
        "#shape_box 0 3 0 0 1 1 1\n");
    const view::LightMarkers small{true, -1, false};
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 32);
    CameraPose cd;
    cd.position = Vec3(0, 1, 8);
    cd.direction = Vec3(0, -0.1, -1);
    const Camera cam = make_camera(cd, kW, kH);
    RenderScene framed = scene;
    framed.camera = cd;
    preview.draw(framed, plan_for(framed), cam, kW, kH);
    glFinish();
    const std::vector<unsigned char> plain = gl.rgba;
    preview.draw_lines(view::overlay_lines(framed, small, 2), framed, cam);
    glFinish();
    EXPECT_NE(plain, gl.rgba);
}

// Where camera `c` sees world point p, in pixels from the top left (as Camera::generate maps
// them).
Vec2 project(const Camera& c, const Vec3& p) {
    const Vec3 d = p - c.position;
    const double z = glm::dot(d, c.forward);
    const double x = glm::dot(d, c.right) / z / c.tan_w, y = glm::dot(d, c.up) / z / c.tan_h;
    return {(x + 1.0) * 0.5 * c.width, (1.0 - y) * 0.5 * c.height};
}

// Whether a pixel within `r` of (x, y) has colour c (0..1) to within 12/255.
bool colour_near(const auto& gl, Vec2 at, const float* c, int r = 2) {
    for (int y = static_cast<int>(at.y) - r; y <= static_cast<int>(at.y) + r; ++y)
        for (int x = static_cast<int>(at.x) - r; x <= static_cast<int>(at.x) + r; ++x) {
            if (x < 0 || y < 0 || x >= kW || y >= kH) continue;
            const Vec3 d = gl.at(x, y) - 255.0 * Vec3(double{c[0]}, double{c[1]}, double{c[2]});
            if (std::abs(d.x) <= 12 && std::abs(d.y) <= 12 && std::abs(d.z) <= 12) return true;
        }
    return false;
}

// A pixel's ray tree drawn in the preview from another camera (the user orbited after the
// click): the camera ray runs from the trace's eye to the trace's hit, the shadow ray from the
// hit to the light, the reflected ray leaves the hit; each lands where the preview's projection
// puts those points.
TEST(GlPreview, ARayTreeIsDrawnWhereTheTraceHit) {
    const RenderScene scene = test::compile(
        "#camera 0 0 5  0 0 -1  0 1 0  0.5\n#background 0 0 0\n"
        "#light_point 1 1 1  3 3 3  1 0 0\n"
        "#material 0 0 0  0 0 0  .5 .5 .5  .5 .5 .5  10  0 0 0  1  -1 !!\n"
        "#shape_sphere 0  0 0 0  1\n");
    RenderSettings rs;
    rs.width = kW;
    rs.height = kH;
    const int px = 90, py = 50;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, rs), rs, px, py);
    ASSERT_TRUE(tree.rays.at(0).hit);
    const Vec3 hit = tree.rays[0].point;
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 32);
    CameraPose side;  // from the right and above, looking at the sphere
    side.position = Vec3(7, 2, 4);
    side.direction = -side.position;
    const Camera cam = make_camera(side, kW, kH);
    preview.draw(scene, plan_for(scene), cam, kW, kH);
    preview.draw_lines(view::inspect_lines(tree, 0.3, 10.0), scene, cam, true);
    glFinish();
    const Vec2 h = project(cam, hit);
    const Vec3 eye = tree.rays[0].ray.o;
    const Vec3 light(3, 3, 3);
    // Along the camera ray (a third of the way from the hit to the eye), along the shadow ray
    // (half way to the light), and where the reflected ray leaves (a little way along it).
    EXPECT_TRUE(
        colour_near(gl, project(cam, hit + (eye - hit) / 3.0), view::InspectColours::camera));
    EXPECT_TRUE(
        colour_near(gl, project(cam, 0.5 * (hit + light)), view::InspectColours::shadow_lit));
    ASSERT_EQ(tree.rays.size(), 2u);
    const InspectRay& refl = tree.rays[1];
    EXPECT_TRUE(colour_near(gl, project(cam, refl.ray.o + 0.6 * glm::normalize(refl.ray.d)),
                            view::InspectColours::reflected));
    // Not a line everywhere: a point off every segment keeps the scene's colours.
    EXPECT_FALSE(colour_near(gl, Vec2(h.x, h.y + 25), view::InspectColours::shadow_lit, 1));
    // Drawn from the trace's own camera, the camera ray is the pixel itself: the lines leave the
    // very pixel inspected.
    const Camera own = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene), own, kW, kH);
    preview.draw_lines(view::inspect_lines(tree, 0.3, 10.0), scene, own, true);
    glFinish();
    const Vec2 at = project(own, hit);
    EXPECT_NEAR(at.x, px + 0.5, 0.01);
    EXPECT_NEAR(at.y, py + 0.5, 0.01);
    EXPECT_TRUE(colour_near(gl, at, view::InspectColours::reflected, 1));  // the last drawn there
}

// Where shadows darken the preview (shadow maps) and the trace (shadow rays): the intersection
// over union of the darkened pixels, the trace's count, and the defines the preview used.
struct ShadowAgreement {
    double iou = 0;
    int in_trace = 0;
    std::vector<std::string> defines;
};

ShadowAgreement shadow_agreement(const RenderScene& scene) {
    Offscreen gl;
    EXPECT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 96);
    const Camera cam = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene, false), cam, kW, kH);
    glFinish();
    const std::vector<unsigned char> lit = gl.rgba;
    preview.draw(scene, plan_for(scene, true), cam, kW, kH);
    glFinish();
    ShadowAgreement out;
    out.defines = preview.active_defines();
    const Image on = test::render(scene, kW, kH, 1, 0.001, true);
    const Image off = test::render(scene, kW, kH, 1, 0.001, false);
    int both = 0, either = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const size_t i = (static_cast<size_t>(kH - 1 - y) * kW + x) * 4;
            const bool preview_dark = lit[i] - gl.rgba[i] > 20;
            const bool trace_dark = to_byte(off.at(x, y).x) - to_byte(on.at(x, y).x) > 20;
            both += preview_dark && trace_dark;
            either += preview_dark || trace_dark;
            out.in_trace += trace_dark;
        }
    out.iou = either ? static_cast<double>(both) / either : 1.0;
    return out;
}

// Shadows: the pixels that shadows darken in the preview (shadow maps) and in the trace (shadow
// rays) agree, for each light kind, and the program is compiled for that kind only.
TEST(GlPreview, ShadowsAgreeWithTheTrace) {
    const std::string geometry =
        "#camera 0 4 9  0 -0.45 -1  0 1 0  0.5\n#background 0 0 0\n#ambient .2 .2 .2\n"
        "#material 0 0 0  .2 .2 .2  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n"
        "#shape_box 0 0 -1 0  10 0.2 10\n#shape_sphere 0 -0.5 1.2 0 0.8\n"
        "#shape_box 0 2 0.6 -1  1 1 1\n#shape_cone 0 -2 0.1 1 0.5 1.5\n";
    const struct {
        const char* light;
        const char* define;
    } cases[] = {
        {"#light_point 1 1 1  0.5 4 0.5  1 0 0\n", "RT_POINT"},
        {"#light_spot 1 1 1  -0.5 4 1  0.1 -1 -0.1  1 0 0  0.9 2\n", "RT_SPOT"},
        {"#light_dir 1 1 1  -0.6 -0.8 -0.5\n", "RT_DIRECTIONAL"},
    };
    for (const auto& c : cases) {
        const RenderScene scene = test::compile(c.light + geometry);
        const ShadowAgreement a = shadow_agreement(scene);
        EXPECT_NE(std::find(a.defines.begin(), a.defines.end(), "RT_SHADOWS"), a.defines.end());
        EXPECT_EQ(a.defines.front(), c.define) << "only the scene's light kind";
        EXPECT_EQ(a.defines.size(), 2u);  // the light kind and shadows: no texture, no highlight
        EXPECT_GT(a.in_trace, kW * kH / 200) << c.light;  // the scene does cast shadows
        // Shadow edges differ by a texel or so of the maps and by the tessellation.
        EXPECT_GE(a.iou, 0.9) << c.light;
    }
}

// A CSG node casts the shadow of its valid surfaces only: light passes through the hole that a
// cylinder drills through a box.
TEST(GlPreview, CsgShadowsAgreeWithTheTrace) {
    const RenderScene scene = test::compile(
        "#camera 0 4 9  0 -0.45 -1  0 1 0  0.5\n"
        "#light_dir 0 0 0  1 1 1  0 0 0  -0.1 -1 -0.05\n"
        "#material 0 0 0  .2 .2 .2  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n"
        "#shape_box 0  0 -1 0  10 0.2 10\n"
        "#shape_difference\n  #shape_box 0  0 1 0  2 2 2\n  #shape_cylinder 0  0 1 0  0.7 3\n");
    const ShadowAgreement a = shadow_agreement(scene);
    EXPECT_GT(a.in_trace, kW * kH / 200);
    EXPECT_GE(a.iou, 0.9);
}

// Light through a transparent object (spec §7.1: S_l is the product of the T of every surface
// the shadow ray crosses, so a glass ball of T 0.5 passes a quarter): the preview's shadow of
// the glass ball is as light as the trace's, and that of an opaque ball as dark.
TEST(GlPreview, TransparentObjectsCastTintedShadows) {
    const RenderScene scene = test::compile(
        "#camera 0 4 9  0 -0.45 -1  0 1 0  0.5\n#background 0 0 0\n#ambient .1 .1 .1\n"
        "#light_dir 1 1 1  -0.2 -1 -0.1\n"
        "#material 0 0 0  .2 .2 .2  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !floor!\n"
        "#material 0 0 0  0 0 0  .1 .1 .1  0 0 0  1  .5 .6 .7  1  -1 !glass!\n"
        "#shape_box 0 0 -1 0  10 0.2 10\n#shape_sphere 1 -1.6 0.5 0 1\n"
        "#shape_sphere 0 1.6 0.5 0 1\n");
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 96);
    const Camera cam = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene, true), cam, kW, kH);
    glFinish();
    const std::vector<std::string> defines = preview.active_defines();
    EXPECT_NE(std::find(defines.begin(), defines.end(), "RT_TRANSMIT_SHADOWS"), defines.end());
    const Image on = test::render(scene, kW, kH, 1, 0.001, true);
    const Image off = test::render(scene, kW, kH, 1, 0.001, false);
    int tinted = 0, tinted_close = 0, dark = 0, dark_close = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Vec3 lit = off.at(x, y), shadowed = on.at(x, y);
            if (!(lit.x > 0.3)) continue;  // the floor in the light
            Vec3 t;
            for (int k = 0; k < 3; ++k) t[k] = to_byte(shadowed[k]);
            const bool close = glm::all(glm::lessThanEqual(glm::abs(gl.at(x, y) - t), Vec3(12.0)));
            if (shadowed.x < 0.2 * lit.x) {  // behind the opaque ball: ambient only
                ++dark;
                dark_close += close;
            } else if (shadowed.x < 0.5 * lit.x) {  // behind the glass ball: T^2
                ++tinted;
                tinted_close += close;
            }
        }
    EXPECT_GT(tinted, kW * kH / 200);
    EXPECT_GT(dark, kW * kH / 200);
    // Shadow edges differ by a texel or so of the maps and by the tessellation.
    EXPECT_GE(tinted_close, tinted * 8 / 10);
    EXPECT_GE(dark_close, dark * 8 / 10);
}

// The shadow maps follow the animation: drawn at t = 0 and then at t = 0.5 with the same preview,
// the shadows are those of t = 0.5 (a #dynamic_affine sphere that slides across a floor; the
// light and the scene's bounds stay the same).
TEST(GlPreview, AnimatedShadowsFollowTheTime) {
    const auto dir = std::filesystem::temp_directory_path() / "rt_gl_animated_shadows";
    std::filesystem::create_directories(dir);
    write_file_atomic((dir / "s.key").string(),
                      "#DOFS 1 slide #DURATION 1 #FRAMES 2\n"
                      "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1   1 0 0 0  0 1 0 0  0 0 1 0  6 0 0 1\n");
    write_file_atomic((dir / "s.ray").string(),
                      "#camera 0 5 9  0 -0.55 -1  0 1 0  0.5\n"
                      "#light_dir 0 0 0  1 1 1  0 0 0  0 -1 0\n"
                      "#material 0 0 0  .2 .2 .2  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n"
                      "#key_file s.key\n#shape_box 0  0 -1 0  12 0.2 6\n"
                      "#shape_sphere 0  -5.5 2.5 0  0.1\n#shape_sphere 0  5.5 2.5 0  0.1\n"
                      "#dynamic_affine slide #shape_sphere 0  -2 1 0  1\n");
    Diagnostics diag;
    const SceneDesc desc = parse_scene_file((dir / "s.ray").string(), diag);
    std::filesystem::remove_all(dir);
    RenderScene scene = compile_scene(desc, nullptr, SceneTime{0, Interpolation::Linear});
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 96);
    const Camera cam = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene, true), cam, kW, kH);  // the maps of t = 0
    animate(scene, desc, SceneTime{0.5, Interpolation::Linear});
    preview.draw(scene, plan_for(scene, false), cam, kW, kH);
    glFinish();
    const std::vector<unsigned char> lit = gl.rgba;
    preview.draw(scene, plan_for(scene, true), cam, kW, kH);
    glFinish();
    const Image on = test::render(scene, kW, kH, 1, 0.001, true);
    const Image off = test::render(scene, kW, kH, 1, 0.001, false);
    int both = 0, either = 0, in_trace = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const size_t i = (static_cast<size_t>(kH - 1 - y) * kW + x) * 4;
            const bool preview_dark = lit[i] - gl.rgba[i] > 20;
            const bool trace_dark = to_byte(off.at(x, y).x) - to_byte(on.at(x, y).x) > 20;
            both += preview_dark && trace_dark;
            either += preview_dark || trace_dark;
            in_trace += trace_dark;
        }
    EXPECT_GT(in_trace, kW * kH / 200);
    EXPECT_GE(static_cast<double>(both) / std::max(either, 1), 0.9);
}

// The preview leaves out what the scene does not use: texture coordinates are uploaded only for
// textured sets, and the program has only the light kinds and features present.
TEST(GlPreview, UploadsAndCompilesOnlyWhatTheSceneUses) {
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    const std::string plain =
        "#light_dir 1 1 1  0 -1 0\n"
        "#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n"
        "#shape_sphere 0 0 0 0 1\n";
    const RenderScene a = test::compile(plain);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(a, 16);
    const size_t plain_floats = preview.uploaded_floats();
    preview.draw(a, plan_for(a, false), make_camera(a, kW, kH), kW, kH);
    EXPECT_EQ(preview.active_defines(), std::vector<std::string>{"RT_DIRECTIONAL"});

    Diagnostics diag;
    const RenderScene b =
        compile_scene(parse_scene_file(std::string(RT_SOURCE_DIR) + "/scenes/textures.ray", diag));
    preview.load(b, 16);
    preview.draw(b, plan_for(b, false), make_camera(b, kW, kH), kW, kH);
    const auto& d = preview.active_defines();
    EXPECT_NE(std::find(d.begin(), d.end(), "RT_TEXTURES"), d.end());
    // The same sphere with a texture: 8 floats a vertex (uv) instead of 6.
    const RenderScene c =
        test::compile("#light_dir 1 1 1  0 -1 0\n#texture " + std::string(RT_SOURCE_DIR) +
                      "/scenes/textures/checker.bmp\n"
                      "#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  "
                      "0 !m!\n#shape_sphere 0 0 0 0 1\n");
    preview.load(c, 16);
    EXPECT_EQ(preview.uploaded_floats() * 6, plain_floats * 8);
    EXPECT_GT(plain_floats, 0u);
}

// Golden image: the preview of scenes/shapes.ray at 160x120, within 4/255 on 99% of pixels
// (llvmpipe is deterministic; the tolerance absorbs other GL drivers' rounding). Set
// RT_UPDATE_GOLDEN=1 to write the golden file again after an intended change.
TEST(GlPreview, MatchesTheGoldenImage) {
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    Diagnostics diag;
    const RenderScene scene =
        compile_scene(parse_scene_file(std::string(RT_SOURCE_DIR) + "/scenes/shapes.ray", diag));
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 48);
    preview.draw(scene, plan_for(scene), make_camera(scene, kW, kH), kW, kH);
    glFinish();
    Image img(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) img.set(x, y, gl.at(x, y) / 255.0);
    const std::string golden = std::string(RT_SOURCE_DIR) + "/tests/golden/preview_shapes.png";
    if (std::getenv("RT_UPDATE_GOLDEN")) save_image(img, golden);
    TextureImage ref;
    std::string err;
    ASSERT_TRUE(load_texture_image(golden, &ref, &err)) << err;
    ASSERT_EQ(ref.width, kW);
    ASSERT_EQ(ref.height, kH);
    int close = 0;
    for (int i = 0; i < kW * kH; ++i) {
        bool ok = true;
        for (int c = 0; c < 3; ++c)
            ok = ok && std::abs(static_cast<int>(to_byte(img.rgb[static_cast<size_t>(i) * 3 + c])) -
                                static_cast<int>(ref.rgb[static_cast<size_t>(i) * 3 + c])) <= 4;
        close += ok;
    }
    EXPECT_GE(close, kW * kH * 99 / 100);
}

// The preview of `scene` at kW x kH: the colour (0..1) at the centre pixel.
Vec3 centre_colour(const RenderScene& scene) {
    Offscreen gl;
    EXPECT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 32);
    preview.draw(scene, plan_for(scene), make_camera(scene, kW, kH), kW, kH);
    glFinish();
    return gl.at(kW / 2, kH / 2) / 255.0;
}

// A wall facing the camera at z = -0.95 (normal +z), seen along -z, no global ambient:
// E = (.05 0 0), K_A = .2, K_D = (.3 .2 .1), K_S = .2 with e = 1.
RenderScene wall() {
    RenderScene s = test::compile(
        "#camera 0 0 5  0 0 -1  0 1 0  0.3\n#background 0 0 0\n"
        "#material .05 0 0  .2 .2 .2  .3 .2 .1  .2 .2 .2  1  0 0 0  1  -1 !w!\n"
        "#shape_box 0 0 0 -1  10 10 0.1\n");
    s.lights.clear();
    return s;
}

Light light(LightKind kind, const Vec3& a, const Vec3& d, const Vec3& s) {
    Light l;
    l.kind = kind;
    l.ambient = a;
    l.diffuse = d;
    l.specular = s;
    return l;
}

// Spec §13.9: ambient, diffuse and specular colours per light; the ambient term is attenuated
// and spot-limited but needs no N.L > 0; sphere lights shade from their centre.
TEST(GlPreview, ThreeColourLightsShadeAsTheSpecSays) {
    const Vec3 a(0.5), d(1, 0.5, 0.5), sp(0.5, 1, 0.5);
    RenderScene s = wall();
    // Head-on directional light: N.L = 1 and R_v.L = 1 at the centre (up to the half-pixel
    // offset of the centre pixel's ray): E + K_A A + K_D D + K_S S'.
    Light dir = light(LightKind::Directional, a, d, sp);
    dir.direction = Vec3(0, 0, -1);
    s.lights = {dir};
    EXPECT_VEC_NEAR(centre_colour(s), Vec3(0.55, 0.4, 0.25), 2.5 / 255);
    // A point light behind the wall (N.L < 0) with ca = 2: only its ambient, halved.
    Light behind = light(LightKind::Point, a, d, sp);
    behind.position = Vec3(0, 0, -3);
    behind.constant_atten = 2;
    s.lights = {behind};
    EXPECT_VEC_NEAR(centre_colour(s), Vec3(0.05 + 0.05, 0.05, 0.05), 2.5 / 255);
    // A spot whose cone misses the centre: no ambient either.
    Light spot = light(LightKind::Spot, a, d, sp);
    spot.position = Vec3(0, 0, 3);
    spot.direction = Vec3(1, 0, 0);
    spot.cutoff_rad = 0.3;
    s.lights = {spot};
    EXPECT_VEC_NEAR(centre_colour(s), Vec3(0.05, 0, 0), 2.5 / 255);
    // A sphere light: a point light at its centre (ca = 1, la = 1 at distance 3.95: f = 1/4.95).
    Light sphere = light(LightKind::Sphere, a, d, Vec3(0.0));
    sphere.position = Vec3(0, 0, 3);
    sphere.radius = 0.5;
    sphere.linear_atten = 1;
    s.lights = {sphere};
    const double f = 1 / 4.95;
    EXPECT_VEC_NEAR(centre_colour(s), Vec3(0.05, 0, 0) + f * Vec3(0.1 + 0.3, 0.1 + 0.1, 0.1 + 0.05),
                    2.5 / 255);
    // A V0/V1 light (one colour, no ambient) under the global ambient: K_A * ambient + K_D * c.
    Light one = light(LightKind::Directional, Vec3(0.0), Vec3(0.0), Vec3(0.0));
    one.diffuse = one.specular = Vec3(0.5);
    one.direction = Vec3(0, 0, -1);
    s.lights = {one};
    s.ambient = Vec3(1.0);
    EXPECT_VEC_NEAR(centre_colour(s),
                    Vec3(0.05 + 0.2 + 0.15 + 0.1, 0.2 + 0.1 + 0.1, 0.2 + 0.05 + 0.1), 2.5 / 255);
}

// V3 shading (spec §13.9) in the preview and the trace: three-colour lights of every kind, a
// sphere light from its centre, the ambient term of every light; no shadows, local shading.
TEST(GlPreview, V3LightsShadeLikeTheTrace) {
    const Comparison c = compare(
        test::compile("#camera 0 1 9  0 -0.1 -1  0 1 0  0.4\n"
                      "#light_point .1 .05 0  1 .8 .6  .5 .5 1  3 4 5  1 0 0.01\n"
                      "#light_dir .05 .05 .1  .3 .3 .4  .2 .2 .2  -1 -1 -1\n"
                      "#light_spot .1 0 0  .8 .8 .8  1 1 1  -2 4 2  0.3 -1 -0.3  1 0 0  0.6 4\n"
                      "#light_sphere .05 .1 .05  .5 .6 .5  .4 .4 .4  0 3 3  0.5  1 0 0.02\n"
                      "#material 0 0 0  .1 .1 .1  .7 .3 .2  .4 .4 .4  30  0 0 0  1  -1 !a!\n"
                      "#material .05 .05 .1  .1 .1 .1  .2 .5 .8  0 0 0  1  0 0 0  1  -1 !b!\n"
                      "#shape_box 1  0 -1.5 -2  8 0.2 4\n"
                      "#shape_sphere 0  -2 0 0  1\n"
                      "#shape_torus 1  0.5 0 0  0.3 0.9\n"
                      "#static_affine  0.7071 0 -0.7071 0  0 1 0 0  0.7071 0 0.7071 0  2.5 0 0 1\n"
                      "  #shape_cylinder 0  0 0 0  0.6 1.5\n"));
    EXPECT_GE(c.iou, 0.98);
    EXPECT_GE(c.colour_match, 0.90);
}

// The repository's V3 scenes (three-colour lights, a torus, CSG, a sphere light's penumbra) cover
// what the trace covers and, where no shadow is involved, shade like it.
TEST(GlPreview, OwnV3ScenesAgreeWithTheTrace) {
    for (const char* name : {"v3_lights.ray", "v3_torus.ray", "v3_csg.ray", "v3_penumbra.ray"}) {
        Diagnostics diag;
        const SceneDesc desc =
            parse_scene_file(std::string(RT_SOURCE_DIR) + "/scenes/" + name, diag);
        ASSERT_EQ(desc.dialect, Dialect::V3) << name;
        const Comparison c = compare(compile_scene(desc));
        EXPECT_GT(c.covered, kW * kH / 10) << name;
        EXPECT_GE(c.iou, 0.98) << name;
        EXPECT_GE(c.colour_match, 0.80) << name;
    }
}

// Spec §13.10 (worked example 3, untextured) parsed from a V3 file. The example's colour at a
// point of the plane y = 0 seen from the eye (the formula of §13.9 with its numbers).
Vec3 worked_example_three(const Vec3& p, const Vec3& eye) {
    const Vec3 to_light = Vec3(5.0) - p, n(0, 1, 0);
    const double dist = glm::length(to_light);
    const Vec3 l = to_light / dist, d = glm::normalize(p - eye);
    const double f = 1 / (0.01 + 0.02 * dist + 0.03 * dist * dist);
    const double spec = std::pow(std::max(0.0, glm::dot(d - 2 * glm::dot(d, n) * n, l)), 100);
    return Vec3(0.1) + Vec3(0.3 * 0.5) * f + Vec3(0.1, 0.1, 0.5) * Vec3(1, 0.5, 1) * l.y * f +
           Vec3(0.2, 0.4, 0.6) * spec * f;
}

TEST(GlPreview, WorkedExampleThreeOfTheSpec) {
    const Vec3 eye(0, 10, 10);
    EXPECT_VEC_NEAR(worked_example_three(Vec3(3, 0, 6), eye) * 255.0, Vec3(92.35, 87.43, 196.67),
                    0.01);
    const RenderScene s = test::compile(
        "#camera 0 10 10  3 -10 -4  0 1 0  0.3\n"
        "#light_point 0.5 0.5 0.5  1 0.5 1  0.2 0.4 0.6  5 5 5  0.01 0.02 0.03\n"
        "#material 0.1 0.1 0.1  0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  100  0 0 0  1  -1 !!\n"
        "#shape_box 0  0 -0.5 0  40 1 40\n");
    // The centre pixel's ray meets the plane half a pixel from P = (3, 0, 6).
    const Ray ray = make_camera(s, kW, kH).generate(kW / 2, kH / 2, 0.5, 0.5);
    const Vec3 p = ray.o - ray.o.y / ray.d.y * ray.d;
    EXPECT_LT(glm::length(p - Vec3(3, 0, 6)), 0.05);
    EXPECT_VEC_NEAR(centre_colour(s) * 255.0, worked_example_three(p, eye) * 255.0, 1.5);
}

// Spec §13.9: with texture_all_terms (V3) the texel multiplies K_E too, else only K_A and K_D.
TEST(GlPreview, TextureModulatesEveryTermInV3) {
    RenderScene s = test::compile(
        "#camera 0 0 5  0 0 -1  0 1 0  0.3\n#background 0 0 0\n#light_dir 0 0 0  0 0 -1\n"
        "#texture " +
        std::string(RT_SOURCE_DIR) +
        "/scenes/textures/checker.bmp\n"
        "#material .8 .8 .8  0 0 0  0 0 0  0 0 0  1  0 0 0  1  0 !w!\n"
        "#shape_box 0 0 0 -1  10 10 0.1\n");
    for (const bool all : {false, true}) {
        s.texture_all_terms = all;
        Offscreen gl;
        ASSERT_NE(gl.ctx, nullptr);
        view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
        preview.load(s, 8);
        preview.draw(s, plan_for(s), make_camera(s, kW, kH), kW, kH);
        glFinish();
        int dark = 0, emissive = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                dark += gl.at(x, y).x < 0.5 * 0.8 * 255;
                emissive += std::abs(gl.at(x, y).x - to_byte(0.8)) <= 1;
            }
        if (all) {
            EXPECT_GT(dark, kW * kH / 10);
        } else {
            EXPECT_EQ(emissive, kW * kH);
        }
    }
}

TEST(GlPreview, ShaderErrorsNameTheFile) {
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    try {
        view::Preview preview("/nonexistent");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/preview.vert"), std::string::npos);
    }
}

// Reflections and refraction (once: mirrors and glass were black): a mirror wall behind a
// red ball and a clear glass ball in front of a green wall. With the trace's depth the preview
// shows what the trace shows, approximately: it is not dark where the trace is lit, and its
// mean difference is a fraction of local shading's.
struct PreviewAgainstTrace {
    double mean_abs = 0;    // per channel, 0-255, over the image
    double dark_share = 0;  // trace luminance > 0.3, preview < 0.05
    double off_share = 0;   // off by more than 32/255 in a channel
    int planes = 0;         // planar reflections drawn
};

// The preview drawn in gl against the trace's image, both kW x kH.
PreviewAgainstTrace against_trace(const Offscreen& gl, const Image& traced) {
    PreviewAgainstTrace out;
    long dark = 0, off = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Vec3 g = gl.at(x, y) / 255.0;
            Vec3 t;
            for (int k = 0; k < 3; ++k) t[k] = to_byte(traced.at(x, y)[k]) / 255.0;
            off += std::max({std::abs(g.x - t.x), std::abs(g.y - t.y), std::abs(g.z - t.z)}) >
                   32.5 / 255;
            out.mean_abs += (std::abs(g.x - t.x) + std::abs(g.y - t.y) + std::abs(g.z - t.z)) / 3;
            auto lum = [](const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
            dark += lum(t) > 0.3 && lum(g) < 0.05;
        }
    out.mean_abs *= 255.0 / (kW * kH);
    out.dark_share = static_cast<double>(dark) / (kW * kH);
    out.off_share = static_cast<double>(off) / (kW * kH);
    return out;
}

// The preview at the recursion depth `depth` against the trace at `trace_depth` (the same by
// default).
PreviewAgainstTrace preview_against_trace(const RenderScene& scene, int depth,
                                          int trace_depth = 0) {
    Offscreen gl;
    EXPECT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, 96);
    const Camera cam = make_camera(scene, kW, kH);
    preview.draw(scene, plan_for(scene, true), cam, kW, kH, depth);
    glFinish();
    EXPECT_EQ(preview.environment_maps() > 0, depth >= 2);
    const Image traced = test::render(scene, kW, kH, trace_depth > 0 ? trace_depth : depth);
    PreviewAgainstTrace out = against_trace(gl, traced);
    out.planes = preview.planar_reflections();
    return out;
}

TEST(GlPreview, MirrorsAndGlassShowWhatTheTraceShows) {
    const RenderScene scene = test::compile(
        "#camera 0 1 6  0 -0.1 -1  0 1 0  0.5\n"
        "#ambient 0.2 0.2 0.2\n"
        "#light_point 1 1 1  2 4 4  1 0 0\n"
        "#material 0 0 0  0 0 0  0 0 0  0.9 0.9 0.9  50  0 0 0  1  -1 !mirror!\n"
        "#material 0 0 0  0.2 0 0  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  0.9 0.9 0.9  1  -1 !glass!\n"
        "#material 0 0 0  0 0.2 0  0.1 0.9 0.1  0 0 0  1  0 0 0  1  -1 !green!\n"
        "#shape_box 0  -1.5 1 -2  2.5 3 0.1\n"
        "#shape_sphere 1  -1.2 0.8 0  0.6\n"
        "#shape_sphere 2  1.3 0.9 1  0.7\n"
        "#shape_box 3  1.5 1 -2  2 3 0.1\n");
    const PreviewAgainstTrace local = preview_against_trace(scene, 1, 5);
    const PreviewAgainstTrace reflected = preview_against_trace(scene, 5);
    std::printf("local shading only: mean difference %.2f, dark where lit %.4f\n", local.mean_abs,
                local.dark_share);
    std::printf("with reflections:   mean difference %.2f, dark where lit %.4f\n",
                reflected.mean_abs, reflected.dark_share);
    EXPECT_GT(local.dark_share, 0.02);  // the scene tests something: glass and mirror dark
    EXPECT_LT(reflected.dark_share, 0.01);
    EXPECT_LT(reflected.mean_abs, 0.5 * local.mean_abs);
}

// A mirror floor (spec §7.4): the trace shows the spheres mirrored in it; the preview draws the
// scene mirrored about the floor's plane for it (a cube map from the floor's centre cannot), and
// the two agree where the reflections are.
TEST(GlPreview, AMirrorFloorReflectsTheScene) {
    const RenderScene scene = test::compile(
        "#camera 0 3 8  0 -0.35 -1  0 1 0  0.45\n#ambient 0.2 0.2 0.2\n"
        "#light_point 1 1 1  0 6 4  1 0 0\n"
        "#material 0 0 0  0.1 0.1 0.1  0.2 0.2 0.2  0.7 0.7 0.7  50  0 0 0  1  -1 !floor!\n"
        "#material 0 0 0  0.2 0 0  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0.2  0.1 0.2 0.9  0 0 0  1  0 0 0  1  -1 !blue!\n"
        "#vertex -6 0 -4  0 0 0  0 0\n#vertex -6 0 4  0 0 0  0 0\n#vertex 6 0 4  0 0 0  0 0\n"
        "#vertex 6 0 -4  0 0 0  0 0\n#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"
        "#shape_sphere 1  -1.5 1.2 0  1\n#shape_sphere 2  1.5 1.2 0.5  1\n");
    const PreviewAgainstTrace reflected = preview_against_trace(scene, 5);
    std::printf("mirror floor: mean difference %.2f, dark where lit %.4f, %d planes\n",
                reflected.mean_abs, reflected.dark_share, reflected.planes);
    EXPECT_EQ(reflected.planes, 1);
    EXPECT_LT(reflected.mean_abs, 0.6);  // 1.19 with the cube map of the floor's centre
}

// What a mirror floor shows is shaded as the trace shades it, reflections included: a chrome
// ball seen in the floor shows what the ball mirrors (its cube map), not its own dark diffuse
// colour. The scene is lit red and blue from the walls the ball reflects.
TEST(GlPreview, AMirrorFloorShowsTheReflectionsOfWhatItMirrors) {
    const RenderScene scene = test::compile(
        "#camera 0 2.2 8  0 -0.3 -1  0 1 0  0.5\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 6 6  1 0 0\n"
        "#material 0 0 0  0 0 0  0 0 0  0.8 0.8 0.8  50  0 0 0  1  -1 !floor!\n"
        "#material 0 0 0  0 0 0  0.02 0.02 0.02  0.9 0.9 0.9  300  0 0 0  1  -1 !chrome!\n"
        "#material 0 0 0  0.9 0.1 0.1  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0.1 0.1 0.9  0.1 0.1 0.9  0 0 0  1  0 0 0  1  -1 !blue!\n"
        "#vertex -8 0 -6  0 0 0  0 0\n#vertex -8 0 12  0 0 0  0 0\n#vertex 8 0 12  0 0 0  0 0\n"
        "#vertex 8 0 -6  0 0 0  0 0\n#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"
        "#shape_sphere 1  0 1.2 0  1.2\n"
        "#shape_box 2  0 4 -5  16 8 0.2\n#shape_box 3  0 4 11  16 8 0.2\n"
        "#shape_box 2  -7 4 3  0.2 8 16\n#shape_box 3  7 4 3  0.2 8 16\n");
    const PreviewAgainstTrace reflected = preview_against_trace(scene, 5);
    std::printf("chrome ball over a mirror floor: mean difference %.2f\n", reflected.mean_abs);
    EXPECT_EQ(reflected.planes, 1);      // the floor; 2 when a facet of the ball was taken too
    EXPECT_LT(reflected.mean_abs, 2.6);  // 3.19 with the ball's local shading in the floor
}

// A mirror box of the floor's material: its faces are weighed against the box, not against
// the floor that shares their material, so its front face is a planar mirror too and shows the
// red wall behind the eye, as in the trace.
TEST(GlPreview, ASmallMirrorOfTheFloorsMaterialReflectsToo) {
    const RenderScene scene = test::compile(
        "#camera 0 2 6  0 -0.2 -1  0 1 0  0.35\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 4 4  1 0 0\n"
        "#material 0 0 0  0.1 0.1 0.1  0.2 0.2 0.2  0.8 0.8 0.8  50  0 0 0  1  -1 !mirror!\n"
        "#material 0 0 0  0.9 0.1 0.1  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#vertex -20 0 -20  0 0 0  0 0\n#vertex -20 0 20  0 0 0  0 0\n"
        "#vertex 20 0 20  0 0 0  0 0\n#vertex 20 0 -20  0 0 0  0 0\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"
        "#shape_box 0  0 1.2 0  2.4 2.4 0.5\n#shape_box 1  0 3 9  20 6 0.2\n");
    const PreviewAgainstTrace mirrored = preview_against_trace(scene, 3);
    std::printf("mirror box of the floor's material: mean difference %.2f, %d planes\n",
                mirrored.mean_abs, mirrored.planes);
    EXPECT_GE(mirrored.planes, 2);      // the floor and the box's front (and more of its faces)
    EXPECT_LT(mirrored.mean_abs, 2.0);  // 12.7 with the box's faces weighed against the floor
}

// A mirror floor of tiles, each of its own material (each its own face, as each instance of a
// tile file is), is one mirror: its plane is ranked by all its tiles together, ahead of the
// faces of two mirror boxes that outrank any one tile (they float a little above it: a box's
// bottom on the floor's plane would give the floor its view), and shows the red wall behind
// them as the trace does.
TEST(GlPreview, AFloorOfManyMirrorTilesIsOnePlanarMirror) {
    std::string text =
        "#camera 0 3 9  0 -0.3 -1  0 1 0  0.4\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 5 6  1 0 0\n"
        "#material 0 0 0  0.9 0.1 0.1  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0.1 0.1 0.1  0.2 0.2 0.2  0.8 0.8 0.8  50  0 0 0  1  -1 !box!\n";
    const int n = 24;  // n x n tiles over [-6, 6] x [-6, 6]
    for (int k = 0; k < n * n; ++k)
        text += "#material 0 0 0  0.1 0.1 0.1  0.2 0.2 " + std::to_string(0.2 + 1e-4 * k) +
                "  0.8 0.8 0.8  50  0 0 0  1  -1 !tile!\n";
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            text += "#vertex " + std::to_string(-6.0 + 12.0 * i / n) + " 0 " +
                    std::to_string(-6.0 + 12.0 * j / n) + "  0 0 0  0 0\n";
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int m = 2 + i * n + j, a = i * (n + 1) + j, b = a + 1, c = a + n + 2,
                      d = a + n + 1;
            text += "#shape_triangle " + std::to_string(m) + " " + std::to_string(a) + " " +
                    std::to_string(b) + " " + std::to_string(c) + "\n#shape_triangle " +
                    std::to_string(m) + " " + std::to_string(a) + " " + std::to_string(c) + " " +
                    std::to_string(d) + "\n";
        }
    text +=
        "#shape_box 1  -2.5 1.3 1  1.5 2 1.5\n#shape_box 1  2.5 1.3 1  1.5 2 1.5\n"
        "#shape_box 0  0 3 -6.5  14 6 0.2\n";
    const RenderScene scene = test::compile(text);
    const PreviewAgainstTrace mirrored = preview_against_trace(scene, 3);
    std::printf("a floor of mirror tiles: mean difference %.2f, off %.4f, %d planes\n",
                mirrored.mean_abs, mirrored.off_share, mirrored.planes);
    EXPECT_LT(mirrored.mean_abs, 4.0);  // 16.6 with each tile ranked alone
}

// A ball of glass is a lens: the trace sees what is behind it through two interfaces, upside
// down (a red wall below a blue one shows red at the ball's top); so does the preview.
TEST(GlPreview, AGlassBallInvertsWhatIsBehindIt) {
    const RenderScene scene = test::compile(
        "#camera 0 0 6  0 0 -1  0 1 0  0.25\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 0 6  1 0 0\n"
        "#material 0 0 0  0.3 0 0  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0.3  0.1 0.1 0.9  0 0 0  1  0 0 0  1  -1 !blue!\n"
        "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  1.5  -1 !glass!\n"
        "#shape_box 0  0 -2 -4  20 4 0.2\n#shape_box 1  0 2 -4  20 4 0.2\n"
        "#shape_sphere 2  0 0 0  1\n");
    const PreviewAgainstTrace through = preview_against_trace(scene, 5);
    std::printf("glass ball: mean difference %.2f\n", through.mean_abs);
    EXPECT_LT(through.mean_abs, 3.0);  // 5.4 through the front surface alone
}

// What a mirror floor shows is as sharp as the trace's once the view is still: a fine checker
// wall seen in it (the reflection rendered at the pane's resolution, not half of it).
TEST(GlPreview, AMirrorShowsFineDetailSharply) {
    const std::string tex = std::string(RT_SOURCE_DIR) + "/scenes/textures/checker.bmp";
    const RenderScene scene = test::compile(
        "#camera 0 1.5 8  0 -0.1 -1  0 1 0  0.3\n#ambient 0.4 0.4 0.4\n"
        "#light_point 1 1 1  0 4 6  1 0 0\n#texture " +
        tex +
        "\n#material 0 0 0  0 0 0  0 0 0  0.9 0.9 0.9  50  0 0 0  1  -1 !mirror!\n"
        "#material 0 0 0  0.3 0.3 0.3  0.8 0.8 0.8  0 0 0  1  0 0 0  1  0 !checker!\n"
        "#vertex -8 0 -3  0 0 0  0 0\n#vertex -8 0 9  0 0 0  0 0\n#vertex 8 0 9  0 0 0  0 0\n"
        "#vertex 8 0 -3  0 0 0  0 0\n#vertex -8 0 -3  0 0 1  0 0\n#vertex 8 0 -3  0 0 1  24 0\n"
        "#vertex 8 6 -3  0 0 1  24 9\n#vertex -8 6 -3  0 0 1  0 9\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"
        "#shape_triangle 1 4 5 6\n#shape_triangle 1 4 6 7\n");
    const PreviewAgainstTrace mirrored = preview_against_trace(scene, 3);
    std::printf("fine checker in a mirror: mean difference %.2f, %.1f%% off\n", mirrored.mean_abs,
                100 * mirrored.off_share);
    EXPECT_EQ(mirrored.planes, 1);
    EXPECT_LT(mirrored.off_share, 0.08);  // 37% at half the resolution
}

// A ball of clear glass with a highlight colour mirrors at its inner surface too: the trace adds
// K_S times what the far side mirrors where the ray leaves, so its upper half shows the lit
// floor below, not only the dark sky behind.
TEST(GlPreview, GlassMirrorsInsideAsTheTraceDoes) {
    const RenderScene scene = test::compile(
        "#camera 0 1 6  0 0 -1  0 1 0  0.25\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 5 5  1 0 0\n"
        "#material 0 0 0  0.3 0.3 0.3  0.9 0.9 0.9  0 0 0  1  0 0 0  1  -1 !floor!\n"
        "#material 0 0 0  0 0 0  0 0 0  0.5 0.5 0.5  100  0.5 0.5 0.5  1  -1 !glass!\n"
        "#shape_box 0  0 -0.1 0  20 0.2 20\n#shape_sphere 1  0 1 0  1\n");
    const PreviewAgainstTrace inside = preview_against_trace(scene, 5);
    std::printf("glass mirroring inside: mean difference %.2f\n", inside.mean_abs);
    // 3.92 without; 2.95 with one hit inside, what it mirrors looked up in the map
    EXPECT_LT(inside.mean_abs, 2.0);
    // At depth 3 the ray refracted in meets the far side at depth 2 and what that mirrors
    // meets the surface at depth 1: shaded, with no rays of its own.
    const PreviewAgainstTrace limited = preview_against_trace(scene, 3);
    std::printf("glass mirroring inside at depth 3: mean difference %.2f\n", limited.mean_abs);
    EXPECT_LT(limited.mean_abs, 1.5);  // 3.26 with four hits whatever the depth
}

// A block of green glass on a checker floor: what shows through it is the floor behind, at a
// grazing angle, where three steps along the map's distances had not found the floor yet.
TEST(GlPreview, AGrazingFloorSeenThroughGlassIsWhereTheTraceSeesIt) {
    const std::string tex = std::string(RT_SOURCE_DIR) + "/scenes/textures/checker.bmp";
    const RenderScene scene = test::compile(
        "#camera 0 1.2 7  0 -0.05 -1  0 1 0  0.14\n#ambient 0.4 0.4 0.4\n"
        "#background 0.45 0.6 0.8\n#light_point 1 1 1  -2 6 6  1 0 0\n#texture " +
        tex +
        "\n#material 0 0 0  0.3 0.3 0.3  0.8 0.8 0.8  0 0 0  1  0 0 0  1  0 !floor!\n"
        "#material 0 0 0  0 0 0  0.05 0.05 0.05  0.1 0.1 0.1  100  0.3 0.8 0.4  1.1  -1 !glass!\n"
        "#vertex -20 0 -20  0 1 0  0 10\n#vertex -20 0 20  0 1 0  0 0\n"
        "#vertex 20 0 20  0 1 0  10 0\n#vertex 20 0 -20  0 1 0  10 10\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n#shape_box 1  0 1 0  1.6 2 0.6\n");
    const PreviewAgainstTrace through = preview_against_trace(scene, 5);
    std::printf("checker floor through green glass: mean difference %.2f, %.1f%% off\n",
                through.mean_abs, 100 * through.off_share);
    EXPECT_LT(through.off_share, 0.08);  // 10.2% with three steps, not eight
}

// Where a ray leaves a tinted glass ball the trace shades the inner surface like any hit (its
// normal facing the ray): lit from above, the ball's lower half glows blue from inside.
TEST(GlPreview, GlassIsShadedWhereTheRayLeaves) {
    const RenderScene scene = test::compile(
        "#camera 0 0 6  0 0 -1  0 1 0  0.25\n#ambient 0.2 0.2 0.2\n"
        "#light_dir 1 1 1  0 -1 -0.2\n"
        "#material 0 0 0  0 0 0.2  0.1 0.1 0.8  0 0 0  1  0.7 0.7 0.7  1  -1 !blue glass!\n"
        "#shape_sphere 0  0 0 0  1\n");
    const PreviewAgainstTrace inner = preview_against_trace(scene, 5);
    std::printf("tinted glass shaded inside: mean difference %.2f\n", inner.mean_abs);
    EXPECT_LT(inner.mean_abs, 2.0);  // 3.75 without the exit's shading
}

// A ring of glass bends what is behind it twice too: the ray leaves the torus where sphere
// tracing its distance from inside finds the surface (spec §13.7), as the trace's does.
TEST(GlPreview, AGlassTorusBendsWhatIsBehindItTwice) {
    const RenderScene scene = test::compile(
        "#camera 0 3 6  0 -0.45 -1  0 1 0  0.35\n#light_point 0 0 0  1 1 1  1 1 1  0 4 6  1 0 0\n"
        "#material 0 0 0  0.3 0 0  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0.3  0.1 0.1 0.9  0 0 0  1  0 0 0  1  -1 !blue!\n"
        "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  1.5  -1 !glass!\n"
        "#shape_box 0  -5 -1 0  10 0.2 20\n#shape_box 1  5 -1 0  10 0.2 20\n"
        "#shape_torus 2  0 0 0  0.6 1.4\n");
    const PreviewAgainstTrace through = preview_against_trace(scene, 5);
    std::printf("glass torus: mean difference %.2f, %.1f%% off\n", through.mean_abs,
                100 * through.off_share);
    EXPECT_LT(through.mean_abs, 3.0);
}

// Light leaving a glass ring (V3, K_S = 1, T = 0.75) past the far edge of the small floor under
// it meets nothing in the trace. From the map's centre, inside the ring, the floor is seen
// that way, so the ray is marched through the map: a point hidden from the centre (under the
// floor, past its edge) is no hit.
TEST(GlPreview, LightLeavingGlassPastAFloorsEdgeMeetsNothing) {
    const RenderScene scene = test::compile(
        "#camera  0 6 6  0 -0.707107 -0.707107  0 0.707107 -0.707107  0.5\n"
        "#light_dir  0.5 0.5 0.5  1 1 1  1 1 1  -0.707107 -0.707107 0\n"
        "#material  0 0 0  0.3 0.3 0.3  0.1 0.1 0.5  1 1 1 128  0 0 0  1.05  -1  !floor!\n"
        "#material  0 0 0  0 0 0  0.25 0.25 0.25  1 1 1 128  0.75 0.75 0.75  1.05  -1  !glass!\n"
        "#vertex  -2.5 0 0  0 1 0  0 1\n#vertex  0 0 2.5  0 1 0  1 1\n"
        "#vertex  2.5 0 0  0 1 0  1 0\n#vertex  0 0 -2.5  0 1 0  0 0\n"
        "#shape_triangles  0\n#shape_list_begin\n#shape_triangle  0 1 2\n"
        "#shape_triangle  0 2 3\n#shape_list_end\n"
        "#shape_torus  1  0 1.2 0  0.7 1.3\n");
    const PreviewAgainstTrace ring = preview_against_trace(scene, 5);
    std::printf("glass ring over a small floor: mean difference %.2f, %.1f%% off\n", ring.mean_abs,
                100 * ring.off_share);
    EXPECT_LT(ring.mean_abs, 6.0);     // 7.0 looking the way out up in the map
    EXPECT_LT(ring.off_share, 0.085);  // 10%
}

// While the view moves a big mesh is drawn coarse (its PreviewGeometry::Set::coarse), and in
// full once still; both look like the trace of the ball.
TEST(GlPreview, BigMeshesAreDrawnCoarseWhileTheViewMoves) {
    const RenderScene scene = test::compile(
        "#camera 0 0 5  0 0 -1  0 1 0  0.4\n#light_dir 1 1 1  -1 -1 -1\n#ambient 0.2 0.2 0.2\n"
        "#material 0 0 0  0.2 0.2 0.2  0.8 0.6 0.4  0 0 0  1  0 0 0  1  -1 !m!\n"
        "#shape_sphere 0  0 0 0  1.5\n");
    const view::PreviewGeometry geometry = view::prepare_preview(scene, 720);  // 518k triangles
    ASSERT_GT(geometry.sets[0].mesh.triangle_count(), view::kCoarseAbove);
    ASSERT_GT(geometry.sets[0].coarse.triangle_count(), 0u);
    const Image traced = test::render(scene, kW, kH, 5);
    Offscreen gl;
    ASSERT_NE(gl.ctx, nullptr);
    view::Preview preview(std::string(RT_SOURCE_DIR) + "/shaders");
    preview.load(scene, geometry);
    const Camera cam = make_camera(scene, kW, kH);
    preview.moving = true;
    preview.draw(scene, plan_for(scene), cam, kW, kH);
    glFinish();
    EXPECT_EQ(preview.triangles_drawn(), geometry.sets[0].coarse.triangle_count());
    EXPECT_LE(preview.triangles_drawn(), view::kCoarseTriangles);
    const double moving = against_trace(gl, traced).mean_abs;
    preview.moving = false;
    preview.draw(scene, plan_for(scene), cam, kW, kH);
    glFinish();
    EXPECT_EQ(preview.triangles_drawn(), geometry.sets[0].mesh.triangle_count());
    const double still = against_trace(gl, traced).mean_abs;
    std::printf("big ball: mean difference %.3f moving (%zu triangles), %.3f still\n", moving,
                geometry.sets[0].coarse.triangle_count(), still);
    EXPECT_LT(moving, 0.5);
    EXPECT_LT(still, 0.5);
}

// A block of glass shifts what is behind it: the ray leaves through the face opposite the one
// it entered, parallel to where it came from (as in the trace), not along the first bend.
TEST(GlPreview, AGlassBlockShiftsWhatIsBehindIt) {
    const RenderScene scene = test::compile(
        "#camera 0 1.5 6  0 -0.25 -1  0 1 0  0.3\n#ambient 0.3 0.3 0.3\n"
        "#light_point 1 1 1  0 3 6  1 0 0\n"
        "#material 0 0 0  0.3 0 0  0.9 0.1 0.1  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0.3  0.1 0.1 0.9  0 0 0  1  0 0 0  1  -1 !blue!\n"
        "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  1.5  -1 !glass!\n"
        "#shape_box 0  -5 0 -4  10 12 0.2\n#shape_box 1  5 0 -4  10 12 0.2\n"
        "#shape_box 0  0 -1.6 0  20 0.2 20\n"
        "#shape_box 2  0 0 0  2.4 2.4 2.4\n");
    const PreviewAgainstTrace through = preview_against_trace(scene, 5);
    std::printf("glass block: mean difference %.2f\n", through.mean_abs);
    // 16.2 through the front face alone; 17.8 weighting total internal reflection by T.
    EXPECT_LT(through.mean_abs, 3.0);
}

}  // namespace
}  // namespace rt

namespace rt::view {
namespace {

// Every shader, as the web page compiles it (GLSL ES 3.00, WebGL 2), with all its switches on,
// passes Khronos' reference compiler (glslangValidator, Debian's glslang-tools). The preview's
// fragment shader is checked with csg.frag after it, as make_program() compiles them.
TEST(ShaderSource, EveryShaderCompilesAsGlslEs300) {
    if (std::system("command -v glslangValidator >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "glslangValidator is not installed (glslang-tools)";
    const std::string dir = RT_SOURCE_DIR "/shaders/";
    const std::vector<std::string> all = {
        "RT_POINT",       "RT_SPOT",    "RT_DIRECTIONAL",      "RT_TEXTURES",
        "RT_SPECULAR",    "RT_SHADOWS", "RT_TRANSMIT_SHADOWS", "RT_CSG",
        "RT_REFLECTIONS", "RT_PLANAR",  "RT_CLIP_PLANE"};
    struct Case {
        std::string file, library;
        bool transmit = false;  // shadow.frag's transmittance maps (RT_TRANSMIT)
    };
    const std::filesystem::path tmp = testing::TempDir();
    for (const Case& c : {Case{"preview.vert", ""}, Case{"preview.frag", "csg.frag"},
                          Case{"shadow.frag", "csg.frag"}, Case{"shadow.frag", "csg.frag", true},
                          Case{"lines.vert", ""}, Case{"lines.frag", ""}}) {
        std::string text;
        ASSERT_TRUE(read_file(dir + c.file, &text));
        std::vector<std::string> defines = all;
        if (c.transmit) defines.push_back("RT_TRANSMIT");
        std::string es = shader_source(text, defines, true);
        ASSERT_EQ(es.rfind("#version 300 es\n", 0), 0u);
        if (!c.library.empty()) {
            std::string lib;
            ASSERT_TRUE(read_file(dir + c.library, &lib));
            es += lib.substr(lib.find('\n'));  // its #version line dropped, as compile_shader()
        }
        const std::filesystem::path file = tmp / c.file;  // the extension names the stage
        write_file_atomic(file.string(), es);
        const std::string log = (tmp / (c.file + ".log")).string();
        const int rc =
            std::system(("glslangValidator " + file.string() + " >" + log + " 2>&1").c_str());
        std::string out;
        read_file(log, &out);
        EXPECT_EQ(rc, 0) << c.file << " as GLSL ES 3.00:\n" << out;
    }
    // The desktop's text is the file's with the defines after its #version line.
    const std::string desktop = shader_source("#version 330 core\nvoid main() {}\n", {"A"}, false);
    EXPECT_EQ(desktop, "#version 330 core\n#define A 1\nvoid main() {}\n");
}

}  // namespace
}  // namespace rt::view
