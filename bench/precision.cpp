// raybench_precision: image error against run time of single and double precision on extreme
// scenes (issue 6, part 3). Each scene is defined exactly (long double, built in code), rounded
// once to the precision under test (geometry, light, and the camera rays, which are computed
// exactly per pixel), and rendered with the kernels of precision_kernels.h, which mirror the
// core's: primary hit, one shadow ray toward a point light, Lambert shading (ambient 0.1 +
// 0.9 max(0, n.l) when lit). Variants:
//   float_eps    float, shadow ray origin p + 1e-4 n (the classic fixed epsilon)
//   float        float, pbrt's error-bound origin (what the core does)
//   double       double, error-bound origin
//   long_double  the oracle (x87 80-bit, 64-bit mantissa), error-bound origin
// Every variant is compared with the oracle pixel by pixel: RMSE of the shade, and the pixels
// that are wrong: a different object hit (or hit/miss), a different shadow state (lit, shadowed,
// facing away from the light; "lit>shd": shadowed where the oracle is lit, acne or a moved shadow
// edge), or a distance off by more than 1e-5 relative. Timings are of the render loop alone (scene
// rounding and BVH build excluded), one thread, median of --repeats runs. A program, not a test: it
// prints a table, `PRECISION` lines and one conclusion per scene.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "precision_kernels.h"

