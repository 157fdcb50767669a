#include "rt/render/render.h"

#include <algorithm>
#include <array>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "camera_sample.h"
#include "parallel.h"
#include "rt/render/sampler.h"
#include "rt/util/limits.h"
#include "rt/util/threads.h"

namespace rt {

void RenderState::reset(int w, int h) {
    width = w;
    height = h;
    sum.assign(static_cast<size_t>(w) * h * 3, 0.0);
    sum_sq.assign(static_cast<size_t>(w) * h * 3, 0.0);
    sum_odd.assign(static_cast<size_t>(w) * h * 3, 0.0);
    odd_sums = true;
    samples.assign(static_cast<size_t>(w) * h, 0);
    active.clear();
    passes = 0;
    rays = {};
}

Image RenderState::image() const {
    Image img(width, height);
    for (size_t i = 0; i < samples.size(); ++i) {
        const double n = samples[i] > 0 ? samples[i] : 1;
        for (int c = 0; c < 3; ++c) img.rgb[i * 3 + c] = sum[i * 3 + c] / n;
    }
    return img;
}

int resolve_thread_count(int threads) {
    if (threads > 0) return std::min(threads, kMaxThreads);
    return static_cast<int>(std::min(hardware_threads(), static_cast<unsigned>(kMaxThreads)));
}

namespace {

// The settings of a render, before any work: a depth within kMaxDepth, and the plan's image size
// (a plan's camera is made for one size: rendering another would map its pixels wrongly).
void check_settings(const RenderPlan& plan, const RenderSettings& settings) {
    check_depth(settings.max_depth);
    if (plan.camera.width != settings.width || plan.camera.height != settings.height)
        throw std::invalid_argument("render plan made for " + std::to_string(plan.camera.width) +
                                    "x" + std::to_string(plan.camera.height) + ", rendered at " +
                                    std::to_string(settings.width) + "x" +
                                    std::to_string(settings.height));
}

constexpr int kTile = 16;

// A rectangle of pixels, [x0, x1) x [y0, y1).
struct PixelRect {
    int x0, y0, x1, y1;
};

// Tile `tile` of a grid of size x size tiles over the image, row-major.
PixelRect tile_rect(int tile, int size, const RenderSettings& settings) {
    const int tiles_x = (settings.width + size - 1) / size;
    const int x0 = (tile % tiles_x) * size, y0 = (tile / tiles_x) * size;
    return {x0, y0, std::min(x0 + size, settings.width), std::min(y0 + size, settings.height)};
}

int tile_count(int size, const RenderSettings& settings) {
    return ((settings.width + size - 1) / size) * ((settings.height + size - 1) / size);
}

// What every pixel of one render_samples() call shares.
struct Pass {
    const RenderScene& scene;
    const RenderPlan& plan;
    const RenderSettings& settings;
    bool stochastic;
};

// The sum and the sum of squares of a pixel's samples, and the sum of its odd-indexed samples.
struct PixelSums {
    Vec3 sum{0.0}, sum_sq{0.0}, odd{0.0};
};
PixelSums operator+(const PixelSums& a, const PixelSums& b) {
    return {a.sum + b.sum, a.sum_sq + b.sum_sq, a.odd + b.odd};
}

// A pixel's samples summed pairwise over the dyadic blocks of their indices: blocks
// [m 2^k, (m + 1) 2^k) are added as left half + right half, and the maximal blocks left over are
// folded from the right. The result depends only on which sample indices were summed, not on how
// they were split into calls or processes: a render split by sample ranges (RenderPart) merges
// into the very bits of the whole render.
class DyadicSum {
public:
    struct Block {
        uint32_t start = 0;
        int level = 0;  // the block is [start, start + 2^level)
        PixelSums v;
    };
    void clear() { m_n = 0; }
    /// Appends the block at the end of the indices summed so far (start = their end).
    void push(uint32_t start, int level, const PixelSums& v) {
        Block b{start, level, v};
        while (m_n > 0) {
            const Block& left = m_stack[static_cast<size_t>(m_n - 1)];
            const uint64_t size = uint64_t{1} << b.level;
            if (left.level != b.level || left.start % (2 * size) != 0 ||
                left.start + size != b.start)
                break;
            b = {left.start, b.level + 1, left.v + b.v};
            --m_n;
        }
        m_stack[static_cast<size_t>(m_n++)] = b;
    }
    PixelSums total() const {
        if (m_n == 0) return {};
        PixelSums t = m_stack[static_cast<size_t>(m_n - 1)].v;
        for (int i = m_n - 2; i >= 0; --i) t = m_stack[static_cast<size_t>(i)].v + t;
        return t;
    }
    int size() const { return m_n; }
    const Block& operator[](int i) const { return m_stack[static_cast<size_t>(i)]; }

private:
    std::array<Block, 66> m_stack;  // a range of 32-bit indices has at most 64 maximal blocks
    int m_n = 0;
};

// Which samples of a pixel one call renders: rng indices index0 .. index0 + count - 1, placed as
// strata strat_first .. of strat_n (spec §6.2; a render split by sample ranges places sample k of
// N where the whole render places it).
struct SampleSpan {
    uint32_t index0 = 0;
    int count = 0;
    int strat_first = 0, strat_n = 1;
};

PixelSums render_pixel(const Pass& pass, int x, int y, const SampleSpan& span, DyadicSum& acc,
                       RayCounters& rays) {
    const RenderSettings& settings = pass.settings;
    const size_t pixel = static_cast<size_t>(y) * settings.width + x;
    const int stratum = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(span.strat_n))));
    const std::array<Vec2, 2> shift = progressive_shifts(settings, pixel);
    // Only a single pass's one centre sample is deterministic (spec §13.9); every other sample
    // draws the random numbers of the features that take them, sphere lights among them.
    const bool random =
        pass.stochastic || span.strat_n > 1 || span.index0 > 0 || !settings.centre_first_sample;
    acc.clear();
    for (int s = 0; s < span.count; ++s) {
        // Every sample's random numbers come from (seed, pixel, index): any thread, same image.
        const uint32_t index = span.index0 + static_cast<uint32_t>(s);
        Rng rng(settings.seed, pixel, index);
        const Vec2 sample = sample_position(
            settings, pass.stochastic, span.strat_first + s, span.strat_n,
            span.index0 - static_cast<uint32_t>(span.strat_first), stratum, shift, rng);
        const Ray ray = camera_ray(pass.plan, settings, x, y, sample, rng);
        ++rays.camera;
        const Vec3 c = trace_ray(pass.scene, pass.plan, settings, ray, settings.max_depth,
                                 Vec3(1.0), rays, random ? &rng : nullptr);
        acc.push(index, 0, {c, c * c, (index & 1) ? c : Vec3(0.0)});
    }
    return acc.total();
}

