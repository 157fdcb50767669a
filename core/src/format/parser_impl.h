// What the three parts of the .ray parser share; private to core/src/format. ParserBase holds the
// one error path, the token helpers and the state of the whole file tree. The directives
// (parser.cpp) derive from it; its dialect pre-scan is in dialect.cpp and its .key grammar in
// key_file.cpp. The shared helpers are defined in parser.cpp.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "format/lexer.h"
#include "rt/format/parser.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"

namespace rt::parser_impl {

/// A token or path in a message: quoted, control bytes and invalid UTF-8 as \xNN, cut after 200
/// bytes.
std::string quote(std::string_view s);
/// "end of file" or the quoted token.
std::string describe(const Token& t);
/// Filesystem queries that never throw (a path too long or otherwise invalid is "not there").
bool is_file(const std::filesystem::path& p);
std::string canonical_path(const std::string& path);
std::string lower(std::string_view s);

// Limits of this reader (docs/format.md, "our choices"): they keep the recursion of every
// consumer of the group tree and the file tree shallow, and memory bounded by the input's size.
constexpr int kMaxGroupDepth = 10000;          // nested #group_begin/#joint_begin in one file
constexpr int kMaxIncludeDepth = 200;          // nested #ray_file includes
constexpr long long kMaxPlacements = 1 << 20;  // file copies placed in the world by instancing

// Items a #*_num count may declare.
enum CountKind { kLights, kTextures, kMaterials, kVertices, kRayFiles, kKeyFiles, kCountKinds };
inline constexpr std::array<const char*, kCountKinds> kCountDirective = {
    "#light_num", "#texture_num", "#material_num", "#vertex_num", "#ray_file_num", "#key_file_num"};
inline constexpr std::array<const char*, kCountKinds> kItemDirective = {
    "light", "#texture", "#material", "#vertex", "#ray_file", "#key_file"};

struct Count {
    bool declared = false;
    int declared_n = 0;
    SourceLoc loc;
    int found = 0;
};

struct KeyFile {
    std::string path;
    std::map<std::string, Mat4> frame0;  // lower-case DOF name -> matrix
};

// Per-file parse state.
struct FileState {
    Lexer lex;
    FileDesc desc;
    bool top = false;
    bool graph_started = false;
    std::array<Count, kCountKinds> counts{};
    std::vector<KeyFile> key_files;
    std::vector<GroupDesc*> stack;  // open groups; stack[0] = &desc.root
    std::vector<char> stack_is_joint;
    bool warned_joint_identity = false;
    std::string dir;  // directory of this file, for relative paths
    struct TextureRef {
        SourceLoc loc;
        int index;
    };
    std::vector<TextureRef> texture_refs;  // material texture indices, checked at end of file

    FileState(std::string_view text, std::shared_ptr<const std::string> name)
        : lex(text, std::move(name)) {}
};

class ParserBase {
protected:
    ParserBase(Diagnostics& diag, const ParseOptions& options) : m_diag(diag), m_options(options) {}

    // ---- errors: every parse error goes through here, with the include chain as notes ----
    [[noreturn]] void fail(const SourceLoc& loc, const std::string& message) const {
        std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
        throw SceneError(loc, message, std::move(chain));
    }
    [[noreturn]] void fail(const FileState& fs_, const Token& t, const std::string& message) const {
        fail(fs_.lex.loc(t), message);
    }

    // ---- token helpers (parser.cpp) ------------------------------------------------------
    SourceLoc arg_loc(FileState& f, const Token& dir, const Token& bad) const;
    double real(FileState& f, const Token& dir, int count);
    Vec3 vec3(FileState& f, const Token& dir, int count);
    int integer(FileState& f, const Token& dir, std::string_view what, SourceLoc* loc = nullptr);
    std::string word(FileState& f, const Token& dir, std::string_view what, bool ascii = false);
    Vec3 colour(FileState& f, const Token& dir, int count, std::string_view what);
    static std::string fmt(double v);
    static std::string fmt(const Vec3& v);

    // ---- counts, paths, matrices (parser.cpp) --------------------------------------------
    void declare_count(FileState& f, const Token& dir, CountKind k);
    void count_item(FileState& f, const Token& dir, CountKind k);
    std::string resolve(FileState& f, const Token& at, const std::string& path,
                        const std::string& what);
    void check_matrix(const Mat4& m, const SourceLoc& loc, const std::string& what);

    // ---- dialect detection (dialect.cpp) -------------------------------------------------
    void detect_dialect(const std::string& text, const std::string& name,
                        const std::string& canonical, const std::string& dir);
    const std::string* cached_text(const std::string& path, const std::string& canonical);

    // ---- key files (key_file.cpp) --------------------------------------------------------
    KeyFile parse_key_file(const std::string& text, const std::string& path);

    Diagnostics& m_diag;
    ParseOptions m_options;
    std::vector<SourceLoc> m_include_locs;       // #ray_file directives, outermost first
    std::map<std::string, std::string> m_texts;  // included files read, not yet parsed
    Dialect m_dialect = Dialect::V1;

private:
    static std::optional<std::string> find_file(const std::string& dir, const std::string& path);
    void prescan(const std::string& text, const std::string& name, const std::string& canonical,
                 const std::string& dir, std::vector<std::string>& visited);

    SourceLoc m_first_v0, m_first_v1;  // first material of each dialect (pre-scan)
    bool m_default_use = false;        // some shape uses material index -1
};

}  // namespace rt::parser_impl
