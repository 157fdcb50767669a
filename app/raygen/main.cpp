// raygen: writes a large .ray scene, a closed bumpy mesh of about N triangles, so users can try
// the renderer on a million triangles:  raygen --triangles 1000000 -o big.ray
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string>

#include "cli.h"
#include "rt/scene/mesh_gen.h"
#include "rt/util/file_io.h"

int main(int argc, char** argv) {
    size_t n = 100000;
    std::string out;
    CLI::App app{"Writes a V1 scene with a closed, bumpy mesh of about N triangles."};
    rtapp::setup_cli(app, "raygen");
    app.option_defaults()->always_capture_default();
    app.add_option("-n,--triangles", n, "about this many triangles")
        ->type_name("N")
        ->check(CLI::Range(size_t{8}, size_t{100000000}));
    app.add_option("-o,--output", out, "the .ray file to write")->type_name("OUT.ray")->required();
    app.footer("exit status: 0 success, 1 the file cannot be written, 2 usage error.");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
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
