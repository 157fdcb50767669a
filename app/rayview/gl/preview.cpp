#define GL_GLEXT_PROTOTYPES
#include "gl/preview.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <stdexcept>

#include "rt/render/sampler.h"
#include "rt/shapes/shapes.h"
#include "rt/shapes/tessellate.h"
#include "rt/util/file_io.h"

namespace rt::view {

namespace {

GLint loc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }
GLint loc(GLuint program, const std::string& name) { return loc(program, name.c_str()); }

}  // namespace

GlMatrices camera_matrices(const Camera& camera, const Bounds3& world) {
    // View space: x along right, y along up', z along -forward (the tracer's frame, spec §6.1).
    // Clip: x_clip = x_v / tan_w, y_clip = y_v / tan_h, w = -z_v, so NDC (x, y) is exactly the
    // tracer's (2(i + 0.5)/W - 1, 1 - 2(j + 0.5)/H) at pixel centres (GL counts rows from the
    // bottom: read back rows in reverse).
    double far = 1.0;
    if (!world.empty())
        for (int i = 0; i < 8; ++i) {
            const Vec3 c{(i & 1) ? world.hi.x : world.lo.x, (i & 2) ? world.hi.y : world.lo.y,
                         (i & 4) ? world.hi.z : world.lo.z};
            far = std::max(far, glm::dot(c - camera.position, camera.forward));
        }
    far *= 1.01;
    // The near plane as far out as the scene allows, for depth precision: every visible point
    // of the bounds lies at depth >= its distance times the cosine of the frustum's corner angle.
    double near = far * 1e-4;
    if (!world.empty()) {
        const Vec3 closest = glm::clamp(camera.position, world.lo, world.hi);
        const double corner_cos =
            1.0 / std::sqrt(1.0 + camera.tan_w * camera.tan_w + camera.tan_h * camera.tan_h);
        near = std::max(near, 0.99 * corner_cos * glm::length(closest - camera.position));
    }
    const Vec3 r = camera.right, u = camera.up, f = camera.forward, p = camera.position;
    // view rows: (r, -r.p), (u, -u.p), (-f, f.p), (0, 0, 0, 1)
    const double a = (far + near) / (near - far), b = 2 * far * near / (near - far);
    double m[4][4] = {};  // m[row][col]
    for (int k = 0; k < 3; ++k) {
        m[0][k] = r[k] / camera.tan_w;
        m[1][k] = u[k] / camera.tan_h;
        m[2][k] = -a * f[k];  // z_clip = a * z_v + b with z_v = -f.(x - p)
        m[3][k] = f[k];       // w_clip = -z_v = f.(x - p)
    }
    m[0][3] = -glm::dot(r, p) / camera.tan_w;
    m[1][3] = -glm::dot(u, p) / camera.tan_h;
    m[2][3] = a * glm::dot(f, p) + b;
    m[3][3] = -glm::dot(f, p);
    GlMatrices out;
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row)
            out.clip_from_world[col * 4 + row] = static_cast<float>(m[row][col]);
    return out;
}

namespace {

// The frames of the six cube faces of a point or spot light's shadow map; preview.frag's
// kFace* tables are the same.
const Vec3 kFaceForward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const Vec3 kFaceRight[6] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {-1, 0, 0}};
const Vec3 kFaceUp[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

}  // namespace

Preview::Preview(const std::string& shader_dir) : m_shader_dir(shader_dir) {
    // Compiled at once with every feature on, so a broken shader file fails here; the other
    // combinations of defines compile on first use (the same source with less of it).
    program_for({"RT_POINT", "RT_SPOT", "RT_DIRECTIONAL", "RT_TEXTURES", "RT_SPECULAR",
                 "RT_SHADOWS", "RT_TRANSMIT_SHADOWS", "RT_CSG", "RT_REFLECTIONS", "RT_PLANAR",
                 "RT_INNER_HITS"});
    m_line_program = make_program(shader_dir, "lines.vert", "lines.frag");
    m_shadow_program = make_program(shader_dir, "preview.vert", "shadow.frag");
    m_shadow_csg_program =
        make_program(shader_dir, "preview.vert", "shadow.frag", {"RT_CSG"}, "csg.frag");
    m_transmit_program = make_program(shader_dir, "preview.vert", "shadow.frag", {"RT_TRANSMIT"});
    m_transmit_csg_program = make_program(shader_dir, "preview.vert", "shadow.frag",
                                          {"RT_TRANSMIT", "RT_CSG"}, "csg.frag");
    m_line_vao = GlVertexArray::make();
    m_line_vbo = GlBuffer::make();
}

