#include "rt/intersect.h"

namespace rt {

namespace {

// Every hit of one primitive of a set, for a ray in the set's frame.
ShapeHits prim_hits(const GeometrySet& set, const Primitive& p, const Ray& ray_set, Interval t) {
    if (p.kind == ShapeKind::Triangle) return intersect(set.triangles[p.index], ray_set, t);
    const Ray r = p.transform < 0
                      ? ray_set
                      : set.transforms[static_cast<size_t>(p.transform)].inv_ray(ray_set);
    switch (p.kind) {
        case ShapeKind::Sphere:
            return intersect(set.spheres[p.index], r, t);
        case ShapeKind::Box:
            return intersect(set.boxes[p.index], r, t);
        case ShapeKind::Cylinder:
            return intersect(set.cylinders[p.index], r, t);
        case ShapeKind::Cone:
            return intersect(set.cones[p.index], r, t);
        case ShapeKind::Triangle:
            break;
    }
    return {};
}

Ray to_set(const Instance& inst, const Ray& ray) {
    return inst.identity ? ray : inst.world_from_set.inv_ray(ray);
}

}  // namespace

// Calls f(instance index, ray in the set's frame, t_max) for the instances whose box the ray
// enters; a scene of one instance (most files) skips the top-level walk.
template <bool kOrdered, class F>
void for_each_instance(const RenderScene& scene, const Ray& ray, double& t_max, F&& f) {
    if (scene.instances.size() == 1) {
        f(0u, to_set(scene.instances[0], ray), t_max);
        return;
    }
    traverse<kOrdered>(scene.top, ray, t_max, [&](uint32_t ii, double& best) {
        return f(ii, to_set(scene.instances[ii], ray), best);
    });
}

// Calls hits(prim, ShapeHits) for the primitives of a set along a ray in its frame. Sets made of
// triangles only go straight to the inline triangle test.
template <bool kOrdered, class F>
bool for_each_hit(const GeometrySet& set, const Ray& r, double& t_max, double t_min, F&& hits) {
    bool stopped = false;
    if (set.triangles_only) {
        traverse<kOrdered>(set.bvh, r, t_max, [&](uint32_t pi, double& best) {
            return stopped = hits(pi, intersect(set.triangles[pi], r, {t_min, best}), best);
        });
    } else {
        traverse<kOrdered>(set.bvh, r, t_max, [&](uint32_t pi, double& best) {
            return stopped = hits(pi, prim_hits(set, set.prims[pi], r, {t_min, best}), best);
        });
    }
    return stopped;
}

bool intersect(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit) {
    double t_max = t.hi;
    bool found = false;
    for_each_instance<true>(scene, ray, t_max, [&](uint32_t ii, const Ray& r, double& best) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        for_each_hit<true>(set, r, best, t.lo, [&](uint32_t pi, const ShapeHits& h, double& b) {
            if (h.count > 0) {
                b = h.t[0];
                *hit = {h.t[0], static_cast<int>(ii), pi, h.part[0]};
                found = true;
            }
            return false;
        });
        return false;
    });
    return found;
}

bool intersect_brute_force(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit) {
    double best = t.hi;
    bool found = false;
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        const GeometrySet& set = scene.sets[static_cast<size_t>(inst.set)];
        const Ray r = to_set(inst, ray);
        for (uint32_t pi = 0; pi < set.prims.size(); ++pi) {
            const ShapeHits h = prim_hits(set, set.prims[pi], r, {t.lo, best});
            if (h.count > 0) {
                best = h.t[0];
                *hit = {h.t[0], static_cast<int>(ii), pi, h.part[0]};
                found = true;
            }
        }
    }
    return found;
}

ShapeHits intersect_primitive(const GeometrySet& set, uint32_t prim, const Ray& ray_set,
                              Interval t) {
    return prim_hits(set, set.prims[prim], ray_set, t);
}

bool occluded(const RenderScene& scene, const Ray& ray, double t_max) {
    double limit = t_max;
    bool hit = false;
    for_each_instance<false>(scene, ray, limit, [&](uint32_t ii, const Ray& r, double&) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        double inner = t_max;
        return hit = for_each_hit<false>(
                   set, r, inner, 0.0,
                   [&](uint32_t, const ShapeHits& h, double&) { return h.count > 0; });
    });
    return hit;
}

