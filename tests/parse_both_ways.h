// A scene parsed serially and with its runs of mesh directives in pieces on several threads
// (ParseOptions::threads, core/src/format/mesh_runs.cpp), reduced to text to compare: the
// description field for field (the top file as the writer writes it, and every file's vertices,
// shapes, groups and their locations), the warnings in order, or the error. Shared by
// test_mesh_runs.cpp and the scene fuzz target.
#pragma once

#include <functional>
#include <string>

#include "rt/format/parser.h"
#include "rt/format/writer.h"
#include "rt/util/charconv.h"

namespace rt::both_ways {

// A number as text that reads back the same (rt/util/charconv.h), then a space.
inline std::string num(double v) {
    char b[40];
    const auto r = to_chars_shortest(b, b + sizeof b, v);
    return std::string(b, r.ptr) + " ";
}

inline void dump_group(const GroupDesc& g, std::string& out) {
    out += "group " + g.loc.str() + " " + g.joint + " " + std::to_string(g.track) + "\n";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out += num(g.matrix[c][r]);
    for (const ShapeDesc& s : g.shapes) {
        out += s.loc.str() + " m" + std::to_string(s.material) + " k" +
               std::to_string(s.geometry.index());
        if (const TriangleDesc* t = std::get_if<TriangleDesc>(&s.geometry))
            for (int v : t->v) out.append(" ").append(std::to_string(v));
        out += "\n";
    }
    for (const InstanceDesc& in : g.instances)
        out += "instance " + in.loc.str() + " " + std::to_string(in.ray_file) + "\n";
    for (const GroupDesc& c : g.groups) dump_group(c, out);
    for (const CsgDesc& c : g.csgs) {
        out += "csg " + c.loc.str() + " " + std::to_string(static_cast<int>(c.op)) + "\n";
        for (const GroupDesc& o : c.operands) dump_group(o, out);
    }
    out += "end\n";
}

/// What parsing gives, as text: the error, or the description and the warnings.
inline std::string outcome(const std::function<SceneDesc(Diagnostics&, const ParseOptions&)>& parse,
                           const ParseOptions& options) {
    Diagnostics diag;
    std::string out;
    try {
        const SceneDesc desc = parse(diag, options);
        try {
            out = write_scene(desc);
        } catch (const SceneError& e) {
            out = std::string("unwritable: ") + e.what() + "\n";
        }
        out += "skipped " + std::to_string(desc.skipped_shapes) + "\n";
        for (const FileDesc& f : desc.files) {
            out += "file " + f.path + " " + std::to_string(f.materials.size()) + " materials\n";
            for (const VertexDesc& v : f.vertices)
                out += num(v.position.x) + num(v.position.y) + num(v.position.z) + num(v.normal.x) +
                       num(v.normal.y) + num(v.normal.z) + num(v.uv.x) + num(v.uv.y) + "\n";
            dump_group(f.root, out);
        }
    } catch (const SceneError& e) {
        out = std::string("error: ") + e.what() + "\n";
    }
    for (const Warning& w : diag.warnings()) out += w.str() + "\n";
    return out;
}

/// The options of the serial parse and of one cut into the smallest pieces on three threads, every
/// included file parsed ahead.
inline ParseOptions serial(ParseOptions o) {
    o.threads = 1;
    return o;
}
inline ParseOptions in_pieces(ParseOptions o) {
    o.threads = 3;
    o.piece = 1;
    o.ahead = 0;  // every included file parsed ahead
    return o;
}

}  // namespace rt::both_ways