unsigned Preview::program_for(const std::vector<std::string>& defines) {
    const auto it = m_programs.find(defines);
    if (it != m_programs.end()) return it->second.id();
    const bool csg = std::find(defines.begin(), defines.end(), "RT_CSG") != defines.end();
    GlProgram program =
        make_program(m_shader_dir, "preview.vert", "preview.frag", defines, csg ? "csg.frag" : "");
    const unsigned id = program.id();
    m_programs.emplace(defines, std::move(program));
    return id;
}

namespace {

// Interleaved position, normal, (uv) and (CSG leaf) as floats, the layout upload_set's vertex
// attributes read.
std::vector<float> interleave(const PreviewMesh& mesh, bool textured, const CsgTexels& csg) {
    const bool leaves = !csg.leaf_of_vertex.empty();
    std::vector<float> vertices;
    vertices.reserve(mesh.positions.size() * ((textured ? 8 : 6) + (leaves ? 1 : 0)));
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(mesh.positions[i][k]));
        for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(mesh.normals[i][k]));
        if (textured)
            for (int k = 0; k < 2; ++k) vertices.push_back(static_cast<float>(mesh.uvs[i][k]));
        if (leaves) vertices.push_back(csg.leaf_of_vertex[i]);
    }
    return vertices;
}

// The CSG trees as a 2D texture, kCsgRow texels a row (csg.frag's csg_texel): OpenGL ES and
// WebGL 2 have no buffer textures.
GlTexture csg_texture(const CsgTexels& csg, int row) {
    const size_t texels = csg.texels.size() / 4;
    const size_t rows = (texels + static_cast<size_t>(row) - 1) / static_cast<size_t>(row);
    std::vector<float> padded(csg.texels);
    padded.resize(rows * static_cast<size_t>(row) * 4, 0.0f);
    GlTexture tex = GlTexture::make();
    glBindTexture(GL_TEXTURE_2D, tex.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, row, static_cast<GLsizei>(rows), 0, GL_RGBA,
                 GL_FLOAT, padded.data());
    set_sampling(GL_TEXTURE_2D, GL_NEAREST, GL_CLAMP_TO_EDGE);  // texelFetch only
    glBindTexture(GL_TEXTURE_2D, 0);
    return tex;
}

// The solid a transmitting range is, for refraction through its second interface
// (preview.frag's u_solid: 0 none, 1 a sphere, 2 a box, 3 a torus about y), in the set's frame:
// the kind and numbers its primitive carries (a torus only when its tube is no wider than its
// ring).
void set_solid_uniforms(GLuint program, const PreviewRange& range) {
    int code = 0;
    glm::dvec4 sphere(0.0);
    Vec2 radii(0.0);
    Bounds3 box = range.bounds;
    if (const std::optional<PreviewShape>& s = range.solid) {
        if (s->kind == ShapeKind::Sphere) {
            code = 1;
            sphere = glm::dvec4(s->centre, s->radius);
        } else if (s->kind == ShapeKind::Box) {
            code = 2;
            box = s->box;
        } else if (s->kind == ShapeKind::Torus && s->radii.x >= s->radii.y) {
            code = 3;
            sphere = glm::dvec4(s->centre, 0.0);
            radii = s->radii;
        }
    }
    glUniform1i(loc(program, "u_solid"), code);
    glUniform4f(loc(program, "u_solid_sphere"), static_cast<float>(sphere.x),
                static_cast<float>(sphere.y), static_cast<float>(sphere.z),
                static_cast<float>(sphere.w));
    glUniform2f(loc(program, "u_solid_radii"), static_cast<float>(radii.x),
                static_cast<float>(radii.y));
    set_vec3(program, "u_solid_lo", box.lo);
    set_vec3(program, "u_solid_hi", box.hi);
}

