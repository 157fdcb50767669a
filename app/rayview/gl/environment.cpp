// The preview's reflections and refraction (spec §7.4, approximated): an environment cube map
// per reflecting or transmitting object, rendered from the object's centre with the preview's
// own local shading and without the object itself; preview.frag looks the reflected and the
// refracted direction up in it, corrected for parallax by the distance each texel stores.
// Objects are the ranges of one material in an instance's set (all the glass spheres of one
// material are one object). The largest kMaxEnvMaps objects get a map at their centre; each
// other object shares the map of the nearest of them, and all the objects of a map are left
// out of it. A second pass renders the maps again with the first pass's maps on the objects
// they show, so a mirror shows the glass beside it as glass (two bounces). Maps are rendered again
// only when the lights, the shadows or the scene change, never for a camera move.
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <numeric>

#include "gl/preview.h"
#include "rt/util/stopwatch.h"

namespace rt::view {

namespace {

// The faces of GL's cube map in its own order (+x, -x, +y, -y, +z, -z), each with the frame
// that puts the texel rows and columns where GL looks them up (OpenGL 3.3, table 3.19: the
// image's x runs along sc, its y along tc).
const Vec3 kEnvForward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const Vec3 kEnvRight[6] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {-1, 0, 0}};
const Vec3 kEnvUp[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};

bool reflects(const Material& m) { return m.specular != Vec3(0.0) || m.transparent != Vec3(0.0); }

Bounds3 world_box(const Bounds3& b, const Instance& inst) {
    return inst.identity ? b : inst.world_from_set.apply(b);
}

}  // namespace

void Preview::choose_environment_maps(const RenderScene& scene) {
    // Chosen again when the joints move: the maps keep their cubes (the old views stand in,
    // not black, until each face is rendered again).
    std::vector<EnvMap> old = std::move(m_env);
    m_env.clear();
    m_env_of.assign(scene.instances.size(), {});
    m_env_chosen = true;
    m_env_valid = false;
    struct Object {
        int instance, range;
        Bounds3 box;
    };
    std::vector<Object> objects;
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        const SetBuffers& buf = m_sets[static_cast<size_t>(inst.set)];
        m_env_of[ii].assign(buf.ranges.size(), -1);
        for (size_t ri = 0; ri < buf.ranges.size(); ++ri) {
            const PreviewRange& r = buf.ranges[ri];
            if (reflects(scene.materials[static_cast<size_t>(r.material)]) && !r.bounds.empty())
                objects.push_back(
                    {static_cast<int>(ii), static_cast<int>(ri), world_box(r.bounds, inst)});
        }
    }
    // The largest objects get their own maps; the others share the nearest map.
    std::stable_sort(objects.begin(), objects.end(), [](const Object& a, const Object& b) {
        return glm::length(a.box.diagonal()) > glm::length(b.box.diagonal());
    });
    for (const Object& o : objects) {
        int slot = -1;
        if (m_env.size() < static_cast<size_t>(kMaxEnvMaps)) {
            EnvMap map;
            map.centre = o.box.centre();
            if (m_env.size() < old.size()) map.cube = std::move(old[m_env.size()].cube);
            m_env.push_back(std::move(map));
            slot = static_cast<int>(m_env.size()) - 1;
        } else {
            double best = kInf;
            for (size_t k = 0; k < m_env.size(); ++k) {
                const double d = glm::length(m_env[k].centre - o.box.centre());
                if (d < best) best = d, slot = static_cast<int>(k);
            }
        }
        m_env_of[static_cast<size_t>(o.instance)][static_cast<size_t>(o.range)] = slot;
    }
}

void Preview::update_environment_maps(const RenderScene& scene, const RenderPlan& plan,
                                      bool shadows) {
    if (!m_env_valid || plan.lights != m_env_lights || shadows != m_env_shadows) {
        m_env_valid = true;  // everything again, the maps shown until then
        m_env_lights = plan.lights;
        m_env_shadows = shadows;
        m_env_next = 0;
    }
    if (!environment_pending()) return;
    for (EnvMap& map : m_env) {
        if (map.cube) continue;
        map.cube = GlTexture::make();
        glBindTexture(GL_TEXTURE_CUBE_MAP, map.cube.id());
        for (int f = 0; f < 6; ++f)
            glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + static_cast<GLenum>(f), 0, GL_RGBA32F,
                         kEnvResolution, kEnvResolution, 0, GL_RGBA, GL_FLOAT, nullptr);
        set_sampling(GL_TEXTURE_CUBE_MAP, GL_LINEAR, GL_CLAMP_TO_EDGE);
    }
    GLint previous_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
    if (!m_env_fbo) m_env_fbo = GlFramebuffer::make();
    glBindFramebuffer(GL_FRAMEBUFFER, m_env_fbo.id());
    if (!m_env_depth) {
        m_env_depth = GlRenderbuffer::make();
        glBindRenderbuffer(GL_RENDERBUFFER, m_env_depth.id());
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, kEnvResolution,
                              kEnvResolution);
    }
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              m_env_depth.id());
    const GLenum colour_buffer = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &colour_buffer);
    glViewport(0, 0, kEnvResolution, kEnvResolution);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const Clock::time_point t0 = Clock::now();
    while (environment_pending()) {
        const size_t faces = 6 * m_env.size();  // per bounce
        const size_t face = m_env_next % faces;
        render_environment_face(scene, plan, shadows, face / 6, static_cast<int>(face % 6),
                                static_cast<int>(m_env_next / faces));
        if (++m_env_next == faces) m_env_ready = true;  // the first bounce of every map
        glFinish();                                     // the time spent, not the time queued
        if (1000 * seconds_since(t0) > env_budget_ms) break;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
}

void Preview::render_environment_face(const RenderScene& scene, const RenderPlan& plan,
                                      bool shadows, size_t k, int f, int bounce) {
    // What no surface covers is the background, infinitely far (as far as a float allows).
    const float far = 1e18f;  // squared, still a float
    std::vector<std::string> defines = frame_defines(plan, shadows);
    defines.push_back("RT_ENV_PASS");
    if (bounce == 1) defines.push_back("RT_REFLECTIONS");  // the first bounce's maps
    const unsigned program = program_for(defines);
    glUseProgram(program);
    const EnvMap& map = m_env[k];
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           GL_TEXTURE_CUBE_MAP_POSITIVE_X + static_cast<GLenum>(f), map.cube.id(),
                           0);
    glClearColor(static_cast<float>(scene.background.x), static_cast<float>(scene.background.y),
                 static_cast<float>(scene.background.z), far);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    Camera c;  // a 90 degree view through the face
    c.position = map.centre;
    c.forward = kEnvForward[f];
    c.right = kEnvRight[f];
    c.up = kEnvUp[f];
    c.tan_w = c.tan_h = 1.0;
    set_frame_uniforms(program, scene, plan, c, shadows);
    set_vec3(program, "u_pass_centre", map.centre);
    glUniform1i(uniform(program, "u_inner_hits"), std::max(1, m_max_depth - 2));  // one deeper
    DrawPass pass;
    pass.reflections = bounce == 1;
    pass.skip_map = static_cast<int>(k);
    draw_instances(scene, program, pass);
}

}  // namespace rt::view
