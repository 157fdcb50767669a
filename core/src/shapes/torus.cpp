// Torus (spec §13.7): axis along +y through c, q = p - c, rho = sqrt(q_x^2 + q_z^2); surface
// (rho - R)^2 + q_y^2 = r^2 with r = tube (iRadius, minor radius) and R = ring (oRadius, major
// radius). A spindle torus (r > R) is its outer surface only: the roots of the quartic on the
// inner "lemon" (rho + R)^2 + q_y^2 = r^2 are not part of it. Outward normal: the gradient of
// f = (rho - R)^2 + q_y^2 - r^2, i.e. from the tube's centre circle to the point; (0, sign q_y, 0)
// at the cusps of a spindle torus (rho = 0). uv: u = azimuth about +y from -z / 2pi (as the
// sphere), v = atan2(q_y, rho - R) / 2pi in [0, 1): 0 on the outer equator, 1/4 on the top
// circle, 1/2 on the inner equator, 3/4 on the bottom circle. Inside: f < 0.
//
// The torus is a V3 shape (#shape_torus, spec §13.5); the V0/V1 writer refuses it.
#include <emmintrin.h>

#include <cstdint>
#include <cstring>
#include <sstream>

#include "common.h"

namespace rt {

namespace {

constexpr double kNoSeed = std::numeric_limits<double>::quiet_NaN();

// Two lanes of double (SSE2) for independent square roots and divisions: one instruction for
// two, each lane's result that of the scalar operation (IEEE, correctly rounded).
using D2 = __m128d;
D2 d2(double a, double b) { return _mm_set_pd(b, a); }
double lane0(D2 v) { return _mm_cvtsd_f64(v); }
double lane1(D2 v) { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
// std::sqrt without the library's errno path (sqrtsd alone).
double root(double x) { return _mm_cvtsd_f64(_mm_sqrt_sd(_mm_setzero_pd(), _mm_set_sd(x))); }

// a * b + c with one rounding (Dekker's product, Knuth's sum: the build has no FMA), in the two
// lanes of an SSE2 pair.
D2 mul_add(D2 a, D2 b, D2 c) {
    const D2 split = _mm_set1_pd(134217729.0);  // 2^27 + 1
    auto hi_of = [&](D2 x) {
        const D2 s = _mm_mul_pd(split, x);
        return _mm_sub_pd(s, _mm_sub_pd(s, x));
    };
    const D2 ah = hi_of(a), al = _mm_sub_pd(a, ah), bh = hi_of(b), bl = _mm_sub_pd(b, bh);
    const D2 p = _mm_mul_pd(a, b);
    const D2 pe =
        _mm_add_pd(_mm_add_pd(_mm_add_pd(_mm_sub_pd(_mm_mul_pd(ah, bh), p), _mm_mul_pd(ah, bl)),
                              _mm_mul_pd(al, bh)),
                   _mm_mul_pd(al, bl));
    const D2 s = _mm_add_pd(p, c);
    const D2 bb = _mm_sub_pd(s, p);
    const D2 se = _mm_add_pd(_mm_sub_pd(p, _mm_sub_pd(s, bb)), _mm_sub_pd(c, bb));
    return _mm_add_pd(s, _mm_add_pd(pe, se));
}

// Brackets refined at once: at most 3 monotone pieces of the quartic, the convex or concave ones
// split in two (f changes sign at most 4 times; more only by rounding, and then dropped).
constexpr int kLanes = 6;

// A bracket [a, b] of a sign change of a function g (ga = g(a), gb = g(b)) and the root's
// estimate x (kNoSeed: none).
struct Bracket {
    double a, b, ga, gb, x;
};

// Newton's method (or a faster one) kept inside each bracket, bisecting when a step leaves it;
// g(x, &step) returns g and the step to subtract from x (Newton's: g / g'). The brackets are
// refined in lockstep: their iterations are independent, so the processor overlaps their square
// roots and divisions. A bracket stops after a Newton step below `tol` (its error is then of the
// order of the step squared) or when it is a few ulp wide. Starts from x when it lies inside the
// bracket, else from the secant's root.
template <class G>
void bracketed_roots(const G& g, Bracket* br, int n, double tol) {
    bool done[kLanes];
    for (int i = 0; i < n; ++i) {
        Bracket& k = br[i];
        done[i] = false;
        if (!(k.x > k.a && k.x < k.b))
            k.x = k.ga != k.gb ? k.a + (k.b - k.a) * (k.ga / (k.ga - k.gb)) : 0.5 * (k.a + k.b);
        if (!(k.x > k.a && k.x < k.b)) k.x = 0.5 * (k.a + k.b);
    }
    for (int it = 0, left = n; it < 80 && left > 0; ++it) {
        for (int i = 0; i < n; ++i) {
            if (done[i]) continue;
            Bracket& k = br[i];
            double step = 0.0;
            const double gx = g(k.x, &step);
            bool stop = gx == 0.0;
            if (!stop) {
                ((gx < 0.0) == (k.ga < 0.0) ? k.a : k.b) = k.x;
                const double xn = k.x - step;
                // Converged: a step below tol that stays in the closed bracket (x itself, now an
                // end of the bracket, when the step rounds to nothing).
                if (std::abs(xn - k.x) <= tol && xn >= k.a && xn <= k.b) {
                    k.x = xn, stop = true;
                } else if (xn > k.a && xn < k.b) {
                    k.x = xn;
                } else {
                    k.x = 0.5 * (k.a + k.b);
                    stop = !(k.b - k.a > 4e-16 * (1.0 + std::abs(k.x)));
                }
            }
            if (stop) done[i] = true, --left;
        }
    }
}

// One bracket's root (x0: a seed, or kNoSeed).
template <class G>
double bracketed_root(const G& g, double a, double b, double ga, double gb, double tol,
                      double x0 = kNoSeed) {
    Bracket k{a, b, ga, gb, x0};
    bracketed_roots(g, &k, 1, tol);
    return k.x;
}

// The ray in the torus's frame, scaled by 1 / (R + r) and moved to its point nearest the centre:
// the quartic's coefficients are then of order 1 whatever the ray's distance (spec §13.7).
struct TorusRay {
    Vec3 p;        // origin: the point of the line nearest c, in units of R + r
    Vec3 e;        // unit direction
    double t0;     // ray parameter of p
    double scale;  // ray parameter per unit of sigma: (R + r) / |d|
    double ring, tube;
    // f = (rho - R)^2 + y^2 - r^2 at p + sigma e.
    double f(double s) const {
        const Vec3 q = p + s * e;
        const double dr = std::sqrt(q.x * q.x + q.z * q.z) - ring;
        return dr * dr + q.y * q.y - tube * tube;
    }
    // f and Newton's step f / (df/dsigma) with one division (NaN on the axis, where f has no
    // derivative: the caller then bisects).
    double f(double s, double* step) const {
        const Vec3 q = p + s * e;
        const double rho = std::sqrt(q.x * q.x + q.z * q.z);
        const double dr = rho - ring;
        const double v = dr * dr + q.y * q.y - tube * tube;
        *step = v * rho / (2.0 * dr * (q.x * e.x + q.z * e.z) + 2.0 * q.y * e.y * rho);
        return v;
    }
    // rho^2 at sigma.
    double rho2(double s) const {
        const double x = p.x + s * e.x, z = p.z + s * e.z;
        return x * x + z * z;
    }
};

// The real roots of c2 x^2 + c1 x + c0 in (lo, hi), ascending.
int quadratic_roots(double c2, double c1, double c0, double lo, double hi, double* out) {
    double r[2];
    int n = 0;
    if (c2 == 0.0) {
        if (c1 != 0.0) r[n++] = -c0 / c1;
    } else {
        const double disc = c1 * c1 - 4.0 * c2 * c0;
        if (disc >= 0.0) {
            const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
            r[n++] = q / c2;
            if (q != 0.0) r[n++] = c0 / q;
        }
    }
    if (n == 2 && r[0] > r[1]) std::swap(r[0], r[1]);
    int m = 0;
    for (int i = 0; i < n; ++i)
        if (r[i] > lo && r[i] < hi) out[m++] = r[i];
    return m;
}

// The quartic Q in sigma (coefficients c[0] + c[1] s + ...) and its derivatives.
struct TorusQuartic {
    double c[5];
    double value(double s, double* dq) const {
        *dq = ((4.0 * c[4] * s + 3.0 * c[3]) * s + 2.0 * c[2]) * s + c[1];
        return (((c[4] * s + c[3]) * s + c[2]) * s + c[1]) * s + c[0];
    }
    double d1(double s, double* d2) const {
        *d2 = (12.0 * c[4] * s + 6.0 * c[3]) * s + 2.0 * c[2];
        return ((4.0 * c[4] * s + 3.0 * c[3]) * s + 2.0 * c[2]) * s + c[1];
    }
};

// The crossings of f in the brackets br[0, n) (ascending; f's signs at each one's ends opposite)
// added to h when they lie in t. Newton on Q, a polynomial (no square root), seeds Newton on f
// where R > r and Q's signs at the ends are f's: f's Newton then only polishes, or where Q
// cancels corrects, it.
void add_crossings(const TorusRay& r, const TorusQuartic& q, Bracket* br, int n, Interval t,
                   ShapeHits& h) {
    if (r.ring > r.tube) {
        Bracket qb[kLanes];
        int lane[kLanes], m = 0;
        for (int i = 0; i < n; ++i) {
            const Bracket& k = br[i];
            double dqa = 0.0, dqb = 0.0, d2a = 0.0, d2b = 0.0;
            const double qa = q.value(k.a, &dqa), qbv = q.value(k.b, &dqb);
            q.d1(k.a, &d2a), q.d1(k.b, &d2b);
            if ((qa < 0.0) != (k.ga < 0.0) || (qbv < 0.0) != (k.gb < 0.0) || qa == 0.0 ||
                qbv == 0.0)
                continue;
            // Start from a Newton step off the end where Q and Q'' agree in sign (Fourier's rule).
            const double xs = (qa < 0.0) == (d2a < 0.0) ? k.a - qa / dqa : k.b - qbv / dqb;
            qb[m] = {k.a, k.b, qa, qbv, xs};
            lane[m++] = i;
        }
        // Halley's steps 2 Q Q' / (2 Q'^2 - Q Q''), one division each: Q only seeds f's Newton.
        auto halley = [&](double s, double* step) {
            double dq = 0.0, d2 = 0.0;
            const double v = q.value(s, &dq);
            q.d1(s, &d2);
            *step = 2.0 * v * dq / (2.0 * dq * dq - v * d2);
            return v;
        };
        bracketed_roots(halley, qb, m, 1e-8);
        for (int j = 0; j < m; ++j) br[lane[j]].x = qb[j].x;
    }
    bracketed_roots([&](double s, double* step) { return r.f(s, step); }, br, n, 1e-10);
    for (int i = 0; i < n; ++i) {
        const double th = r.t0 + br[i].x * r.scale;
        if (t.contains(th) && h.count < ShapeHits::kMax && (h.count == 0 || th > h.t[h.count - 1]))
            h.add(th, 0);
    }
}

// The line in the torus's frame (see TorusRay); false when it misses the bounding sphere.
bool torus_ray(const Torus& tor, const Ray& ray, TorusRay& r, double& pp) {
    const double dd = glm::dot(ray.d, ray.d), size = tor.ring + tor.tube;
    if (!(dd > 0.0) || !(size > 0.0)) return false;
    // q = o - c exactly as hi + lo, then p = q + t0 d with one rounding: p is accurate to its own
    // size (at most R + r), not to the ray's distance.
    Vec3 qh = ray.o - tor.centre, ql;
    for (int i = 0; i < 3; ++i) {
        const double bb = qh[i] - ray.o[i];
        ql[i] = (ray.o[i] - (qh[i] - bb)) + (-tor.centre[i] - bb);
    }
    const D2 it = _mm_div_pd(d2(1.0, -glm::dot(qh, ray.d)), d2(size, dd));  // 1 / size, t0
    const double inv = lane0(it), inv_len = 1.0 / std::sqrt(dd);
    r.t0 = lane1(it);
    r.ring = tor.ring * inv, r.tube = tor.tube * inv;
    r.e = ray.d * inv_len;
    r.scale = size * inv_len;
    const D2 t0 = _mm_set1_pd(r.t0), iv = _mm_set1_pd(inv);
    const D2 pxy = _mm_mul_pd(
        _mm_add_pd(mul_add(t0, d2(ray.d.x, ray.d.y), d2(qh.x, qh.y)), d2(ql.x, ql.y)), iv);
    const D2 pz =
        _mm_mul_pd(_mm_add_pd(mul_add(t0, d2(ray.d.z, 0.0), d2(qh.z, 0.0)), d2(ql.z, 0.0)), iv);
    r.p = Vec3(lane0(pxy), lane1(pxy), lane0(pz));
    pp = glm::dot(r.p, r.p);
    return pp < 1.0;
}

// The sigma range [lo, hi] to search: the bounding sphere's chord (pp = |p|^2), the interval t
// (tlo, thi in sigma), the slab |y| <= r (inv_ey = 1 / e_y) and the outer cylinder rho <= R + r,
// each widened by rounding margins. False when it is empty or lies in the hole's cylinder
// rho < R - r (rho^2 is convex in sigma).
bool sigma_range(const TorusRay& r, double pp, double tlo, double thi, double inv_ey, double& lo,
                 double& hi) {
    const double w = std::sqrt(1.0 - pp) + 1e-12;
    lo = std::max(-w, tlo), hi = std::min(w, thi);
    const double slab = r.tube * (1.0 + 1e-12);
    if (r.e.y != 0.0) {
        const double inv = inv_ey, a = (-slab - r.p.y) * inv, b = (slab - r.p.y) * inv;
        lo = std::max(lo, std::min(a, b)), hi = std::min(hi, std::max(a, b));
    } else if (std::abs(r.p.y) > slab) {
        return false;
    }
    if (!(lo < hi)) return false;
    // The cylinder: exz s^2 + 2 bxz s + pxz <= 1 (a miss when its discriminant is negative, or
    // for a vertical line outside it).
    const Vec3& p = r.p;
    const Vec3& e = r.e;
    const double exz = e.x * e.x + e.z * e.z, bxz = p.x * e.x + p.z * e.z;
    const double c = p.x * p.x + p.z * p.z - (1.0 + 1e-12);
    if (bxz * bxz - exz * c < 0.0 || (exz == 0.0 && c > 0.0)) return false;
    if (r.ring > r.tube) {
        const double hole = (r.ring - r.tube) * (r.ring - r.tube) - 1e-12;
        if (r.rho2(lo) < hole && r.rho2(hi) < hole) return false;
    }
    return true;
}

// The critical point of Q in [a, b], where Q is convex or concave (Q' = da, db at the ends):
// first roughly, then exactly when f's sign there does not split the piece's crossings.
double critical_point(const TorusQuartic& q, double a, double b, double da, double db) {
    auto d1 = [&](double s, double* step) {
        double d2 = 0.0;
        const double v = q.d1(s, &d2);
        *step = v / d2;
        return v;
    };
    double d2a = 0.0, d2b = 0.0;
    q.d1(a, &d2a), q.d1(b, &d2b);
    const double d3a = 24.0 * q.c[4] * a + 6.0 * q.c[3];  // Fourier's rule, as for Q
    const double xs = (da < 0.0) == (d3a < 0.0) ? a - da / d2a : b - db / d2b;
    return bracketed_root(d1, a, b, da, db, 1e-9, xs);
}

// The brackets of f's crossings in [lo, hi], ascending. The quartic
// (|P|^2 + R^2 - r^2)^2 - 4 R^2 (P_x^2 + P_z^2) in sigma: its critical points (roots of the cubic
// Q', bracketed by the roots of Q'') split [lo, hi] into pieces where it is monotone, with at
// most one root each. A piece holds a crossing of the torus when f, not the quartic, changes sign
// over it: f is accurate where the quartic cancels (thin tori, grazing rays), and the lemon roots
// of a spindle torus, where f keeps its sign, drop out.
int torus_brackets(const TorusRay& r, const TorusQuartic& q, double lo, double hi, Bracket* br) {
    const double exz = r.e.x * r.e.x + r.e.z * r.e.z;
    const double s_axis = exz > 0.0 ? -(r.p.x * r.e.x + r.p.z * r.e.z) / exz : 0.5 * (lo + hi);
    double bnd[4];
    int nb = 0, n = 0;
    bnd[nb++] = lo;
    nb += quadratic_roots(12.0 * q.c[4], 6.0 * q.c[3], 2.0 * q.c[2], lo, hi, bnd + 1);
    bnd[nb++] = hi;
    double fv[4], dv[4], dummy = 0.0;
    for (int i = 0; i < nb; ++i) fv[i] = r.f(bnd[i]), dv[i] = q.d1(bnd[i], &dummy);
    for (int i = 1; i < nb && n + 2 <= kLanes; ++i) {
        const double a = bnd[i - 1], bb = bnd[i], fa = fv[i - 1], fb = fv[i];
        const double da = dv[i - 1], db = dv[i];
        if ((fa < 0.0) != (fb < 0.0)) {
            br[n++] = {a, bb, fa, fb, kNoSeed};
        } else if ((da < 0.0) != (db < 0.0) && da != 0.0 && db != 0.0) {
            // Q is convex or concave here (no inflection inside): 0 or 2 crossings, split by its
            // critical point c. Any split point where f changes sign brackets both: the first try
            // is the ray's point nearest the axis (in the hole when the ray passes through it
            // between two chords); only when it fails is c found, as its sign then decides.
            double c = s_axis > a && s_axis < bb ? s_axis : 0.5 * (a + bb);
            double fc = r.f(c);
            if ((fc < 0.0) == (fa < 0.0)) c = critical_point(q, a, bb, da, db), fc = r.f(c);
            if ((fc < 0.0) != (fa < 0.0)) {
                br[n++] = {a, c, fa, fc, kNoSeed};
                br[n++] = {c, bb, fc, fb, kNoSeed};
            }
        }
    }
    return n;
}

// The largest real root of z^3 + a z^2 + b z + c (the caller checks the factorisation it gives):
// with one real root (h > 0) Cardano's formula, w = cbrt(x) by an exponent-third guess (3% off)
// and two of Halley's steps; with three the trigonometric one, cos(acos(m) / 3) = y(sqrt((1 + m) /
// 2)) by a degree-5 polynomial (1.4e-6 off); then one of Halley's steps on the cubic. Only the
// case at hand is computed: on the rays of a torus test nine in ten have one real root.
double largest_cubic_root(double a, double b, double c) {
    const double a3 = a * (1.0 / 3.0);
    const double p = b - a * a3, q = (2.0 * a3 * a3 - b) * a3 + c;  // x^3 + p x + q, z = x - a/3
    const double h = 0.25 * q * q + p * p * p * (1.0 / 27.0);
    double x = 0.0;
    if (h > 0.0) {
        // x = w - p / (3 w), w = cbrt(-q/2 - sign(q) sqrt(h)).
        const double wq = std::max(0.5 * std::abs(q) + root(h), 1e-300);
        std::uint64_t bits = 0;
        std::memcpy(&bits, &wq, sizeof bits);
        bits = bits / 3 + 0x2a9f7893782da1ceULL;
        double w = 0.0;
        std::memcpy(&w, &bits, sizeof w);
        for (int i = 0; i < 2; ++i) {
            const double w3 = w * w * w;
            w *= (w3 + 2.0 * wq) / (2.0 * w3 + wq);
        }
        w = -std::copysign(w, q);
        x = w - p / (3.0 * w);
    } else {
        // x = 2 m cos(acos(cs) / 3), m = sqrt(-p / 3).
        const double m = root(std::max(-p * (1.0 / 3.0), 1e-300));
        const double cs = std::clamp(-0.5 * q / (m * m * m), -1.0, 1.0);
        const double sg = root(0.5 * (1.0 + cs));
        const double y =
            ((((0.004120803299140144 * sg - 0.01912182853543716) * sg + 0.04763450696127365) * sg -
              0.10988445983996663) *
                 sg +
             0.5772504050076003) *
                sg +
            0.5000013730081603;
        x = 2.0 * m * y;
    }
    double z = x - a3;
    const double g = ((z + a) * z + b) * z + c, dg = (3.0 * z + 2.0 * a) * z + b;
    z -= 2.0 * g * dg / (2.0 * dg * dg - g * (6.0 * z + 2.0 * a));  // Halley's step
    return z;
}

// The checks of a root x after the Newton step `step` (f' rho = df), for the two lanes of a pair
// at once: true when both pass. Quadratic convergence: the error is below step^2 f'' / f', f''
// of order 1 + R / rho, so the step must be tiny against the slope; and the root must not lie
// within `margin` of an end of t (tlo, thi in sigma). A NaN root fails, one at infinity is not
// checked (it is not in t).
struct PairChecks {
    D2 min_df, lo, hi, margin;
    bool pass(D2 x, D2 df, D2 step) const {
        const D2 absm = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
        const D2 as = _mm_and_pd(step, absm), ad = _mm_and_pd(df, absm);
        D2 good = _mm_and_pd(_mm_cmple_pd(as, _mm_set1_pd(1e-7)), _mm_cmpge_pd(ad, min_df));
        good = _mm_and_pd(good,
                          _mm_cmple_pd(_mm_mul_pd(step, step), _mm_mul_pd(_mm_set1_pd(1e-14), ad)));
        good = _mm_and_pd(good, _mm_cmpgt_pd(_mm_and_pd(_mm_sub_pd(x, lo), absm), margin));
        good = _mm_andnot_pd(_mm_cmple_pd(_mm_and_pd(_mm_sub_pd(x, hi), absm), margin), good);
        good = _mm_or_pd(good, _mm_cmpnlt_pd(x, _mm_set1_pd(kInf)));
        return _mm_movemask_pd(_mm_and_pd(good, _mm_cmpord_pd(x, x))) == 3;
    }
};

// One quadratic's two roots 0.5 (U - S), 0.5 (U + S) (sigma + sh), polished by one Newton step
// on f in the two lanes of an SSE2 pair: x and f' rho (its sign, and |f'| >= |f' rho| as
// rho <= 1); true when both pass the checks.
bool newton_pair(const TorusRay& r, double sh, double U, double S, const PairChecks& c, double* x,
                 double* df) {
    const D2 sv = _mm_sub_pd(_mm_mul_pd(_mm_set1_pd(0.5), _mm_add_pd(_mm_set1_pd(U), d2(-S, S))),
                             _mm_set1_pd(sh));
    const D2 ex = _mm_set1_pd(r.e.x), ey = _mm_set1_pd(r.e.y), ez = _mm_set1_pd(r.e.z);
    const D2 ptx = _mm_add_pd(_mm_set1_pd(r.p.x), _mm_mul_pd(sv, ex));
    const D2 pty = _mm_add_pd(_mm_set1_pd(r.p.y), _mm_mul_pd(sv, ey));
    const D2 ptz = _mm_add_pd(_mm_set1_pd(r.p.z), _mm_mul_pd(sv, ez));
    const D2 rho = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(ptx, ptx), _mm_mul_pd(ptz, ptz)));
    const D2 dr = _mm_sub_pd(rho, _mm_set1_pd(r.ring));
    const D2 fv = _mm_sub_pd(_mm_add_pd(_mm_mul_pd(dr, dr), _mm_mul_pd(pty, pty)),
                             _mm_set1_pd(r.tube * r.tube));
    const D2 rad = _mm_add_pd(_mm_mul_pd(ptx, ex), _mm_mul_pd(ptz, ez));
    const D2 drho = _mm_mul_pd(
        _mm_set1_pd(2.0), _mm_add_pd(_mm_mul_pd(dr, rad), _mm_mul_pd(_mm_mul_pd(pty, ey), rho)));
    const D2 st = _mm_div_pd(_mm_mul_pd(fv, rho), drho);  // f / f', f' = drho / rho
    const D2 xs = _mm_sub_pd(sv, st);
    _mm_storeu_pd(df, drho);
    _mm_storeu_pd(x, xs);
    return c.pass(xs, drho, st);
}

// The fast path for a well-conditioned ring torus (R > r): the quartic's real roots in closed
// form (Descartes' factorisation into two quadratics, with the resolvent cubic's largest root),
// each polished by one Newton step on f, a quadratic's pair of roots in the two lanes of an SSE2
// pair (only the quadratics with real roots: one on nine rays in ten that hit). inv4 = 1 / c4;
// tlo, thi: t's ends in sigma. Returns false, leaving h untouched, unless every root is certain:
// each quadratic's discriminant clear of zero (no near-double root, no grazing ray), each root's
// last Newton step tiny against its slope (simple roots, error of the order of the step squared),
// the roots apart with f's slope alternating in sign, and none near an end of t. The caller then
// falls back to the robust brackets.
bool fast_crossings(const TorusRay& r, const TorusQuartic& q, double inv4, double tlo, double thi,
                    Interval t, ShapeHits& h) {
    const double a3 = q.c[3] * inv4, a2 = q.c[2] * inv4, a1 = q.c[1] * inv4, a0 = q.c[0] * inv4;
    const double sh = 0.25 * a3;  // s = y - sh: y^4 + P y^2 + Q y + S
    const double P = a2 - 6.0 * sh * sh, Q = a1 - 2.0 * sh * a2 + 8.0 * sh * sh * sh;
    const double S = a0 - sh * a1 + sh * sh * a2 - 3.0 * sh * sh * sh * sh;
    const double z = largest_cubic_root(2.0 * P, P * P - 4.0 * S, -Q * Q);
    if (!(z > 1e-6)) return false;
    // (y^2 + u y + v)(y^2 - u y + w), u^2 = z.
    const double u = root(z), qu = Q * u * (1.0 / z);  // square root and division at once
    const double v = 0.5 * (P + z - qu), w = 0.5 * (P + z + qu);
    const double d1 = z - 4.0 * v, d2v = z - 4.0 * w;
    constexpr double kClear = 1e-8;  // discriminants closer to 0: a near-double root
    // The factorisation is exact but for v w = S, off by the error of z: an exact one of a quartic
    // within 1e-13 of Q (of order 1), far below what moves a discriminant by kClear.
    if (!(std::abs(d1) > kClear && std::abs(d2v) > kClear &&
          std::abs(v * w - S) <= 1e-13 * (1.0 + std::abs(S))))
        return false;
    const bool real1 = d1 > 0.0, real2 = d2v > 0.0;
    if (!real1 && !real2) return true;  // no crossing
    const PairChecks checks{_mm_set1_pd(1e-3 * r.tube), _mm_set1_pd(tlo), _mm_set1_pd(thi),
                            _mm_set1_pd(1e-7 * (1.0 + std::abs(tlo)))};
    double x[4], df[4];
    int n = 2;
    bool ok = true;
    if (real1 && real2) {
        const D2 s12 = _mm_sqrt_pd(d2(d1, d2v));
        ok = newton_pair(r, sh, -u, lane0(s12), checks, x, df);
        ok &= newton_pair(r, sh, u, lane1(s12), checks, x + 2, df + 2);
        n = 4;
    } else {
        ok = newton_pair(r, sh, real1 ? -u : u, root(real1 ? d1 : d2v), checks, x, df);
    }
    if (n == 4) {
        // The two sorted pairs merged (each quadratic's pair is in order, else a gap check fails).
        auto cx = [&](int i, int j) {
            const bool sw = x[j] < x[i];
            const double xi = x[i], di = df[i];
            x[i] = sw ? x[j] : xi, df[i] = sw ? df[j] : di;
            x[j] = sw ? xi : x[j], df[j] = sw ? di : df[j];
        };
        cx(0, 2), cx(1, 3), cx(1, 2);
    }
    for (int i = 1; i < n; ++i)
        ok &= !(x[i] < kInf) || (x[i] - x[i - 1] > 1e-6 && (df[i] < 0.0) != (df[i - 1] < 0.0));
    if (!ok) return false;
    for (int i = 0; i < n; ++i) {
        const double th = r.t0 + x[i] * r.scale;
        if (x[i] < kInf && t.contains(th) && (h.count == 0 || th > h.t[h.count - 1])) h.add(th, 0);
    }
    return true;
}

}  // namespace

