// The torus test against the sphere test on the same rays (the sphere is the torus's bounding
// sphere, radius R + r): nanoseconds per test and their ratio, for rays aimed at the bounding box
// from 3 sizes away (hits and misses mixed) and for rays aimed at the torus's surface (every ray
// hits). Asserts nothing. Times are the thread's CPU time (not wall time): a machine shared with
// other jobs then slows both tests alike instead of adding its pre-emptions to one.
#include <time.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <random>
#include <vector>

#include "cli.h"
#include "rt/shapes/shapes.h"

namespace {

double thread_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

template <class S>
double ns_per_test(const S& shape, const std::vector<rt::Ray>& rays, int repeats, double* sink) {
    double best = 1e30;
    for (int k = 0; k < repeats; ++k) {
        const double t0 = thread_seconds();
        double acc = 0.0;
        for (const rt::Ray& r : rays) {
            const rt::ShapeHits h = rt::intersect(shape, r, {0.0, rt::kInf});
            acc += h.count ? h.t[0] : 0.0;
        }
        const double s = thread_seconds() - t0;
        *sink += acc;
        best = std::min(best, s * 1e9 / static_cast<double>(rays.size()));
    }
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Times the torus test against a sphere test on the same rays (a table)."};
    rtapp::setup_cli(app, "torusbench", true);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    if (!rtapp::isa_usable("torusbench")) return 2;
    const rt::Torus torus{{0.2, -0.1, 0.3}, 0.25, 1.0};
    const rt::Sphere sphere{torus.centre, torus.ring + torus.tube};
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    auto unit = [&] {
        for (;;) {
            const rt::Vec3 v(u(rng), u(rng), u(rng));
            if (glm::dot(v, v) > 1e-4 && glm::dot(v, v) <= 1.0) return glm::normalize(v);
        }
    };
    const double size = torus.ring + torus.tube;
    const int n = 1 << 20;
    std::vector<rt::Ray> mixed, hitting;
    for (int i = 0; i < n; ++i) {
        const rt::Bounds3 b = rt::bounds(torus);
        const rt::Vec3 aim(b.lo.x + (b.hi.x - b.lo.x) * u01(rng),
                           b.lo.y + (b.hi.y - b.lo.y) * u01(rng),
                           b.lo.z + (b.hi.z - b.lo.z) * u01(rng));
        const rt::Vec3 o = aim + 3.0 * size * unit();
        mixed.push_back({o, glm::normalize(aim - o)});
        const double phi = 2 * rt::kPi * u01(rng), theta = 2 * rt::kPi * u01(rng);
        const rt::Vec3 dir(-std::sin(phi), 0, -std::cos(phi));
        const rt::Vec3 p = torus.centre + (torus.ring + torus.tube * std::cos(theta)) * dir +
                           rt::Vec3(0, torus.tube * std::sin(theta), 0);
        rt::Vec3 nrm(std::cos(theta) * dir.x, std::sin(theta), std::cos(theta) * dir.z);
        const rt::Vec3 d = glm::normalize(-nrm + 0.7 * unit());
        hitting.push_back({p - 3.0 * size * d, d});
    }
    double sink = 0.0;
    std::printf("torus r %.2f R %.2f vs its bounding sphere, %d rays, best of 5\n", torus.tube,
                torus.ring, n);
    for (int set = 0; set < 2; ++set) {
        const std::vector<rt::Ray>& rays = set ? hitting : mixed;
        int hits = 0;
        for (const rt::Ray& r : rays) hits += rt::intersect(torus, r, {0.0, rt::kInf}).count > 0;
        const double ts = ns_per_test(sphere, rays, 5, &sink);
        const double tt = ns_per_test(torus, rays, 5, &sink);
        std::printf("%-22s torus hit by %5.1f%%: sphere %6.2f ns, torus %6.2f ns, ratio %.2f\n",
                    set ? "aimed at the surface" : "aimed at the box", 100.0 * hits / n, ts, tt,
                    tt / ts);
    }
    return sink == 12345.0;  // keeps the loops
}
