// The preview's planar reflections (spec §7.4's K_S x reflected on flat mirrors, approximated):
// an environment cube map seen from an object's centre cannot show what a floor or a wall
// mirrors, since the centre is not on the plane. The usual raster technique does: the scene is
// drawn once more with the camera's view mirrored about the plane, what lies behind the plane
// clipped away, into a texture that the mirror's fragments read at their own pixel. The faces
// that get one are the largest flat faces of reflecting materials (triangle planes, a box's
// faces, a tessellation's flat parts: flat_faces in state/preview_ranges.h) facing the eye, at
// most kMaxPlanes a frame (one while the view moves), rendered with the preview's shading and
// shadows at the pane's resolution once the view is still, where what the mirror shows also
// reflects through the cube maps (half the resolution and local shading while it moves; the curved
// mirrors keep their cube maps).
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>

#include "gl/preview.h"
#include "state/overlay.h"

namespace rt::view {

namespace {

bool mirrors(const Material& m) { return m.specular != Vec3(0.0); }

// The reflection about the plane n.p + d = 0 (n unit), as a 4x4 matrix: p - 2 (n.p + d) n.
Mat4 reflection(const glm::dvec4& plane) {
    const Vec3 n(plane);
    Mat4 r(1.0);
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) r[c][k] -= 2.0 * n[k] * n[c];
    for (int k = 0; k < 3; ++k) r[3][k] = -2.0 * plane.w * n[k];
    return r;
}

// The world seen from the eye mirrored by `r` is the mirrored world seen from the eye: clip from
// world = P V R, with near and far planes that enclose the mirrored scene too.
GlMatrices mirrored_clip_from_world(const Camera& camera, const Bounds3& world, const Mat4& r) {
    Bounds3 both = world;
    both.extend(Transform::from_matrix(r).apply(world));
    const GlMatrices pv = camera_matrices(camera, both);
    GlMatrices out;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double sum = 0;
            for (int k = 0; k < 4; ++k)
                sum += static_cast<double>(pv.clip_from_world[k * 4 + row]) * r[c][k];
            out.clip_from_world[c * 4 + row] = static_cast<float>(sum);
        }
    return out;
}

}  // namespace

std::vector<Preview::PlanarView> Preview::choose_planes(const RenderScene& scene,
                                                        const Camera& camera) const {
    struct Candidate {
        PlanarView view;
        double score;
    };
    std::vector<Candidate> candidates;
    const double scene_size = std::max(glm::length(scene.world_bounds.diagonal()), 1e-300);
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        const SetBuffers& buf = m_sets[static_cast<size_t>(inst.set)];
        if (!buf.vao) continue;
        const Transform& xf = inst.world_from_set;
        const double scale = std::cbrt(std::abs(glm::determinant(Mat3(xf.m))));
        for (const PreviewRange& r : buf.ranges) {
            if (!mirrors(scene.materials[static_cast<size_t>(r.material)])) continue;
            for (const FlatFace& f : r.faces) {
                const Vec3 centre = xf.point(f.centroid);
                Vec3 n = glm::normalize(xf.normal_dir(f.n));
                double d = -glm::dot(n, centre);
                const double side = glm::dot(n, camera.position) + d;
                if (!std::isfinite(side) || std::abs(side) < 1e-9 * scene_size) continue;
                if (side < 0) n = -n, d = -d;
                // Some of it in front of the eye.
                const Bounds3 world = xf.apply(f.bounds);
                bool ahead = false;
                for (int i = 0; i < 8 && !ahead; ++i) {
                    const Vec3 corner{(i & 1) ? world.hi.x : world.lo.x,
                                      (i & 2) ? world.hi.y : world.lo.y,
                                      (i & 4) ? world.hi.z : world.lo.z};
                    ahead = glm::dot(corner - camera.position, camera.forward) > 0;
                }
                if (!ahead) continue;
                const double dist = glm::length(centre - camera.position);
                const double area = f.area * scale * scale;
                candidates.push_back(
                    {{glm::dvec4(n, d), 1e-4 * scene_size}, area / std::max(dist * dist, 1e-300)});
            }
        }
    }
    // One view serves every face of the same plane (a floor of many tiles, each its own
    // instance), so a plane is ranked by the sum of its faces' scores.
    const auto same_plane = [](const PlanarView& a, const PlanarView& b) {
        return glm::dot(Vec3(a.plane), Vec3(b.plane)) > 1 - 1e-9 &&
               std::abs(a.plane.w - b.plane.w) < b.epsilon;
    };
    std::vector<Candidate> planes;
    for (const Candidate& c : candidates) {
        const auto it = std::find_if(planes.begin(), planes.end(), [&](const Candidate& p) {
            return same_plane(p.view, c.view);
        });
        if (it == planes.end())
            planes.push_back(c);
        else
            it->score += c.score;
    }
    std::stable_sort(planes.begin(), planes.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    std::vector<PlanarView> out;
    for (const Candidate& c : planes) {
        if (out.size() == static_cast<size_t>(moving ? 1 : kMaxPlanes)) break;
        out.push_back(c.view);
    }
    return out;
}

