// raybench: our BVH against Embree 3 on the same rays. For generated meshes (10k, 100k, 1M
// triangles, closed) and for the scenes in scenes/, it times primary rays (closest hit), shadow
// rays (any hit) and random incoherent rays, single-threaded and on all cores, and the BVH build;
// it reports bytes per triangle and checks that both return the same hits on every timed ray.
// It prints a table and one `BENCH <workload> <figure> ours=.. embree=.. speedup=..` line per
// figure (all cores). A program, not a test: it asserts nothing.
#include <immintrin.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iterator>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cli.h"
#include "rt/accel/intersect.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/camera.h"
#include "rt/render/render.h"
#include "rt/scene/mesh_gen.h"
#include "rt/util/isa.h"
#include "rt/util/stopwatch.h"
#include "walk_counts.h"

#ifdef RT_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

using namespace rt;

// Runs body(begin, end) over [0, n) in chunks on `threads` threads.
// Both tracers' rays run with flush-to-zero and denormals-are-zero on (Embree warns when they are
// off), restored afterwards on the calling thread. The hit check below shows that the answers do
// not change with them.
void parallel_for(size_t n, int threads, const std::function<void(size_t, size_t)>& body) {
    constexpr size_t kChunk = 1024;
    std::atomic<size_t> next{0};
    auto worker = [&]() {
        const unsigned saved = _mm_getcsr();
        _mm_setcsr(saved | _MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON);
        struct Restore {
            unsigned csr;
            ~Restore() { _mm_setcsr(csr); }
        } restore{saved};
        for (;;) {
            const size_t b = next.fetch_add(kChunk);
            if (b >= n) return;
            body(b, std::min(n, b + kChunk));
        }
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
}

struct RayBatch {
    std::vector<Ray> rays;
    std::vector<double> t_max;
};

// A hit as both libraries report it: distance and a global primitive id (instance, prim).
struct Result {
    double t = -1;  // < 0: miss
    int instance = -1;
    uint32_t prim = 0;
};

// ---- workloads -------------------------------------------------------------------------------

struct Workload {
    std::string name;
    RenderScene scene;
    CompileReport report;
    size_t triangles = 0;  // unique triangles (for bytes per triangle)
};

RenderScene compile_mesh(const TriangleMesh& mesh, CompileReport* report) {
    SceneDesc desc;
    FileDesc file;
    file.path = "generated";
    MaterialDesc m;
    m.diffuse = Vec3(0.8);
    file.materials.push_back(m);
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        file.vertices.push_back({mesh.positions[i], mesh.normals[i], Vec2(0.0)});
    file.root.shapes.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        ShapeDesc s;
        s.geometry = TriangleDesc{{t[0], t[1], t[2]}};
        file.root.shapes.push_back(std::move(s));
    }
    desc.files.push_back(std::move(file));
    CameraDesc cam;
    cam.position = Vec3(0, 0.6, 4.2);
    cam.direction = Vec3(0, -0.15, -1);
    cam.half_height_angle_rad = 0.32;
    desc.camera = cam;
    LightDesc light;
    light.position = Vec3(2, 2, 3);
    desc.lights.push_back(light);
    return compile_scene(desc, report);
}