// Instance transform `xf` into the program's uniforms (its inverse too for `reflections`); a
// mirroring instance turns its triangles' winding on screen (the two-sided rule), and so does
// a planar reflection's pass (`mirrored`).
void set_instance_uniforms(GLuint program, const Transform& xf, bool reflections, bool mirrored) {
    float world[16], normal[9];
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) world[c * 4 + r] = static_cast<float>(xf.m[c][r]);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) normal[c * 3 + r] = static_cast<float>(xf.normal[c][r]);
    glUniformMatrix4fv(loc(program, "u_world_from_object"), 1, GL_FALSE, world);
    glUniformMatrix3fv(loc(program, "u_normal_matrix"), 1, GL_FALSE, normal);
    if (reflections) {
        float set_from_world[16];
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                set_from_world[c * 4 + r] = static_cast<float>(xf.inv[c][r]);
        glUniformMatrix4fv(loc(program, "u_set_from_world"), 1, GL_FALSE, set_from_world);
    }
    glUniform1i(loc(program, "u_mirrored"), (glm::determinant(Mat3(xf.m)) < 0) != mirrored ? 1 : 0);
}

}  // namespace

Preview::SetBuffers Preview::upload_set(const PreviewMesh& mesh,
                                        const std::vector<PreviewShape>& shapes, bool textured,
                                        const CsgTexels& csg, size_t* floats) {
    // Triangles grouped by material, a draw call each.
    const bool leaves = !csg.leaf_of_vertex.empty();
    const int per_vertex = (textured ? 8 : 6) + (leaves ? 1 : 0);
    const std::vector<float> vertices = interleave(mesh, textured, csg);
    *floats += vertices.size();
    MaterialRanges grouped = material_ranges(mesh, shapes);
    const std::vector<unsigned>& indices = grouped.indices;
    SetBuffers buf;
    buf.uvs = textured;
    buf.ranges = std::move(grouped.ranges);
    buf.vao = GlVertexArray::make();
    glBindVertexArray(buf.vao.id());
    buf.vbo = GlBuffer::make();
    glBindBuffer(GL_ARRAY_BUFFER, buf.vbo.id());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                 vertices.data(), GL_STATIC_DRAW);
    buf.ebo = GlBuffer::make();
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buf.ebo.id());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)), indices.data(),
                 GL_STATIC_DRAW);
    const GLsizei stride = per_vertex * static_cast<GLsizei>(sizeof(float));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    if (textured) {
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>(6 * sizeof(float)));
    } else {
        glDisableVertexAttribArray(2);  // reads the constant (0, 0)
    }
    if (leaves) {
        glEnableVertexAttribArray(3);
        glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>((per_vertex - 1) * sizeof(float)));
    } else {
        glDisableVertexAttribArray(3);  // reads the constant draw() sets: -1, no leaf
    }
    glBindVertexArray(0);
    if (leaves) {
        buf.csg_texture = csg_texture(csg, kCsgRow);
        buf.csg_nodes = csg.nodes;
        buf.csg_children = csg.children;
        buf.csg_leaves = csg.leaves;
    }
    return buf;
}

void Preview::materials_changed(const RenderScene& scene) {
    m_env_chosen = false;
    m_shadows_valid = false;
    m_transparent = std::any_of(scene.materials.begin(), scene.materials.end(),
                                [](const Material& m) { return m.transparent != Vec3(0.0); });
}

bool Preview::needs_upload(const RenderScene& scene) const {
    for (const SetBuffers& buf : m_sets)
        for (const PreviewRange& r : buf.ranges) {
            const int t = scene.materials[static_cast<size_t>(r.material)].texture;
            if (t >= 0 && (!buf.uvs || static_cast<size_t>(t) >= m_textures.size() ||
                           !m_textures[static_cast<size_t>(t)]))
                return true;
        }
    return false;
}

void Preview::load(const RenderScene& scene, int detail) {
    load(scene, prepare_preview(scene, detail));
}

