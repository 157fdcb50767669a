#define GL_GLEXT_PROTOTYPES
#include "gl/gl_util.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <stdexcept>

#include "rt/util/file_io.h"

namespace rt::view {

unsigned GlTextureKind::create() {
    GLuint id = 0;
    glGenTextures(1, &id);
    return id;
}
void GlTextureKind::destroy(unsigned id) { glDeleteTextures(1, &id); }

unsigned GlBufferKind::create() {
    GLuint id = 0;
    glGenBuffers(1, &id);
    return id;
}
void GlBufferKind::destroy(unsigned id) { glDeleteBuffers(1, &id); }

unsigned GlVertexArrayKind::create() {
    GLuint id = 0;
    glGenVertexArrays(1, &id);
    return id;
}
void GlVertexArrayKind::destroy(unsigned id) { glDeleteVertexArrays(1, &id); }

unsigned GlFramebufferKind::create() {
    GLuint id = 0;
    glGenFramebuffers(1, &id);
    return id;
}
void GlFramebufferKind::destroy(unsigned id) { glDeleteFramebuffers(1, &id); }

unsigned GlRenderbufferKind::create() {
    GLuint id = 0;
    glGenRenderbuffers(1, &id);
    return id;
}
void GlRenderbufferKind::destroy(unsigned id) { glDeleteRenderbuffers(1, &id); }

void GlShaderKind::destroy(unsigned id) { glDeleteShader(id); }

unsigned GlProgramKind::create() { return glCreateProgram(); }
void GlProgramKind::destroy(unsigned id) { glDeleteProgram(id); }

std::string shader_source(std::string src, const std::vector<std::string>& defines, bool es) {
    size_t eol = src.find('\n');
    if (eol == std::string::npos) eol = src.size();
    std::string prelude;
    if (es) {
        // "#version 330 core" -> GLSL ES 3.00, with the precisions GLSL 3.30 leaves implicit
        // (ES has no default for floats in fragment shaders, nor for these samplers).
        src.replace(0, eol, "#version 300 es");
        eol = src.find('\n');
        prelude +=
            "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
            "precision highp samplerCube;\nprecision highp sampler2DArrayShadow;\n"
            "precision highp sampler2DArray;\n";
    }
    for (const std::string& d : defines) {
        prelude += "#define ";
        prelude += d;
        prelude += " 1\n";
    }
    if (eol == std::string::npos) src += '\n', eol = src.size() - 1;
    src.insert(eol + 1, prelude);
    return src;
}

GlShader compile_shader(unsigned kind, const std::vector<std::string>& paths,
                        const std::vector<std::string>& defines) {
    // One shader of several source strings (GLSL ES links one shader per stage): the first
    // file as shader_source() makes it, the others without their #version line, kept blank so
    // line numbers hold (the log's "N:line" counts the strings from 0).
    std::vector<std::string> sources;
    for (const std::string& path : paths) {
        std::string file;
        if (!read_file(path, &file)) throw std::runtime_error("cannot open shader '" + path + "'");
        if (sources.empty()) {
            sources.push_back(shader_source(std::move(file), defines, kGlslEs));
        } else {
            if (file.rfind("#version", 0) == 0) file.erase(0, file.find('\n'));
            sources.push_back(std::move(file));
        }
    }
    std::vector<const char*> texts;
    for (const std::string& src : sources) texts.push_back(src.c_str());
    GlShader shader = GlShader::adopt(glCreateShader(kind));
    glShaderSource(shader.id(), static_cast<GLsizei>(texts.size()), texts.data(), nullptr);
    glCompileShader(shader.id());
    GLint ok = 0;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(shader.id(), sizeof log, nullptr, log);
        std::string message;  // "shaders/preview.frag: 0:12(5): error: ..."
        for (const std::string& path : paths) message += (message.empty() ? "" : " + ") + path;
        message += ": ";
        message += log;
        throw std::runtime_error(message);
    }
    return shader;
}

GlProgram make_program(const std::string& dir, const std::string& vert, const std::string& frag,
                       const std::vector<std::string>& defines, const std::string& library) {
    const GlShader vs = compile_shader(GL_VERTEX_SHADER, {dir + "/" + vert}, defines);
    std::vector<std::string> fragment = {dir + "/" + frag};
    if (!library.empty()) fragment.push_back(dir + "/" + library);
    const GlShader fs = compile_shader(GL_FRAGMENT_SHADER, fragment, defines);
    GlProgram program = GlProgram::make();
    glAttachShader(program.id(), vs.id());
    glAttachShader(program.id(), fs.id());
    glLinkProgram(program.id());
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(program.id(), sizeof log, nullptr, log);
        std::string message = dir;
        message += "/{";
        message += vert;
        message += ",";
        message += frag;
        if (!library.empty()) message += "," + library;
        message += "}: link: ";
        message += log;
        throw std::runtime_error(message);
    }
    return program;  // the shaders are deleted here; the program keeps what it linked
}

int uniform(unsigned program, const std::string& name) {
    return glGetUniformLocation(program, name.c_str());
}

void set_vec3(unsigned program, const std::string& name, const Vec3& v) {
    glUniform3f(uniform(program, name), static_cast<float>(v.x), static_cast<float>(v.y),
                static_cast<float>(v.z));
}

void set_matrix(unsigned program, const char* name, const double m[4][4]) {
    float out[16];
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) out[col * 4 + row] = static_cast<float>(m[row][col]);
    glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, out);
}

std::string indexed(const char* name, int i) {
    // Built by appending: GCC 12 warns falsely (-Wrestrict) on "[" + std::to_string(i).
    std::string k = name;
    k += '[';
    k += std::to_string(i);
    k += ']';
    return k;
}

void set_sampling(unsigned target, int filter, int wrap) {
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, wrap);
    glTexParameteri(target, GL_TEXTURE_WRAP_R, wrap);
}

void ImageTexture::upload(const Image& img) {
    if (!texture) texture = GlTexture::make();
    const std::vector<uint8_t> bytes = to_bytes(img);  // as raytrace writes
    glBindTexture(GL_TEXTURE_2D, texture.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, img.width, img.height, 0, GL_RGB, GL_UNSIGNED_BYTE,
                 bytes.data());
    set_sampling(GL_TEXTURE_2D, GL_LINEAR, GL_CLAMP_TO_EDGE);
    w = img.width;
    h = img.height;
}

void RenderTarget::resize(int width, int height) {
    if (width == w && height == h && fbo) return;
    fbo.reset();
    color.reset();
    depth.reset();
    w = width;
    h = height;
    color = GlTexture::make();
    glBindTexture(GL_TEXTURE_2D, color.id());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    set_sampling(GL_TEXTURE_2D, GL_LINEAR, GL_CLAMP_TO_EDGE);
    depth = GlRenderbuffer::make();
    glBindRenderbuffer(GL_RENDERBUFFER, depth.id());
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    fbo = GlFramebuffer::make();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color.id(), 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth.id());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace rt::view
