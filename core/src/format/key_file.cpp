// The .key file grammar (spec §14.1). Every key is kept: the SceneBuilder binds a joint's name
// to a DOF of its file's key files (spec §14.2) and makes one KeyTrack per bound DOF.
#include <algorithm>
#include <string>
#include <vector>

#include "format/grammar.h"

namespace rt::parser_impl {

namespace {

// "16·n·f = total", the count a key file's header asks for.
std::string expected_count(int n, int nf) {
    return "16\u00b7" + std::to_string(n) + "\u00b7" + std::to_string(nf) + " = " +
           std::to_string(16LL * n * nf);
}

bool affine_bottom_row(const Mat4& m) {
    return std::abs(m[0][3]) <= 1e-9 && std::abs(m[1][3]) <= 1e-9 && std::abs(m[2][3]) <= 1e-9 &&
           std::abs(m[3][3] - 1.0) <= 1e-9;
}

// Spec §14.1: #DOFS n names #DURATION s #FRAMES f; the DOFs' names into `key`; n and f.
std::pair<int, int> read_header(SceneBuilder& b, Lexer& lex, KeyFile& key) {
    auto expect = [&](std::string_view name) {
        const Token t = lex.next();
        if (name == "#DOFS" && t.kind != TokenKind::End && !printable_text(t.text))
            b.fail(lex.loc(t), not_text_message(key.path, "a .key file"));
        if (t.kind != TokenKind::Directive || t.text != name)
            b.fail(lex.loc(t), "expected " + std::string(name) + ", got " + describe(t));
        return t;
    };
    const Token dofs = expect("#DOFS");
    SourceLoc nloc;
    const int n = Directive{b, lex, dofs, false}.integer("DOF count", &nloc);
    if (n <= 0) b.fail(nloc, "#DOFS must be >= 1, got " + std::to_string(n));
    for (int i = 0; i < n; ++i) {
        const Token nt = lex.peek();
        std::string name = Directive{b, lex, dofs, false}.word("a DOF name", true);
        // Spec §14.1: names equal as strings are an error; differing only in case is allowed.
        if (!key.by_name.try_emplace(name, key.names.size()).second)
            b.fail(lex.loc(nt), "duplicate DOF name " + quote(name));
        key.by_lower_name[lower(name)].push_back(key.names.size());
        key.names.push_back(std::move(name));
        key.name_locs.push_back(lex.loc(nt));
    }
    const Token dur = expect("#DURATION");
    const Token dur_tok = lex.peek();
    key.duration = Directive{b, lex, dur, false}.real(1);
    if (key.duration <= 0)
        b.fail(lex.loc(dur_tok), "#DURATION must be > 0, got " + fmt(key.duration));
    const Token frames = expect("#FRAMES");
    SourceLoc floc;
    const int nf = Directive{b, lex, frames, false}.integer("frame count", &floc);
    if (nf <= 0) b.fail(floc, "#FRAMES must be >= 1, got " + std::to_string(nf));
    if (16LL * n * nf > 1LL << 31)
        b.fail(floc, "key file too large: " + expected_count(n, nf) + " numbers");
    return {n, nf};
}

// The keys' matrices that are not affine (V0/V1) and singular: how many, and the first.
struct Odd {
    int count = 0;
    SourceLoc first;
    void add(const SourceLoc& at) {
        if (count++ == 0) first = at;
    }
};

// Spec §14.1: f*n column-major 4x4 blocks, frame-major. The numbers read.
long long read_keys(SceneBuilder& b, Lexer& lex, KeyFile& key, int n, int nf, bool v3,
                    Odd& not_affine, Odd& singular) {
    long long read = 0;
    for (int fr = 0; fr < nf; ++fr) {
        for (int j = 0; j < n; ++j) {
            Mat4& m = key.keys[static_cast<size_t>(j)].emplace_back();
            const SourceLoc first = lex.loc(lex.peek());
            for (int i = 0; i < 16; ++i, ++read) {
                const Token t = lex.next();
                double x = 0.0;
                bool nonfin = false;
                if (t.kind == TokenKind::Word && parse_real(t.text, &x, &nonfin)) {
                    m[i / 4][i % 4] = x;  // column-major: GLM's own order
                    continue;
                }
                if (nonfin) b.fail(lex.loc(t), "non-finite number " + quote(t.text));
                const std::string has = "key file has " + std::to_string(read) +
                                        " numbers after #FRAMES, expected " + expected_count(n, nf);
                if (t.kind == TokenKind::End) b.fail(lex.loc(t), has);
                b.fail(lex.loc(t), has + "; then " + describe(t));
            }
            // Spec §14.1: V3 ignores the bottom row; V0/V1 warn when it is not (0, 0, 0, 1).
            if (!v3 && !affine_bottom_row(m)) not_affine.add(first);
            m[0][3] = m[1][3] = m[2][3] = 0.0;
            m[3][3] = 1.0;
            if (singular_3x3(Mat3(m))) singular.add(first);
        }
    }
    return read;
}

}  // namespace

KeyFile parse_key_file(SceneBuilder& b, const std::string& text, const std::string& path, bool v3) {
    Lexer lex(text, intern_file_name(path));
    KeyFile key;
    key.path = path;
    const auto [n, nf] = read_header(b, lex, key);
    // Keys are added as they are read, each DOF's room reserved for no more frames than the rest
    // of the text can hold (a key is 16 numbers of at least 2 bytes each): a #FRAMES larger than
    // the file allocates nothing before the file runs out.
    const size_t frames_that_fit = (lex.remaining() + 1) / (32 * static_cast<size_t>(n));
    key.keys.resize(static_cast<size_t>(n));
    for (std::vector<Mat4>& dof_keys : key.keys)
        dof_keys.reserve(std::min(static_cast<size_t>(nf), frames_that_fit));
    key.track.assign(static_cast<size_t>(n), -1);
    Odd not_affine, singular;
    const long long read = read_keys(b, lex, key, n, nf, v3, not_affine, singular);
    // More: the count of numbers when only numbers follow, else the first token that is not one.
    Token extra = lex.next();
    if (extra.kind != TokenKind::End) {
        const SourceLoc at = lex.loc(extra);
        long long more = 0;
        for (double x = 0; extra.kind != TokenKind::End; extra = lex.next(), ++more) {
            bool nonfin = false;
            if (extra.kind != TokenKind::Word || !parse_real(extra.text, &x, &nonfin))
                b.fail(lex.loc(extra), "unexpected " + describe(extra) + " after the " +
                                           expected_count(n, nf) + " numbers of the key file");
        }
        b.fail(at, "key file has " + std::to_string(read + more) +
                       " numbers after #FRAMES, expected " + expected_count(n, nf));
    }
    const auto matrices = [](int k) {
        return std::to_string(k) + " key matri" + (k == 1 ? "x is" : "ces are");
    };
    if (not_affine.count > 0)
        b.warn(not_affine.first, "key-not-affine",
               "key file: " + matrices(not_affine.count) + " not affine; " +
                   (not_affine.count == 1 ? "its" : "their") + " bottom row is ignored");
    if (singular.count > 0)
        b.warn(singular.first, "key-singular",
               "key file: " + matrices(singular.count) +
                   " singular; a joint is left out wherever its matrix is singular");
    return key;
}

}  // namespace rt::parser_impl