void Preview::load(const RenderScene& scene, const PreviewGeometry& geometry) {
    m_sets.clear();
    m_textures.clear();
    m_detail = geometry.detail;
    m_shadows_valid = false;
    m_csg = false;
    m_transparent = false;
    m_env_chosen = m_env_valid = m_env_ready = false;
    m_env.clear();
    m_env_next = 0;
    // What the scene uses decides what is uploaded: texture coordinates only for sets with a
    // textured material, textures only when used.
    std::vector<char> texture_used(scene.textures.size(), 0);
    m_uploaded_floats = 0;
    for (size_t si = 0; si < scene.sets.size(); ++si) {
        if (si >= geometry.sets.size() || !geometry.sets[si].placed) {
            m_sets.emplace_back();
            continue;
        }
        const PreviewMesh& mesh = geometry.sets[si].mesh;
        const CsgTexels& csg = geometry.sets[si].csg;
        bool textured = false;  // the materials drawn, CSG leaves' included
        std::vector<char> seen(scene.materials.size(), 0);
        for (const int m : mesh.materials) {
            if (seen[static_cast<size_t>(m)]) continue;
            seen[static_cast<size_t>(m)] = 1;
            m_transparent |= scene.materials[static_cast<size_t>(m)].transparent != Vec3(0.0);
            const int t = scene.materials[static_cast<size_t>(m)].texture;
            if (t >= 0) {
                textured = true;
                texture_used[static_cast<size_t>(t)] = 1;
            }
        }
        m_csg |= !csg.leaf_of_vertex.empty();
        m_sets.push_back(
            upload_set(mesh, geometry.sets[si].shapes, textured, csg, &m_uploaded_floats));
        const PreviewMesh& coarse = geometry.sets[si].coarse;
        if (coarse.triangle_count() > 0) {
            SetBuffers& full = m_sets.back();
            full.coarse = std::make_unique<SetBuffers>(
                upload_set(coarse, {}, textured, CsgTexels{}, &m_uploaded_floats));
            // Its ranges are the full ones' primitives, coarser: the same solids.
            for (PreviewRange& r : full.coarse->ranges) {
                size_t k = 0;
                while (k + 1 < full.ranges.size() && full.ranges[k].material != r.material) ++k;
                full.coarse->full_range.push_back(k);
                r.solid = full.ranges[k].solid;
            }
        }
    }
    // Textures: 8-bit RGB, row 0 first, bilinear with wrap and no mipmaps (spec §7.3).
    for (size_t ti = 0; ti < scene.textures.size(); ++ti) {
        if (!texture_used[ti]) {
            m_textures.emplace_back();  // never bound
            continue;
        }
        const auto& tex = scene.textures[ti];
        GlTexture id = GlTexture::make();
        glBindTexture(GL_TEXTURE_2D, id.id());
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, tex->width, tex->height, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, tex->rgb.data());
        set_sampling(GL_TEXTURE_2D, GL_LINEAR, GL_REPEAT);
        m_textures.push_back(std::move(id));
    }
}

std::vector<Preview::ShadowView> Preview::shadow_views(const RenderScene& scene,
                                                       const std::vector<Light>& lights,
                                                       int* layers_out) {
    std::vector<ShadowView> views;
    const Bounds3& w = scene.world_bounds;
    const Vec3 centre = w.empty() ? Vec3(0.0) : w.centre();
    const double half = w.empty() ? 1.0 : std::max(0.5 * glm::length(w.diagonal()), 1e-30) * 1.01;
    int& layers = *layers_out;
    layers = 0;
    for (size_t i = 0; i < lights.size() && i < 16; ++i) {
        const Light& l = lights[i];
        ShadowView v;
        v.kind = l.kind;
        v.position = l.position;
        v.direction = l.direction;
        if (layers / 6 < kMaxShadowLights && (l.diffuse != Vec3(0.0) || l.specular != Vec3(0.0))) {
            v.layer = layers;
            layers += 6;
            if (l.kind == LightKind::Directional) {
                v.centre = centre;
                v.scale = half;
                orthonormal_basis(l.direction, &v.a1, &v.a2);
            } else {
                double far = 0.0;
                for (int c = 0; c < 8; ++c) {
                    const Vec3 corner{(c & 1) ? w.hi.x : w.lo.x, (c & 2) ? w.hi.y : w.lo.y,
                                      (c & 4) ? w.hi.z : w.lo.z};
                    far = std::max(far, glm::length(corner - l.position));
                }
                v.scale = std::max(far * 1.01, 1e-30);
            }
        }
        views.push_back(v);
    }
    return views;
}

