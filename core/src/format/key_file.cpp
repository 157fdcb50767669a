// The .key file grammar (spec §14.1) and the binding of a joint's name to a DOF of its file's key
// files (spec §14.2). Every key is kept: the scene description holds one KeyTrack per bound DOF,
// and a joint's matrix is its key 0 as read (the static render of spec §14.7).
#include <algorithm>
#include <string>
#include <vector>

#include "format/parser_impl.h"

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

}  // namespace

// Spec §14.1: #DOFS n names #DURATION s #FRAMES f, then f*n column-major 4x4 blocks, frame-major.
KeyFile ParserBase::parse_key_file(const std::string& text, const std::string& path) {
    FileState k(text, intern_file_name(path));
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
    if (n <= 0) fail(nloc, "#DOFS must be >= 1, got " + std::to_string(n));
    for (int i = 0; i < n; ++i) {
        const Token nt = k.lex.peek();
        std::string name = word(k, dofs, "a DOF name", true);
        // Spec §14.1: names equal as strings are an error; differing only in case is allowed.
        if (!key.by_name.try_emplace(name, key.names.size()).second)
            fail(k, nt, "duplicate DOF name " + quote(name));
        key.by_lower_name[lower(name)].push_back(key.names.size());
        key.names.push_back(std::move(name));
        key.name_locs.push_back(k.lex.loc(nt));
    }
    const Token dur = expect("#DURATION");
    const Token dur_tok = k.lex.peek();
    key.duration = real(k, dur, 1);
    if (key.duration <= 0) fail(k, dur_tok, "#DURATION must be > 0, got " + fmt(key.duration));
    const Token frames = expect("#FRAMES");
    SourceLoc floc;
    const int nf = integer(k, frames, "frame count", &floc);
    if (nf <= 0) fail(floc, "#FRAMES must be >= 1, got " + std::to_string(nf));
    if (16LL * n * nf > 1LL << 31)
        fail(floc, "key file too large: " + expected_count(n, nf) + " numbers");
    // Keys are added as they are read, each DOF's room reserved for no more frames than the rest
    // of the text can hold (a key is 16 numbers of at least 2 bytes each): a #FRAMES larger than
    // the file allocates nothing before the file runs out.
    const size_t frames_that_fit = (k.lex.remaining() + 1) / (32 * static_cast<size_t>(n));
    key.keys.resize(static_cast<size_t>(n));
    for (std::vector<Mat4>& dof_keys : key.keys)
        dof_keys.reserve(std::min(static_cast<size_t>(nf), frames_that_fit));
    key.track.assign(static_cast<size_t>(n), -1);
    long long read = 0;
    int not_affine = 0, singular = 0;
    SourceLoc first_not_affine, first_singular;
    for (int fr = 0; fr < nf; ++fr) {
        for (int j = 0; j < n; ++j) {
            Mat4& m = key.keys[static_cast<size_t>(j)].emplace_back();
            const SourceLoc first = k.lex.loc(k.lex.peek());
            for (int i = 0; i < 16; ++i, ++read) {
                const Token t = k.lex.next();
                double x = 0.0;
                bool nonfin = false;
                if (t.kind == TokenKind::Word && parse_real(t.text, &x, &nonfin)) {
                    m[i / 4][i % 4] = x;  // column-major: GLM's own order
                    continue;
                }
                if (nonfin) fail(k.lex.loc(t), "non-finite number " + quote(t.text));
                const std::string has = "key file has " + std::to_string(read) +
                                        " numbers after #FRAMES, expected " + expected_count(n, nf);
                if (t.kind == TokenKind::End) fail(k.lex.loc(t), has);
                fail(k.lex.loc(t), has + "; then " + describe(t));
            }
            // Spec §14.1: V3 ignores the bottom row; V0/V1 warn when it is not (0, 0, 0, 1).
            if (m_dialect != Dialect::V3 && !affine_bottom_row(m) && not_affine++ == 0)
                first_not_affine = first;
            m[0][3] = m[1][3] = m[2][3] = 0.0;
            m[3][3] = 1.0;
            if (singular_3x3(Mat3(m)) && singular++ == 0) first_singular = first;
        }
    }
    // More: the count of numbers when only numbers follow, else the first token that is not one.
    Token extra = k.lex.next();
    if (extra.kind != TokenKind::End) {
        const SourceLoc at = k.lex.loc(extra);
        long long more = 0;
        for (double x = 0; extra.kind != TokenKind::End; extra = k.lex.next(), ++more) {
            bool nonfin = false;
            if (extra.kind != TokenKind::Word || !parse_real(extra.text, &x, &nonfin))
                fail(k.lex.loc(extra), "unexpected " + describe(extra) + " after the " +
                                           expected_count(n, nf) + " numbers of the key file");
        }
        fail(at, "key file has " + std::to_string(read + more) +
                     " numbers after #FRAMES, expected " + expected_count(n, nf));
    }
    if (not_affine > 0)
        warn(first_not_affine, "key-not-affine",
             "key file: " + std::to_string(not_affine) + " key matri" +
                 (not_affine == 1 ? "x is" : "ces are") + " not affine; " +
                 (not_affine == 1 ? "its" : "their") + " bottom row is ignored");
    if (singular > 0)
        warn(first_singular, "key-singular",
             "key file: " + std::to_string(singular) + " key matri" +
                 (singular == 1 ? "x is" : "ces are") +
                 " singular; a joint is left out wherever its matrix is singular");
    return key;
}