void Preview::render_planar_maps(const RenderScene& scene, const RenderPlan& plan,
                                 const Camera& camera, bool shadows, int width, int height) {
    m_planes = choose_planes(scene, camera);
    if (m_planes.empty()) return;
    // Half the pane's resolution while the view moves; the pane's own once it is still, so a
    // mirror shows a checker floor as sharp as the trace does.
    const int scale = moving ? 2 : 1;
    const int w = std::max(1, width / scale), h = std::max(1, height / scale);
    if (!m_planar_tex) m_planar_tex = GlTexture::make();
    if (!m_planar_depth) m_planar_depth = GlRenderbuffer::make();
    if (!m_planar_fbo) m_planar_fbo = GlFramebuffer::make();
    if (w != m_planar_w || h != m_planar_h) {
        glBindTexture(GL_TEXTURE_2D_ARRAY, m_planar_tex.id());
        glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA16F, w, h, kMaxPlanes, 0, GL_RGBA, GL_FLOAT,
                     nullptr);
        set_sampling(GL_TEXTURE_2D_ARRAY, GL_LINEAR, GL_CLAMP_TO_EDGE);
        glBindRenderbuffer(GL_RENDERBUFFER, m_planar_depth.id());
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
        m_planar_w = w;
        m_planar_h = h;
    }
    GLint previous_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_planar_fbo.id());
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              m_planar_depth.id());
    const GLenum colour = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &colour);
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    // The shading and shadows of the main pass, linear (no display transform), with what lies
    // behind the mirror dropped (RT_CLIP_PLANE). What the mirror shows reflects and refracts
    // through its own cube maps, as it does in the main pass (a chrome ball seen in the floor
    // is not its dark diffuse colour) once the view is still; while it moves, local shading
    // keeps the frame time.
    std::vector<std::string> defines = frame_defines(plan, shadows);
    if (!moving) defines.insert(defines.end(), {"RT_REFLECTIONS", "RT_INNER_HITS"});
    defines.push_back("RT_CLIP_PLANE");
    const unsigned program = program_for(defines);
    glUseProgram(program);
    set_frame_uniforms(program, scene, plan, camera, shadows);
    glUniform1f(uniform(program, "u_exposure_scale"), 1.0f);
    glUniform1i(uniform(program, "u_tonemap"), 0);
    glUniform1i(uniform(program, "u_inner_hits"), std::max(1, m_max_depth - 2));  // one deeper
    const Bounds3 world = view_bounds(scene);
    for (size_t k = 0; k < m_planes.size(); ++k) {
        const PlanarView& v = m_planes[k];
        glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, m_planar_tex.id(), 0,
                                  static_cast<GLint>(k));
        glClearColor(static_cast<float>(scene.background.x), static_cast<float>(scene.background.y),
                     static_cast<float>(scene.background.z), 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        const Mat4 r = reflection(v.plane);
        const GlMatrices clip = mirrored_clip_from_world(camera, world, r);
        glUniformMatrix4fv(uniform(program, "u_clip_from_world"), 1, GL_FALSE,
                           clip.clip_from_world);
        // Highlights as the mirrored eye sees them.
        set_vec3(program, "u_eye", Vec3(r * glm::dvec4(camera.position, 1.0)));
        glUniform4f(uniform(program, "u_clip_plane"), static_cast<float>(v.plane.x),
                    static_cast<float>(v.plane.y), static_cast<float>(v.plane.z),
                    static_cast<float>(v.plane.w));
        glUniform1f(uniform(program, "u_clip_epsilon"), static_cast<float>(v.epsilon));
        DrawPass pass;
        pass.mirrored = true;
        pass.reflections = !moving;
        pass.coarse = moving;
        draw_instances(scene, program, pass);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
    glViewport(0, 0, width, height);
}

void Preview::set_planar_uniforms(unsigned program, int width, int height) const {
    glUniform1i(uniform(program, "u_planar_count"), static_cast<int>(m_planes.size()));
    for (size_t k = 0; k < m_planes.size(); ++k) {
        const glm::dvec4& p = m_planes[k].plane;
        glUniform4f(uniform(program, "u_planar[" + std::to_string(k) + "]"),
                    static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                    static_cast<float>(p.w));
        glUniform1f(uniform(program, "u_planar_epsilon[" + std::to_string(k) + "]"),
                    static_cast<float>(4.0 * m_planes[k].epsilon));
    }
    glUniform2f(uniform(program, "u_viewport"), static_cast<float>(width),
                static_cast<float>(height));
    glUniform1i(uniform(program, "u_planar_map"), 5);
    glActiveTexture(GL_TEXTURE5);
    glBindTexture(GL_TEXTURE_2D_ARRAY, m_planar_tex.id());
    glActiveTexture(GL_TEXTURE0);
}

}  // namespace rt::view
