// The grammar walks of the .ray dialects: one table of directives per dialect (V0/V1 in
// grammar_v1.cpp, V3 in grammar_v3.cpp), each entry reading its directive's arguments and
// handing the values, with their file:line:col, to the SceneBuilder, which holds what they
// mean. The readers of the directives both dialects share (#texture, #material, #vertex,
// #ray_file, #key_file, a shape's material index and numbers) are here, and so is the .key
// grammar (key_file.cpp). Private to core/src/format.
#pragma once

#include <string>
#include <string_view>

#include "format/parser_impl.h"
#include "format/scene_builder.h"

namespace rt::parser_impl {

/// One directive being read: its arguments, token by token, from the file's lexer. A missing
/// argument is an error at the directive, a bad one at itself (spec §2).
struct Directive {
    SceneBuilder& b;
    FileState& f;
    const Token& d;

    std::string_view name() const { return d.text; }
    SourceLoc loc() const { return f.lex.loc(d); }
    SourceLoc loc(const Token& t) const { return f.lex.loc(t); }
    /// Where the next argument is (the directive when there is none).
    SourceLoc next_loc() { return arg_loc(f.lex.peek()); }
    SourceLoc arg_loc(const Token& bad) const;
    [[noreturn]] void fail(const std::string& message) const { b.fail(loc(), message); }
    [[noreturn]] void fail(const Token& t, const std::string& message) const {
        b.fail(loc(t), message);
    }

    /// One of `count` numbers the directive takes.
    double real(int count);
    Vec3 vec3(int count);
    /// A colour: three numbers, none negative ("negative <what> -1").
    Vec3 colour(int count, std::string_view what);
    int integer(std::string_view what, SourceLoc* at = nullptr);
    /// A word (a path, a name); `ascii`: no byte above 0x7F.
    std::string word(std::string_view what, bool ascii = false);
};

/// The readers both dialects share.
namespace shared {
CameraDesc camera(Directive& d);  // the ten numbers of #camera
void texture(Directive& d);
void material(Directive& d);
void vertex(Directive& d);
void ray_file(Directive& d);
void key_file(Directive& d);
int material_index(Directive& d);
/// The three vertex indices of a triangle, each checked.
TriangleDesc triangle(Directive& d);
/// A shape's geometry after its material index: the numbers of #shape_<kind> (shapes.h), or a
/// triangle's indices. Whether it is kept (SceneBuilder::keep_shape).
bool shape(Directive& d, ShapeDesc& s);
}  // namespace shared

/// V0 and V1 (spec §3, §4).
class V1Grammar {
public:
    explicit V1Grammar(SceneBuilder& b) : m_b(b) {}
    void directive(FileState& f, const Token& d);
    void end_of_file(FileState& f, const SourceLoc& eof);

private:
    SceneBuilder& m_b;
};

/// V3 (spec §13): the three parts of a file, and the shapes part read with an explicit stack of
/// open constructs (FileState::v3), so deep nesting never recurses.
class V3Grammar {
public:
    explicit V3Grammar(SceneBuilder& b) : m_b(b) {}
    void directive(FileState& f, const Token& d);
    void end_of_file(FileState& f, const SourceLoc& eof);

private:
    SceneBuilder& m_b;
};

/// A .key file (spec §14.1): every key of every DOF; errors through `b` (with its include
/// chain).
KeyFile parse_key_file(SceneBuilder& b, const std::string& text, const std::string& path);

}  // namespace rt::parser_impl
