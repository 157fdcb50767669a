// OpenGL objects as RAII values (each deletes its name when it dies; move-only), shader programs
// loaded from files with the file's name in every error, and uniform setters. Needs a current GL
// 3.3 context; this header itself includes no GL header (GLuint is `unsigned`).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "rt/image/image.h"
#include "rt/util/math.h"

namespace rt::view {

/// One GL object name of the kind `Kind` (which knows how to make and delete one); 0 is none.
template <class Kind>
class GlName {
public:
    GlName() = default;
    ~GlName() { reset(); }
    GlName(GlName&& o) noexcept : m_id(std::exchange(o.m_id, 0u)) {}
    GlName& operator=(GlName&& o) noexcept {
        if (this != &o) {
            reset();
            m_id = std::exchange(o.m_id, 0u);
        }
        return *this;
    }
    GlName(const GlName&) = delete;
    GlName& operator=(const GlName&) = delete;

    /// A new object (glGen*, glCreate*).
    static GlName make() { return GlName(Kind::create()); }
    /// Takes over a name made elsewhere.
    static GlName adopt(unsigned id) { return GlName(id); }

    unsigned id() const { return m_id; }
    explicit operator bool() const { return m_id != 0; }
    void reset() {
        if (m_id) Kind::destroy(m_id);
        m_id = 0;
    }

private:
    explicit GlName(unsigned id) : m_id(id) {}
    unsigned m_id = 0;
};

struct GlTextureKind {
    static unsigned create();
    static void destroy(unsigned id);
};
struct GlBufferKind {
    static unsigned create();
    static void destroy(unsigned id);
};
struct GlVertexArrayKind {
    static unsigned create();
    static void destroy(unsigned id);
};
struct GlFramebufferKind {
    static unsigned create();
    static void destroy(unsigned id);
};
struct GlRenderbufferKind {
    static unsigned create();
    static void destroy(unsigned id);
};
struct GlShaderKind {  // made by compile_shader() (glCreateShader needs the stage)
    static void destroy(unsigned id);
};
struct GlProgramKind {
    static unsigned create();
    static void destroy(unsigned id);
};

using GlTexture = GlName<GlTextureKind>;
using GlBuffer = GlName<GlBufferKind>;
using GlVertexArray = GlName<GlVertexArrayKind>;
using GlFramebuffer = GlName<GlFramebufferKind>;
using GlRenderbuffer = GlName<GlRenderbufferKind>;
using GlShader = GlName<GlShaderKind>;
using GlProgram = GlName<GlProgramKind>;

/// The shaders are written in GLSL 3.30 core; the web page's WebGL 2 compiles GLSL ES 3.00.
#ifdef __EMSCRIPTEN__
inline constexpr bool kGlslEs = true;
#else
inline constexpr bool kGlslEs = false;
#endif
/// A shader file's text as compiled: `defines` inserted after its #version line as
/// `#define NAME 1`; with `es`, that line made `#version 300 es` and the default precisions
/// declared (highp floats, ints and samplers).
std::string shader_source(std::string src, const std::vector<std::string>& defines, bool es);

/// Compiles one shader from its files (`kind`: GL_VERTEX_SHADER, ...; the later files are
/// source strings after the first, their #version line dropped) with `defines` inserted after
/// the first one's #version line as `#define NAME 1` (as GLSL ES in the web page:
/// shader_source()). Throws std::runtime_error naming the file
/// ("shaders/preview.frag: 0:12(5): error: ...").
GlShader compile_shader(unsigned kind, const std::vector<std::string>& paths,
                        const std::vector<std::string>& defines);
/// Compiles and links dir/vert + dir/frag (+ dir/library, functions `frag` declares, compiled
/// with it as a second source string when not empty) with `defines`; errors name the files.
GlProgram make_program(const std::string& dir, const std::string& vert, const std::string& frag,
                       const std::vector<std::string>& defines = {},
                       const std::string& library = "");

/// Uniform setters by name on the program in use.
int uniform(unsigned program, const std::string& name);
void set_vec3(unsigned program, const std::string& name, const Vec3& v);
/// A row-major 4x4 (m[row][col]) as GL's column-major matrix.
void set_matrix(unsigned program, const char* name, const double m[4][4]);
/// The bound texture of `target`'s filtering (min and mag: GL_LINEAR, ...) and wrapping on
/// every axis (GL_REPEAT, GL_CLAMP_TO_EDGE, ...).
void set_sampling(unsigned target, int filter, int wrap);

/// "name[i]", the uniform name of an array element.
std::string indexed(const char* name, int i);

/// An image shown as a texture: 8-bit RGB as raytrace writes it, filtered (bilinear) when the
/// pane magnifies it.
struct ImageTexture {
    GlTexture texture;
    int w = 0, h = 0;
    void upload(const Image& img);
};

/// A framebuffer to draw into and show as a texture: RGBA colour and a 24-bit depth buffer.
struct RenderTarget {
    GlFramebuffer fbo;
    GlTexture color;
    GlRenderbuffer depth;
    int w = 0, h = 0;
    /// Makes the buffers again when the size changes (keeps them otherwise).
    void resize(int width, int height);
};

}  // namespace rt::view