// Primary rays from the camera, shadow rays from their hits toward the first light (or up),
// random rays from points in the scene's box in uniform directions.
void make_rays(const RenderScene& scene, const RenderPlan& plan, RayBatch* primary,
               RayBatch* shadow, RayBatch* random) {
    const Camera& cam = plan.camera;
    const int w = cam.width, h = cam.height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            primary->rays.push_back(cam.generate(x, y, 0.5, 0.5));
            primary->t_max.push_back(kInf);
        }
    // Shadow origins are pushed off the surface by 1e-5 of the scene's size: far enough that
    // Embree's float arithmetic does not find the surface itself again, so both answer the same
    // question.
    const double push = 1e-5 * glm::length(scene.world_bounds.diagonal());
    for (const Ray& r : primary->rays) {
        Hit hit;
        if (!intersect(scene, plan, r, {0, kInf}, &hit)) continue;
        const SurfaceInteraction si = interaction(scene, plan, r, hit);
        const bool to_point =
            !scene.lights.empty() && scene.lights[0].kind != LightKind::Directional;
        const Vec3 dir = to_point               ? scene.lights[0].position - si.p
                         : scene.lights.empty() ? Vec3(0, 1, 0)
                                                : -scene.lights[0].direction;
        const Vec3 n = glm::dot(dir, si.n_geometric) >= 0 ? si.n_geometric : -si.n_geometric;
        const Vec3 o = si.p + push * n;
        if (to_point) {
            shadow->rays.push_back({o, scene.lights[0].position - o});
            shadow->t_max.push_back(1.0);
        } else {
            shadow->rays.push_back({o, dir});
            shadow->t_max.push_back(kInf);
        }
    }
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(0, 1);
    const Bounds3 b = scene.world_bounds;
    for (size_t i = 0; i < primary->rays.size(); ++i) {
        const Vec3 o = b.lo + Vec3(u(rng), u(rng), u(rng)) * b.diagonal();
        const double z = 2 * u(rng) - 1, phi = 2 * kPi * u(rng), s = std::sqrt(1 - z * z);
        random->rays.push_back({o, Vec3(s * std::cos(phi), s * std::sin(phi), z)});
        random->t_max.push_back(kInf);
    }
}

// ---- ours ------------------------------------------------------------------------------------

// The ray queries with the walk the plan picked for the scene (what the renderer uses).
void ours_closest(const RenderScene& scene, const RenderPlan& plan, const RayBatch& batch,
                  std::vector<Result>& out, int threads) {
    parallel_for(batch.rays.size(), threads, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            Hit hit;
            if (intersect(scene, plan, batch.rays[i], {0, batch.t_max[i]}, &hit))
                out[i] = {hit.t, hit.instance, hit.prim};
            else
                out[i] = {};
        }
    });
}

void ours_occluded(const RenderScene& scene, const RenderPlan& plan, const RayBatch& batch,
                   std::vector<Result>& out, int threads) {
    parallel_for(batch.rays.size(), threads, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
            out[i].t = occluded(scene, plan, batch.rays[i], batch.t_max[i]) ? 1.0 : -1.0;
    });
}

size_t ours_bytes(const RenderScene& scene) {
    size_t bytes = scene.top.nodes.size() * sizeof(Bvh4Node) + scene.top.indices.size() * 4;
    for (const GeometrySet& s : scene.sets) {
        bytes += s.bvh.nodes.size() * sizeof(Bvh4Node) + s.bvh.nodes8.size() * sizeof(Bvh8Node) +
                 s.bvh.indices.size() * 4;
        // What rays read: nodes, leaf order, primitives, the float triangles the kernel tests and
        // the double vertices (and their indices) surface_at() refines hits with (not the
        // normals and uvs).
        bytes += s.vertex_positions.size() * sizeof(Vec3) + s.triangle_count() * 12 +
                 s.tri4.size() * sizeof(Tri4) + s.tri4_prim.size() * 16 +
                 s.prims.size() * sizeof(Primitive);
    }
    return bytes;
}

double ours_build_seconds(const RenderScene& scene) {
    // The bounds the compile builds from, made before the clock starts.
    std::vector<std::vector<Bounds3>> prim_bounds(scene.sets.size());
    for (size_t k = 0; k < scene.sets.size(); ++k)
        for (size_t i = 0; i < scene.sets[k].prims.size(); ++i)
            prim_bounds[k].push_back(scene.sets[k].prim_bounds(i));
    const auto t0 = Clock::now();
    for (size_t k = 0; k < scene.sets.size(); ++k) {
        const Bvh b = build_bvh(prim_bounds[k], set_bvh_settings(scene.sets[k].layout));
        if (b.nodes.empty() && !scene.sets[k].prims.empty()) std::printf("?");
    }
    return seconds_since(t0);
}

