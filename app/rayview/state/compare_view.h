// The comparison pane: an image (a student's render) beside the trace, which renders the
// reference at the image's size from the file's camera as raytrace renders it (the spec's
// sampling, `spp` samples per pixel); its views (theirs, ours, a heat map of the difference,
// the pixels off by more than the tolerance), its figures and the pixel probed. The comparison
// is rt/image/compare.h's, raycompare's. No GL.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "rt/image/compare.h"
#include "rt/image/image.h"

namespace rt::view {

/// What the comparison pane shows.
enum class CompareShow { Theirs, Ours, Difference, Threshold };
const char* compare_show_name(CompareShow s);

struct CompareView {
    std::string path;  // the image compared ("": no comparison)
    Image theirs;      // as read
    /// The tolerance and the neighbourhood; `linear` from the file's format (PFM, EXR).
    CompareSettings settings;
    int spp = 1;  // the reference's samples per pixel (raytrace --spp)
    CompareShow show = CompareShow::Difference;
    Image reference;       // the trace compared (linear), once it is done
    bool current = false;  // `reference` is the running trace's (false: one is rendering)
    std::optional<ImageComparison> result;  // of theirs against `reference`
    int probe_x = -1, probe_y = -1;         // the pixel clicked in the pane (-1: none)
    int version = 0;  // counts changes of what the pane shows, so it uploads again

    bool active() const { return !path.empty(); }
    /// Compares again (a new reference, or another tolerance or neighbourhood).
    void recompare();
    /// The pane's view; flip() swaps theirs and ours (from any other view: theirs), next_view()
    /// cycles the four.
    void set_show(CompareShow s) { show = s; }
    void flip() { show = show == CompareShow::Theirs ? CompareShow::Ours : CompareShow::Theirs; }
    void next_view() { show = static_cast<CompareShow>((static_cast<int>(show) + 1) % 4); }
    /// The tolerance in 8-bit steps and the 3x3 neighbourhood: compared again.
    void set_tolerance(double t) {
        settings.tolerance = t;
        recompare();
    }
    void set_neighbourhood(bool on) {
        settings.neighbourhood = on;
        recompare();
    }
};

/// The image the pane shows (`c.show`): theirs as read (a linear file and ours through the
/// display's exposure and tonemap), the heat map, or the threshold view. Empty before the
/// reference is done (except theirs).
Image compare_pane_image(const CompareView& c, float exposure, Tonemap tonemap);

/// The status bar's figures: the mean absolute difference, the share of pixels off by more than
/// the tolerance, the largest difference and where; what is awaited before that.
std::string compare_status(const CompareView& c);

/// Theirs and ours at pixel (x, y), in 8-bit steps as compared (linear files: 255 x the value),
/// and the difference counted there: "theirs (r g b), ours (r g b), off by d".
std::string compare_probe_text(const CompareView& c, int x, int y);

/// An image file rayview compares with (by its extension), not a scene to open.
bool is_image_path(const std::string& path);

/// Reads an image to compare with (load_image), or throws std::runtime_error saying why not in
/// words of the file: "'x' is a directory, not a regular file", "cannot open 'x': No such file
/// or directory", a decoder's message.
Image read_compare_image(const std::string& path);

/// Reads the image to compare with off the interface thread (a large EXR takes seconds): the
/// window stays interactive and the comparison starts when the image is read. A read started
/// while another is under way abandons that one (its thread ends in the background, its result
/// is dropped). Without threads (the single-thread web page) the image is read in start().
class CompareLoader {
public:
    CompareLoader() = default;
    ~CompareLoader();
    CompareLoader(const CompareLoader&) = delete;
    CompareLoader& operator=(const CompareLoader&) = delete;

    void start(const std::string& path);
    bool busy() const { return m_job != nullptr; }
    /// Once the read under way has ended: the path, and the image or why not (`error` not
    /// empty); false while it runs or when none runs.
    bool take(std::string* path, Image* image, std::string* error);

private:
    struct Job {
        std::string path;
        Image image;
        std::string error;
        std::atomic<bool> done{false};
        std::thread thread;
    };
    void reap();  // joins abandoned reads that have ended
    std::unique_ptr<Job> m_job;
    std::vector<std::unique_ptr<Job>> m_abandoned;
};

}  // namespace rt::view
