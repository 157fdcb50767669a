#include "rt/image/diagnose.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rt/image/fit.h"

namespace rt {

const Image& MutantRenders::get(std::vector<std::string> mistakes) {
    std::sort(mistakes.begin(), mistakes.end());
    std::unique_ptr<Image>& image = m_images[mistakes];
    if (!image) image = std::make_unique<Image>(m_render(mistakes));
    return *image;
}

std::string Explanation::name() const {
    std::string s;
    for (const std::string& m : mistakes) s += (s.empty() ? "" : " + ") + m;
    return detail.empty() ? s : s + " (" + detail + ")";
}

std::string Diagnosis::summary() const {
    if (ranked.empty()) return "none of the known mistakes explains this image";
    std::string s;
    for (size_t i = 0; i < ranked.size(); ++i) {
        char share[48];
        std::snprintf(share, sizeof share, " (explains %.0f%%)", 100 * ranked[i].explained);
        s += (i ? "; " : "") + std::to_string(i + 1) + ". " + ranked[i].name() + share;
    }
    return s;
}

namespace {

// The mean squared difference of the 4x4 blocks' means, in 8-bit steps: a mistake whose
// difference is a speckle (no offset on secondary rays: acne) makes another pattern of specks
// in each renderer, the same darkening on average.
double block_error(const Image& a, const Image& b) {
    constexpr int kBlock = 4;
    const std::vector<uint8_t> x = to_bytes(a), y = to_bytes(b);
    double sum = 0;
    size_t n = 0;
    for (int by = 0; by < a.height; by += kBlock)
        for (int bx = 0; bx < a.width; bx += kBlock)
            for (size_t k = 0; k < 3; ++k) {
                double d = 0;
                int count = 0;
                for (int py = by; py < std::min(by + kBlock, a.height); ++py)
                    for (int px = bx; px < std::min(bx + kBlock, a.width); ++px) {
                        const size_t i = (size_t(py) * a.width + px) * 3 + k;
                        d += double(x[i]) - double(y[i]);
                        ++count;
                    }
                sum += (d / count) * (d / count);
                ++n;
            }
    return n ? sum / double(n) : 0.0;
}

// How much of the image's difference from the reference a mutant explains: the larger of the
// shares explained pixel by pixel and block by block.
struct Scorer {
    const Image& image;
    double before = 0, block_before = 0;
    double explained(const Image& mutant) const {
        const double pixels = 1.0 - mean_squared_bytes(mutant, image) / before;
        if (block_before <= 0) return pixels;
        return std::max(pixels, 1.0 - block_error(mutant, image) / block_before);
    }
};

// The global fits of `image` against `base` (the reference, or a mutant), each as an
// explanation that adds its change to `with` (the base's mistakes).
void add_fits(const Image& base, const Scorer& score, const std::vector<std::string>& with,
              double half_angle, std::vector<Explanation>* out) {
    const Image& image = score.image;
    for (const FitResult& f : fit_global(base, image)) {
        std::string name = f.name;
        if (f.fit.kind == FitKind::Zoom && half_angle > 0) {
            const std::string named =
                zoom_mistake(f.fit.value, half_angle, double(image.width) / image.height);
            if (!named.empty()) name = named;
        }
        Explanation e;
        e.mistakes = with;
        e.mistakes.push_back(name);
        // A fit the catalogue names by itself (gamma, bgr, flip-vertical) needs no parameter.
        e.detail = name == f.name && f.fit.kind != FitKind::FlipVertical &&
                           f.fit.kind != FitKind::FlipHorizontal && f.fit.kind != FitKind::Channels
                       ? f.detail
                       : "";
        e.mutant = apply_fit(base, f.fit);
        e.explained = score.explained(e.mutant);
        out->push_back(std::move(e));
    }
}

// Keeps the best explanation of each set of mistakes (a mutant render and a fit may both name
// gamma), best first.
void rank(std::vector<Explanation>* all) {
    std::stable_sort(all->begin(), all->end(), [](const Explanation& a, const Explanation& b) {
        return a.explained > b.explained;
    });
    std::vector<Explanation> kept;
    for (Explanation& e : *all) {
        std::vector<std::string> key = e.mistakes;
        std::sort(key.begin(), key.end());
        const bool seen = std::any_of(kept.begin(), kept.end(), [&](const Explanation& k) {
            std::vector<std::string> other = k.mistakes;
            std::sort(other.begin(), other.end());
            return other == key;
        });
        if (!seen) kept.push_back(std::move(e));
    }
    *all = std::move(kept);
}

}  // namespace

Diagnosis diagnose(const Image& image, MutantRenders& renders,
                   const std::vector<std::string>& catalogue, const DiagnoseSettings& settings) {
    Diagnosis d;
    const Image& reference = renders.get({});
    d.error_before = mean_squared_bytes(reference, image);
    if (d.error_before <= 0) return d;
    const Scorer score{image, d.error_before, block_error(reference, image)};
    std::vector<Explanation> singles;
    add_fits(reference, score, {}, settings.half_angle, &singles);
    for (const std::string& m : catalogue) {
        const Image& mutant = renders.get({m});
        if (mean_squared_bytes(reference, mutant) == 0) continue;  // changes nothing here
        Explanation e;
        e.mistakes = {m};
        e.mutant = mutant;
        e.explained = score.explained(mutant);
        singles.push_back(std::move(e));
    }
    rank(&singles);
    std::vector<Explanation> all = singles;
    // Two mistakes at once: the mutants that explain most, each with every other mistake and
    // every fit. A pair counts when it removes at least half of the error its better mistake
    // alone leaves (so a second mistake is not named for the noise of another renderer).
    if (!singles.empty() && singles[0].explained < settings.pair_below) {
        std::vector<Explanation> pairs;
        int tried = 0;
        for (const Explanation& first : singles) {
            const bool rendered =
                first.mistakes.size() == 1 && first.detail.empty() &&
                std::find(catalogue.begin(), catalogue.end(), first.mistakes[0]) != catalogue.end();
            if (!rendered) continue;  // a fit: paired through the mutants' fits
            if (tried++ >= settings.pair_candidates) break;
            add_fits(first.mutant, score, first.mistakes, settings.half_angle, &pairs);
            for (const std::string& m : catalogue) {
                if (m == first.mistakes[0]) continue;
                Explanation e;
                e.mistakes = {first.mistakes[0], m};
                e.mutant = renders.get(e.mistakes);
                e.explained = score.explained(e.mutant);
                pairs.push_back(std::move(e));
            }
        }
        for (Explanation& p : pairs) {
            double alone = 0;  // the best of its mistakes by itself
            for (const Explanation& s : singles)
                if (s.mistakes.size() == 1 && std::find(p.mistakes.begin(), p.mistakes.end(),
                                                        s.mistakes[0]) != p.mistakes.end())
                    alone = std::max(alone, s.explained);
            if (p.explained > alone + 0.5 * (1.0 - alone)) all.push_back(std::move(p));
        }
        rank(&all);
    }
    for (Explanation& e : all) {
        if (e.explained < settings.enough || int(d.ranked.size()) >= settings.ranked) break;
        d.ranked.push_back(std::move(e));
    }
    return d;
}

}  // namespace rt