// ---- Embree ----------------------------------------------------------------------------------

#ifdef RT_HAVE_EMBREE

std::atomic<long long> g_embree_bytes{0};

bool memory_monitor(void*, ssize_t bytes, bool) {
    g_embree_bytes += bytes;
    return true;
}

struct UserGeometry {
    const GeometrySet* set;
    std::vector<uint32_t> prims;  // our prim index of each user primitive
};

void user_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* ug = static_cast<const UserGeometry*>(args->geometryUserPtr);
    const Bounds3 b = ug->set->prim_bounds(ug->prims[args->primID]);
    args->bounds_o->lower_x = float_lower(b.lo.x);
    args->bounds_o->lower_y = float_lower(b.lo.y);
    args->bounds_o->lower_z = float_lower(b.lo.z);
    args->bounds_o->upper_x = float_upper(b.hi.x);
    args->bounds_o->upper_y = float_upper(b.hi.y);
    args->bounds_o->upper_z = float_upper(b.hi.z);
}

Ray to_ray(const RTCRay& r) { return {{r.org_x, r.org_y, r.org_z}, {r.dir_x, r.dir_y, r.dir_z}}; }

void user_intersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* ug = static_cast<const UserGeometry*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const ShapeHits h = intersect_primitive(*ug->set, ug->prims[args->primID], to_ray(rh->ray),
                                            {rh->ray.tnear, rh->ray.tfar});
    if (h.count == 0) return;
    rh->ray.tfar = static_cast<float>(h.t[0]);
    rh->hit.geomID = args->geomID;
    rh->hit.primID = args->primID;
    rh->hit.instID[0] = args->context->instID[0];
    rh->hit.Ng_x = rh->hit.Ng_y = 0;
    rh->hit.Ng_z = 1;
    rh->hit.u = rh->hit.v = 0;
}

void user_occluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* ug = static_cast<const UserGeometry*>(args->geometryUserPtr);
    auto* r = reinterpret_cast<RTCRay*>(args->ray);
    if (intersect_primitive(*ug->set, ug->prims[args->primID], to_ray(*r), {r->tnear, r->tfar})
            .count > 0)
        r->tfar = -INFINITY;
}

struct EmbreeScene {
    const RenderScene* scene = nullptr;
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> sets;
    std::vector<std::unique_ptr<UserGeometry>> users;
    // Per set: geometry ids -> our prim index (triangles: the id's order; users: the list).
    struct Map {
        unsigned tri_geom = RTC_INVALID_GEOMETRY_ID, user_geom = RTC_INVALID_GEOMETRY_ID;
        std::vector<uint32_t> tri_prims, user_prims;
    };
    std::vector<Map> maps;
    double build_seconds = 0;
    long long bytes = 0;

