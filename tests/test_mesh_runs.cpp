// The parse of long mesh runs in pieces on several threads (core/src/format/mesh_runs.cpp): the
// same description, warnings and errors as the serial parse, on every scene we have and on
// meshes with errors and warnings placed in later pieces.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "parse_both_ways.h"
#include "rt/format/parser.h"
#include "rt/util/file_io.h"

namespace fs = std::filesystem;

namespace rt {
namespace {

std::string string_outcome(const std::string& text, const ParseOptions& options) {
    return both_ways::outcome(
        [&](Diagnostics& diag, const ParseOptions& o) {
            return parse_scene_string(text, "mesh.ray", diag, o);
        },
        options);
}

// A V1 strip of n triangles over n + 2 vertices, one directive per line (line k + 3 holds
// vertex k; the triangles follow), with `edit` applied to the text of each line.
std::string strip(int n, const std::function<std::string(int line, std::string)>& edit = {}) {
    std::vector<std::string> lines = {
        "#camera 0 0 5 0 0 -1 0 1 0 0.5",
        "#material 0 0 0 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 1 0 0 0 1 -1 !m!",
        "#vertex_num " + std::to_string(n + 2)};
    for (int k = 0; k < n + 2; ++k)
        lines.push_back("#vertex " + std::to_string(k / 2) + " " + std::to_string(k % 2) +
                        " 0 0 0 1 0 0");
    for (int k = 0; k < n; ++k)
        lines.push_back("#shape_triangle 0 " + std::to_string(k) + " " + std::to_string(k + 1) +
                        " " + std::to_string(k + 2));
    std::string text;
    for (size_t i = 0; i < lines.size(); ++i)
        text += (edit ? edit(static_cast<int>(i) + 1, lines[i]) : lines[i]) + "\n";
    return text;
}

// The outcome in pieces of `size` directives on `threads` threads, having checked that it is
// the serial one.
std::string same_both_ways(const std::string& text, unsigned threads = 3, size_t size = 1) {
    ParseOptions pieces;
    pieces.threads = threads;
    pieces.piece = size;
    const std::string serial = string_outcome(text, both_ways::serial({}));
    const std::string split = string_outcome(text, pieces);
    EXPECT_EQ(serial, split);
    return split;
}

TEST(MeshRuns, AStripInPiecesIsTheSerialStrip) {
    for (unsigned threads : {2u, 3u, 8u})
        for (size_t size : {1u, 7u, 100u}) {
            SCOPED_TRACE(std::to_string(threads) + " threads, pieces of " + std::to_string(size));
            const std::string out = same_both_ways(strip(1000), threads, size);
            EXPECT_EQ(out.find("error"), std::string::npos) << out.substr(0, 300);
            EXPECT_NE(out.find("mesh.ray:1006:1 m0 k"), std::string::npos);  // the 1000th
        }
}

TEST(MeshRuns, TheFirstErrorInFileOrderIsReported) {
    // A degenerate triangle early (a warning), then two errors in later pieces: the first wins.
    const std::string text = strip(600, [](int line, std::string s) {
        if (line == 700) return std::string("#shape_triangle 0 5 5 6");
        if (line == 900) return std::string("#shape_triangle 0 1 2 9999");
        if (line == 1100) return std::string("#shape_triangle 7 1 2 3");
        return s;
    });
    const std::string out = same_both_ways(text, 3, 50);
    EXPECT_NE(out.find("error: mesh.ray:900:23: error: vertex index 9999 out of range [0,602)"),
              std::string::npos)
        << out.substr(0, 400);
    EXPECT_NE(out.find("mesh.ray:700:1: warning: degenerate triangle skipped"), std::string::npos)
        << out.substr(0, 400);
}

TEST(MeshRuns, WarningsKeepTheirOrderAndCounts) {
    // Degenerate triangles in every piece: one warning of that kind with its count, the skipped
    // shapes counted, the others kept in order.
    const std::string text = strip(900, [](int line, std::string s) {
        if (line > 905 && line % 97 == 0) return std::string("#shape_triangle 0 3 3 4");
        return s;
    });
    const std::string out = same_both_ways(text, 4, 13);
    EXPECT_NE(out.find("skipped 9\n"), std::string::npos) << out.substr(out.size() - 300);
    EXPECT_NE(out.find("degenerate triangle skipped (9 times in this file)"), std::string::npos)
        << out.substr(out.size() - 300);
}

TEST(MeshRuns, VertexCountsHoldAcrossPieces) {
    // #vertex_num 502 with 503 vertices: the error at the one too many, in the last piece.
    std::string text = strip(500, [](int line, std::string s) {
        return line == 505 ? s + "\n#vertex 9 9 9 0 0 1 0 0" : s;
    });
    std::string out = same_both_ways(text, 3, 16);
    EXPECT_NE(out.find("mesh.ray:506:1: error: more #vertex than declared by #vertex_num at "
                       "mesh.ray:3:1"),
              std::string::npos)
        << out.substr(0, 300);
    // And one too few: reported at the end of the file, after every piece.
    text = strip(500, [](int line, std::string s) { return line == 3 ? "#vertex_num 503" : s; });
    out = same_both_ways(text, 3, 16);
    EXPECT_NE(out.find("#vertex_num at mesh.ray:3:1 declares 503, found 502"), std::string::npos)
        << out.substr(0, 300);
}

TEST(MeshRuns, BadTokensBetweenPiecesGiveTheSerialMessages) {
    // A #vertex one number short takes the next directive as its eighth number; one with a
    // number too many leaves a word where a directive should be; a string stops the run.
    for (const char* bad : {"#vertex 1 2 3 0 0 1 0", "#vertex 1 2 3 0 0 1 0 0 5",
                            "#vertex 1 2 3 0 0 1 0 0 !x!", "#vertex 1 2 3 0 0 1 0 nan"}) {
        SCOPED_TRACE(bad);
        for (int line : {10, 11, 12, 300}) {
            const std::string text =
                strip(400, [&](int l, std::string s) { return l == line ? bad : s; });
            const std::string out = same_both_ways(text, 3, 9);
            EXPECT_EQ(out.rfind("error: mesh.ray:", 0), 0u) << out.substr(0, 200);
        }
    }
}

// A V3 scene: 300 vertices, a sphere, a list of 298 triangles (six degenerate), then a second
// list, whose #shape_triangles is inside the first when `unclosed`.
std::string v3_scene(bool unclosed) {
    std::string text =
        "#camera 0 0 5 0 0 -1 0 1 0 0.5\n#light_point 0 0 0 1 1 1 1 1 1 0 0 5 1 0 0\n"
        "#material 0 0 0 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 1 0 0 0 1 -1 !m!\n";
    for (int k = 0; k < 300; ++k)
        text += "#vertex " + std::to_string(k / 2) + " " + std::to_string(k % 2) + " 0 0 0 1 0 0\n";
    text += "#shape_sphere 0 0 0 0 1\n#shape_triangles 0\n#shape_list_begin\n";
    for (int k = 0; k < 298; ++k)
        text += "#shape_triangle " + std::to_string(k) + " " + std::to_string(k + 1) + " " +
                std::to_string(k % 50 == 0 ? k : k + 2) + "\n";
    if (!unclosed) text += "#shape_list_end\n";
    text +=
        "#shape_triangles 0\n#shape_list_begin\n#shape_triangle 0 1 2\n"
        "#shape_triangle 1 2 3\n#shape_list_end\n";
    return text;
}

TEST(MeshRuns, V3TriangleListsAndVerticesInPieces) {
    const std::string out = same_both_ways(v3_scene(false), 3, 5);
    EXPECT_EQ(out.find("error"), std::string::npos) << out.substr(0, 300);
    EXPECT_NE(out.find("skipped 6\n"), std::string::npos);
    // A directive inside the list that only #shape_triangle may be in: the serial message.
    EXPECT_NE(same_both_ways(v3_scene(true), 3, 5).find("inside the list of #shape_triangles"),
              std::string::npos);
}

// Options that cut runs into pieces of `size` directives on `threads` threads and report to
// `progress`.
ParseOptions with_progress(unsigned threads, size_t size, ParseProgress* progress) {
    ParseOptions options;
    options.threads = threads;
    options.piece = size;
    options.progress = progress;
    return options;
}

TEST(MeshRuns, ProgressCountsEveryByteOnce) {
    const fs::path dir = fs::temp_directory_path() / "rt_mesh_runs_progress";
    fs::create_directories(dir);
    const std::string part = strip(3000, [](int line, std::string s) {
        return line == 1 ? "#camera 0 0 0 0 0 0 0 0 0 0" : s;  // a sub-file's dummy camera
    });
    const std::string top = strip(2000, [](int line, std::string s) {
        return line == 1 ? s + "\n#ray_file_num 1\n"
                               "#ray_file part.ray"
                         : s;
    });
    std::ofstream(dir / "part.ray") << part;
    std::ofstream(dir / "top.ray") << top;
    for (unsigned threads : {1u, 3u}) {
        SCOPED_TRACE(threads);
        ParseProgress progress;
        const ParseOptions options = with_progress(threads, 100, &progress);
        Diagnostics diag;
        const SceneDesc desc = parse_scene_file((dir / "top.ray").string(), diag, options);
        ASSERT_EQ(desc.files.size(), 2u);
        EXPECT_EQ(progress.total.load(), top.size() + part.size());
        EXPECT_EQ(progress.done.load(), progress.total.load());
    }
    fs::remove_all(dir);
}

TEST(MeshRuns, CancellingStopsTheParse) {
    const std::string text = strip(200000);
    for (unsigned threads : {1u, 2u}) {
        SCOPED_TRACE(threads);
        ParseProgress progress;
        const ParseOptions options = with_progress(threads, 1000, &progress);
        std::string error;
        std::thread parse([&] {
            try {
                Diagnostics diag;
                parse_scene_string(text, "mesh.ray", diag, options);
            } catch (const SceneError& e) {
                error = e.what();
            }
        });
        while (progress.done.load() == 0) std::this_thread::yield();
        progress.cancel = true;
        parse.join();
        EXPECT_NE(error.find(": error: loading cancelled"), std::string::npos) << error;
        EXPECT_LT(progress.done.load(), text.size());
    }
    // Cancelled before it starts: in the pre-scan.
    ParseProgress progress;
    progress.cancel = true;
    EXPECT_NE(
        string_outcome(text, with_progress(0, 16384, &progress)).find("error: loading cancelled"),
        std::string::npos);
}

// Included files parsed ahead, each on a thread of its own, and merged where the walk of the
// tree meets them: the files numbered, the key tracks made, the missing textures warned about
// once, the warnings and the first error (with their include chains) all in the serial order.
TEST(MeshRuns, IncludedFilesParsedAheadGiveTheSerialTree) {
    const fs::path dir = fs::temp_directory_path() / "rt_mesh_runs_ahead";
    fs::create_directories(dir);
    const auto write = [&](const char* name, const std::string& text) {
        std::ofstream(dir / name) << text;
    };
    const std::string identity = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n";
    write("k.key", "#DOFS 2 arm leg #DURATION 1 #FRAMES 1\n" + identity + identity);
    const std::string material = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 0 !t!\n";
    const std::string c_text = "#key_file k.key\n#texture missing.png\n" + material +
                               "#vertex 0 0 0 0 0 1 0 0\n#vertex 1 0 0 0 0 1 0 0\n"
                               "#vertex 2 0 0 0 0 1 0 0\n#shape_triangle 0 0 1 2\n"
                               "#joint_begin leg\n#shape_sphere 0 0 0 0 1\n#joint_end\n";
    write("c.ray", c_text);
    write("a.ray", "#ray_file c.ray\n#key_file k.key\n#texture missing.png\n" + material +
                       "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 -2 -1 !refind!\n"
                       "#joint_begin arm\n#ray_file_instance 0\n#joint_end\n");
    write("b.ray",
          "#ray_file a.ray\n#ray_file c.ray\n#ray_file_instance 0\n"
          "#ray_file_instance 1\n");
    write("top.ray",
          "#camera 0 0 5 0 0 -1 0 1 0 0.5\n#ray_file b.ray\n#ray_file a.ray\n"
          "#ray_file_instance 0\n#ray_file_instance 1\n");
    const auto both = [&](const char* what) {
        SCOPED_TRACE(what);
        ParseOptions options;
        options.missing_textures = MissingTextures::Checker;
        const auto parse = [&](Diagnostics& diag, const ParseOptions& o) {
            return parse_scene_file((dir / "top.ray").string(), diag, o);
        };
        ParseOptions ahead = options;
        ahead.threads = 3;
        ahead.ahead = 0;
        const std::string serial = both_ways::outcome(parse, both_ways::serial(options));
        EXPECT_EQ(serial, both_ways::outcome(parse, ahead));
        EXPECT_EQ(serial, both_ways::outcome(parse, both_ways::in_pieces(options)));
        return serial;
    };
    const std::string tree = both("a tree");
    EXPECT_EQ(tree.find("error"), std::string::npos) << tree;
    EXPECT_NE(tree.find("refractive index -2"), std::string::npos) << tree;
    EXPECT_NE(tree.find("included from"), std::string::npos) << tree;
    {
        ParseOptions ahead;
        ahead.threads = 3;
        ahead.ahead = 0;
        ahead.missing_textures = MissingTextures::Checker;
        Diagnostics diag;
        const SceneDesc desc = parse_scene_file((dir / "top.ray").string(), diag, ahead);
        ASSERT_EQ(desc.files.size(), 4u);  // top, b, a, c: in the order the walk meets them
        EXPECT_EQ(fs::path(desc.files[2].path).filename(), "a.ray");
        EXPECT_EQ(fs::path(desc.files[3].path).filename(), "c.ray");
        ASSERT_EQ(desc.tracks.size(), 2u);  // c's leg is bound first, then a's arm
        EXPECT_EQ(desc.tracks[0].name, "leg");
        EXPECT_EQ(desc.files[2].root.groups.at(0).track, 1);
        EXPECT_EQ(desc.missing_textures.size(), 1u);
        int missing = 0;
        for (const Warning& w : diag.warnings()) missing += w.kind == "missing-texture:missing.png";
        EXPECT_EQ(missing, 1);
    }
    // An error in the innermost file, then an include cycle: the serial messages.
    write("c.ray", c_text + "#shape_sphere 0 0 0 0 -1\n");
    EXPECT_NE(both("an error").find("error: negative sphere radius -1"), std::string::npos);
    write("c.ray", "#ray_file b.ray\n" + c_text);
    EXPECT_NE(both("a cycle").find("include cycle: b.ray -> a.ray -> c.ray -> b.ray"),
              std::string::npos);
    fs::remove_all(dir);
}

// Every scene of scenes/, ../shared/public-scenes and the scene fuzz corpus and crashers, with
// every run cut into pieces of one directive on three threads.
TEST(MeshRuns, EveryScenePartsTheSameWayInPieces) {
    int files = 0, loaded = 0;
    const auto check = [&](const fs::path& p, const std::string& text) {
        SCOPED_TRACE(p.string());
        ParseOptions options;
        options.missing_textures = MissingTextures::Checker;
        const auto parse = [&](Diagnostics& diag, const ParseOptions& o) {
            return text.empty() ? parse_scene_file(p.string(), diag, o)
                                : parse_scene_string(text, p.filename().string(), diag, o,
                                                     p.parent_path().string());
        };
        const std::string serial = both_ways::outcome(parse, both_ways::serial(options));
        EXPECT_EQ(serial, both_ways::outcome(parse, both_ways::in_pieces(options)));
        ++files;
        loaded += serial.rfind("error: ", 0) != 0;
    };
    for (const char* root : {RT_SOURCE_DIR "/scenes", RT_PUBLIC_SCENES_DIR})
        for (const auto& e : fs::recursive_directory_iterator(root))
            if (e.path().extension() == ".ray") check(e.path(), "");
    for (const char* dir : {"/tests/fuzz/corpus/scene", "/tests/fuzz/crashers/scene"})
        for (const auto& e : fs::directory_iterator(std::string(RT_SOURCE_DIR) + dir)) {
            std::string text, why;
            ASSERT_TRUE(read_file(e.path().string(), &text, &why)) << why;
            check(e.path(), text.empty() ? " " : text);
        }
    EXPECT_GT(files, 120);
    EXPECT_GT(loaded, 90);
}

}  // namespace
}  // namespace rt