// The clip matrix a shadow view's face is rendered with: a 90 degree view through cube face
// `face` from a point or spot light (the depth written is the distance), or for a directional
// light an orthographic view along its direction of travel over the scene's bounding sphere.
Preview::ClipMatrix Preview::shadow_clip_from_world(const ShadowView& v, int face,
                                                    const Bounds3& w) {
    ClipMatrix clip;
    auto& out = clip.m;
    if (v.kind != LightKind::Directional) {
        Camera c;
        c.position = v.position;
        c.forward = kFaceForward[face];
        c.right = kFaceRight[face];
        c.up = kFaceUp[face];
        c.tan_w = c.tan_h = 1.0;
        const GlMatrices m = camera_matrices(c, w);
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) out[r][k] = m.clip_from_world[k * 4 + r];
        return clip;
    }
    const Vec3 axes[3] = {v.a1, v.a2, v.direction};
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) out[r][k] = axes[r][k] / v.scale;
        out[r][3] = -glm::dot(axes[r], v.centre) / v.scale;
    }
    out[3][3] = 1.0;
    return clip;
}

void Preview::render_shadow_maps(const RenderScene& scene, const std::vector<Light>& lights) {
    // Which lights get a map, and the view each is rendered with.
    int layers = 0;
    const std::vector<ShadowView> views = shadow_views(scene, lights, &layers);
    const Bounds3& w = scene.world_bounds;
    // The joints' time too: a #dynamic_affine moves its shapes without moving the lights or, in
    // general, the scene's bounds.
    if (m_shadows_valid && views == m_shadow_views && scene.time == m_shadow_time) return;
    m_shadow_views = views;
    m_shadow_time = scene.time;
    m_shadows_valid = true;
    if (layers == 0) return;

    if (!m_shadow_fbo) m_shadow_fbo = GlFramebuffer::make();
    if (!m_shadow_tex) m_shadow_tex = GlTexture::make();
    glBindTexture(GL_TEXTURE_2D_ARRAY, m_shadow_tex.id());
    if (layers > m_shadow_layers) {
        glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT24, kShadowResolution,
                     kShadowResolution, layers, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, nullptr);
        m_shadow_layers = layers;
        set_sampling(GL_TEXTURE_2D_ARRAY, GL_LINEAR, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }

    GLint previous_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_shadow_fbo.id());
    const GLenum none = GL_NONE;
    glDrawBuffers(1, &none);
    glReadBuffer(GL_NONE);
    glViewport(0, 0, kShadowResolution, kShadowResolution);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const GlProgram& shadow_program = m_csg ? m_shadow_csg_program : m_shadow_program;
    const unsigned sp = shadow_program.id();
    glUseProgram(sp);
    glUniform1i(loc(sp, "u_csg"), 2);
    glVertexAttrib1f(3, -1.0f);  // the leaf of vertices of sets without CSG: none
    for (const ShadowView& v : views) {
        if (v.layer < 0) continue;
        const bool radial = v.kind != LightKind::Directional;
        glUniform1i(loc(sp, "u_radial"), radial ? 1 : 0);
        set_vec3(sp, "u_light_position", v.position);
        glUniform1f(loc(sp, "u_far"), static_cast<float>(v.scale));
        for (int face = 0; face < (radial ? 6 : 1); ++face) {
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, m_shadow_tex.id(), 0,
                                      v.layer + face);
            glClear(GL_DEPTH_BUFFER_BIT);
            set_matrix(sp, "u_clip_from_world", shadow_clip_from_world(v, face, w).m);
            DrawPass pass;
            pass.opaque_only = true;
            draw_instances(scene, sp, pass);
        }
    }
    if (m_transparent) render_transmit_maps(scene, views, layers);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));  // draw buffers are
                                                                           // per framebuffer
}