Bounds3 bounds(const Torus& t) {
    const Vec3 e(t.ring + t.tube, t.tube, t.ring + t.tube);
    return {t.centre - e, t.centre + e};
}

Bounds3 bounds(const Torus& t, const Mat4& m) {
    // The solid is the ring circle swept by a ball of radius r: its image's extent along world
    // axis i is that of the transformed circle plus r times the length of row i of A (exact).
    Bounds3 b = transformed_disc_bounds(t.centre, t.ring, m);
    for (int i = 0; i < 3; ++i) {
        const double e = t.tube * glm::length(Vec3(m[0][i], m[1][i], m[2][i]));
        b.lo[i] -= e, b.hi[i] += e;
    }
    return b;
}

ShapeHits intersect(const Torus& tor, const Ray& ray, Interval t) {
    ShapeHits h;
    TorusRay r;
    double pp = 0.0, lo = 0.0, hi = 0.0;
    if (!torus_ray(tor, ray, r, pp)) return h;
    const Vec3& p = r.p;
    const Vec3& e = r.e;
    const double ee = glm::dot(e, e);
    // The divisions the tests share, two at a time: t's ends in sigma, 1 / e_y and 1 / |e|^4.
    const D2 tr = _mm_div_pd(_mm_sub_pd(d2(t.lo, t.hi), _mm_set1_pd(r.t0)), _mm_set1_pd(r.scale));
    const D2 ir = _mm_div_pd(_mm_set1_pd(1.0), d2(e.y, ee * ee));
    const double tlo = lane0(tr), thi = lane1(tr);
    if (!sigma_range(r, pp, tlo, thi, lane0(ir), lo, hi)) return h;
    const double R2 = r.ring * r.ring, b = glm::dot(p, e);
    const double k = pp + R2 - r.tube * r.tube;
    const double exz = e.x * e.x + e.z * e.z, bxz = p.x * e.x + p.z * e.z;
    const double c4 = ee * ee, c3 = 4.0 * ee * b, c2 = 4.0 * b * b + 2.0 * ee * k - 4.0 * R2 * exz;
    const double c1 = 4.0 * b * k - 8.0 * R2 * bxz;
    const double c0 = k * k - 4.0 * R2 * (p.x * p.x + p.z * p.z);
    const TorusQuartic q{{c0, c1, c2, c3, c4}};
    if (r.ring > r.tube && fast_crossings(r, q, lane1(ir), tlo, thi, t, h)) return h;
    Bracket br[kLanes];
    const int n = torus_brackets(r, q, lo, hi, br);
    add_crossings(r, q, br, n, t, h);
    return h;
}