    /// robust: RTC_SCENE_FLAG_ROBUST on every scene (Embree's watertight mode: no ray slips
    /// between triangles that share an edge, the fair match for our kernel).
    EmbreeScene(const RenderScene& rs, int threads, bool robust) : scene(&rs) {
        const std::string config = "threads=" + std::to_string(threads);
        device = rtcNewDevice(config.c_str());
        rtcSetDeviceMemoryMonitorFunction(device, memory_monitor, nullptr);
        g_embree_bytes = 0;
        const auto t0 = Clock::now();
        for (const GeometrySet& s : rs.sets) {
            RTCScene sc = rtcNewScene(device);
            if (robust) rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
            Map map;
            std::vector<uint32_t> analytic;
            for (uint32_t i = 0; i < s.prims.size(); ++i) {
                if (s.prims[i].kind == ShapeKind::Triangle && s.prims[i].csg < 0)
                    map.tri_prims.push_back(i);
                else
                    analytic.push_back(i);
            }
            if (!map.tri_prims.empty()) {
                RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
                const size_t n = map.tri_prims.size();
                auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
                    g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
                auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
                    g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
                for (size_t k = 0; k < n; ++k) {
                    const Triangle t = s.triangle(s.prims[map.tri_prims[k]].index);
                    const Vec3 p[3] = {t.p0, t.p1, t.p2};
                    for (int c = 0; c < 3; ++c) {
                        for (int a = 0; a < 3; ++a)
                            v[(3 * k + c) * 3 + a] = static_cast<float>(p[c][a]);
                        idx[3 * k + c] = static_cast<unsigned>(3 * k + c);
                    }
                }
                rtcCommitGeometry(g);
                map.tri_geom = rtcAttachGeometry(sc, g);
                rtcReleaseGeometry(g);
            }
            if (!analytic.empty()) {
                auto ug = std::make_unique<UserGeometry>();
                ug->set = &s;
                ug->prims = analytic;
                map.user_prims = analytic;
                RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
                rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(analytic.size()));
                rtcSetGeometryUserData(g, ug.get());
                rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
                rtcSetGeometryIntersectFunction(g, user_intersect);
                rtcSetGeometryOccludedFunction(g, user_occluded);
                rtcCommitGeometry(g);
                map.user_geom = rtcAttachGeometry(sc, g);
                rtcReleaseGeometry(g);
                users.push_back(std::move(ug));
            }
            rtcCommitScene(sc);
            sets.push_back(sc);
            maps.push_back(std::move(map));
        }
        top = rtcNewScene(device);
        if (robust) rtcSetSceneFlags(top, RTC_SCENE_FLAG_ROBUST);
        for (const Instance& inst : rs.instances) {
            RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(g, sets[static_cast<size_t>(inst.set)]);
            float xf[12];
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 3; ++r)
                    xf[c * 3 + r] = static_cast<float>(inst.world_from_set.m[c][r]);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xf);
            rtcCommitGeometry(g);
            rtcAttachGeometry(top, g);  // ids follow our instance order
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(top);
        build_seconds = seconds_since(t0);
        bytes = g_embree_bytes.load();
    }
    ~EmbreeScene() {
        rtcReleaseScene(top);
        for (RTCScene s : sets) rtcReleaseScene(s);
        rtcReleaseDevice(device);
    }

    static void set_ray(RTCRay& r, const Ray& ray, double t_max) {
        r.org_x = static_cast<float>(ray.o.x);
        r.org_y = static_cast<float>(ray.o.y);
        r.org_z = static_cast<float>(ray.o.z);
        r.dir_x = static_cast<float>(ray.d.x);
        r.dir_y = static_cast<float>(ray.d.y);
        r.dir_z = static_cast<float>(ray.d.z);
        r.tnear = 0.0f;
        r.tfar = std::isfinite(t_max) ? static_cast<float>(t_max) : INFINITY;
        r.mask = 0xFFFFFFFF;
        r.flags = 0;
        r.time = 0;
    }

    void closest(const RayBatch& batch, std::vector<Result>& out, int threads) const {
        parallel_for(batch.rays.size(), threads, [&](size_t b, size_t e) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (size_t i = b; i < e; ++i) {
                RTCRayHit rh;
                set_ray(rh.ray, batch.rays[i], batch.t_max[i]);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(top, &ctx, &rh);
                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                    out[i] = {};
                    continue;
                }
                const int inst = static_cast<int>(rh.hit.instID[0]);
                out[i].t = rh.ray.tfar;
                out[i].instance = inst;
                out[i].prim = prim_of(inst, rh.hit.geomID, rh.hit.primID);
            }
        });
    }

    void occluded(const RayBatch& batch, std::vector<Result>& out, int threads) const {
        parallel_for(batch.rays.size(), threads, [&](size_t b, size_t e) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (size_t i = b; i < e; ++i) {
                RTCRay r;
                set_ray(r, batch.rays[i], batch.t_max[i]);
                rtcOccluded1(top, &ctx, &r);
                out[i].t = r.tfar == -INFINITY ? 1.0 : -1.0;
            }
        });
    }

    uint32_t prim_of(int inst, unsigned geom, unsigned prim) const {
        const Map& m = maps[static_cast<size_t>(scene->instances[static_cast<size_t>(inst)].set)];
        return geom == m.tri_geom ? m.tri_prims[prim] : m.user_prims[prim];
    }
};