// Where one render_samples() call writes its sums: the state's own sums (the first pass of a
// fresh state, whose sums are all zero) or the scratch buffer, committed when the pass completes.
struct PassOutput {
    double* sum;
    double* sum_sq;
    double* sum_odd;
    bool direct;
};

// One tile of a pass; false when a stop request was seen (within one pixel row: milliseconds even
// at many samples per pixel; the pass is then discarded).
bool render_tile(const Pass& pass, const RenderState& state, const PixelRect& r, int spp,
                 const PassOutput& out, const std::atomic<bool>* stop, RayCounters& rays) {
    const bool all_active = state.active.size() != state.samples.size();
    DyadicSum acc;
    for (int y = r.y0; y < r.y1; ++y) {
        if (stop && stop->load(std::memory_order_relaxed)) return false;
        for (int x = r.x0; x < r.x1; ++x) {
            const size_t pixel = static_cast<size_t>(y) * pass.settings.width + x;
            const int n = all_active ? spp : spp * state.active[pixel];
            PixelSums sums;  // zero: in place, the sums stay as they are
            if (n == 0 && out.direct) continue;
            if (n > 0) sums = render_pixel(pass, x, y, {state.samples[pixel], n, 0, n}, acc, rays);
            for (size_t c = 0; c < 3; ++c) {
                out.sum[pixel * 3 + c] = sums.sum[static_cast<int>(c)];
                out.sum_sq[pixel * 3 + c] = sums.sum_sq[static_cast<int>(c)];
                out.sum_odd[pixel * 3 + c] = sums.odd[static_cast<int>(c)];
            }
        }
    }
    return true;
}