namespace {

using namespace prec;
using LD = long double;
using Clock = std::chrono::steady_clock;

constexpr LD kPi = 3.141592653589793238462643383279502884L;
constexpr double kAmbient = 0.1, kDiffuse = 0.9;
constexpr double kFixedEpsilon = 1e-4;  // world units, the textbook shadow-ray offset
constexpr double kRelTTolerance = 1e-5;

// ---- scenes ----------------------------------------------------------------------------------

struct SceneDef {
    std::string name, what;
    std::vector<Sphere<LD>> spheres;
    std::vector<Triangle<LD>> triangles;  // one object (id = spheres.size())
    V3<LD> light;
    V3<LD> eye, target, up{0, 1, 0};
    LD half_width = 1;  // of the view, at the target's distance
};

V3<LD> unit(LD x, LD y, LD z) { return normalize(V3<LD>(x, y, z)); }

// A plane through the origin (tilted so no coordinate is exactly zero) with a sphere above it,
// seen from `distance`: the shadow-acne test.
SceneDef plane_scene(const char* name, LD distance) {
    SceneDef s;
    s.name = name;
    s.what = "tilted plane + sphere, camera at distance ";
    s.what += std::to_string(static_cast<double>(distance));
    const V3<LD> n = unit(0.15L, 1, 0.1L);
    const V3<LD> u = normalize(cross(n, V3<LD>(0, 0, 1)));
    const V3<LD> w = cross(u, n);
    const LD e = 10;
    const V3<LD> c00 = (-e) * u + (-e) * w, c10 = e * u + (-e) * w, c01 = (-e) * u + e * w,
                 c11 = e * u + e * w;
    s.triangles.push_back({{c00, c10, c11}});
    s.triangles.push_back({{c00, c11, c01}});
    s.spheres.push_back({0.4L * n, 0.25L});
    s.light = V3<LD>(3, 6, 2);
    s.eye = distance * unit(0.3L, 0.8L, 1);
    s.target = V3<LD>(0, 0, 0);
    s.half_width = 1.5L;
    return s;
}

// A sphere of radius 1e-3 at distance 1e3, partly shadowed by a smaller one.
SceneDef tiny_scene() {
    SceneDef s;
    s.name = "tiny_sphere";
    s.what = "sphere r=1e-3 at distance 1e3 + occluder r=5e-4";
    const V3<LD> c(0, 0, -1000);
    const V3<LD> to_light = unit(1, 2, 1);
    s.spheres.push_back({c, 1e-3L});
    s.spheres.push_back({c + 2.2e-3L * to_light, 5e-4L});
    s.light = c + LD(10) * to_light;
    s.eye = V3<LD>(0, 0, 0);
    s.target = c;
    s.half_width = 2.5e-3L;
    return s;
}

// A sphere of radius 1e4 as the ground, a unit sphere just above it.
SceneDef huge_ground_scene() {
    SceneDef s;
    s.name = "huge_ground";
    s.what = "ground = sphere r=1e4, unit sphere 0.05 above it";
    s.spheres.push_back({V3<LD>(0, -1e4L, 0), 1e4L});
    s.spheres.push_back({V3<LD>(0, 1.05L, 0), 1});
    s.light = V3<LD>(4, 8, 3);
    s.eye = V3<LD>(0, 3, 9);
    s.target = V3<LD>(0, 0.5L, 0);
    s.half_width = 4;
    return s;
}

// A unit sphere whose centre is 1e6 from the origin on every axis, partly shadowed.
SceneDef far_sphere_scene() {
    SceneDef s;
    s.name = "sphere_1e6";
    s.what = "unit sphere at (1e6,1e6,1e6) + occluder r=0.3";
    const V3<LD> c(1e6L, 1e6L, 1e6L);
    s.spheres.push_back({c, 1});
    s.spheres.push_back({c + 1.6L * unit(3, 5, 4), 0.3L});
    s.light = c + V3<LD>(3, 5, 4);
    s.eye = c + V3<LD>(0, 1, 4);
    s.target = c;
    s.half_width = 1.5L;
    return s;
}

// A UV-sphere mesh of radius 1 (48 x 24, 2208 triangles, shared vertices) at `centre`, with an
// analytic occluder.
SceneDef mesh_scene(const char* name, LD offset) {
    SceneDef s;
    s.name = name;
    s.what = "triangle mesh sphere (2208 tris) at offset ";
    s.what += std::to_string(static_cast<double>(offset));
    s.what += " on each axis + sphere occluder";
    const V3<LD> c(offset, offset, offset);
    constexpr int kStacks = 24, kSlices = 48;
    std::vector<V3<LD>> v;
    for (int i = 0; i <= kStacks; ++i)
        for (int j = 0; j < kSlices; ++j) {
            const LD th = kPi * i / kStacks, ph = 2 * kPi * j / kSlices;
            v.push_back(
                c + V3<LD>(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
        }
    auto at = [&](int i, int j) { return v[static_cast<size_t>(i * kSlices + j % kSlices)]; };
    for (int i = 0; i < kStacks; ++i)
        for (int j = 0; j < kSlices; ++j) {
            if (i > 0) s.triangles.push_back({{at(i, j), at(i, j + 1), at(i + 1, j)}});
            if (i < kStacks - 1)
                s.triangles.push_back({{at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)}});
        }
    s.spheres.push_back({c + 1.7L * unit(4, 5, 3), 0.3L});
    s.light = c + V3<LD>(4, 5, 3);
    s.eye = c + V3<LD>(0.5L, 1, 4);
    s.target = c;
    s.half_width = 1.3L;
    return s;
}

// Pixel-centre camera rays, computed exactly (long double), unit directions.
std::vector<Ray<LD>> camera_rays(const SceneDef& s, int size) {
    const V3<LD> f0 = s.target - s.eye;
    const LD dist = length(f0);
    const V3<LD> f = (1 / dist) * f0;
    const V3<LD> r = normalize(cross(f, s.up));
    const V3<LD> u = cross(r, f);
    std::vector<Ray<LD>> rays;
    rays.reserve(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const LD px = ((x + 0.5L) / size * 2 - 1) * s.half_width;
            const LD py = (1 - (y + 0.5L) / size * 2) * s.half_width;
            rays.push_back({s.eye, normalize(dist * f + px * r + py * u)});
        }
    return rays;
}

// ---- a scene in precision T ------------------------------------------------------------------

template <class T>
struct SceneT {
    std::vector<Sphere<T>> spheres;
    std::vector<Triangle<T>> triangles;
    V3<T> light;
    std::vector<Ray<T>> rays;
    struct Node {
        Box<T> box;
        int first = 0, count = 0;  // leaf when count > 0
        int right = 0;             // internal: left child is the next node
    };
    std::vector<Node> nodes;
    std::vector<int> order;
};

// Median-split BVH over the rounded triangles; boxes are min/max of T values, hence exact.
template <class T>
int build_bvh(SceneT<T>& s, int begin, int end) {
    using Node = typename SceneT<T>::Node;
    const int index = static_cast<int>(s.nodes.size());
    s.nodes.push_back(Node{});
    Box<T> box{s.triangles[static_cast<size_t>(s.order[static_cast<size_t>(begin)])].p[0],
               s.triangles[static_cast<size_t>(s.order[static_cast<size_t>(begin)])].p[0]};
    V3<LD> clo(1e300L, 1e300L, 1e300L), chi(-1e300L, -1e300L, -1e300L);
    auto centroid = [&](int t) {
        const Triangle<T>& tri = s.triangles[static_cast<size_t>(t)];
        V3<LD> sum;
        for (const auto& p : tri.p) sum = sum + V3<LD>::from(p);
        return (1 / LD(3)) * sum;
    };
    for (int i = begin; i < end; ++i) {
        const int t = s.order[static_cast<size_t>(i)];
        for (const auto& p : s.triangles[static_cast<size_t>(t)].p)
            for (int a = 0; a < 3; ++a) {
                box.lo[a] = std::min(box.lo[a], p[a]);
                box.hi[a] = std::max(box.hi[a], p[a]);
            }
        const V3<LD> ce = centroid(t);
        for (int a = 0; a < 3; ++a) {
            clo[a] = std::min(clo[a], ce[a]);
            chi[a] = std::max(chi[a], ce[a]);
        }
    }
    s.nodes[static_cast<size_t>(index)].box = box;
    if (end - begin <= 4) {
        s.nodes[static_cast<size_t>(index)].first = begin;
        s.nodes[static_cast<size_t>(index)].count = end - begin;
        return index;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
    const int mid = (begin + end) / 2;
    std::nth_element(s.order.begin() + begin, s.order.begin() + mid, s.order.begin() + end,
                     [&](int a, int b) { return centroid(a)[axis] < centroid(b)[axis]; });
    build_bvh(s, begin, mid);
    const int right = build_bvh(s, mid, end);
    s.nodes[static_cast<size_t>(index)].right = right;
    return index;
}

template <class T>
SceneT<T> round_scene(const SceneDef& d, const std::vector<Ray<LD>>& rays) {
    SceneT<T> s;
    for (const auto& sp : d.spheres) s.spheres.push_back({V3<T>::from(sp.c), static_cast<T>(sp.r)});
    for (const auto& tri : d.triangles)
        s.triangles.push_back(
            {{V3<T>::from(tri.p[0]), V3<T>::from(tri.p[1]), V3<T>::from(tri.p[2])}});
    s.light = V3<T>::from(d.light);
    for (const auto& r : rays) s.rays.push_back({V3<T>::from(r.o), V3<T>::from(r.d)});
    for (int i = 0; i < static_cast<int>(s.triangles.size()); ++i) s.order.push_back(i);
    if (!s.triangles.empty()) build_bvh(s, 0, static_cast<int>(s.triangles.size()));
    return s;
}

// Nearest triangle hit in (lo, *best_t); any_hit: stop at the first one.
template <class T>
bool trace_triangles(const SceneT<T>& s, const Ray<T>& ray, T lo, T* best_t, bool any_hit,
                     int* tri_out, TriHit<T>* hit_out) {
    if (s.nodes.empty()) return false;
    const WtRay<T> wr(ray);
    const V3<T> inv(T(1) / ray.d[0], T(1) / ray.d[1], T(1) / ray.d[2]);
    int stack[64], top = 0;
    stack[top++] = 0;
    bool found = false;
    while (top > 0) {
        const int ni = stack[--top];
        const auto& node = s.nodes[static_cast<size_t>(ni)];
        if (!intersect_box(node.box, ray, inv, lo, *best_t)) continue;
        if (node.count > 0) {
            for (int i = node.first; i < node.first + node.count; ++i) {
                const int t = s.order[static_cast<size_t>(i)];
                TriHit<T> h;
                if (intersect_triangle(s.triangles[static_cast<size_t>(t)], ray, wr, lo, *best_t,
                                       &h)) {
                    found = true;
                    *best_t = h.t;
                    if (tri_out) *tri_out = t;
                    if (hit_out) *hit_out = h;
                    if (any_hit) return true;
                }
            }
        } else {
            stack[top++] = node.right;
            stack[top++] = ni + 1;
        }
    }
    return found;
}

// ---- rendering -------------------------------------------------------------------------------

enum class Offset { Epsilon, ErrorBound };
enum State : uint8_t { kMiss, kAway, kLit, kShadowed };

struct Image {
    std::vector<double> value;
    std::vector<LD> t;
    std::vector<int> object;  // -1: miss
    std::vector<uint8_t> state;
    void reset(size_t n) {
        value.assign(n, 0.0);
        t.assign(n, 0);
        object.assign(n, -1);
        state.assign(n, kMiss);
    }
};

template <class T>
bool occluded(const SceneT<T>& s, const Ray<T>& ray) {
    for (const auto& sp : s.spheres) {
        T t;
        if (intersect_sphere(sp, ray, T(0), T(1), &t)) return true;
    }
    T hi = T(1);
    return trace_triangles<T>(s, ray, T(0), &hi, true, nullptr, nullptr);
}

// Returns the number of rays traced.
template <class T>
uint64_t render(const SceneT<T>& s, Offset offset, Image* img) {
    uint64_t rays = 0;
    const int n_spheres = static_cast<int>(s.spheres.size());
    for (size_t i = 0; i < s.rays.size(); ++i) {
        const Ray<T>& ray = s.rays[i];
        ++rays;
        T best = std::numeric_limits<T>::infinity();
        int object = -1;
        for (int k = 0; k < n_spheres; ++k) {
            T t;
            if (intersect_sphere(s.spheres[static_cast<size_t>(k)], ray, T(0), best, &t)) {
                best = t;
                object = k;
            }
        }
        int tri = -1;
        TriHit<T> th;
        if (trace_triangles(s, ray, T(0), &best, false, &tri, &th)) object = n_spheres;
        img->object[i] = object;
        if (object < 0) continue;
        img->t[i] = static_cast<LD>(best);
        const SurfacePoint<T> sp =
            object < n_spheres ? sphere_surface(s.spheres[static_cast<size_t>(object)], ray, best)
                               : triangle_surface(s.triangles[static_cast<size_t>(tri)], th);
        V3<T> n = sp.n;
        if (dot(n, ray.d) > T(0)) n = -n;  // two-sided: the side the camera sees
        const V3<T> l = s.light - sp.p;
        const T n_dot_l = dot(n, l) / length(l);
        if (!(n_dot_l > T(0))) {
            img->state[i] = kAway;
            img->value[i] = kAmbient;
            continue;
        }
        const V3<T> o = offset == Offset::ErrorBound ? offset_origin(sp.p, sp.p_error, n, l)
                                                     : sp.p + static_cast<T>(kFixedEpsilon) * n;
        ++rays;
        const bool shadowed = occluded(s, Ray<T>{o, s.light - o});
        img->state[i] = shadowed ? kShadowed : kLit;
        img->value[i] = kAmbient + (shadowed ? 0.0 : kDiffuse * static_cast<double>(n_dot_l));
    }
    return rays;
}

struct Measure {
    double seconds = 0, rays_per_s = 0, rmse = 0, max_rel_t = 0;
    int wrong = 0, wrong_object = 0, wrong_shadow = 0, wrong_t = 0;
    int false_shadow = 0;  // of wrong_shadow: shadowed where the oracle is lit
};

template <class T>
Measure run(const SceneDef& def, const std::vector<Ray<LD>>& rays, Offset offset, int repeats,
            Image* img) {
    const SceneT<T> s = round_scene<T>(def, rays);
    img->reset(rays.size());
    std::vector<double> times;
    uint64_t n_rays = 0;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        n_rays = render(s, offset, img);
        times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    Measure m;
    m.seconds = times[times.size() / 2];
    m.rays_per_s = static_cast<double>(n_rays) / m.seconds;
    return m;
}

void compare(const Image& img, const Image& ref, Measure* m) {
    double sum_sq = 0;
    for (size_t i = 0; i < img.value.size(); ++i) {
        const double dv = img.value[i] - ref.value[i];
        sum_sq += dv * dv;
        bool bad = false;
        if (img.object[i] != ref.object[i]) {
            ++m->wrong_object;
            bad = true;
        } else if (ref.object[i] >= 0) {
            if (img.state[i] != ref.state[i]) {
                ++m->wrong_shadow;
                if (img.state[i] == kShadowed && ref.state[i] == kLit) ++m->false_shadow;
                bad = true;
            }
            const double rel = static_cast<double>(std::abs(img.t[i] - ref.t[i]) / ref.t[i]);
            m->max_rel_t = std::max(m->max_rel_t, rel);
            if (rel > kRelTTolerance) {
                ++m->wrong_t;
                bad = true;
            }
        }
        if (bad) ++m->wrong;
    }
    m->rmse = std::sqrt(sum_sq / static_cast<double>(img.value.size()));
}

bool passes(const Measure& m) { return m.wrong == 0 && m.max_rel_t < kRelTTolerance; }

}  // namespace

int main(int argc, char** argv) {
    int size = 256, repeats = 5;
    std::vector<std::string> only;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") {
            size = 48;
            repeats = 1;
        } else if (a == "--size" && i + 1 < argc) {
            size = std::max(8, std::atoi(argv[++i]));
        } else if (a == "--repeats" && i + 1 < argc) {
            repeats = std::max(1, std::atoi(argv[++i]));
        } else if (a == "-h" || a == "--help") {
            std::printf(
                "usage: raybench_precision [--quick] [--size N] [--repeats N] [SCENE...]\n"
                "scenes: plane_1 plane_1e3 plane_1e5 tiny_sphere huge_ground sphere_1e6\n"
                "        mesh_origin mesh_1e4\n");
            return 0;
        } else {
            only.push_back(a);
        }
    }
    std::vector<SceneDef> scenes;
    scenes.push_back(plane_scene("plane_1", 1));
    scenes.push_back(plane_scene("plane_1e3", 1e3L));
    scenes.push_back(plane_scene("plane_1e5", 1e5L));
    scenes.push_back(tiny_scene());
    scenes.push_back(huge_ground_scene());
    scenes.push_back(far_sphere_scene());
    scenes.push_back(mesh_scene("mesh_origin", 0));
    scenes.push_back(mesh_scene("mesh_1e4", 1e4L));
    if (!only.empty()) {
        std::vector<SceneDef> kept;
        for (auto& s : scenes)
            if (std::find(only.begin(), only.end(), s.name) != only.end())
                kept.push_back(std::move(s));
        if (kept.empty()) {
            std::fprintf(stderr, "raybench_precision: no such scene (see --help)\n");
            return 2;
        }
        scenes = std::move(kept);
    }

