// raygen: writes a large .ray scene, a closed bumpy mesh of about N triangles, so users can try
// the renderer on a million triangles:  raygen --triangles 1000000 -o big.ray
#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "rt/scene/mesh_gen.h"
#include "rt/util/file_io.h"

int main(int argc, char** argv) {
    size_t n = 100000;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if ((a == "--triangles" || a == "-n") && i + 1 < argc) {
            const std::string v = argv[++i];
            const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
            if (r.ec != std::errc() || r.ptr != v.data() + v.size() || n < 8 || n > 100000000) {
                std::cerr << "raygen: --triangles needs a count between 8 and 1e8, got '" << v
                          << "'\n";
                return 2;
            }
        } else if ((a == "-o" || a == "--output") && i + 1 < argc) {
            out = argv[++i];
        } else if (a == "-h" || a == "--help") {
            std::cout
                << "usage: raygen --triangles N -o OUT.ray   (-n N is short for --triangles N)\n"
                   "Writes a V1 scene with a closed, bumpy mesh of about N triangles.\n";
            return 0;
        } else {
            std::cerr << "raygen: unknown argument '" << a << "' (see raygen --help)\n";
            return 2;
        }
    }
    if (out.empty()) {
        std::cerr << "raygen: no output file (-o OUT.ray)\n";
        return 2;
    }
    const rt::TriangleMesh mesh = rt::make_blob_mesh(n);
    const std::string text = rt::ray_text_for_mesh(mesh);
    try {
        rt::write_file_atomic(out, text);
    } catch (const std::exception& e) {
        std::cerr << "raygen: " << e.what() << "\n";
        return 1;
    }
    std::printf("wrote %s: %zu triangles, %zu vertices\n", out.c_str(), mesh.triangles.size(),
                mesh.positions.size());
    return 0;
}