// Adds a completed pass's sums and sample counts to the state.
void commit_pass(RenderState& state, const PassOutput& out, int spp) {
    const bool all_active = state.active.size() != state.samples.size();
    if (!out.direct) {
        for (size_t i = 0; i < state.sum.size(); ++i) {
            state.sum[i] += out.sum[i];
            state.sum_sq[i] += out.sum_sq[i];
            state.sum_odd[i] += out.sum_odd[i];
        }
    }
    for (size_t i = 0; i < state.samples.size(); ++i)
        state.samples[i] += static_cast<uint32_t>(all_active ? spp : spp * state.active[i]);
    ++state.passes;
}

}  // namespace

std::vector<std::pair<uint32_t, int>> dyadic_blocks(uint32_t first, uint32_t count) {
    std::vector<std::pair<uint32_t, int>> out;
    DyadicSum d;
    for (uint32_t i = 0; i < count; ++i) d.push(first + i, 0, {});
    for (int i = 0; i < d.size(); ++i) out.emplace_back(d[i].start, d[i].level);
    return out;
}

std::vector<RenderPart> tile_parts(int width, int height, int tile_w, int tile_h, uint32_t first,
                                   uint32_t count, uint32_t total) {
    std::vector<RenderPart> out;
    if (width <= 0 || height <= 0 || tile_w <= 0 || tile_h <= 0) return out;
    out.reserve(static_cast<size_t>((width + tile_w - 1) / tile_w) *
                static_cast<size_t>((height + tile_h - 1) / tile_h));
    for (int y = 0; y < height; y += tile_h)
        for (int x = 0; x < width; x += tile_w) {
            RenderPart& p = out.emplace_back();
            p.x0 = x, p.y0 = y;
            p.x1 = x + std::min(tile_w, width - x), p.y1 = y + std::min(tile_h, height - y);
            p.first = first, p.count = count, p.total = total;
        }
    return out;
}