SurfacePoint surface_at(const Torus& tor, const Ray& ray, double t, int /*part*/, bool uv) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - tor.centre;
    const double rho = std::sqrt(q.x * q.x + q.z * q.z);
    if (rho > 0.0) {
        // Re-project onto the tube: the point at distance r from the centre circle's point of
        // the same azimuth, along the gradient of f.
        const Vec3 c(tor.ring * q.x / rho, 0.0, tor.ring * q.z / rho);
        const Vec3 w = q - c;
        const double wl = glm::length(w);
        sp.n_geometric = wl > 0.0 ? w / wl : Vec3(q.x / rho, 0.0, q.z / rho);
        q = c + tor.tube * sp.n_geometric;
    } else {
        // A cusp of a spindle torus, on the axis.
        const double sy = q.y < 0.0 ? -1.0 : 1.0;
        sp.n_geometric = Vec3(0.0, sy, 0.0);
        q = Vec3(0.0, sy * std::sqrt(std::max(0.0, (tor.tube - tor.ring) * (tor.tube + tor.ring))),
                 0.0);
    }
    sp.p = tor.centre + q;
    sp.p_error = kAnalyticRetestMargin * gamma(8) *
                 (glm::abs(tor.centre) + glm::abs(q) + Vec3(tor.ring + tor.tube));
    sp.n_shading = sp.n_geometric;
    if (uv) {
        double theta = std::atan2(q.y, std::sqrt(q.x * q.x + q.z * q.z) - tor.ring);
        if (theta < 0.0) theta += 2 * kPi;
        sp.uv = {azimuth(q) / (2 * kPi), std::min(theta / (2 * kPi), std::nextafter(1.0, 0.0))};
    }
    return sp;
}

