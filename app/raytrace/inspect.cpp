#include "inspect.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <new>
#include <stdexcept>

#include "rt/render/inspect.h"
#include "rt/render/plan.h"
#include "rt/util/file_io.h"

namespace raytrace {

namespace {

// The JSON file, written as it is made into a scratch file beside its name and renamed to it
// when complete: a run that fails leaves no file (and the old one, if any, as it was), and a
// SIGINT, SIGTERM or SIGHUP meanwhile removes the scratch file (rt/util/file_io.h).
class JsonOutput {
public:
    explicit JsonOutput(const std::string& path) : m_path(path) {
        if (path.empty()) return;
        int fd = -1;
        m_scratch = rt::create_scratch_file(path, &fd);
        ::close(fd);
        m_out.open(m_scratch, std::ios::binary | std::ios::trunc);
        if (!m_out) {
            const int e = errno;
            rt::discard_scratch_file(m_scratch);  // no destructor after a throwing constructor
            errno = e;
            fail();
        }
    }
    JsonOutput(const JsonOutput&) = delete;
    JsonOutput& operator=(const JsonOutput&) = delete;
    ~JsonOutput() {
        if (!m_scratch.empty()) rt::discard_scratch_file(m_scratch);
    }

    std::ostream* stream() { return m_path.empty() ? nullptr : &m_out; }

    void commit() {
        if (m_path.empty()) return;
        m_out.close();
        if (!m_out) fail();
        const std::string scratch = std::move(m_scratch);
        m_scratch.clear();
        rt::commit_scratch_file(scratch, m_path);  // or discards it and throws
    }

private:
    [[noreturn]] void fail() const {
        throw std::runtime_error("cannot write '" + m_path + "': " + std::strerror(errno));
    }

    std::string m_path, m_scratch;
    std::ofstream m_out;
};

}  // namespace

int run_inspect(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                const rt::CompileReport& report) {
    const rt::RenderPlan plan = rt::make_render_plan(scene, opt);
    const InspectOptions& in = opt.inspect;
    // A light number past the scene's: a usage error (exit 2), as a pixel outside the image.
    if (in.light && static_cast<size_t>(*in.light) >= scene.lights.size()) {
        std::cerr << "raytrace: --inspect-light " << *in.light << ": "
                  << (scene.lights.empty()
                          ? std::string("the scene has no lights")
                          : "the scene's lights are 0.." + std::to_string(scene.lights.size() - 1))
                  << "\n(see raytrace --help)\n";
        return 2;
    }
    rt::PixelTree tree =
        rt::inspect_pixel(scene, plan, opt, in.x, in.y, static_cast<uint32_t>(in.sample), opt.spp);
    if (in.depth || in.light)
        tree = rt::filter_tree(tree, {in.depth.value_or(0), in.light.value_or(-1)});
    const rt::InspectNames names{&desc, &report.prim_locs, &report.material_names};
    // The text first: when it cannot be written (a full disk, out of memory, a closed pipe's
    // SIGPIPE), no JSON file has been started.
    try {
        rt::inspect_text(std::cout, tree, scene, names);
        std::cout.flush();
        if (!std::cout) throw std::runtime_error("cannot write the tree to the standard output");
        JsonOutput json(in.json);
        if (std::ostream* out = json.stream()) rt::inspect_json(*out, tree, scene, names);
        json.commit();
    } catch (const std::bad_alloc&) {
        throw std::runtime_error("out of memory while formatting the ray tree of pixel " +
                                 std::to_string(in.x) + "," + std::to_string(in.y) + " of " +
                                 opt.scene);
    }
    if (!in.json.empty() && !opt.quiet) std::cout << "wrote     " << in.json << "\n";
    return 0;
}

}  // namespace raytrace