bool render_part(RenderPart& part, const RenderScene& scene, const RenderPlan& plan,
                 const RenderSettings& settings, const ProgressFn& progress,
                 const std::atomic<bool>* stop) {
    check_settings(plan, settings);
    if (part.x0 < 0 || part.y0 < 0 || part.x1 > settings.width || part.y1 > settings.height ||
        part.x0 >= part.x1 || part.y0 >= part.y1)
        throw std::invalid_argument("the part's pixels lie outside the image");
    if (part.count == 0 || part.total == 0 || part.first >= part.total ||
        part.count > part.total - part.first)
        throw std::invalid_argument("the part's samples lie outside 0.." +
                                    std::to_string(part.total));
    const std::vector<std::pair<uint32_t, int>> shape = dyadic_blocks(part.first, part.count);
    part.blocks.assign(shape.size(), {});
    for (size_t b = 0; b < shape.size(); ++b) {
        part.blocks[b].start = shape[b].first;
        part.blocks[b].level = shape[b].second;
        part.blocks[b].sum.assign(3 * part.pixels(), 0.0);
        part.blocks[b].sum_sq.assign(3 * part.pixels(), 0.0);
        part.blocks[b].sum_odd.assign(3 * part.pixels(), 0.0);
    }
    const Pass pass{scene, plan, settings, settings.stochastic()};
    const SampleSpan span{part.first, static_cast<int>(part.count), static_cast<int>(part.first),
                          static_cast<int>(part.total)};
    const int w = part.x1 - part.x0, h = part.y1 - part.y0;
    const int tiles_x = (w + kTile - 1) / kTile, tiles = tiles_x * ((h + kTile - 1) / kTile);
    std::atomic<int> done_tiles{0};
    std::mutex progress_mutex;
    RayCounters rays;
    const bool done = parallel_tiles(
        resolve_thread_count(settings.threads), tiles, stop, rays,
        [&](int tile, RayCounters& counters) {
            const int tx = part.x0 + (tile % tiles_x) * kTile,
                      ty = part.y0 + (tile / tiles_x) * kTile;
            DyadicSum acc;
            for (int y = ty; y < std::min(ty + kTile, part.y1); ++y) {
                if (stop && stop->load(std::memory_order_relaxed)) return false;
                for (int x = tx; x < std::min(tx + kTile, part.x1); ++x) {
                    render_pixel(pass, x, y, span, acc, counters);
                    const size_t p = static_cast<size_t>(y - part.y0) * w + (x - part.x0);
                    for (int b = 0; b < acc.size(); ++b)
                        for (int c = 0; c < 3; ++c) {
                            part.blocks[static_cast<size_t>(b)].sum[p * 3 + c] = acc[b].v.sum[c];
                            part.blocks[static_cast<size_t>(b)].sum_sq[p * 3 + c] =
                                acc[b].v.sum_sq[c];
                            part.blocks[static_cast<size_t>(b)].sum_odd[p * 3 + c] =
                                acc[b].v.odd[c];
                        }
                }
            }
            const int n = ++done_tiles;
            if (progress) {
                std::lock_guard lock(progress_mutex);
                progress(n, tiles);
            }
            return true;
        });
    part.rays = rays;
    return done;
}

namespace {

// One part's block over one pixel, as merge_parts() gathers them.
struct Piece {
    uint32_t start;
    int level;
    uint32_t part, block;
};

// `p` is the piece that does not start where the samples before it end; `prev` the piece before
// it, which covers sample p->start too when they overlap.
std::string pieces_error(int x, int y, uint32_t expected, const Piece* p, const Piece* prev,
                         uint32_t total, const std::vector<std::string>& names) {
    auto name = [&](uint32_t k) {
        return k < names.size() ? names[k] : "part " + std::to_string(k);
    };
    std::string s = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): ";
    if (!p)
        return s + "samples " + std::to_string(expected) + ".." + std::to_string(total - 1) +
               " are in no part";
    if (!prev || p->start >= expected)
        return s + "samples " + std::to_string(expected) + ".." + std::to_string(p->start - 1) +
               " are in no part (" + name(p->part) + " starts at sample " +
               std::to_string(p->start) + ")";
    return s + "sample " + std::to_string(p->start) + " is in two parts (" + name(prev->part) +
           " and " + name(p->part) + ")";
}

// Pixel k's sums in a part's block (its odd samples' sum zero when the block has none: a part
// read from a file).
PixelSums block_sums(const RenderPart::Block& b, size_t k) {
    PixelSums v;
    const bool odd = !b.sum_odd.empty();
    for (int c = 0; c < 3; ++c) {
        v.sum[c] = b.sum[k * 3 + c], v.sum_sq[c] = b.sum_sq[k * 3 + c];
        v.odd[c] = odd ? b.sum_odd[k * 3 + c] : 0.0;
    }
    return v;
}

bool has_odd_sums(const RenderPart& part) {
    for (const RenderPart::Block& b : part.blocks)
        if (b.sum_odd.empty()) return false;
    return true;
}

}  // namespace