    std::printf(
        "raybench_precision: %dx%d pixels, 1 primary + 1 shadow ray per lit pixel, one thread, "
        "median of %d runs\n"
        "oracle: long double (%d-bit mantissa); wrong pixel = other object or hit/miss, other "
        "shadow state, or |t - t_oracle| / t_oracle > %.0e\n"
        "float_eps: shadow origin p + %.0e n; the others: pbrt's error-bound origin\n\n",
        size, size, repeats, std::numeric_limits<LD>::digits, kRelTTolerance, kFixedEpsilon);
    std::printf("%-12s %-12s %9s %8s %9s %7s %7s %7s %7s %7s %10s\n", "scene", "precision",
                "time ms", "Mray/s", "rmse", "wrong", "object", "shadow", "lit>shd", "t",
                "max_rel_t");

    struct Verdict {
        std::string scene;
        Measure eps, flt, dbl;
    };
    std::vector<Verdict> verdicts;
    for (const SceneDef& def : scenes) {
        const std::vector<Ray<LD>> rays = camera_rays(def, size);
        Image ref, img;
        const Measure oracle = run<LD>(def, rays, Offset::ErrorBound, repeats, &ref);
        struct Row {
            const char* name;
            Measure m;
        };
        std::vector<Row> rows;
        rows.push_back({"float_eps", run<float>(def, rays, Offset::Epsilon, repeats, &img)});
        compare(img, ref, &rows.back().m);
        rows.push_back({"float", run<float>(def, rays, Offset::ErrorBound, repeats, &img)});
        compare(img, ref, &rows.back().m);
        rows.push_back({"double", run<double>(def, rays, Offset::ErrorBound, repeats, &img)});
        compare(img, ref, &rows.back().m);
        rows.push_back({"long_double", oracle});
        std::printf("%s: %s\n", def.name.c_str(), def.what.c_str());
        for (const Row& r : rows) {
            const Measure& m = r.m;
            std::printf("%-12s %-12s %9.2f %8.2f %9.2e %7d %7d %7d %7d %7d %10.2e\n",
                        def.name.c_str(), r.name, m.seconds * 1e3, m.rays_per_s * 1e-6, m.rmse,
                        m.wrong, m.wrong_object, m.wrong_shadow, m.false_shadow, m.wrong_t,
                        m.max_rel_t);
        }
        for (const Row& r : rows)
            std::printf(
                "PRECISION %s %s time=%.6f rays_per_s=%.4g rmse=%.4g wrong=%d wrong_object=%d "
                "wrong_shadow=%d false_shadow=%d wrong_t=%d max_rel_t=%.3g\n",
                def.name.c_str(), r.name, r.m.seconds, r.m.rays_per_s, r.m.rmse, r.m.wrong,
                r.m.wrong_object, r.m.wrong_shadow, r.m.false_shadow, r.m.wrong_t, r.m.max_rel_t);
        std::printf("\n");
        verdicts.push_back({def.name, rows[0].m, rows[1].m, rows[2].m});
    }

    std::printf(
        "criterion: a precision is enough for a scene when it has zero wrong pixels and max "
        "relative t error < %.0e against the oracle\n",
        kRelTTolerance);
    for (const Verdict& v : verdicts) {
        std::string line = "CONCLUSION ";
        line += v.scene;
        line += ": ";
        if (passes(v.flt))
            line += "single precision is enough";
        else if (passes(v.dbl))
            line += "single precision is NOT enough, double is";
        else
            line += "neither single nor double precision is enough";
        line += " (float: " + std::to_string(v.flt.wrong) + " wrong";
        line += ", double: " + std::to_string(v.dbl.wrong) + " wrong";
        line += "; fixed epsilon instead of error bounds: " + std::to_string(v.eps.wrong);
        line += " wrong, shadow ";
        line += std::to_string(v.eps.wrong_shadow) + " (falsely shadowed " +
                std::to_string(v.eps.false_shadow);
        line += ") against " + std::to_string(v.flt.wrong_shadow) + " (";
        line += std::to_string(v.flt.false_shadow) + ") with error bounds)";
        std::printf("%s\n", line.c_str());
    }
    return 0;
}
