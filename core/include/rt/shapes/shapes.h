// The shapes of the format in their local frame (spec §5, the torus §13.7), each in its own file
// core/src/shapes/<kind>.cpp with the same small API: bounds, intersect (every hit in an interval,
// nearest first), surface_at (point, outward geometric normal, shading normal, texture
// coordinates, and a bound on the point's error), inside (the solid's open interior) and
// tessellate (the viewer's preview mesh). One dispatch, visit_shape(), calls a function with the
// concrete shape of a primitive; no call site switches on the kind.
//
// Each struct also says how its directive #shape_<kName> lists it (spec §3.3, §13.7): params()
// visits its numbers in that order (p.point(v) for three, p.size(x, what) for one that is never
// negative), which the format's reader and writer and the viewer's CSG preview follow, and
// kEmpty names it when a size of 0 leaves it out.
//
// Adding a kind: its struct here (with kKind, kName, params and kEmpty), its enumerator in
// ShapeKind, its place in Shape, the declarations of its functions, then its file and its line
// in core/CMakeLists.txt.
#pragma once

#include <bit>
#include <cassert>
#include <cstdint>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "rt/util/math.h"

namespace rt {

enum class ShapeKind : uint8_t { Sphere, Box, Cylinder, Cone, Triangle, Torus };
const char* shape_kind_name(ShapeKind k);

struct Sphere {
    static constexpr ShapeKind kKind = ShapeKind::Sphere;
    static constexpr const char* kName = "sphere";
    static constexpr const char* kEmpty = "sphere of radius 0";
    Vec3 centre{0.0};
    double radius = 1.0;
    bool operator==(const Sphere&) const = default;
    template <class P>
    void params(P& p) {
        p.point(centre), p.size(radius, "sphere radius");
    }
};
struct Box {
    static constexpr ShapeKind kKind = ShapeKind::Box;
    static constexpr const char* kName = "box";
    static constexpr const char* kEmpty = "box with a zero side";
    Vec3 centre{0.0};
    Vec3 half{0.5};  // half side lengths (the file gives full lengths: BoxDesc)
    bool operator==(const Box&) const = default;
    template <class P>
    void params(P& p) {
        p.point(centre);
        for (int i = 0; i < 3; ++i) p.size(half[i], "box half side");
    }
};
/// Axis along +y, from centre.y - height/2 to centre.y + height/2, closed by two caps.
struct Cylinder {
    static constexpr ShapeKind kKind = ShapeKind::Cylinder;
    static constexpr const char* kName = "cylinder";
    static constexpr const char* kEmpty = "cylinder with zero radius or height";
    Vec3 centre{0.0};
    double radius = 1.0, height = 1.0;
    bool operator==(const Cylinder&) const = default;
    template <class P>
    void params(P& p) {
        p.point(centre), p.size(radius, "cylinder radius"), p.size(height, "cylinder height");
    }
};
/// Axis along +y: base disc (closed) at centre.y - height/2, apex at centre.y + height/2.
struct Cone {
    static constexpr ShapeKind kKind = ShapeKind::Cone;
    static constexpr const char* kName = "cone";
    static constexpr const char* kEmpty = "cone with zero radius or height";
    Vec3 centre{0.0};
    double radius = 1.0, height = 1.0;
    bool operator==(const Cone&) const = default;
    template <class P>
    void params(P& p) {
        p.point(centre), p.size(radius, "cone radius"), p.size(height, "cone height");
    }
};
struct Triangle {
    static constexpr ShapeKind kKind = ShapeKind::Triangle;
    static constexpr const char* kName = "triangle";
    Vec3 p0{0.0}, p1{0.0}, p2{0.0};
    bool operator==(const Triangle&) const = default;
};
/// Axis along +y through centre (spec §13.7): (rho - ring)^2 + q_y^2 = tube^2. A spindle torus
/// (tube > ring) is its outer surface only.
struct Torus {
    static constexpr ShapeKind kKind = ShapeKind::Torus;
    static constexpr const char* kName = "torus";
    static constexpr bool kV3Only = true;  // #shape_torus exists in V3 only (spec §13.5)
    static constexpr const char* kEmpty = "torus with a zero radius";
    /// What the render plan says of a scene with and without tori (its own test per ray).
    static constexpr const char* kPlanNote[2] = {"quartics solved (spec §13.7)",
                                                 "no quartic is solved"};
    Vec3 centre{0.0};
    double tube = 0.25, ring = 1.0;  // r (iRadius, minor) and R (oRadius, major)
    bool operator==(const Torus&) const = default;
    template <class P>
    void params(P& p) {  // m cx cy cz iRadius (tube) oRadius (ring)
        p.point(centre), p.size(tube, "torus radius"), p.size(ring, "torus radius");
    }
    /// The reader's warning for a torus that is read as written but may not be what was meant
    /// (a spindle torus): its kind and text, or two empty strings.
    std::pair<std::string, std::string> file_warning() const;
};

/// The closed set of shapes, in ShapeKind order: the one list the dispatch, the per-kind arrays
/// and the description's variant are derived from.
using Shape = std::variant<Sphere, Box, Cylinder, Cone, Triangle, Torus>;
inline constexpr int kShapeKinds = static_cast<int>(std::variant_size_v<Shape>);
template <ShapeKind K>
using ShapeOf = std::variant_alternative_t<static_cast<size_t>(K), Shape>;

/// Whether a kind exists only in the V3 dialect: its #shape_<kName> directive is then a V3 marker
/// (spec §10) and V0/V1 cannot write it.
template <class T>
inline constexpr bool kV3OnlyShape = requires {
    T::kV3Only;
};

constexpr uint32_t kind_bit(ShapeKind k) { return 1u << static_cast<uint32_t>(k); }
/// Sets of kinds as bit masks, for dispatches that know which kinds can occur.
inline constexpr uint32_t kAllKinds = (1u << kShapeKinds) - 1u;
inline constexpr uint32_t kAnalyticKinds = kAllKinds & ~kind_bit(ShapeKind::Triangle);

namespace detail {
template <size_t... I>
constexpr bool kinds_in_order(std::index_sequence<I...>) {
    return ((std::variant_alternative_t<I, Shape>::kKind == static_cast<ShapeKind>(I)) && ...);
}
static_assert(kinds_in_order(std::make_index_sequence<kShapeKinds>{}),
              "Shape lists the kinds in ShapeKind's order");
static_assert(kShapeKinds <= 32, "kind masks are 32 bits");

template <class V>
struct AnalyticArrays;
template <class... T>
struct AnalyticArrays<std::variant<T...>> {
    using type = decltype(std::tuple_cat(
        std::declval<std::conditional_t<std::is_same_v<T, Triangle>, std::tuple<>,
                                        std::tuple<std::vector<T>>>>()...));
};
}  // namespace detail

/// One array per analytic kind (triangles have arrays of their own: GeometrySet::triangles).
struct ShapeArrays {
    typename detail::AnalyticArrays<Shape>::type arrays;
    template <class T>
    std::vector<T>& of() {
        return std::get<std::vector<T>>(arrays);
    }
    template <class T>
    const std::vector<T>& of() const {
        return std::get<std::vector<T>>(arrays);
    }
};

/// Calls f(std::type_identity<T>{}) for the shape type T of kind k, which must be in kKinds. A
/// single kind is a direct call (nothing is tested), so a walk over a one-kind set folds; else
/// the kinds are tested in order and the last one is not tested.
template <uint32_t kKinds = kAllKinds, class F>
decltype(auto) visit_kind(ShapeKind k, F&& f) {
    static_assert(kKinds != 0 && (kKinds & ~kAllKinds) == 0);
    constexpr int kFirst = std::countr_zero(kKinds);
    using T = std::variant_alternative_t<kFirst, Shape>;
    if constexpr ((kKinds & (kKinds - 1u)) == 0) {
        static_cast<void>(k);  // checked in debug builds only
        assert(k == static_cast<ShapeKind>(kFirst) && "a kind outside kKinds");
        return f(std::type_identity<T>{});
    } else {
        if (k == static_cast<ShapeKind>(kFirst)) return f(std::type_identity<T>{});
        return visit_kind<kKinds&(kKinds - 1u)>(k, static_cast<F&&>(f));
    }
}

/// The shape of type T that primitive p of `set` is (p.kind must be T's kind): a reference into
/// the set's arrays, or for a triangle a value made from its vertices.
template <class T, class Set, class Prim>
decltype(auto) shape_of(const Set& set, const Prim& p) {
    if constexpr (std::is_same_v<T, Triangle>)
        return set.triangle(p.index);
    else
        return set.shapes.template of<T>()[p.index];
}

/// THE dispatch on a primitive's kind: calls f(shape) with the concrete shape of primitive p of
/// `set` (a GeometrySet, rt/render_scene.h: a template so that this header needs none of
/// the compile stage's types). kKinds narrows the kinds the set can hold (a set's layout), see
/// visit_kind.
template <uint32_t kKinds = kAllKinds, class Set, class Prim, class F>
decltype(auto) visit_shape(const Set& set, const Prim& p, F&& f) {
    return visit_kind<kKinds>(p.kind, [&](auto tag) -> decltype(auto) {
        return f(shape_of<typename decltype(tag)::type>(set, p));
    });
}

/// Per-vertex attributes of a triangle, kept apart from the positions the traversal reads.
struct TriangleAttribs {
    Vec3 n[3]{Vec3(0.0), Vec3(0.0), Vec3(0.0)};
    Vec2 uv[3]{Vec2(0.0), Vec2(0.0), Vec2(0.0)};
    bool has_normals = false;  // all three vertices have non-zero normals
};

/// The hits of a shape inside an interval, nearest first: up to two for the convex shapes, up
/// to four for the torus. `part` tells which surface piece was hit (box face, cylinder side or
/// cap, ...), for surface_at. The hits of a CSG primitive are on one of its leaves (`leaf`).
struct ShapeHits {
    static constexpr int kMax = 4;
    int count = 0;
    int leaf = -1;  // hits of a CSG primitive: the leaf (GeometrySet::csg.leaves) they are on
    double t[kMax] = {0.0, 0.0, 0.0, 0.0};
    int part[kMax] = {0, 0, 0, 0};
    void add(double tt, int p) {
        t[count] = tt;
        part[count] = p;
        ++count;
    }
};

/// Analytic shapes are tested in double, and the test of a ray spawned at a hit carries an
/// error of the same order as the hit point's own (a quadratic's constant term near zero), so
/// their point error bounds are widened by this factor: the spawned ray then starts clearly
/// outside the surface's error band at every scale.
inline constexpr double kAnalyticRetestMargin = 64.0;

struct SurfacePoint {
    Vec3 p{0.0};            // on the surface, refined (re-projected) where the shape allows
    Vec3 p_error{0.0};      // conservative absolute error bound of p, per component, that a
                            // spawned ray must clear (see kAnalyticRetestMargin, gamma_float)
    Vec3 n_geometric{0.0};  // outward, unit
    Vec3 n_shading{0.0};    // unit; equals n_geometric except for triangles with normals
    Vec2 uv{0.0};
};

Bounds3 bounds(const Sphere& s);
Bounds3 bounds(const Box& b);
Bounds3 bounds(const Cylinder& c);
Bounds3 bounds(const Cone& c);
Bounds3 bounds(const Triangle& t);
Bounds3 bounds(const Torus& t);

/// Tight bounds of the shape under an affine transform p' = m p (exact for every kind, so the
/// default camera frames what is really there).
Bounds3 bounds(const Sphere& s, const Mat4& m);
Bounds3 bounds(const Box& b, const Mat4& m);
Bounds3 bounds(const Cylinder& c, const Mat4& m);
Bounds3 bounds(const Cone& c, const Mat4& m);
Bounds3 bounds(const Triangle& t, const Mat4& m);
Bounds3 bounds(const Torus& t, const Mat4& m);

ShapeHits intersect(const Sphere& s, const Ray& ray, Interval t);
ShapeHits intersect(const Box& b, const Ray& ray, Interval t);
ShapeHits intersect(const Cylinder& c, const Ray& ray, Interval t);
ShapeHits intersect(const Cone& c, const Ray& ray, Interval t);
/// The renderer's triangle test (watertight, single precision: triangle4.h) on one triangle.
ShapeHits intersect(const Triangle& tri, const Ray& ray, Interval t);
/// Every crossing of the torus surface in the interval (up to four), nearest first.
ShapeHits intersect(const Torus& tor, const Ray& ray, Interval t);

/// `uv` false: texture coordinates are not computed (left at 0) for scenes without textures.
SurfacePoint surface_at(const Sphere& s, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Box& b, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Cylinder& c, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Cone& c, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Torus& tor, const Ray& ray, double t, int part, bool uv = true);
/// For triangles, `origin` is the point the float copy of the set's triangles is relative to
/// (GeometrySet::tri_origin): the point's error bound is the float rounding about it.
SurfacePoint surface_at(const Triangle& tri, const TriangleAttribs& attr, const Ray& ray, double t,
                        bool uv = true, const Vec3& origin = Vec3(0.0));

/// Whether the object-space point lies strictly inside the solid: points on the surface (up to
/// the rounding of the test's few operations) and outside it are not inside. Triangles bound no
/// solid: no point is inside one.
bool inside(const Sphere& s, const Vec3& p_object);
bool inside(const Box& b, const Vec3& p_object);
bool inside(const Cylinder& c, const Vec3& p_object);
bool inside(const Cone& c, const Vec3& p_object);
bool inside(const Triangle& t, const Vec3& p_object);
bool inside(const Torus& t, const Vec3& p_object);

/// The CSG inside test (spec §13.8): the sign function s of the point in the shape's frame
/// (negative inside, zero on the surface, positive outside; +inf for a triangle, which is never
/// inside) and the tolerance epsilon = 1e-9 (|c| + size). Strictly inside: s < -epsilon;
/// inside or on: s <= epsilon.
double csg_sign(const Sphere& s, const Vec3& p_object);
double csg_sign(const Box& b, const Vec3& p_object);
double csg_sign(const Cylinder& c, const Vec3& p_object);
double csg_sign(const Cone& c, const Vec3& p_object);
double csg_sign(const Triangle& t, const Vec3& p_object);
double csg_sign(const Torus& t, const Vec3& p_object);
double csg_epsilon(const Sphere& s);
double csg_epsilon(const Box& b);
double csg_epsilon(const Cylinder& c);
double csg_epsilon(const Cone& c);
double csg_epsilon(const Triangle& t);
double csg_epsilon(const Torus& t);
inline constexpr double kCsgTolerance = 1e-9;

/// A triangle mesh for the viewer's rasterized preview. Positions, outward normals and texture
/// coordinates follow spec §5, so the preview and the trace agree; no GL here, the viewer
/// uploads these arrays.
struct PreviewMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // unit, outward (the shader applies the two-sided rule)
    std::vector<Vec2> uvs;
    std::vector<uint32_t> indices;  // three per triangle
    std::vector<int> materials;     // one per triangle: index into RenderScene::materials
    /// One per triangle, or empty when no triangle belongs to a CSG node: the CSG leaf
    /// (GeometrySet::csg.leaves) the triangle tessellates, -1 for none. The leaves are
    /// tessellated whole; the CSG filtering is the viewer's.
    std::vector<int> csg;

    size_t triangle_count() const { return indices.size() / 3; }
    /// Appends `other` with every vertex mapped by `xf` (points by M, normals by (A^-1)^T).
    void append(const PreviewMesh& other, const Transform* xf = nullptr);
};

/// `detail` is the number of segments around the y axis (at least 3); rings follow from it. A
/// box is its six faces whatever the detail.
PreviewMesh tessellate(const Sphere& s, int detail);
PreviewMesh tessellate(const Box& b, int detail = 0);
PreviewMesh tessellate(const Cylinder& c, int detail);
PreviewMesh tessellate(const Cone& c, int detail);
PreviewMesh tessellate(const Torus& t, int detail);
/// Appends the triangle in the file's winding, with its vertex normals when it has them (else
/// the geometric normal) and its vertex uvs; no material (the caller tags it).
void tessellate(const Triangle& t, const TriangleAttribs& attr, PreviewMesh& out);

/// Spec §5: azimuth about +y measured from -z, in [0, 2*pi).
inline double azimuth(const Vec3& q) {
    double phi = std::atan2(-q.x, -q.z);
    if (phi < 0) phi += 2 * kPi;
    return phi;
}

}  // namespace rt
