#define GL_GLEXT_PROTOTYPES
#include "preview.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "rt/file_io.h"
#include "rt/sampler.h"
#include "rt/tessellate.h"

namespace rt::view {

namespace {

GLuint compile(GLenum kind, const std::string& path) {
    std::string src;
    if (!read_file(path, &src)) throw std::runtime_error("cannot open shader '" + path + "'");
    const char* text = src.c_str();
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        std::string message = path;  // "shaders/preview.frag: 0:12(5): error: ..."
        message += ": ";
        message += log;
        throw std::runtime_error(message);
    }
    return shader;
}

GLint loc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }
GLint loc(GLuint program, const std::string& name) { return loc(program, name.c_str()); }

void set_vec3(GLuint program, const std::string& name, const Vec3& v) {
    glUniform3f(loc(program, name), static_cast<float>(v.x), static_cast<float>(v.y),
                static_cast<float>(v.z));
}

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
    const double near = far * 1e-5;
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

// Compiles and links name.vert + name.frag from dir; errors name the files.
GLuint make_program(const std::string& dir, const std::string& name) {
    const GLuint vs = compile(GL_VERTEX_SHADER, dir + "/" + name + ".vert");
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, dir + "/" + name + ".frag");
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        std::string message = dir;
        message += "/";
        message += name;
        message += ".{vert,frag}: link: ";
        message += log;
        throw std::runtime_error(message);
    }
    return program;
}

}  // namespace

Preview::Preview(const std::string& shader_dir) {
    m_program = make_program(shader_dir, "preview");
    try {
        m_line_program = make_program(shader_dir, "lines");
    } catch (...) {
        glDeleteProgram(m_program);
        throw;
    }
    glGenVertexArrays(1, &m_line_vao);
    glGenBuffers(1, &m_line_vbo);
}

Preview::~Preview() {
    release();
    glDeleteBuffers(1, &m_line_vbo);
    glDeleteVertexArrays(1, &m_line_vao);
    glDeleteProgram(m_line_program);
    glDeleteProgram(m_program);
}

void Preview::release() {
    for (SetBuffers& s : m_sets) {
        glDeleteBuffers(1, &s.vbo);
        glDeleteBuffers(1, &s.ebo);
        glDeleteVertexArrays(1, &s.vao);
    }
    m_sets.clear();
    if (!m_textures.empty())
        glDeleteTextures(static_cast<GLsizei>(m_textures.size()), m_textures.data());
    m_textures.clear();
}

void Preview::load(const RenderScene& scene, int detail) {
    release();
    for (const GeometrySet& set : scene.sets) {
        const PreviewMesh mesh = tessellate_set(set, detail);
        // Interleaved position, normal, uv as floats; triangles grouped by material.
        std::vector<float> vertices;
        vertices.reserve(mesh.positions.size() * 8);
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            for (int k = 0; k < 3; ++k)
                vertices.push_back(static_cast<float>(mesh.positions[i][k]));
            for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(mesh.normals[i][k]));
            for (int k = 0; k < 2; ++k) vertices.push_back(static_cast<float>(mesh.uvs[i][k]));
        }
        std::vector<size_t> order(mesh.triangle_count());
        std::iota(order.begin(), order.end(), size_t{0});
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t a, size_t b) { return mesh.materials[a] < mesh.materials[b]; });
        std::vector<unsigned> indices;
        SetBuffers buf;
        for (size_t t : order) {
            const int m = mesh.materials[t];
            if (buf.ranges.empty() || buf.ranges.back().material != m)
                buf.ranges.push_back({m, static_cast<unsigned>(indices.size()), 0});
            for (int k = 0; k < 3; ++k)
                indices.push_back(mesh.indices[t * 3 + static_cast<size_t>(k)]);
            buf.ranges.back().count += 3;
        }
        glGenVertexArrays(1, &buf.vao);
        glBindVertexArray(buf.vao);
        glGenBuffers(1, &buf.vbo);
        glBindBuffer(GL_ARRAY_BUFFER, buf.vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                     vertices.data(), GL_STATIC_DRAW);
        glGenBuffers(1, &buf.ebo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buf.ebo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)), indices.data(),
                     GL_STATIC_DRAW);
        const GLsizei stride = 8 * sizeof(float);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>(3 * sizeof(float)));
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>(6 * sizeof(float)));
        glBindVertexArray(0);
        m_sets.push_back(buf);
    }
    // Textures: 8-bit RGB, row 0 first, bilinear with wrap and no mipmaps (spec §7.3).
    for (const auto& tex : scene.textures) {
        GLuint id = 0;
        glGenTextures(1, &id);
        glBindTexture(GL_TEXTURE_2D, id);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, tex->width, tex->height, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, tex->rgb.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
        m_textures.push_back(id);
    }
}

