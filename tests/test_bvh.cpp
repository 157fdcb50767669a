// The BVH against brute force: the same nearest hit (distance and primitive) on many random rays,
// for every primitive kind and under instancing; empty scenes and degenerate layouts.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "render/variants.h"
#include "rt/accel/intersect.h"
#include "rt/util/isa.h"
#include "test_util.h"

namespace rt {
namespace {

// n random shapes cycling through `kinds` (0 sphere, 1 box, 2 cylinder, 3 cone, 4 triangle).
// Half transparent with `glass` (every crossing counts in transmittance).
std::string random_scene(std::mt19937& rng, int n, const std::vector<int>& kinds = {0, 1, 2, 3, 4},
                         bool glass = false) {
    std::uniform_real_distribution<double> u(-5, 5), s(0.05, 0.8);
    std::string text = glass ? "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 .5 .5 .5 1 -1 !!\n"
                             : "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    for (int i = 0; i < 3 * n; ++i)
        text += "#vertex " + std::to_string(u(rng)) + " " + std::to_string(u(rng)) + " " +
                std::to_string(u(rng)) + " 0 0 0 0 0\n";
    for (int i = 0; i < n; ++i) {
        const std::string c =
            std::to_string(u(rng)) + " " + std::to_string(u(rng)) + " " + std::to_string(u(rng));
        switch (kinds[static_cast<size_t>(i) % kinds.size()]) {
            case 0:
                text += "#shape_sphere 0 " + c + " " + std::to_string(s(rng)) + "\n";
                break;
            case 1:
                text += "#shape_box 0 " + c + " " + std::to_string(s(rng)) + " " +
                        std::to_string(s(rng)) + " " + std::to_string(s(rng)) + "\n";
                break;
            case 2:
                text += "#shape_cylinder 0 " + c + " " + std::to_string(s(rng)) + " " +
                        std::to_string(s(rng)) + "\n";
                break;
            case 3:
                text += "#shape_cone 0 " + c + " " + std::to_string(s(rng)) + " " +
                        std::to_string(s(rng)) + "\n";
                break;
            default:
                text += "#shape_triangle 0 " + std::to_string(3 * i) + " " +
                        std::to_string(3 * i + 1) + " " + std::to_string(3 * i + 2) + "\n";
        }
    }
    return text;
}

void expect_same_hits(const RenderScene& scene, std::mt19937& rng, int rays) {
    std::uniform_real_distribution<double> u(-8, 8), d(-1, 1);
    int hits = 0;
    for (int i = 0; i < rays; ++i) {
        Ray r{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
        if (i % 7 == 0) r.d = Vec3(0, 0, d(rng) < 0 ? -1 : 1);  // axis-parallel rays too
        if (glm::length(r.d) == 0) continue;
        Hit a, b;
        const bool ha = intersect(scene, r, {0, kInf}, &a);
        const bool hb = intersect_brute_force(scene, r, {0, kInf}, &b);
        ASSERT_EQ(ha, hb) << "ray " << i;
        if (!ha) continue;
        ++hits;
        EXPECT_EQ(a.t, b.t) << "ray " << i;
        EXPECT_EQ(a.instance, b.instance);
        EXPECT_EQ(a.prim, b.prim);
        // Shadow queries agree with brute force as well.
        const bool blocked_bvh = transmittance(scene, r, a.t * 1.000001) == Vec3(0.0);
        EXPECT_TRUE(blocked_bvh);
    }
    EXPECT_GT(hits, rays / 20);
}

// The geometry variant read from the scene and the generic walk give the same
// answers to every query, to the bit: nearest hit and its surface, any hit and transmittance.
void expect_variant_matches_generic(const RenderScene& scene, std::mt19937& rng, int rays) {
    const GeometryQueries& mine = geometry_queries(read_geometry(scene).variant);
    const GeometryQueries& generic = geometry_queries(kGeomGeneric);
    ASSERT_NE(&mine, &generic);
    std::uniform_real_distribution<double> u(-8, 8), d(-1, 1), len(0.5, 20);
    int hits = 0, blocked = 0;
    for (int i = 0; i < rays; ++i) {
        Ray r{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
        if (i % 7 == 0) r.d = Vec3(0, 0, d(rng) < 0 ? -1 : 1);
        if (glm::length(r.d) == 0) continue;
        Hit a, b;
        const bool ha = mine.intersect(scene, r, {0, kInf}, &a);
        ASSERT_EQ(ha, generic.intersect(scene, r, {0, kInf}, &b)) << "ray " << i;
        if (ha) {
            ++hits;
            EXPECT_EQ(a.t, b.t) << "ray " << i;
            EXPECT_EQ(a.instance, b.instance);
            EXPECT_EQ(a.prim, b.prim);
            EXPECT_EQ(a.part, b.part);
            const SurfaceInteraction sa = mine.interaction(scene, r, a, true),
                                     sb = generic.interaction(scene, r, b, true);
            EXPECT_EQ(sa.p, sb.p);
            EXPECT_EQ(sa.p_error, sb.p_error);
            EXPECT_EQ(sa.n_geometric, sb.n_geometric);
            EXPECT_EQ(sa.n_shading, sb.n_shading);
            EXPECT_EQ(sa.material, sb.material);
            EXPECT_EQ(sa.uv, sb.uv);
        }
        const double t_max = len(rng);
        const bool occ = mine.occluded(scene, r, t_max);
        EXPECT_EQ(occ, generic.occluded(scene, r, t_max)) << "ray " << i;
        blocked += occ;
        EXPECT_EQ(mine.transmittance(scene, r, t_max), generic.transmittance(scene, r, t_max))
            << "ray " << i;
    }
    EXPECT_GT(hits, rays / 50);
    EXPECT_GT(blocked, rays / 100);
}

uint32_t layout_bits(const RenderScene& scene) {
    return read_geometry(scene).variant & kGeomPerSet;
}

// Every walk the scenes pick: one kind per set (each analytic kind, packed triangles), the
// analytic kinds together, all five, a transformed single instance, several instances whose
// files differ (the layout picked per set) and several of one file.
TEST(Bvh, EveryGeometryVariantMatchesTheGenericWalk) {
    std::mt19937 rng(17);
    const struct {
        std::vector<int> kinds;
        SetLayout layout;
    } layouts[] = {{{0}, SetLayout::Spheres},          {{1}, SetLayout::Boxes},
                   {{2}, SetLayout::Cylinders},        {{3}, SetLayout::Cones},
                   {{4}, SetLayout::Triangles},        {{0, 1, 2, 3}, SetLayout::Analytic},
                   {{0, 1, 2, 3, 4}, SetLayout::Mixed}};
    for (const auto& l : layouts) {
        SCOPED_TRACE(static_cast<int>(l.layout));
        const std::string text = random_scene(rng, 150, l.kinds, true);
        const RenderScene scene = test::compile(text);
        EXPECT_EQ(read_geometry(scene).variant, geom_layout_bits(l.layout));  // one instance, no xf
        expect_variant_matches_generic(scene, rng, 1500);
        // The same file under a transform: the top-level box test and transformed rays.
        // (Definitions first, then the group around the shapes.)
        const size_t shapes = text.find("#shape_");
        const RenderScene moved = test::compile(
            text.substr(0, shapes) + "#group_begin 1 0.2 0 0.5  0 1.5 0 -1  0 0 0.8 0  0 0 0 1\n" +
            text.substr(shapes) + "#group_end\n");
        // (Triangles are flattened into the file's frame: no transform is left.)
        EXPECT_EQ(
            read_geometry(moved).variant,
            geom_layout_bits(l.layout) | (l.layout == SetLayout::Triangles ? 0u : kGeomTransforms));
        expect_variant_matches_generic(moved, rng, 1500);
    }

    const std::string dir = ::testing::TempDir();
    const std::string balls = (std::filesystem::path(dir) / "rt_variant_balls.ray").string();
    const std::string mesh = (std::filesystem::path(dir) / "rt_variant_mesh.ray").string();
    { std::ofstream(balls) << random_scene(rng, 40, {0}, true); }
    { std::ofstream(mesh) << random_scene(rng, 60, {4}, true); }
    auto placed = [](int file, double x) {
        return "#group_begin 1 0 0 " + std::to_string(x) + "  0 1 0 0  0 0 1 0  0 0 0 1\n" +
               "#ray_file_instance " + std::to_string(file) + "\n#group_end\n";
    };
    const std::string files = "#ray_file " + balls + "\n#ray_file " + mesh + "\n";
    // Instanced, the top file's own shapes a third layout: each set walked by its own.
    const std::string own = random_scene(rng, 20, {1, 2}, true);
    const size_t own_shapes = own.find("#shape_");
    const RenderScene differ = test::compile(files + own.substr(0, own_shapes) + placed(0, -4) +
                                             placed(1, 0) + placed(0, 4) + own.substr(own_shapes));
    EXPECT_EQ(read_geometry(differ).variant, kGeomInstancing | kGeomTransforms | kGeomPerSet);
    expect_variant_matches_generic(differ, rng, 2000);
    // Two files placed where they are (identity): the top-level walk without transforms.
    const RenderScene still = test::compile(files + "#ray_file_instance 0\n#ray_file_instance 1\n");
    EXPECT_EQ(read_geometry(still).variant, kGeomInstancing | kGeomPerSet);
    expect_variant_matches_generic(still, rng, 2000);
    // One transformed instance: its box is tested before its rays are transformed.
    const RenderScene one = test::compile(files + placed(0, 2));
    EXPECT_EQ(read_geometry(one).variant,
              kGeomInstancing | kGeomTransforms | geom_layout_bits(SetLayout::Spheres));
    expect_variant_matches_generic(one, rng, 2000);
    // Instances of one mesh only: packed triangles throughout.
    const RenderScene same = test::compile(files + placed(1, -3) + placed(1, 3) + placed(1, 0));
    EXPECT_EQ(layout_bits(same), geom_layout_bits(SetLayout::Triangles));
    EXPECT_TRUE(read_geometry(same).variant & kGeomInstancing);
    expect_variant_matches_generic(same, rng, 2000);
}

// A scene of `triangles` random triangles of about `size`, each written `copies` times: exact
// copies but the last, whose corners move by up to 1e-6 (near-coincident pairs, as in a
// z-fighting mesh).
std::string copied_triangles(std::mt19937& rng, int triangles, int copies, double size) {
    std::uniform_real_distribution<double> u(-5, 5), e(-1e-6, 1e-6);
    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 .5 .5 .5 1 -1 !!\n", shapes;
    int nv = 0;
    for (int i = 0; i < triangles; ++i) {
        Vec3 v[3];
        for (Vec3& p : v) p = size * Vec3(u(rng), u(rng), u(rng));
        const Vec3 c(u(rng), u(rng), u(rng));
        for (int copy = 0; copy < copies; ++copy) {
            for (const Vec3& p : v) {
                char buf[200];
                const Vec3 q =
                    c + p + (copy == copies - 1 ? Vec3(e(rng), e(rng), e(rng)) : Vec3(0.0));
                std::snprintf(buf, sizeof buf, "#vertex %.17g %.17g %.17g 0 0 0 0 0\n", q.x, q.y,
                              q.z);
                text += buf;
            }
            shapes += "#shape_triangle 0 " + std::to_string(nv) + " " + std::to_string(nv + 1) +
                      " " + std::to_string(nv + 2) + "\n";
            nv += 3;
        }
    }
    return text + shapes;
}

// Pairs of near-coincident triangles (the copy's vertices moved by up to 1e-6, as in a
// z-fighting mesh): the packed walk tests four lanes against the bound at the start of a block,
// the generic walk one triangle at a time against a bound tightened by the hits before. The
// kernel's upper test is conservative, so both find the same triangle of every pair (before it
// was, 2,942 of 325k hits differed).
TEST(Bvh, NearCoincidentTrianglesGiveThePackedAndTheGenericWalkTheSameHit) {
    std::mt19937 rng(2);
    const RenderScene scene = test::compile(copied_triangles(rng, 300, 2, 0.3));
    ASSERT_EQ(read_geometry(scene).variant, geom_layout_bits(SetLayout::Triangles));
    expect_variant_matches_generic(scene, rng, 60000);
}

TEST(Bvh, SceneWithoutShapesAnswersAtOnce) {
    const RenderScene empty = test::compile("#background 0 0 0\n#light_dir 1 1 1  0 -1 0\n");
    EXPECT_EQ(read_geometry(empty).variant, static_cast<uint32_t>(kGeomEmpty));
    const Ray r{{0, 0, 0}, {0, 0, -1}};
    Hit h;
    EXPECT_FALSE(intersect(empty, r, {0, kInf}, &h));
    EXPECT_FALSE(occluded(empty, r, kInf));
    EXPECT_EQ(transmittance(empty, r, kInf), Vec3(1.0));
    // The generic walk agrees (an empty top-level BVH).
    EXPECT_FALSE(geometry_queries(kGeomGeneric).intersect(empty, r, {0, kInf}, &h));
}

TEST(Bvh, MatchesBruteForceOnEveryPrimitiveKind) {
    std::mt19937 rng(7);
    const RenderScene scene = test::compile(random_scene(rng, 400));
    expect_same_hits(scene, rng, 4000);
}

TEST(Bvh, MatchesBruteForceUnderInstancingAndGroups) {
    std::mt19937 rng(11);
    // (A path with "//" would start a comment, spec §2: build it with filesystem::path.)
    const std::string part =
        (std::filesystem::path(::testing::TempDir()) / "rt_bvh_part.ray").string();
    { std::ofstream(part) << random_scene(rng, 60); }
    std::string text = "#ray_file " + part + "\n";
    std::uniform_real_distribution<double> u(-6, 6), s(0.3, 1.5);
    for (int i = 0; i < 12; ++i) {
        text += "#group_begin " + std::to_string(s(rng)) + " 0.2 0 " + std::to_string(u(rng)) +
                "  0 " + std::to_string(s(rng)) + " 0 " + std::to_string(u(rng)) + "  0.1 0 " +
                std::to_string(s(rng)) + " " + std::to_string(u(rng)) +
                "  0 0 0 1\n#ray_file_instance 0\n#group_end\n";
    }
    const RenderScene scene = test::compile(text);
    EXPECT_EQ(scene.sets.size(), 1u);  // one compiled copy for all twelve instances
    EXPECT_EQ(scene.instances.size(), 12u);
    expect_same_hits(scene, rng, 3000);
}

TEST(Bvh, EmptySceneAndOnePrimitive) {
    const RenderScene empty = test::compile("#background 0 0 0\n");
    Hit h;
    EXPECT_FALSE(intersect(empty, {{0, 0, 0}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_EQ(transmittance(empty, {{0, 0, 0}, {0, 0, -1}}, kInf), Vec3(1.0));
    const RenderScene one = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere 0 0 0 -5 1\n");
    ASSERT_TRUE(intersect(one, {{0, 0, 0}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_NEAR(h.t, 4, 1e-12);
}

TEST(Bvh, AllPrimitivesAtOnePointAndExtremeExtents) {
    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    for (int i = 0; i < 300; ++i) text += "#shape_sphere 0 1 1 1 " + std::to_string(1 + i) + "\n";
    text += "#shape_sphere 0 1e6 0 0 1e-3\n#shape_sphere 0 -1e6 0 0 1e4\n";
    const RenderScene scene = test::compile(text);
    std::mt19937 rng(3);
    expect_same_hits(scene, rng, 500);
    Hit h;
    ASSERT_TRUE(intersect(scene, {{1e6, 0, 10}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_NEAR(h.t, 10 - 1e-3, 1e-9);
}

// A direction component below 1e-30 is a containment test in the node boxes, widened by how far
// the ray drifts along that axis before t_max: a ray with d.y = 5e-31 from y = 0 reaches y = 2.5
// at x = 5e30, where a box sits among spheres (so there is a BVH to walk).
TEST(Bvh, TinyDirectionComponentsDriftIntoBoxes) {
    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    for (int i = 0; i < 40; ++i) text += "#shape_sphere 0 " + std::to_string(i) + " -50 0 1\n";
    text += "#shape_box 0 5e30 2.5 0 1e29 1 1\n";  // y in [2, 3]
    const RenderScene scene = test::compile(text);
    const Ray r{{0, 0, 0}, {1, 5e-31, 0}};
    Hit h, hb;
    ASSERT_TRUE(intersect_brute_force(scene, r, {0, kInf}, &hb));
    ASSERT_TRUE(intersect(scene, r, {0, kInf}, &h));
    EXPECT_EQ(h.t, hb.t);
    // Exactly zero: the containment test alone (the origin on the box's face counts as inside).
    const Ray flat{{0, -49, 0}, {1, 0, 0}};
    ASSERT_TRUE(intersect(scene, flat, {0, kInf}, &h));
    ASSERT_TRUE(intersect_brute_force(scene, flat, {0, kInf}, &hb));
    EXPECT_EQ(h.t, hb.t);
}

TEST(Bvh, GeometricChainOfSizesKeepsTheTreeShallow) {
    // SAH peels one sphere at a time off sizes growing as 1.3^i: without a depth limit the tree
    // became a chain deeper than the traversal stack.
    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    for (int i = 0; i < 1500; ++i) {
        const double x = std::pow(1.3, i);
        text += "#shape_sphere 0 " + std::to_string(x) + " 0 0 " + std::to_string(0.4 * x) + "\n";
    }
    const RenderScene scene = test::compile(text);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 200; ++i) {
        const Ray r{{std::pow(1.3, i % 1400), 0, 1e3}, glm::normalize(Vec3(u(rng), u(rng), -1))};
        Hit a, b;
        ASSERT_EQ(intersect(scene, r, {0, kInf}, &a),
                  intersect_brute_force(scene, r, {0, kInf}, &b));
        EXPECT_EQ(a.prim, b.prim);
    }
}

// Calls f(node, slot, first, count) for every leaf of a tree.
template <class F>
void for_each_leaf(const Bvh& bvh, F&& f) {
    for (const Bvh4Node& n : bvh.nodes)
        for (uint32_t c = 0; c < n.num_children; ++c) {
            if (!(n.child[c] & Bvh4Node::kLeaf)) continue;
            f(n, c, Bvh4Node::leaf_first(n.child[c]), Bvh4Node::leaf_count(n.child[c]));
        }
}

TEST(Bvh, BuildCoversEveryPrimitiveOnce) {
    std::vector<Bounds3> boxes;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-100, 100);
    for (int i = 0; i < 5000; ++i) {
        const Vec3 c(u(rng), u(rng), u(rng));
        boxes.push_back({c - Vec3(0.5), c + Vec3(0.5)});
    }
    const Bvh bvh = build_bvh(boxes);
    std::vector<int> seen(boxes.size(), 0);
    // Every leaf range appears once, and each float box contains its primitives' double boxes.
    for_each_leaf(bvh, [&](const Bvh4Node& n, uint32_t c, uint32_t first, uint32_t count) {
        EXPECT_GE(count, 1u);
        EXPECT_LE(count, Bvh4Node::kMaxLeafCount);
        for (uint32_t i = first; i < first + count; ++i) {
            const Bounds3& b = boxes[bvh.indices[i]];
            ++seen[bvh.indices[i]];
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(static_cast<double>(n.lo[a][c]), b.lo[a]);
                EXPECT_GE(static_cast<double>(n.hi[a][c]), b.hi[a]);
            }
        }
    });
    for (int s : seen) EXPECT_EQ(s, 1);
}

// The 8-wide nodes hold the same leaves as the 4-wide ones (collapsed from the same binary tree),
// each box containing what is under it, at most eight children a node.
TEST(Bvh, WideNodesHoldTheSameLeavesAsTheFourWideOnes) {
    std::vector<Bounds3> boxes;
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-100, 100);
    for (int i = 0; i < 5000; ++i) {
        const Vec3 c(u(rng), u(rng), u(rng));
        boxes.push_back({c - Vec3(0.5), c + Vec3(0.5)});
    }
    const Bvh bvh = build_bvh(boxes, {4, 16, 4, true});
    ASSERT_FALSE(bvh.nodes8.empty());
    EXPECT_LT(bvh.nodes8.size(), bvh.nodes.size());
    std::vector<std::pair<uint32_t, uint32_t>> leaves4, leaves8;
    for_each_leaf(bvh, [&](const Bvh4Node&, uint32_t, uint32_t first, uint32_t count) {
        leaves4.emplace_back(first, count);
    });
    std::vector<int> reached(bvh.nodes8.size(), 0);  // as some node's child
    for (const Bvh8Node& n : bvh.nodes8) {
        EXPECT_GE(n.num_children, 1u);
        EXPECT_LE(n.num_children, 8u);
        for (uint32_t c = 0; c < n.num_children; ++c) {
            if (!(n.child[c] & Bvh4Node::kLeaf)) {
                ++reached[n.child[c]];
                continue;
            }
            const uint32_t first = Bvh4Node::leaf_first(n.child[c]);
            const uint32_t count = Bvh4Node::leaf_count(n.child[c]);
            leaves8.emplace_back(first, count);
            for (uint32_t i = first; i < first + count; ++i)
                for (int a = 0; a < 3; ++a) {
                    EXPECT_LE(static_cast<double>(n.lo[a][c]), boxes[bvh.indices[i]].lo[a]);
                    EXPECT_GE(static_cast<double>(n.hi[a][c]), boxes[bvh.indices[i]].hi[a]);
                }
        }
        for (uint32_t c = n.num_children; c < 8; ++c) EXPECT_EQ(n.child[c], Bvh4Node::kEmpty);
    }
    for (size_t k = 0; k < reached.size(); ++k) EXPECT_EQ(reached[k], k == 0 ? 0 : 1) << k;
    std::sort(leaves4.begin(), leaves4.end());
    std::sort(leaves8.begin(), leaves8.end());
    EXPECT_EQ(leaves4, leaves8);
}

// Every instruction set's walks give the same answers, to the bit, on a mesh whose triangles
// come in 24 exact copies and one near-exact one: the AVX2 and AVX-512 walks take the 8-wide
// nodes, the SSE2 ones the 4-wide nodes, and the copies of a triangle lie in several leaves
// that the two trees visit in other orders. Of hits at the same distance the lowest primitive
// wins in both, as in the brute-force walk.
TEST(Bvh, EveryInstructionSetFindsTheSameHitsAsBruteForce) {
    std::mt19937 rng(29);
    const RenderScene scene = test::compile(copied_triangles(rng, 200, 25, 0.6));
    const uint32_t variant = read_geometry(scene).variant;
    ASSERT_EQ(variant, geom_layout_bits(SetLayout::Triangles));
    EXPECT_EQ(scene.sets[0].bvh.nodes8.empty(), active_isa() == Isa::Sse2);
    std::vector<std::pair<Isa, const GeometryQueries*>> sets;
    for (const Isa isa : supported_isas())
#ifdef RT_SSE2_ONLY  // built without the wide kernels: the CPU "runs" SSE2 alone
        sets.emplace_back(isa, &sse2::geometry_queries(variant));
#else
        sets.emplace_back(isa, isa == Isa::Sse2   ? &sse2::geometry_queries(variant)
                               : isa == Isa::Avx2 ? &avx2::geometry_queries(variant)
                                                  : &avx512::geometry_queries(variant));
#endif
    std::uniform_real_distribution<double> u(-5, 5), d(-1, 1), len(0.5, 20);
    int hits = 0;
    for (int i = 0; i < 3000; ++i) {
        const Ray r{{u(rng), u(rng), u(rng)}, {d(rng), d(rng), d(rng)}};
        if (glm::length(r.d) == 0) continue;
        Hit b;
        const bool hb = intersect_brute_force(scene, r, {0, kInf}, &b);
        hits += hb;
        const double t_max = len(rng);
        for (const auto& [isa, q] : sets) {
            SCOPED_TRACE(std::string(isa_name(isa)) + ", ray " + std::to_string(i));
            Hit a;
            ASSERT_EQ(q->intersect(scene, r, {0, kInf}, &a), hb);
            if (hb) {
                EXPECT_EQ(a.t, b.t);
                EXPECT_EQ(a.prim, b.prim);
            }
            EXPECT_EQ(q->occluded(scene, r, t_max), sets[0].second->occluded(scene, r, t_max));
            EXPECT_EQ(q->transmittance(scene, r, t_max),
                      sets[0].second->transmittance(scene, r, t_max));
        }
    }
    EXPECT_GT(hits, 300);
}

// The build sorts float copies of the bounds: shapes out to the compile's limit of 1e300 have
// infinite float bounds, and a centroid of -inf + inf would be NaN. Every primitive still lands
// in exactly one leaf, and rays find the same hits as the brute-force walk.
TEST(Bvh, BoundsBeyondFloatRangeStillBuild) {
    std::vector<Bounds3> boxes;
    for (int i = 0; i < 200; ++i) boxes.push_back({Vec3(i, 0, 0), Vec3(i + 0.5, 1, 1)});
    boxes.push_back({Vec3(-1e300), Vec3(1e300)});
    boxes.push_back({Vec3(1e39, 0, 0), Vec3(1e300, 1, 1)});
    const Bvh bvh = build_bvh(boxes);
    std::vector<int> seen(boxes.size(), 0);
    for_each_leaf(bvh, [&](const Bvh4Node&, uint32_t, uint32_t first, uint32_t count) {
        EXPECT_LE(count, 4u);  // SAH splits (NaN centroids fell back to halving, up to 15)
        for (uint32_t i = first; i < first + count; ++i) ++seen[bvh.indices[i]];
    });
    for (int s : seen) EXPECT_EQ(s, 1);

    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    for (int i = 0; i < 100; ++i) text += "#shape_sphere 0 " + std::to_string(i) + " 0 0 0.3\n";
    text += "#shape_sphere 0 0 0 0 1e100\n#shape_sphere 0 1e60 0 0 1e59\n";  // beyond float
    const RenderScene scene = test::compile(text);
    std::mt19937 rng(8);
    expect_same_hits(scene, rng, 300);
}

// A direction component beyond 1e38 has a float reciprocal of zero, and an empty slot of a node
// (lo = +inf, hi = -inf) then gives inf * 0 = NaN distances: the walk must still skip the slot
// (it once treated it as a leaf of 15 primitives far out of range).
TEST(Bvh, HugeDirectionComponentsNeverEnterEmptySlots) {
    const std::string material = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    std::string spheres = material, triangles;
    for (int i = 0; i < 5; ++i) {
        spheres += "#shape_sphere 0 " + std::to_string(3 * i) + " 0 0 1\n";
        const std::string x = std::to_string(3 * i), x1 = std::to_string(3 * i + 1);
        triangles += "#vertex " + x + " 0 -3 0 0 0 0 0\n#vertex " + x1 + " 0 -3 0 0 0 0 0\n" +
                     "#vertex " + x + " 1 -3 0 0 0 0 0\n";
    }
    triangles += material;
    for (int i = 0; i < 5; ++i)
        triangles += "#shape_triangle 0 " + std::to_string(3 * i) + " " +
                     std::to_string(3 * i + 1) + " " + std::to_string(3 * i + 2) + "\n";
    for (const std::string& text : {spheres, triangles}) {
        const RenderScene scene = test::compile(text);
        for (const Vec3 d :
             {Vec3(1e300, 0.5, -1), Vec3(-1e300, 1e300, 1e-3), Vec3(1e39, -1e300, 1e300)}) {
            Hit a;
            if (intersect(scene, {{-20, 0, 0}, d}, {0, kInf}, &a)) {
                EXPECT_LT(a.prim, 5u);
            }
            occluded(scene, {{-20, 0, 0}, d}, kInf);
        }
    }
}

}  // namespace
}  // namespace rt