bool inside(const Torus& t, const Vec3& p_object) {
    const Vec3 q = p_object - t.centre;
    const double dr = std::sqrt(q.x * q.x + q.z * q.z) - t.ring;
    return dr * dr + q.y * q.y < t.tube * t.tube;
}

PreviewMesh tessellate(const Torus& t, int detail) {
    const int segments = std::max(3, detail), rows = std::max(2, detail / 4);
    // Two grids, theta in [0, theta_max] and [2pi - theta_max, 2pi]: the whole tube (theta_max =
    // pi), or for a spindle torus the outer surface down to the cusps, where rho = 0.
    const double theta_max = t.tube > t.ring ? std::acos(-t.ring / t.tube) : kPi;
    MeshBuilder b;
    for (int half = 0; half < 2; ++half) {
        const double theta0 = half ? 2 * kPi - theta_max : 0.0;
        b.grid(rows, segments, [&](int i, int j, Vec3* p, Vec3* n, Vec2* uv) {
            const double u = static_cast<double>(j) / segments;
            const double theta = theta0 + theta_max * static_cast<double>(i) / rows;
            const double phi = 2 * kPi * u;
            const Vec3 dir = around(phi, 1.0);  // unit horizontal direction
            *n = Vec3(std::cos(theta) * dir.x, std::sin(theta), std::cos(theta) * dir.z);
            *p = t.centre + around(phi, std::max(0.0, t.ring + t.tube * std::cos(theta)));
            p->y += t.tube * std::sin(theta);
            *uv = {u, theta / (2 * kPi)};
        });
    }
    return std::move(b.mesh);
}

// The CSG sign function and tolerance of spec §13.8 (kept apart from the intersection code).
double csg_sign(const Torus& t, const Vec3& p_object) {
    const Vec3 q = p_object - t.centre;
    return std::hypot(std::hypot(q.x, q.z) - t.ring, q.y) - t.tube;
}

double csg_epsilon(const Torus& t) {
    return kCsgTolerance * (glm::length(t.centre) + t.ring + t.tube);
}

std::pair<std::string, std::string> Torus::file_warning() const {
    if (!(tube > ring)) return {};
    std::ostringstream m;
    m << "spindle torus (iRadius " << tube << " > oRadius " << ring
      << "): only its outer surface exists";
    return {"torus-spindle", m.str()};
}

}  // namespace rt