void add_part_samples(RenderState& state, const RenderPart& part) {
    if (part.x0 < 0 || part.y0 < 0 || part.x1 > state.width || part.y1 > state.height)
        throw std::invalid_argument("the part's pixels lie outside the image");
    DyadicSum acc;
    for (int y = part.y0; y < part.y1; ++y)
        for (int x = part.x0; x < part.x1; ++x) {
            const size_t k = static_cast<size_t>(y - part.y0) * (part.x1 - part.x0) + (x - part.x0);
            acc.clear();
            for (const RenderPart::Block& b : part.blocks)
                acc.push(b.start, b.level, block_sums(b, k));
            const PixelSums t = acc.total();
            const size_t i = static_cast<size_t>(y) * state.width + x;
            for (int c = 0; c < 3; ++c) {
                state.sum[i * 3 + c] += t.sum[c];
                state.sum_sq[i * 3 + c] += t.sum_sq[c];
                state.sum_odd[i * 3 + c] += t.odd[c];
            }
            state.samples[i] += part.count;
        }
    state.odd_sums = state.odd_sums && has_odd_sums(part);
    state.rays += part.rays;
}

RenderState merge_parts(const std::vector<const RenderPart*>& parts, int width, int height,
                        uint32_t total, const std::vector<std::string>& names) {
    // Every pixel's pieces, gathered by a counting sort (no vector per pixel).
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<uint32_t> offset(pixels + 1, 0);
    for (const RenderPart* p : parts) {
        if (p->x0 < 0 || p->y0 < 0 || p->x1 > width || p->y1 > height || p->total != total)
            throw std::invalid_argument(
                "a part of another image: its pixels or sample count differ");
        for (int y = p->y0; y < p->y1; ++y)
            for (int x = p->x0; x < p->x1; ++x)
                offset[static_cast<size_t>(y) * width + x + 1] +=
                    static_cast<uint32_t>(p->blocks.size());
    }
    for (size_t i = 0; i < pixels; ++i) offset[i + 1] += offset[i];
    std::vector<Piece> pieces(offset[pixels]);
    std::vector<uint32_t> fill(offset.begin(), offset.end() - 1);
    for (uint32_t pi = 0; pi < parts.size(); ++pi) {
        const RenderPart& p = *parts[pi];
        for (int y = p.y0; y < p.y1; ++y)
            for (int x = p.x0; x < p.x1; ++x)
                for (uint32_t b = 0; b < p.blocks.size(); ++b)
                    pieces[fill[static_cast<size_t>(y) * width + x]++] = {p.blocks[b].start,
                                                                          p.blocks[b].level, pi, b};
    }
    RenderState state;
    state.reset(width, height);
    DyadicSum acc;
    for (size_t i = 0; i < pixels; ++i) {
        Piece* first = pieces.data() + offset[i];
        Piece* last = pieces.data() + offset[i + 1];
        std::sort(first, last, [](const Piece& a, const Piece& b) {
            return a.start < b.start || (a.start == b.start && a.part < b.part);
        });
        const int x = static_cast<int>(i % static_cast<size_t>(width));
        const int y = static_cast<int>(i / static_cast<size_t>(width));
        acc.clear();
        uint32_t next = 0;  // the first sample not yet covered
        for (Piece* q = first; q != last; ++q) {
            if (q->start != next)
                throw std::invalid_argument(
                    pieces_error(x, y, next, q, q == first ? nullptr : q - 1, total, names));
            const RenderPart& p = *parts[q->part];
            const RenderPart::Block& blk = p.blocks[q->block];
            const size_t k = static_cast<size_t>(y - p.y0) * (p.x1 - p.x0) + (x - p.x0);
            acc.push(q->start, q->level, block_sums(blk, k));
            next = q->start + static_cast<uint32_t>(uint64_t{1} << q->level);
        }
        if (next != total)
            throw std::invalid_argument(pieces_error(x, y, next, nullptr, nullptr, total, names));
        const PixelSums t = acc.total();
        for (int c = 0; c < 3; ++c) {
            state.sum[i * 3 + c] = t.sum[c], state.sum_sq[i * 3 + c] = t.sum_sq[c];
            state.sum_odd[i * 3 + c] = t.odd[c];
        }
        state.samples[i] = total;
    }
    state.passes = 1;
    for (const RenderPart* p : parts) state.odd_sums = state.odd_sums && has_odd_sums(*p);
    for (const RenderPart* p : parts) state.rays += p->rays;
    return state;
}