Vec3 transmittance(const RenderScene& scene, const Ray& ray, double t_max) {
    Vec3 s(1.0);
    double limit = t_max;  // never shrinks: every crossing counts, order does not matter
    for_each_instance<false>(scene, ray, limit, [&](uint32_t ii, const Ray& r, double&) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        double inner = t_max;
        return for_each_hit<false>(
            set, r, inner, 0.0, [&](uint32_t pi, const ShapeHits& h, double&) {
                const Primitive& p = set.prims[pi];
                const Vec3& tr = scene.materials[static_cast<size_t>(p.material)].transparent;
                for (int k = 0; k < h.count; ++k) s *= tr;
                return h.count > 0 && s == Vec3(0.0);
            });
    });
    return s;
}

SurfaceInteraction interaction(const RenderScene& scene, const Ray& ray, const Hit& hit) {
    const Instance& inst = scene.instances[static_cast<size_t>(hit.instance)];
    const GeometrySet& set = scene.sets[static_cast<size_t>(inst.set)];
    const Primitive& p = set.prims[hit.prim];
    const Ray r_set = to_set(inst, ray);

    SurfacePoint sp;
    const Transform* shape_xf =
        p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)];
    const Ray r = shape_xf ? shape_xf->inv_ray(r_set) : r_set;
    switch (p.kind) {
        case ShapeKind::Sphere:
            sp = surface_at(set.spheres[p.index], r, hit.t, hit.part);
            break;
        case ShapeKind::Box:
            sp = surface_at(set.boxes[p.index], r, hit.t, hit.part);
            break;
        case ShapeKind::Cylinder:
            sp = surface_at(set.cylinders[p.index], r, hit.t, hit.part);
            break;
        case ShapeKind::Cone:
            sp = surface_at(set.cones[p.index], r, hit.t, hit.part);
            break;
        case ShapeKind::Triangle:
            sp = surface_at(set.triangles[p.index], set.triangle_attribs[p.index], r, hit.t);
            break;
    }
    // Shape frame -> set frame -> world: points by M, normals by (A^-1)^T (spec §4.1). The error
    // bound grows by |A| applied to the local bound plus the rounding of the transform itself.
    auto apply = [](const Transform& xf, SurfacePoint& s) {
        const Mat3 a(xf.m);
        Mat3 abs_a;
        for (int c = 0; c < 3; ++c) abs_a[c] = glm::abs(a[c]);
        const Vec3 p_new = xf.point(s.p);
        s.p_error = abs_a * s.p_error +
                    gamma(3) * (abs_a * glm::abs(s.p) + glm::abs(Vec3(xf.m[3]))) + Vec3(0.0);
        s.p = p_new;
        s.n_geometric = glm::normalize(xf.normal_dir(s.n_geometric));
        s.n_shading = glm::normalize(xf.normal_dir(s.n_shading));
    };
    if (shape_xf) apply(*shape_xf, sp);
    if (!inst.identity) apply(inst.world_from_set, sp);

    SurfaceInteraction si;
    si.p = sp.p;
    si.p_error = sp.p_error;
    si.n_geometric = sp.n_geometric;
    si.n_shading = sp.n_shading;
    si.uv = sp.uv;
    si.material = p.material;
    return si;
}

Vec3 offset_origin(const SurfaceInteraction& si, const Vec3& dir) {
    const Vec3 n = si.n_geometric;
    // Distance along n that moves the point outside its error box (pbrt-v4 OffsetRayOrigin).
    // The factor covers the rounding of the next intersection test itself (a quadratic's constant
    // term near zero carries an error of the same order as p's), so the spawned ray starts
    // clearly outside the surface's error band at every scale.
    constexpr double kSafety = 64.0;
    const double d = kSafety * glm::dot(glm::abs(n), si.p_error);
    Vec3 offset = d * n;
    if (glm::dot(dir, n) < 0) offset = -offset;
    Vec3 po = si.p + offset;
    // Round away from the surface so the offset point is not rounded back onto it.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0)
            po[i] = std::nextafter(po[i], kInf);
        else if (offset[i] < 0)
            po[i] = std::nextafter(po[i], -kInf);
    }
    return po;
}

Ray spawn_ray(const SurfaceInteraction& si, const Vec3& dir) {
    return {offset_origin(si, dir), dir};
}

}  // namespace rt