void Preview::draw(const RenderScene& scene, const Camera& camera, int width, int height) const {
    glViewport(0, 0, width, height);
    glClearColor(static_cast<float>(scene.background.x), static_cast<float>(scene.background.y),
                 static_cast<float>(scene.background.z), 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);  // two-sided, as the tracer
    glUseProgram(m_program);
    const GlMatrices mats = camera_matrices(camera, scene.world_bounds);
    glUniformMatrix4fv(loc(m_program, "u_clip_from_world"), 1, GL_FALSE, mats.clip_from_world);
    set_vec3(m_program, "u_eye", camera.position);
    set_vec3(m_program, "u_ambient_light", scene.ambient);
    const int lights = std::min<int>(16, static_cast<int>(scene.lights.size()));
    glUniform1i(loc(m_program, "u_light_count"), lights);
    for (int i = 0; i < lights; ++i) {
        const Light& l = scene.lights[static_cast<size_t>(i)];
        // Built by appending: GCC 12 warns falsely (-Wrestrict) on "[" + std::to_string(i).
        std::string k = "[";
        k += std::to_string(i);
        k += ']';
        glUniform1i(loc(m_program, std::string("u_light_kind").append(k)),
                    l.kind == LightKind::Directional ? 0
                    : l.kind == LightKind::Point     ? 1
                                                     : 2);
        set_vec3(m_program, std::string("u_light_color").append(k), l.color);
        set_vec3(m_program, std::string("u_light_position").append(k), l.position);
        set_vec3(m_program, std::string("u_light_direction").append(k), l.direction);
        set_vec3(m_program, std::string("u_light_atten").append(k),
                 Vec3(l.constant_atten, l.linear_atten, l.quadratic_atten));
        glUniform1f(loc(m_program, std::string("u_light_cutoff").append(k)),
                    static_cast<float>(l.cutoff_rad));
        glUniform1f(loc(m_program, std::string("u_light_exponent").append(k)),
                    static_cast<float>(l.spot_exponent));
    }
    glUniform1i(loc(m_program, "u_texture"), 0);
    glActiveTexture(GL_TEXTURE0);
    for (const Instance& inst : scene.instances) {
        float world[16], normal[9];
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                world[c * 4 + r] = static_cast<float>(inst.world_from_set.m[c][r]);
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r)
                normal[c * 3 + r] = static_cast<float>(inst.world_from_set.normal[c][r]);
        glUniformMatrix4fv(loc(m_program, "u_world_from_object"), 1, GL_FALSE, world);
        glUniformMatrix3fv(loc(m_program, "u_normal_matrix"), 1, GL_FALSE, normal);
        const SetBuffers& buf = m_sets[static_cast<size_t>(inst.set)];
        glBindVertexArray(buf.vao);
        for (const Range& range : buf.ranges) {
            const Material& m = scene.materials[static_cast<size_t>(range.material)];
            set_vec3(m_program, "u_emissive", m.emissive);
            set_vec3(m_program, "u_ambient", m.ambient);
            set_vec3(m_program, "u_diffuse", m.diffuse);
            set_vec3(m_program, "u_specular", m.specular);
            glUniform1f(loc(m_program, "u_exponent"), static_cast<float>(m.specular_exponent));
            glUniform1i(loc(m_program, "u_textured"), m.texture >= 0 ? 1 : 0);
            if (m.texture >= 0)
                glBindTexture(GL_TEXTURE_2D, m_textures[static_cast<size_t>(m.texture)]);
            glDrawElements(
                GL_TRIANGLES, static_cast<GLsizei>(range.count), GL_UNSIGNED_INT,
                reinterpret_cast<const void*>(static_cast<size_t>(range.first) * sizeof(unsigned)));
        }
    }
    glBindVertexArray(0);
}

void Preview::draw_lines(const std::vector<LineVertex>& lines, const RenderScene& scene,
                         const Camera& camera) const {
    if (lines.empty()) return;
    glUseProgram(m_line_program);
    const GlMatrices mats = camera_matrices(camera, scene.world_bounds);
    glUniformMatrix4fv(loc(m_line_program, "u_clip_from_world"), 1, GL_FALSE, mats.clip_from_world);
    glBindVertexArray(m_line_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_line_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines.size() * sizeof(LineVertex)),
                 lines.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(lines.size()));
    glBindVertexArray(0);
}