Image render_coarse(const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int block, const std::atomic<bool>* stop) {
    check_settings(plan, settings);
    block = std::max(1, block);
    Image img(settings.width, settings.height);
    RayCounters rays;
    parallel_tiles(resolve_thread_count(settings.threads), tile_count(block, settings), stop, rays,
                   [&](int tile, RayCounters& counters) {
                       const PixelRect r = tile_rect(tile, block, settings);
                       // The block's centre, in pixel units; no Rng: deterministic.
                       const double cx = 0.5 * (r.x0 + r.x1), cy = 0.5 * (r.y0 + r.y1);
                       const int ix = static_cast<int>(cx), iy = static_cast<int>(cy);
                       const Ray ray = plan.camera.generate(ix, iy, cx - ix, cy - iy);
                       const Vec3 c = trace_ray(scene, plan, settings, ray, settings.max_depth,
                                                Vec3(1.0), counters);
                       for (int y = r.y0; y < r.y1; ++y)
                           for (int x = r.x0; x < r.x1; ++x) img.set(x, y, c);
                       return true;
                   });
    return img;
}

bool render_samples(RenderState& state, const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int spp, const ProgressFn& progress,
                    const std::atomic<bool>* stop) {
    check_settings(plan, settings);
    if (state.width != settings.width || state.height != settings.height)
        state.reset(settings.width, settings.height);
    if (spp <= 0) return true;
    const Pass pass{scene, plan, settings, settings.stochastic()};
    // New sums go to a scratch buffer and are committed only when the pass completes. The first
    // pass of a fresh state (all sums zero) writes the sums directly and, when stopped, puts the
    // zeros back: no scratch to fill, commit or fault in.
    const bool direct = state.passes == 0;
    const size_t n = state.sum.size();
    if (!direct) state.scratch.resize(3 * n);
    const PassOutput out{direct ? state.sum.data() : state.scratch.data(),
                         direct ? state.sum_sq.data() : state.scratch.data() + n,
                         direct ? state.sum_odd.data() : state.scratch.data() + 2 * n, direct};

    const int tiles_x = (settings.width + kTile - 1) / kTile;
    std::atomic<int> rows_done{0};
    std::mutex progress_mutex;
    RayCounters rays;
    const bool done = parallel_tiles(
        resolve_thread_count(settings.threads), tile_count(kTile, settings), stop, rays,
        [&](int tile, RayCounters& counters) {
            const PixelRect r = tile_rect(tile, kTile, settings);
            const bool finished = render_tile(pass, state, r, spp, out, stop, counters);
            // Progress by rows: the last tile of a tile row counts its rows.
            if (r.x1 == settings.width) rows_done += r.y1 - r.y0;
            if (progress && tile % tiles_x == 0) {
                std::lock_guard lock(progress_mutex);
                progress(rows_done.load(), settings.height);
            }
            return finished;
        });
    if (!done) {
        if (direct) {
            std::fill(state.sum.begin(), state.sum.end(), 0.0);
            std::fill(state.sum_sq.begin(), state.sum_sq.end(), 0.0);
            std::fill(state.sum_odd.begin(), state.sum_odd.end(), 0.0);
        }
        return false;
    }
    commit_pass(state, out, spp);
    state.rays += rays;
    if (progress) progress(settings.height, settings.height);
    return true;
}

Vec3 render_pixel_value(const RenderScene& scene, const RenderPlan& plan,
                        const RenderSettings& settings, int x, int y, int spp) {
    check_settings(plan, settings);
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height || spp < 1)
        throw std::invalid_argument("pixel " + std::to_string(x) + "," + std::to_string(y) +
                                    " or " + std::to_string(spp) + " samples out of range");
    const Pass pass{scene, plan, settings, settings.stochastic()};
    DyadicSum acc;
    RayCounters rays;
    const PixelSums sums = render_pixel(pass, x, y, {0, spp, 0, spp}, acc, rays);
    // As RenderState::image() divides the sums.
    return sums.sum / static_cast<double>(spp);
}

}  // namespace rt