// Spec §14.2: the DOF `name` among the file's key files (the first that has it wins; an exact
// match first, else one ignoring ASCII case, with a warning); its track in the scene.
int ParserBase::bind_dof(FileState& f, const Token& nt, const std::string& name) {
    KeyFile* hit = nullptr;
    size_t dof = 0;
    const std::string key = lower(name);
    for (KeyFile& k : f.key_files) {
        // The exact match, else every DOF that matches ignoring case (`here` the last of them).
        std::vector<size_t> similar;
        size_t here = 0;
        if (const auto exact = k.by_name.find(name); exact != k.by_name.end()) {
            here = exact->second;
        } else if (const auto folded = k.by_lower_name.find(key); folded != k.by_lower_name.end()) {
            similar = folded->second;
            here = similar.back();
        } else {
            continue;
        }
        if (hit) {
            warn(f.lex.loc(nt), "dof-repeat",
                 "DOF " + quote(k.names[here]) + " is also in " + quote(k.named) +
                     "; the first key file (" + quote(hit->named) + ") wins");
            continue;
        }
        if (similar.size() > 1) {
            std::string list;
            for (size_t s : similar) list += (list.empty() ? "" : ", ") + quote(k.names[s]);
            fail(f, nt,
                 "joint " + quote(name) + " matches several DOFs of " + quote(k.named) +
                     " when case is ignored: " + list);
        }
        hit = &k, dof = similar.empty() ? here : similar.front();
    }
    if (!hit) {
        std::string names;
        for (const KeyFile& k : f.key_files) names += (names.empty() ? "" : ", ") + k.named;
        fail(f, nt, "no DOF " + quote(name) + " in key files " + names);
    }
    if (hit->names[dof] != name)
        warn(f.lex.loc(nt), "joint-case",
             "joint " + quote(name) + " matches DOF " + quote(hit->names[dof]) +
                 " only when case is ignored");
    int& track = hit->track[dof];
    if (track < 0) {
        track = static_cast<int>(m_scene.tracks.size());
        KeyTrack t;
        t.name = hit->names[dof];
        t.duration = hit->duration;
        t.keys = hit->keys[dof];
        t.loc = f.lex.loc(nt);
        m_scene.tracks.push_back(std::move(t));
    }
    return track;
}

}  // namespace rt::parser_impl