namespace {

struct LineBuilder {
    std::vector<LineVertex> out;
    void segment(const Vec3& a, const Vec3& b, const Vec3& c) {
        LineVertex va{}, vb{};
        for (int k = 0; k < 3; ++k) {
            va.position[k] = static_cast<float>(a[k]);
            vb.position[k] = static_cast<float>(b[k]);
            va.color[k] = vb.color[k] = static_cast<float>(c[k]);
        }
        out.push_back(va);
        out.push_back(vb);
    }
    // The 12 edges of a box, its corners mapped by `xf` when given.
    void box(const Vec3& lo, const Vec3& hi, const Vec3& c, const Transform* xf) {
        auto corner = [&](int i) {
            const Vec3 p{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
            return xf ? xf->point(p) : p;
        };
        for (int i = 0; i < 8; ++i)
            for (int bit : {1, 2, 4})
                if (!(i & bit)) segment(corner(i), corner(i | bit), c);
    }
};

Vec3 marker_colour(const Vec3& c) {
    const double m = std::max(c.x, std::max(c.y, c.z));
    return m > 0 ? glm::clamp(c / m, 0.2, 1.0) : Vec3(1.0);
}

}  // namespace

std::vector<LineVertex> overlay_lines(const RenderScene& scene, bool lights, int bvh_depth) {
    LineBuilder b;
    const Bounds3& w = scene.world_bounds;
    const double size = w.empty() ? 1.0 : glm::length(w.diagonal());
    if (lights) {
        for (const Light& l : scene.lights) {
            const Vec3 c = marker_colour(l.color);
            const double s = 0.03 * size;
            if (l.kind == LightKind::Directional) {
                // An arrow along the direction of travel, ending at the scene's centre.
                const Vec3 end = w.empty() ? Vec3(0.0) : w.centre();
                const Vec3 start = end - 0.3 * size * l.direction;
                b.segment(start, end, c);
                Vec3 a1, a2;
                orthonormal_basis(l.direction, &a1, &a2);
                for (const Vec3& side : {a1, -a1, a2, -a2})
                    b.segment(end, end - 2 * s * l.direction + s * side, c);
                continue;
            }
            for (int axis = 0; axis < 3; ++axis) {
                Vec3 d(0.0);
                d[axis] = s;
                b.segment(l.position - d, l.position + d, c);
            }
            if (l.kind == LightKind::Spot) {
                // The cut-off cone, 0.15 of the scene's size long.
                Vec3 a1, a2;
                orthonormal_basis(l.direction, &a1, &a2);
                const double len = 0.15 * size, angle = std::min(l.cutoff_rad, 1.4);
                Vec3 prev(0.0);
                for (int k = 0; k <= 16; ++k) {
                    const double phi = 2 * kPi * k / 16;
                    const Vec3 rim =
                        l.position +
                        len * (std::cos(angle) * l.direction +
                               std::sin(angle) * (std::cos(phi) * a1 + std::sin(phi) * a2));
                    if (k % 4 == 0) b.segment(l.position, rim, c);
                    if (k > 0) b.segment(prev, rim, c);
                    prev = rim;
                }
            }
        }
    }
    if (bvh_depth > 0) {
        for (const Instance& inst : scene.instances) {
            const Transform* xf = inst.identity ? nullptr : &inst.world_from_set;
            const Bvh& bvh = scene.sets[static_cast<size_t>(inst.set)].bvh;
            b.box(inst.world_bounds.lo, inst.world_bounds.hi, Vec3(1, 1, 0.3), nullptr);
            // Node boxes level by level, dimmer deeper down.
            std::vector<std::pair<uint32_t, int>> stack;
            if (!bvh.empty()) stack.push_back({0u, 1});
            while (!stack.empty()) {
                const auto [node_index, depth] = stack.back();
                stack.pop_back();
                const Bvh4Node& node = bvh.nodes[node_index];
                const double fade = 1.0 / depth;
                for (uint32_t c = 0; c < node.num_children; ++c) {
                    const Vec3 lo(node.lo[0][c], node.lo[1][c], node.lo[2][c]);
                    const Vec3 hi(node.hi[0][c], node.hi[1][c], node.hi[2][c]);
                    b.box(lo, hi, Vec3(0.3, 1.0, 0.5) * fade + Vec3(0.1), xf);
                    if (!(node.child[c] & Bvh4Node::kLeaf) && depth < bvh_depth)
                        stack.push_back({node.child[c], depth + 1});
                }
            }
        }
    }
    return std::move(b.out);
}

}  // namespace rt::view
