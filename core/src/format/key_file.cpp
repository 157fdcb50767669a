// The .key file grammar (spec §3.4): the DOF names, the duration, the frame count and the
// column-major matrices. The parser keeps frame 0 of each DOF for #joint_begin (spec §4.4).
#include <string>
#include <vector>

#include "format/parser_impl.h"

namespace rt::parser_impl {

// Spec §3.4: #DOFS n names #DURATION s #FRAMES f, then f*n column-major 4x4 blocks.
KeyFile ParserBase::parse_key_file(const std::string& text, const std::string& path) {
    FileState k(text, std::make_shared<const std::string>(path));
    KeyFile key;
    key.path = path;
    auto expect = [&](std::string_view name) {
        const Token t = k.lex.next();
        if (t.kind != TokenKind::Directive || t.text != name)
            fail(k.lex.loc(t), "expected " + std::string(name) + ", got " + describe(t));
        return t;
    };
    const Token dofs = expect("#DOFS");
    SourceLoc nloc;
    const int n = integer(k, dofs, "DOF count", &nloc);
    if (n <= 0) fail(nloc, "DOF count must be positive, got " + std::to_string(n));
    std::vector<std::string> names, exact;
    for (int i = 0; i < n; ++i) {
        const Token nt = k.lex.peek();
        exact.push_back(word(k, dofs, "a DOF name", true));
        // Spec §14.1: names equal as strings are an error; differing only in case is allowed.
        for (int j = 0; j < i; ++j)
            if (exact[static_cast<size_t>(j)] == exact.back())
                fail(k, nt, "duplicate DOF name " + quote(exact.back()));
        names.push_back(lower(exact.back()));
    }
    const Token dur = expect("#DURATION");
    const Token dur_tok = k.lex.peek();
    if (real(k, dur, 1) <= 0) fail(k, dur_tok, "duration must be positive");
    const Token frames = expect("#FRAMES");
    SourceLoc floc;
    const int nf = integer(k, frames, "frame count", &floc);
    if (nf <= 0) fail(floc, "frame count must be positive, got " + std::to_string(nf));
    const long long total = 16LL * n * nf;
    long long read = 0;
    for (int fr = 0; fr < nf; ++fr) {
        for (int j = 0; j < n; ++j) {
            Mat4 m(1.0);
            const Token first = k.lex.peek();
            for (int i = 0; i < 16; ++i, ++read) {
                const Token t = k.lex.next();
                double x = 0.0;
                bool nonfin = false;
                if (t.kind != TokenKind::Word || !parse_real(t.text, &x, &nonfin)) {
                    if (nonfin) fail(k.lex.loc(t), "non-finite number " + quote(t.text));
                    fail(k.lex.loc(t), "key file needs " + std::to_string(total) +
                                           " numbers (16 per DOF per frame), got " +
                                           std::to_string(read) + " then " + describe(t));
                }
                m[i / 4][i % 4] = x;  // column-major: GLM's own order
            }
            if (fr == 0) {
                // V3 (spec §14.1): numbers 4, 8, 12 and 16 are ignored.
                if (m_dialect == Dialect::V3) {
                    m[0][3] = m[1][3] = m[2][3] = 0.0;
                    m[3][3] = 1.0;
                }
                check_matrix(m, k.lex.loc(first), "key frame matrix");
                key.frame0[names[static_cast<size_t>(j)]] = m;
                key.frame0_exact[exact[static_cast<size_t>(j)]] = m;
            }
        }
    }
    const Token extra = k.lex.next();
    if (extra.kind != TokenKind::End)
        fail(k.lex.loc(extra), "key file has more than " + std::to_string(total) +
                                   " numbers: unexpected " + describe(extra));
    return key;
}

}  // namespace rt::parser_impl