#endif  // RT_HAVE_EMBREE

// ---- measurement -----------------------------------------------------------------------------

template <class F>
double median_rate(size_t rays, int repeats, F&& run) {
    std::vector<double> rates;
    for (int i = 0; i < repeats; ++i) {
        const auto t0 = Clock::now();
        run();
        rates.push_back(static_cast<double>(rays) / seconds_since(t0));
    }
    std::sort(rates.begin(), rates.end());
    return rates[rates.size() / 2];
}

struct Check {
    size_t rays = 0, hit_miss = 0, distance = 0, primitive = 0;
    void compare(const std::vector<Result>& a, const std::vector<Result>& b, bool any_hit) {
        for (size_t i = 0; i < a.size(); ++i) {
            ++rays;
            if ((a[i].t >= 0) != (b[i].t >= 0)) {
                ++hit_miss;
                continue;
            }
            if (any_hit || a[i].t < 0) continue;
            if (std::abs(a[i].t - b[i].t) > 1e-4 * std::max(std::abs(a[i].t), 1e-30))
                ++distance;
            else if (a[i].instance != b[i].instance || a[i].prim != b[i].prim)
                ++primitive;
        }
    }
};

std::string rate(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f M/s", v / 1e6);
    return buf;
}

// Nodes, leaves and triangle blocks visited per ray by the 4-wide and the 8-wide walks, when
// the scene is one triangle set seen directly (the meshes) and the CPU runs AVX2.
void print_walk_counts(const RenderScene& scene,
                       std::initializer_list<std::tuple<const char*, RayBatch*, bool>> batches) {
    const std::vector<Isa> isas = supported_isas();
    if (scene.instances.size() != 1 || !scene.instances[0].identity ||
        std::find(isas.begin(), isas.end(), Isa::Avx2) == isas.end())
        return;
    const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[0].set)];
    if (set.layout != SetLayout::Triangles || set.bvh.nodes8.empty()) return;
    std::printf("  visited per ray   %8s %8s %8s   %8s %8s %8s\n", "4: nodes", "leaves", "blocks",
                "8: nodes", "leaves", "blocks");
    for (const auto& [figure, batch, any_hit] : batches) {
        WalkCount c[2];
        for (int k = 0; k < 2; ++k)
            for (size_t i = 0; i < batch->rays.size(); ++i)
                avx2::count_walk(set, batch->rays[i], batch->t_max[i], any_hit, k == 0 ? 4 : 8,
                                 c[k]);
        auto per_ray = [](uint64_t v, const WalkCount& w) {
            return w.rays ? static_cast<double>(v) / static_cast<double>(w.rays) : 0.0;
        };
        std::printf("  %-16s %9.2f %8.2f %8.2f   %8.2f %8.2f %8.2f\n", figure,
                    per_ray(c[0].nodes, c[0]), per_ray(c[0].leaves, c[0]),
                    per_ray(c[0].blocks, c[0]), per_ray(c[1].nodes, c[1]),
                    per_ray(c[1].leaves, c[1]), per_ray(c[1].blocks, c[1]));
    }
}