void Preview::render_transmit_maps(const RenderScene& scene, const std::vector<ShadowView>& views,
                                   int layers) {
    if (!m_transmit_fbo) m_transmit_fbo = GlFramebuffer::make();
    if (!m_transmit_tex) m_transmit_tex = GlTexture::make();
    glBindTexture(GL_TEXTURE_2D_ARRAY, m_transmit_tex.id());
    if (layers > m_transmit_layers) {
        glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, kTransmitResolution, kTransmitResolution,
                     layers, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        m_transmit_layers = layers;
        set_sampling(GL_TEXTURE_2D_ARRAY, GL_LINEAR, GL_CLAMP_TO_EDGE);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m_transmit_fbo.id());
    const GLenum colour = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &colour);
    glViewport(0, 0, kTransmitResolution, kTransmitResolution);
    // No depth test: every transparent surface on the light's way multiplies the colour (each
    // face of a closed object once, as the trace's shadow ray crosses both), and the alpha keeps
    // the nearest one's depth (a receiver nearer to the light than that is not behind any).
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_MIN);
    glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ONE, GL_ONE);
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    const unsigned tp = (m_csg ? m_transmit_csg_program : m_transmit_program).id();
    glUseProgram(tp);
    glUniform1i(loc(tp, "u_csg"), 2);
    glVertexAttrib1f(3, -1.0f);
    const Bounds3& w = scene.world_bounds;
    for (const ShadowView& v : views) {
        if (v.layer < 0) continue;
        const bool radial = v.kind != LightKind::Directional;
        glUniform1i(loc(tp, "u_radial"), radial ? 1 : 0);
        set_vec3(tp, "u_light_position", v.position);
        glUniform1f(loc(tp, "u_far"), static_cast<float>(v.scale));
        for (int face = 0; face < (radial ? 6 : 1); ++face) {
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, m_transmit_tex.id(), 0,
                                      v.layer + face);
            glClear(GL_COLOR_BUFFER_BIT);
            set_matrix(tp, "u_clip_from_world", shadow_clip_from_world(v, face, w).m);
            DrawPass pass;
            pass.transparent_only = true;
            draw_instances(scene, tp, pass);
        }
    }
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glEnable(GL_DEPTH_TEST);
}

void Preview::draw_instances(const RenderScene& scene, unsigned program,
                             const DrawPass& pass) const {
    const bool shading = !pass.opaque_only && !pass.transparent_only,
               opaque_only = pass.opaque_only;
    const bool reflections = shading && pass.reflections;
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        set_instance_uniforms(program, inst.world_from_set, reflections, pass.mirrored);
        const SetBuffers& full = m_sets[static_cast<size_t>(inst.set)];
        const SetBuffers& buf = pass.coarse && full.coarse ? *full.coarse : full;
        if (!buf.vao) continue;
        glBindVertexArray(buf.vao.id());
        if (buf.csg_texture) {
            glActiveTexture(GL_TEXTURE2);
            glBindTexture(GL_TEXTURE_2D, buf.csg_texture.id());
            glActiveTexture(GL_TEXTURE0);
            glUniform1i(loc(program, "u_csg_nodes"), buf.csg_nodes);
            glUniform1i(loc(program, "u_csg_children"), buf.csg_children);
            glUniform1i(loc(program, "u_csg_leaves"), buf.csg_leaves);
        }
        for (size_t ri = 0; ri < buf.ranges.size(); ++ri) {
            const PreviewRange& range = buf.ranges[ri];
            const size_t fri = &buf == &full ? ri : buf.full_range[ri];  // the full set's range
            if (pass.skip_map >= 0 && m_env_of[ii][fri] == pass.skip_map) continue;
            const Material& m = scene.materials[static_cast<size_t>(range.material)];
            if (opaque_only && m.transparent != Vec3(0.0)) continue;
            if (pass.transparent_only) {
                if (m.transparent == Vec3(0.0)) continue;
                set_vec3(program, "u_transmit", m.transparent);
            }
            if (reflections) {
                const int e = m_env_of[ii][fri];
                glUniform1i(loc(program, "u_env_on"), e >= 0 ? 1 : 0);
                if (e >= 0) {
                    const EnvMap& map = m_env[static_cast<size_t>(e)];
                    glActiveTexture(GL_TEXTURE3);
                    glBindTexture(GL_TEXTURE_CUBE_MAP, map.cube.id());
                    glActiveTexture(GL_TEXTURE0);
                    set_vec3(program, "u_env_centre", map.centre);
                    set_vec3(program, "u_transparent", m.transparent);
                    glUniform1f(loc(program, "u_refind"), static_cast<float>(m.refractive_index));
                    set_solid_uniforms(program, range);
                }
            }
            if (shading) {
                set_vec3(program, "u_emissive", m.emissive);
                set_vec3(program, "u_ambient", m.ambient);
                set_vec3(program, "u_diffuse", m.diffuse);
                set_vec3(program, "u_specular", m.specular);
                glUniform1f(loc(program, "u_exponent"), static_cast<float>(m.specular_exponent));
                glUniform1i(loc(program, "u_textured"), m.texture >= 0 ? 1 : 0);
                if (m.texture >= 0)
                    glBindTexture(GL_TEXTURE_2D, m_textures[static_cast<size_t>(m.texture)].id());
            }
            if (pass.main) m_triangles_drawn += range.count / 3;
            glDrawElements(
                GL_TRIANGLES, static_cast<GLsizei>(range.count), GL_UNSIGNED_INT,
                reinterpret_cast<const void*>(static_cast<size_t>(range.first) * sizeof(unsigned)));
        }
    }
    glBindVertexArray(0);
}

