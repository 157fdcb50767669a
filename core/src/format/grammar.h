// The grammar walks of the .ray dialects: one table of directives per dialect (V0/V1 in
// grammar_v1.cpp, V3 in grammar_v3.cpp), each entry reading its directive's arguments and
// handing the values, with their file:line:col, to the SceneBuilder, which holds what they
// mean. The readers of the directives both dialects share (#texture, #material, #vertex,
// #ray_file, #key_file, a shape's material index and numbers) are here, and so is the .key
// grammar (key_file.cpp). Private to core/src/format.
#pragma once

#include <string>
#include <string_view>

#include "format/lexer.h"
#include "format/parser_impl.h"
#include "format/scene_builder.h"

namespace rt::parser_impl {

/// One directive being read: its arguments, token by token, from the file's lexer, for the
/// builder. A missing argument is an error at the directive, a bad one at itself (spec §2).
struct Directive {
    SceneBuilder& b;
    Lexer& lex;
    const Token& d;
    bool top;  // in the tree's top-level file

    std::string_view name() const { return d.text; }
    SourceLoc loc() const { return lex.loc(d); }
    SourceLoc loc(const Token& t) const { return lex.loc(t); }
    /// Where the next argument is (the directive when there is none).
    SourceLoc next_loc() { return arg_loc(lex.peek()); }
    SourceLoc arg_loc(const Token& bad) const;
    [[noreturn]] void fail(const std::string& message) const { b.fail(loc(), message); }
    [[noreturn]] void fail(const Token& t, const std::string& message) const {
        b.fail(loc(t), message);
    }

    /// One of `count` numbers the directive takes.
    double real(int count);
    /// One of `count` numbers, and where it is (`at`).
    double real(int count, SourceLoc* at);
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
/// #shape_<kind> with a material index: the numbers of its kind (shapes.h), or a triangle's
/// indices (V0/V1).
void shape(Directive& d);
/// A spot light's cutoff and drop-off, the last of its `count` numbers.
void spot(Directive& d, LightDesc& l, int count);
}  // namespace shared

/// One directive of a V0/V1 file (spec §3, §4), read into the builder.
void read_v1(Directive& d);
/// One directive of a V3 file (spec §13): its part of the file, and the shapes part's lists.
/// `marker`: the tree's first V3 marker, for the error at a V0/V1 directive.
void read_v3(Directive& d, const std::string& marker);

/// A .key file (spec §14.1): every key of every DOF; errors through `b` (with its include
/// chain). In a V3 tree a key need not be affine.
KeyFile parse_key_file(SceneBuilder& b, const std::string& text, const std::string& path, bool v3);

}  // namespace rt::parser_impl