void run_workload(Workload& w, int repeats, int threads, bool quick) {
    const int width = quick ? 320 : 640, height = quick ? 240 : 480;
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    const RenderPlan plan = make_render_plan(w.scene, settings);
    RayBatch primary, shadow, random;
    make_rays(w.scene, plan, &primary, &shadow, &random);
    std::printf(
        "\n%s: %zu triangles, %zu primitives after instancing; %zu primary, %zu shadow, "
        "%zu random rays\n",
        w.name.c_str(), w.triangles,
        std::accumulate(std::begin(w.report.prims_by_kind), std::end(w.report.prims_by_kind),
                        size_t{0}),
        primary.rays.size(), shadow.rays.size(), random.rays.size());

    const double ours_build = [&] {
        std::vector<double> t;
        for (int i = 0; i < repeats; ++i) t.push_back(ours_build_seconds(w.scene));
        std::sort(t.begin(), t.end());
        return t[t.size() / 2];
    }();
    const double ours_bpt =
        w.triangles ? static_cast<double>(ours_bytes(w.scene)) / static_cast<double>(w.triangles)
                    : 0;

    struct Row {
        const char* figure;
        RayBatch* batch;
        bool any_hit;
        double ours[2] = {0, 0}, embree[2] = {0, 0};
        double robust = 0;  // Embree with RTC_SCENE_FLAG_ROBUST, all threads
        Check check, check_robust;
    };
    Row rows[] = {{"primary", &primary, false, {0, 0}, {0, 0}, 0, {}, {}},
                  {"shadow", &shadow, true, {0, 0}, {0, 0}, 0, {}, {}},
                  {"random", &random, false, {0, 0}, {0, 0}, 0, {}, {}}};
    double embree_build = 0, embree_bpt = 0;
    bool have_embree = false;
#ifdef RT_HAVE_EMBREE
    {
        std::vector<double> t;
        long long bytes = 0;
        for (int i = 0; i < repeats; ++i) {
            EmbreeScene e(w.scene, threads, false);
            t.push_back(e.build_seconds);
            bytes = e.bytes;
        }
        std::sort(t.begin(), t.end());
        embree_build = t[t.size() / 2];
        embree_bpt =
            w.triangles ? static_cast<double>(bytes) / static_cast<double>(w.triangles) : 0;
    }
    EmbreeScene embree(w.scene, threads, false), robust(w.scene, threads, true);
    have_embree = true;
#endif
    for (Row& row : rows) {
        const RayBatch& b = *row.batch;
        std::vector<Result> ours(b.rays.size()), theirs(b.rays.size());
        for (int ti = 0; ti < 2; ++ti) {
            const int nt = ti == 0 ? 1 : threads;
            row.ours[ti] = median_rate(b.rays.size(), repeats, [&] {
                row.any_hit ? ours_occluded(w.scene, plan, b, ours, nt)
                            : ours_closest(w.scene, plan, b, ours, nt);
            });
#ifdef RT_HAVE_EMBREE
            row.embree[ti] = median_rate(b.rays.size(), repeats, [&] {
                row.any_hit ? embree.occluded(b, theirs, nt) : embree.closest(b, theirs, nt);
            });
            if (ti == 1) row.check.compare(ours, theirs, row.any_hit);
#endif
        }
#ifdef RT_HAVE_EMBREE
        row.robust = median_rate(b.rays.size(), repeats, [&] {
            row.any_hit ? robust.occluded(b, theirs, threads) : robust.closest(b, theirs, threads);
        });
        row.check_robust.compare(ours, theirs, row.any_hit);
#endif
    }

    std::printf("  %-8s %13s %13s %6s %13s %13s %6s %13s %6s\n", "figure", "ours 1 thr",
                "Embree 1 thr", "ratio", "ours all", "Embree all", "ratio", "robust all", "ratio");
    auto ratio = [&](double a, double b) { return have_embree && b > 0 ? a / b : 0.0; };
    auto theirs = [&](double v) { return have_embree ? rate(v) : std::string("n/a"); };
    for (const Row& row : rows)
        std::printf("  %-8s %13s %13s %6.2f %13s %13s %6.2f %13s %6.2f\n", row.figure,
                    rate(row.ours[0]).c_str(), theirs(row.embree[0]).c_str(),
                    ratio(row.ours[0], row.embree[0]), rate(row.ours[1]).c_str(),
                    theirs(row.embree[1]).c_str(), ratio(row.ours[1], row.embree[1]),
                    theirs(row.robust).c_str(), ratio(row.ours[1], row.robust));
    std::printf("  %-8s %13.3fs %13.3fs %8.2f   (both builds use %d threads)\n", "build",
                ours_build, embree_build, have_embree ? embree_build / ours_build : 0.0, threads);
    if (w.triangles)
        std::printf("  %-8s %12.1f B %12.1f B   bytes per triangle (BVH + geometry)\n", "memory",
                    ours_bpt, embree_bpt);
    if (have_embree)
        for (const Row& row : rows)
            std::printf(
                "  %-8s hits checked on %zu rays: %zu hit/miss, %zu distance (>1e-4 rel), "
                "%zu primitive differences\n",
                row.figure, row.check.rays, row.check.hit_miss, row.check.distance,
                row.check.primitive);
    if (have_embree)
        for (const Row& row : rows)
            std::printf("  %-8s against robust Embree: %zu hit/miss, %zu distance, %zu primitive\n",
                        row.figure, row.check_robust.hit_miss, row.check_robust.distance,
                        row.check_robust.primitive);
    print_walk_counts(
        w.scene,
        {{"primary", &primary, false}, {"shadow", &shadow, true}, {"random", &random, false}});
    for (const Row& row : rows)
        std::printf(
            "BENCH %s %s ours=%.6g embree=%.6g speedup=%.3f embree_robust=%.6g "
            "speedup_robust=%.3f\n",
            w.name.c_str(), row.figure, row.ours[1], have_embree ? row.embree[1] : 0.0,
            ratio(row.ours[1], row.embree[1]), row.robust, ratio(row.ours[1], row.robust));
    std::printf("BENCH %s build ours=%.6g embree=%.6g speedup=%.3f\n", w.name.c_str(), ours_build,
                embree_build, have_embree ? embree_build / ours_build : 0.0);
    std::fflush(stdout);
}