std::vector<std::string> Preview::frame_defines(const RenderPlan& plan, bool shadows) const {
    // The program for what the plan says this scene uses: the light kinds that light, textures,
    // highlights, shadows (what a scene does not need is left out, as in the trace).
    const PlanUses& uses = plan.uses;
    std::vector<std::string> defines;
    // A sphere light shades as a point light at its centre (spec §13.9: L, f_l and the
    // highlight use the centre; only the shadow factor is an area integral).
    if (uses.light_kinds[static_cast<int>(LightKind::Point)] ||
        uses.light_kinds[static_cast<int>(LightKind::Sphere)])
        defines.push_back("RT_POINT");
    if (uses.light_kinds[static_cast<int>(LightKind::Spot)]) defines.push_back("RT_SPOT");
    if (uses.light_kinds[static_cast<int>(LightKind::Directional)])
        defines.push_back("RT_DIRECTIONAL");
    if (uses.textures) defines.push_back("RT_TEXTURES");
    if (uses.highlights) defines.push_back("RT_SPECULAR");
    if (shadows) defines.push_back("RT_SHADOWS");
    if (shadows && m_transparent) defines.push_back("RT_TRANSMIT_SHADOWS");
    if (m_csg) defines.push_back("RT_CSG");
    return defines;
}

void Preview::set_frame_uniforms(unsigned program, const RenderScene& scene, const RenderPlan& plan,
                                 const Camera& camera, bool shadows) const {
    const int lights = std::min<int>(16, static_cast<int>(plan.lights.size()));
    const GlMatrices mats = camera_matrices(camera, view_bounds(scene));
    glUniformMatrix4fv(loc(program, "u_clip_from_world"), 1, GL_FALSE, mats.clip_from_world);
    set_vec3(program, "u_eye", camera.position);
    set_vec3(program, "u_ambient_light", scene.ambient);
    set_vec3(program, "u_background", scene.background);
    glUniform1i(loc(program, "u_light_count"), lights);
    for (int i = 0; i < lights; ++i) {
        const Light& l = plan.lights[static_cast<size_t>(i)];
        const LightKind kind = l.kind == LightKind::Sphere ? LightKind::Point : l.kind;
        glUniform1i(loc(program, indexed("u_light_kind", i)), static_cast<int>(kind));
        set_vec3(program, indexed("u_light_ambient", i), l.ambient);
        set_vec3(program, indexed("u_light_diffuse", i), l.diffuse);
        set_vec3(program, indexed("u_light_specular", i), l.specular);
        set_vec3(program, indexed("u_light_position", i), l.position);
        set_vec3(program, indexed("u_light_direction", i), l.direction);
        set_vec3(program, indexed("u_light_atten", i),
                 Vec3(l.constant_atten, l.linear_atten, l.quadratic_atten));
        glUniform1f(loc(program, indexed("u_light_cutoff", i)), static_cast<float>(l.cutoff_rad));
        glUniform1f(loc(program, indexed("u_light_exponent", i)),
                    static_cast<float>(l.spot_exponent));
        if (shadows) {
            const ShadowView& v = m_shadow_views[static_cast<size_t>(i)];
            glUniform1i(loc(program, indexed("u_shadow_layer", i)), v.layer);
            set_vec3(program, indexed("u_shadow_centre", i), v.centre);
            set_vec3(program, indexed("u_shadow_a1", i), v.a1);
            set_vec3(program, indexed("u_shadow_a2", i), v.a2);
            glUniform1f(loc(program, indexed("u_shadow_scale", i)), static_cast<float>(v.scale));
        }
    }
    glUniform1i(loc(program, "u_texture"), 0);
    glUniform1i(loc(program, "u_texture_all"), scene.texture_all_terms ? 1 : 0);
    glUniform1i(loc(program, "u_csg"), 2);
    glUniform1i(loc(program, "u_env"), 3);
    glVertexAttrib1f(3, -1.0f);  // the leaf of vertices of sets without CSG: none
    if (shadows) {
        glUniform1i(loc(program, "u_shadow_map"), 1);
        glUniform1f(loc(program, "u_shadow_res"), static_cast<float>(kShadowResolution));
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D_ARRAY, m_shadow_tex.id());
        if (m_transparent) {
            glUniform1i(loc(program, "u_transmit_map"), 4);
            glActiveTexture(GL_TEXTURE4);
            glBindTexture(GL_TEXTURE_2D_ARRAY, m_transmit_tex.id());
        }
    }
    glActiveTexture(GL_TEXTURE0);
}

