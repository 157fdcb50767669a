#include "state/compare_view.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <new>
#include <stdexcept>

#include "rt/util/file_io.h"
#include "rt/util/threads.h"

namespace rt::view {

const char* compare_show_name(CompareShow s) {
    switch (s) {
        case CompareShow::Theirs:
            return "theirs";
        case CompareShow::Ours:
            return "ours";
        case CompareShow::Difference:
            return "difference";
        case CompareShow::Threshold:
            return "threshold";
    }
    return "?";
}

void CompareView::recompare() {
    if (reference.width != theirs.width || reference.height != theirs.height || theirs.width == 0) {
        result.reset();
    } else {
        result = compare_images(theirs, reference, settings);
    }
    ++version;
}

Image compare_pane_image(const CompareView& c, float exposure, Tonemap tonemap) {
    switch (c.show) {
        case CompareShow::Theirs:
            return c.settings.linear ? display_transform(c.theirs, exposure, tonemap) : c.theirs;
        case CompareShow::Ours:
            return c.result ? display_transform(c.reference, exposure, tonemap) : Image();
        case CompareShow::Difference:
            return c.result ? heat_map(*c.result) : Image();
        case CompareShow::Threshold:
            return c.result ? threshold_map(*c.result, c.reference, c.settings.tolerance) : Image();
    }
    return {};
}

std::string compare_status(const CompareView& c) {
    const std::string name = std::filesystem::path(c.path).filename().string();
    if (!c.result) return "vs " + name + ": rendering the reference";
    const ImageComparison& r = *c.result;
    char line[256];
    std::snprintf(line, sizeof line,
                  "vs %s: mean |diff| %.2f (%.2f %.2f %.2f), %.2f%% off by > %g/255%s, "
                  "largest %.0f at %d,%d",
                  name.c_str(), r.mean(), r.mean_abs.x, r.mean_abs.y, r.mean_abs.z,
                  100.0 * r.share_off, c.settings.tolerance,
                  c.settings.neighbourhood ? " (3x3)" : "", r.max_diff, r.max_x, r.max_y);
    return c.current ? line : std::string(line) + " (rendering the reference again)";
}

std::string compare_probe_text(const CompareView& c, int x, int y) {
    if (!c.result || x < 0 || y < 0 || x >= c.theirs.width || y >= c.theirs.height) return "";
    auto steps = [&](const Vec3& v) {
        char s[64];
        if (c.settings.linear)
            std::snprintf(s, sizeof s, "%.1f %.1f %.1f", 255 * v.x, 255 * v.y, 255 * v.z);
        else
            std::snprintf(s, sizeof s, "%d %d %d", to_byte(v.x), to_byte(v.y), to_byte(v.z));
        return std::string(s);
    };
    const float d = c.result->error[static_cast<size_t>(y) * c.theirs.width + x];
    char off[64];
    std::snprintf(off, sizeof off, "%.1f", static_cast<double>(d));
    return "pixel " + std::to_string(x) + "," + std::to_string(y) + ": theirs (" +
           steps(c.theirs.at(x, y)) + "), ours (" + steps(c.reference.at(x, y)) + "), off by " +
           off + (c.settings.neighbourhood ? " (3x3)" : "");
}

bool is_image_path(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    for (const char* e : {".png", ".bmp", ".ppm", ".pfm", ".exr", ".jpg", ".jpeg"})
        if (ext == e) return true;
    return false;
}

Image read_compare_image(const std::string& path) {
    if (const std::string why = regular_file_error(path); !why.empty())
        throw std::runtime_error(why);
    try {
        return load_image(path);
    } catch (const std::bad_alloc&) {
        throw std::runtime_error("out of memory while reading '" + path + "'");
    }
}

CompareLoader::~CompareLoader() {
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
    for (auto& j : m_abandoned)
        if (j->thread.joinable()) j->thread.join();
}

void CompareLoader::start(const std::string& path) {
    reap();
    if (m_job) m_abandoned.push_back(std::move(m_job));
    m_job = std::make_unique<Job>();
    m_job->path = path;
    Job* job = m_job.get();
    auto read = [job] {
        try {
            job->image = read_compare_image(job->path);
        } catch (const std::exception& e) {
            job->error = e.what();
        }
        job->done = true;
    };
    if (have_threads())
        job->thread = std::thread(read);
    else
        read();
}

bool CompareLoader::take(std::string* path, Image* image, std::string* error) {
    reap();
    if (!m_job || !m_job->done) return false;
    if (m_job->thread.joinable()) m_job->thread.join();
    *path = std::move(m_job->path);
    *image = std::move(m_job->image);
    *error = std::move(m_job->error);
    m_job.reset();
    return true;
}

void CompareLoader::reap() {
    for (auto it = m_abandoned.begin(); it != m_abandoned.end();) {
        if ((*it)->done) {
            if ((*it)->thread.joinable()) (*it)->thread.join();
            it = m_abandoned.erase(it);
        } else {
            ++it;
        }
    }
}

}  // namespace rt::view