// --leave-out: every scene rendered by the generic renderer and by the one specialized to its
// features, alternating, best of `repeats` renders each; the images must be equal.
void run_leave_out(const std::vector<std::filesystem::path>& files, int repeats, bool quick,
                   int threads, const std::vector<std::string>& only) {
    std::printf(
        "\nleave out what a scene does not need: generic vs specialized renderer, %s, "
        "1 spp, %d thread%s, best of %d renders each, alternating\n",
        quick ? "160x120" : "640x480", threads, threads == 1 ? "" : "s", repeats);
    std::printf("%-44s %10s %12s %8s %9s\n", "scene", "generic s", "specialized s", "speedup",
                "identical");
    for (const auto& f : files) {
        // Named scenes only (file stems), when some are named.
        if (!only.empty() && std::find(only.begin(), only.end(), f.stem().string()) == only.end())
            continue;
        Diagnostics diag;
        RenderScene scene;
        try {
            scene = compile_scene(parse_scene_file(f.string(), diag));
        } catch (const SceneError&) {
            continue;  // parts of scenes (no camera of their own) and files with errors
        }
        if (!scene.camera) continue;
        RenderSettings settings;
        settings.width = quick ? 160 : 640;
        settings.height = quick ? 120 : 480;
        settings.threads = threads;
        std::vector<double> times[2];
        Image images[2];
        for (int r = 0; r < repeats; ++r)
            for (int specialize = 0; specialize < 2; ++specialize) {
                settings.specialize = specialize == 1;
                RenderState state;
                const auto t0 = std::chrono::steady_clock::now();
                // The plan as a 1-spp raytrace run makes it: once, inside the time.
                render_samples(state, scene, make_render_plan(scene, settings), settings, 1);
                times[specialize].push_back(
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                images[specialize] = state.image();
            }
        for (auto& t : times) std::sort(t.begin(), t.end());
        // The fastest of the runs: on a shared machine the others measure its load.
        const double generic = times[0].front();
        const double special = times[1].front();
        const bool identical = images[0].rgb == images[1].rgb;
        std::string name = f.parent_path().filename().string();
        name += "/";
        name += f.filename().string();
        std::printf("%-44s %10.4f %12.4f %8.2f %9s\n", name.c_str(), generic, special,
                    generic / special, identical ? "yes" : "NO");
        std::printf("LEAVEOUT %s generic=%.6f specialized=%.6f speedup=%.3f identical=%s\n",
                    name.c_str(), generic, special, generic / special, identical ? "yes" : "no");
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 3;
    bool quick = false;
    std::vector<std::string> only;
    std::string scenes_dir = RT_SOURCE_DIR "/scenes";
    bool leave_out = false;
    int leave_out_threads = 1;
    CLI::App app{
        "Measures our BVH against Embree 3 on the same rays (primary, shadow and random rays;\n"
        "Embree's default and robust modes) and checks that both find the same hits; with\n"
        "--leave-out, the generic against the specialized renderer on every scene of scenes/\n"
        "and ../shared/public-scenes (one LEAVEOUT line each)."};
    rtapp::setup_cli(app, "raybench", true);
    app.option_defaults()->always_capture_default();
    app.add_flag("--quick", quick, "one run of each, fewer rays");
    app.add_option("--repeats", repeats, "the median of N runs")
        ->type_name("N")
        ->check(CLI::PositiveNumber);
    app.add_flag("--leave-out", leave_out, "the generic against the specialized renderer");
    app.add_option("--threads", leave_out_threads, "threads of --leave-out's renders")
        ->type_name("N")
        ->check(CLI::PositiveNumber);
    app.add_option("--scenes", scenes_dir, "the scenes measured")->type_name("DIR");
    app.add_option("workloads", only,
                   "mesh10k mesh100k mesh1m and the scene names of DIR (default: all); with\n"
                   "--leave-out, the file stems of the scenes")
        ->type_name("WORKLOAD");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    if (!rtapp::isa_usable("raybench")) return 2;
    if (quick && app.count("--repeats") == 0) repeats = 1;
    if (leave_out) {
        std::vector<std::filesystem::path> files;
        for (const std::string& dir :
             {scenes_dir, std::string(RT_SOURCE_DIR "/../shared/public-scenes")}) {
            std::vector<std::filesystem::path> found;
            if (std::filesystem::exists(dir))
                for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
                    if (e.path().extension() == ".ray") found.push_back(e.path());
            std::sort(found.begin(), found.end());
            files.insert(files.end(), found.begin(), found.end());
        }
        run_leave_out(files, quick ? 1 : std::max(repeats, 5), quick, leave_out_threads, only);
        return 0;
    }
    auto wanted = [&](const std::string& n) {
        return only.empty() || std::find(only.begin(), only.end(), n) != only.end();
    };
    const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::printf("raybench: %d hardware threads, median of %d runs%s\n", threads, repeats,
#ifdef RT_HAVE_EMBREE
                ", Embree " RTC_VERSION_STRING
#else
                ", built without Embree (install libembree-dev)"
#endif
    );

    const std::pair<const char*, size_t> meshes[] = {
        {"mesh10k", 10000}, {"mesh100k", 100000}, {"mesh1m", 1000000}};
    for (const auto& [name, n] : meshes) {
        if (!wanted(name)) continue;
        Workload w;
        w.name = name;
        const TriangleMesh mesh = make_blob_mesh(n);
        w.triangles = mesh.triangles.size();
        w.scene = compile_mesh(mesh, &w.report);
        run_workload(w, repeats, threads, quick);
    }
    std::vector<std::filesystem::path> files;
    if (std::filesystem::exists(scenes_dir))
        for (const auto& e : std::filesystem::directory_iterator(scenes_dir))
            if (e.path().extension() == ".ray") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        const std::string name = f.stem().string();
        if (!wanted(name)) continue;
        Workload w;
        w.name = name;
        Diagnostics diag;
        try {
            w.scene = compile_scene(parse_scene_file(f.string(), diag), &w.report);
        } catch (const SceneError& e) {
            std::printf("\n%s: skipped: %s\n", name.c_str(), e.what());
            continue;
        }
        for (const GeometrySet& s : w.scene.sets) w.triangles += s.triangle_count();
        run_workload(w, repeats, threads, quick);
    }
    return 0;
}