void Preview::draw(const RenderScene& scene, const RenderPlan& plan, const Camera& camera,
                   int width, int height, int max_depth, const DisplaySettings& display) {
    const bool shadows = plan.uses.shadows && !plan.lights.empty();
    m_max_depth = max_depth;
    if (shadows) render_shadow_maps(scene, plan.lights);
    std::vector<std::string> defines = frame_defines(plan, shadows);
    // The joints moved (animate() rebuilds the instances): the maps are chosen again.
    if (!m_env_chosen || scene.time != m_env_time) choose_environment_maps(scene);
    m_env_time = scene.time;
    if (max_depth >= 2 && !m_env.empty()) update_environment_maps(scene, plan, shadows);
    const bool reflections = max_depth >= 2 && m_env_ready;
    if (reflections) defines.push_back("RT_REFLECTIONS");
    // Hits inside a solid past the first, once the view is still: each repeats a glass
    // fragment's shading, which the frame time while the view moves does without.
    if (reflections && !moving) defines.push_back("RT_INNER_HITS");
    m_env_drawn = reflections ? static_cast<int>(m_env.size()) : 0;
    m_planes.clear();
    if (reflections) render_planar_maps(scene, plan, camera, shadows, width, height);
    if (!m_planes.empty()) defines.push_back("RT_PLANAR");
    const GLuint program = program_for(defines);
    m_defines = defines;

    glViewport(0, 0, width, height);
    Image background(1, 1);
    background.set(0, 0, scene.background);
    const Vec3 bg = display_transform(background, display.exposure_stops, display.tonemap).at(0, 0);
    glClearColor(static_cast<float>(bg.x), static_cast<float>(bg.y), static_cast<float>(bg.z),
                 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);  // two-sided, as the tracer
    glUseProgram(program);
    set_frame_uniforms(program, scene, plan, camera, shadows);
    glUniform1f(loc(program, "u_exposure_scale"),
                static_cast<float>(std::exp2(display.exposure_stops)));
    glUniform1i(loc(program, "u_tonemap"), static_cast<int>(display.tonemap));
    if (!m_planes.empty()) set_planar_uniforms(program, width, height);
    // The camera ray has the full depth: the ray refracted into a solid hits its inside at
    // depth - 1, and so on.
    glUniform1i(loc(program, "u_inner_hits"), std::max(1, max_depth - 1));
    DrawPass pass;
    pass.reflections = reflections;
    pass.coarse = moving;
    pass.main = true;
    m_triangles_drawn = 0;
    draw_instances(scene, program, pass);
}

void Preview::draw_lines(const std::vector<LineVertex>& lines, const RenderScene& scene,
                         const Camera& camera, bool on_top) const {
    if (lines.empty()) return;
    glUseProgram(m_line_program.id());
    const GlMatrices mats = camera_matrices(camera, view_bounds(scene));
    glUniformMatrix4fv(loc(m_line_program.id(), "u_clip_from_world"), 1, GL_FALSE,
                       mats.clip_from_world);
    glBindVertexArray(m_line_vao.id());
    glBindBuffer(GL_ARRAY_BUFFER, m_line_vbo.id());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines.size() * sizeof(LineVertex)),
                 lines.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    if (on_top) glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(lines.size()));
    if (on_top) glEnable(GL_DEPTH_TEST);
    glBindVertexArray(0);
}

}  // namespace rt::view
