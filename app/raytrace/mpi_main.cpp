// raytrace-mpi: raytrace across the ranks of an MPI job (`mpirun -n N raytrace-mpi SCENE
// [raytrace's options]`). Every rank loads the scene; rank 0 hands out tiles of the image to the
// workers as they ask (work pulling: uneven tiles and machines balance), gathers their sums, and
// writes the image, which is the one-process render's bit for bit (the parts merge as raymerge
// merges them). A worker that does not finish a tile in --tile-timeout seconds, a worker that
// cannot load the scene, or a job stopped because a rank died, is an error naming the rank (a dead
// one where its process can be looked for, on rank 0's host) and the tiles under way; no image is
// written then, and a sequence's frames written so far are removed.
#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cli.h"
#include "frames.h"
#include "options.h"
#include "output.h"
#include "reference_cache.h"
#include "report.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/util/stopwatch.h"
#include "version.h"

namespace {

using namespace raytrace;

// kTagError: a worker's failure (its scene does not load, a frame's animation fails), as text.
constexpr int kTagRequest = 1, kTagAssign = 2, kTagResult = 3, kTagError = 4;
constexpr int kTileSize = 32;
volatile std::sig_atomic_t g_stopped = 0;

// Rank 0's knowledge for the messages of a failed job: each rank's host and process id, and the
// frames of a sequence written so far (removed when the job fails).
struct RankInfo {
    char host[MPI_MAX_PROCESSOR_NAME] = {};
    int pid = 0;
};
std::vector<RankInfo> g_ranks;
rtapp::WrittenFrames g_written;

struct Job {
    Options opt;
    double tile_timeout_s = 600;
    rt::SceneDesc desc;
    std::optional<rt::RenderScene> scene;
    rt::RenderPlan plan;
    std::vector<rt::RenderPart> tiles;  // the work items: tiles of the image, or whole frames
    bool frames = false;                // --frames: item k is frame k
    rt::RenderSettings settings;        // what the workers render with (progressive: jittered)
    int frames_written = 0;
};

std::string tile_name(const Job& job, int t) {
    if (job.frames) return "frame " + std::to_string(t);
    const rt::RenderPart& p = job.tiles[static_cast<size_t>(t)];
    return "tile " + std::to_string(t) + " (pixels " + std::to_string(p.x0) + "," +
           std::to_string(p.y0) + ".." + std::to_string(p.x1 - 1) + "," + std::to_string(p.y1 - 1) +
           ")";
}

void make_tiles(Job& job) {
    const Options& o = job.opt;
    auto whole = [&] {
        rt::RenderPart p;
        p.x1 = o.width, p.y1 = o.height;
        p.count = p.total = static_cast<uint32_t>(o.spp);
        return p;
    };
    if (job.frames) {  // a sequence: each frame is one item, rendered whole by one worker
        job.tiles.assign(static_cast<size_t>(o.animation.frames), whole());
        return;
    }
    const auto spp = static_cast<uint32_t>(o.spp);
    job.tiles = rt::tile_parts(o.width, o.height, kTileSize, kTileSize, 0, spp, spp);
}

// A finished tile as one message: its blocks' sums and sums of squares (and for --progressive
// their sums of odd samples, for the error estimate), then the ray counts.
std::vector<double> pack(const rt::RenderPart& p, bool odd) {
    std::vector<double> out;
    for (const rt::RenderPart::Block& b : p.blocks) {
        out.insert(out.end(), b.sum.begin(), b.sum.end());
        out.insert(out.end(), b.sum_sq.begin(), b.sum_sq.end());
        if (odd) out.insert(out.end(), b.sum_odd.begin(), b.sum_odd.end());
    }
    for (uint64_t r : {p.rays.camera, p.rays.shadow, p.rays.reflected, p.rays.refracted})
        out.push_back(static_cast<double>(r));
    return out;
}

void unpack(const std::vector<double>& in, rt::RenderPart& p, bool odd) {
    size_t at = 0;
    p.blocks.clear();
    for (const auto& [start, level] : rt::dyadic_blocks(p.first, p.count)) {
        rt::RenderPart::Block b;
        b.start = start, b.level = level;
        std::vector<std::vector<double>*> fields = {&b.sum, &b.sum_sq};
        if (odd) fields.push_back(&b.sum_odd);
        for (std::vector<double>* v : fields) {
            v->assign(in.begin() + static_cast<long>(at),
                      in.begin() + static_cast<long>(at + 3 * p.pixels()));
            at += 3 * p.pixels();
        }
        p.blocks.push_back(std::move(b));
    }
    p.rays.camera = static_cast<uint64_t>(in[at]);
    p.rays.shadow = static_cast<uint64_t>(in[at + 1]);
    p.rays.reflected = static_cast<uint64_t>(in[at + 2]);
    p.rays.refracted = static_cast<uint64_t>(in[at + 3]);
}

size_t packed_size(const rt::RenderPart& p, bool odd) {
    return (odd ? 9 : 6) * p.pixels() * rt::dyadic_blocks(p.first, p.count).size() + 4;
}

// --tile-timeout's limit: a week.
constexpr double kMaxTileTimeout = 7 * 24 * 3600;

// --tile-timeout's seconds; NaN (refused with the usage error) unless the whole text is a
// number.
double parse_tile_timeout(const char* text) {
    char* end = nullptr;
    const double s = std::strtod(text, &end);
    return end != text && *end == '\0' ? s : std::nan("");
}

// Tests inject faults: RT_MPI_FAULT=die:RANK:K or hang:RANK:K, at the rank's K-th tile (from 0).
void maybe_fault(int rank, int nth) {
    const char* f = std::getenv("RT_MPI_FAULT");
    if (!f) return;
    char kind[8] = {};
    int r = -1, t = -1;
    if (std::sscanf(f, "%7[a-z]:%d:%d", kind, &r, &t) != 3 || r != rank || t != nth) return;
    if (std::string(kind) == "die") std::_Exit(3);
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));  // hang
}

// A worker's failure, for rank 0 to stop the job with ("rank N " + text).
void send_error(const std::string& text) {
    MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kTagError, MPI_COMM_WORLD);
}

// After a worker's error: rank 0 ends the job with MPI_Abort. A rank that finalized meanwhile
// could leave mpirun waiting for ever (seen with OpenMPI 4.1: every rank gone, mpirun still
// there), so the worker waits for the abort, taking whatever rank 0 still sends.
void await_abort() {
    for (;;) {
        MPI_Status st;
        MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
        int count = 0;
        MPI_Get_count(&st, MPI_BYTE, &count);
        std::vector<char> ignored(static_cast<size_t>(std::max(count, 1)));
        MPI_Recv(ignored.data(), count, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
}

void worker(Job& job, int rank) {
    const int ready = 1;
    MPI_Send(&ready, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD);
    for (int nth = 0;; ++nth) {
        int msg[4] = {-1, 0, 0, 0};  // item, first sample, count, total
        MPI_Recv(msg, 4, MPI_INT, 0, kTagAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        const int t = msg[0];
        if (t < 0) return;
        maybe_fault(rank, nth);
        rt::RenderPart& p = job.tiles[static_cast<size_t>(t)];
        p.first = static_cast<uint32_t>(msg[1]);
        p.count = static_cast<uint32_t>(msg[2]);
        p.total = static_cast<uint32_t>(msg[3]);
        if (job.frames) {  // the joints to frame t's time, and a plan for it
            try {
                rt::animate(*job.scene, job.desc, job.opt.animation.time(t));
            } catch (const std::exception& e) {  // rank 0 stops the job, and removes the frames
                send_error("failed at frame " + std::to_string(t) + ": " +
                           rtapp::error_text(e, "moving its joints"));
                await_abort();
                return;
            }
            job.plan = rt::make_render_plan(*job.scene, job.opt);
        }
        rt::render_part(p, *job.scene, job.plan, job.settings);
        const std::vector<double> data = pack(p, job.opt.progressive.enabled);
        MPI_Send(data.data(), static_cast<int>(data.size()), MPI_DOUBLE, 0, kTagResult,
                 MPI_COMM_WORLD);
        p.blocks.clear();
    }
}

[[noreturn]] void abort_job(const std::string& why) {
    // A sequence: nothing of a failed job stays (as raytrace --frames).
    const std::string outcome = g_written.count() > 0 ? g_written.remove_all() : "no image written";
    std::cerr << "raytrace-mpi: error: " << why << "; " << outcome << "\n";
    std::fflush(stderr);
    // mpirun forwards our stderr through a pipe it stops reading once the job aborts: under load
    // the message was lost (the test's "a worker's load error is printed with its rank", once).
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    MPI_Abort(MPI_COMM_WORLD, 1);
    std::_Exit(1);
}

// A sequence's frame, written as soon as it arrives (atomically, as raytrace --frames does).
void write_frame(Job& job, int k) {
    rt::RenderPart& p = job.tiles[static_cast<size_t>(k)];
    const rt::RenderState state = rt::merge_parts({&p}, job.opt.width, job.opt.height, p.total);
    const std::string path = rtapp::frame_path(job.opt.output, k);
    try {
        write_outputs(state.image(), path, {}, job.opt.scene,
                      ExrOutput{job.opt.exr.full_float, {}});
    } catch (const std::exception& e) {  // a full disk: the frames written so far go too
        abort_job("frame " + std::to_string(k) + " not written (" +
                  rtapp::error_text(e, "writing it") + ")");
    }
    g_written.add(path);
    p.blocks.clear();
    ++job.frames_written;
}

struct Assignment {
    int tile = -1;
    rt::Clock::time_point since;
};

// The workers whose process is gone, of those on rank 0's host (the others cannot be looked at
// from here: mpirun's own message names them).
std::string gone_ranks() {
    std::string s;
    for (size_t r = 1; r < g_ranks.size(); ++r)
        if (std::strcmp(g_ranks[r].host, g_ranks[0].host) == 0 && g_ranks[r].pid > 0 &&
            ::kill(g_ranks[r].pid, 0) != 0 && errno == ESRCH)
            s += (s.empty() ? "" : ", ") + std::string("rank ") + std::to_string(r) + " (pid " +
                 std::to_string(g_ranks[r].pid) + ")";
    return s;
}

// The ranks and tiles under way, for the messages of a failed job.
std::string under_way(const Job& job, const std::vector<Assignment>& work) {
    std::string s;
    for (size_t r = 1; r < work.size(); ++r)
        if (work[r].tile >= 0)
            s += (s.empty() ? "" : ", ") + std::string("rank ") + std::to_string(r) + " had " +
                 tile_name(job, work[r].tile);
    return s.empty() ? "no tile was under way" : s;
}

// Rank 0's side: hands out work items to the ranks that ask, takes their results, watches the
// time. A rank asks once at the start and then with each result; between passes of a
// progressive run it waits for the next pass.
class Master {
public:
    Master(Job& job, int ranks, double* bytes)
        : m_job(job),
          m_ranks(ranks),
          m_bytes(bytes),
          m_work(static_cast<size_t>(ranks), Assignment{-2, rt::Clock::now()}) {}

    // Every item of job.tiles (their samples as set there), returned once every result is in;
    // on_result(t) after each.
    void run_items(const std::function<void(int)>& on_result) {
        const int total = static_cast<int>(m_job.tiles.size());
        int next = 0, done = 0;
        const rt::ProgressFn bar = m_job.opt.progressive.enabled
                                       ? rt::ProgressFn{}
                                       : terminal_progress_bar(m_job.opt.quiet);
        auto give = [&](int rank) {
            if (next >= total) return m_idle.push_back(rank);
            const int t = next++;
            const rt::RenderPart& p = m_job.tiles[static_cast<size_t>(t)];
            const int msg[4] = {t, static_cast<int>(p.first), static_cast<int>(p.count),
                                static_cast<int>(p.total)};
            MPI_Send(msg, 4, MPI_INT, rank, kTagAssign, MPI_COMM_WORLD);
            m_work[static_cast<size_t>(rank)] = {t, rt::Clock::now()};
        };
        std::vector<int> idle = std::move(m_idle);
        m_idle.clear();
        for (int r : idle) give(r);
        while (done < total) {
            const std::optional<MPI_Status> st = poll();
            if (!st) continue;
            if (st->MPI_TAG == kTagRequest) {
                int ready = 0;
                MPI_Recv(&ready, 1, MPI_INT, st->MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
            } else {
                on_result(receive(*st));
                if (bar)
                    bar(++done, total);
                else
                    ++done;
            }
            m_work[static_cast<size_t>(st->MPI_SOURCE)].tile = -1;
            give(st->MPI_SOURCE);
        }
    }

    // Tells every worker to stop, once each has asked.
    void finish() {
        while (static_cast<int>(m_idle.size()) < m_ranks - 1) {
            const std::optional<MPI_Status> st = poll();
            if (!st) continue;
            int ready = 0;
            MPI_Recv(&ready, 1, MPI_INT, st->MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            m_work[static_cast<size_t>(st->MPI_SOURCE)].tile = -1;
            m_idle.push_back(st->MPI_SOURCE);
        }
        const int msg[4] = {-1, 0, 0, 0};
        for (int r : m_idle) MPI_Send(msg, 4, MPI_INT, r, kTagAssign, MPI_COMM_WORLD);
        m_idle.clear();
    }

private:
    // A message, or none after checking the time limits (and a short sleep).
    std::optional<MPI_Status> poll() {
        if (g_stopped) {
            const std::string gone = gone_ranks();
            abort_job("the job was stopped: " +
                      (gone.empty() ? std::string("a rank died or was killed") : gone + " died") +
                      "; under way: " + under_way(m_job, m_work));
        }
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (flag && st.MPI_TAG == kTagError) {
            int count = 0;
            MPI_Get_count(&st, MPI_CHAR, &count);
            std::string text(static_cast<size_t>(count), '\0');
            MPI_Recv(text.data(), count, MPI_CHAR, st.MPI_SOURCE, kTagError, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            abort_job("rank " + std::to_string(st.MPI_SOURCE) + " " + text);
        }
        if (flag) return st;
        const double limit = m_job.tile_timeout_s;
        char secs[32];
        std::snprintf(secs, sizeof secs, "%g", limit);
        for (int r = 1; r < m_ranks; ++r) {
            const Assignment& a = m_work[static_cast<size_t>(r)];
            if (a.tile == -2 && rt::seconds_since(a.since) > limit)
                abort_job("rank " + std::to_string(r) + " did not ask for a tile within " +
                          std::string(secs) + " s (--tile-timeout): it could not load the scene?");
            if (a.tile >= 0 && rt::seconds_since(a.since) > limit)
                abort_job("rank " + std::to_string(r) + " did not finish " +
                          tile_name(m_job, a.tile) + " within " + std::string(secs) +
                          " s (--tile-timeout)");
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        return std::nullopt;
    }

    int receive(const MPI_Status& st) {
        const int t = m_work[static_cast<size_t>(st.MPI_SOURCE)].tile;
        int count = 0;
        MPI_Get_count(&st, MPI_DOUBLE, &count);
        const bool odd = m_job.opt.progressive.enabled;
        const size_t want = t >= 0 ? packed_size(m_job.tiles[static_cast<size_t>(t)], odd) : 0;
        if (t < 0 || static_cast<size_t>(count) != want)
            abort_job("rank " + std::to_string(st.MPI_SOURCE) + " sent a result of " +
                      std::to_string(count) + " numbers for " +
                      (t < 0 ? std::string("no tile") : tile_name(m_job, t)));
        std::vector<double> data(want);
        MPI_Recv(data.data(), count, MPI_DOUBLE, st.MPI_SOURCE, kTagResult, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        unpack(data, m_job.tiles[static_cast<size_t>(t)], odd);
        *m_bytes += static_cast<double>(data.size() * sizeof(double));
        return t;
    }

    Job& m_job;
    int m_ranks;
    double* m_bytes;
    std::vector<Assignment> m_work;  // [rank]: -2 not asked yet, -1 idle, else its item
    std::vector<int> m_idle;         // ranks waiting for an item
};

// Every rank loads the scene; rank 0 alone prints its warnings and errors. A worker that fails
// where rank 0 did not (another file system, say) sends its error to rank 0, which stops the job
// with it.
bool load(Job& job, int rank) {
    const Options& opt = job.opt;
    rt::Diagnostics diag;
    try {
        rt::ParseOptions po;
        po.dialect = opt.dialect;
        po.missing_textures = opt.missing_textures;
        po.threads = static_cast<unsigned>(opt.threads);
        job.desc = rt::parse_scene_file(opt.scene, diag, po);
        job.scene = rt::compile_scene_releasing(job.desc, nullptr, opt.animation.time(), &diag,
                                                static_cast<unsigned>(opt.threads));
    } catch (const std::exception& e) {  // a SceneError, or out of memory
        if (rank == 0) {
            std::cerr << e.what() << "\n";
        } else {
            // Exiting now could let mpirun stop rank 0 before it reads and prints the error.
            send_error(std::string("could not load the scene: ") + e.what());
            await_abort();
        }
        return false;
    }
    if (rank == 0)
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
    return true;
}

void print_summary(const Job& job, int ranks, double seconds, double bytes) {
    rt::RayCounters rays;
    for (const rt::RenderPart& p : job.tiles) rays += p.rays;
    Timings t;
    t.render_s = seconds;
    print_render_summary(t, rays);
    const Options& opt = job.opt;
    const int rendering = std::max(1, ranks - 1);
    if (job.frames)
        std::printf("mpi       %d ranks (%d rendering), %d frames, %.2f MB of results\n", ranks,
                    rendering, job.frames_written, bytes / 1e6);
    else
        std::printf("mpi       %d ranks (%d rendering), %zu tiles of %dx%d, %.2f MB of results\n",
                    ranks, rendering, job.tiles.size(), kTileSize, kTileSize, bytes / 1e6);
    const std::string what = job.frames ? std::to_string(job.frames_written) + " frames, " +
                                              rtapp::frame_path(opt.output, 0) + " .."
                                        : opt.output;
    std::printf("wrote     %s\n", what.c_str());
}

// One image or a sequence: every item once.
int run_image(Job& job, int ranks) {
    const Options& opt = job.opt;
    const auto t0 = rt::Clock::now();
    double bytes = 0;
    if (ranks > 1) {
        Master m(job, ranks, &bytes);
        m.run_items([&](int t) {
            if (job.frames) write_frame(job, t);
        });
        m.finish();
    } else if (job.frames) {  // no worker: rank 0 renders every frame itself
        for (int k = 0; k < opt.animation.frames; ++k) {
            try {
                if (k > 0) rt::animate(*job.scene, job.desc, opt.animation.time(k));
            } catch (const std::exception& e) {
                abort_job("frame " + std::to_string(k) + " not written (" +
                          rtapp::error_text(e, "moving its joints") + ")");
            }
            job.plan = rt::make_render_plan(*job.scene, opt);
            rt::render_part(job.tiles[static_cast<size_t>(k)], *job.scene, job.plan, opt);
            write_frame(job, k);
        }
    } else {  // no worker: rank 0 renders the whole image as one part
        job.tiles.assign(1, rt::RenderPart{});
        rt::RenderPart& p = job.tiles[0];
        p.x1 = opt.width, p.y1 = opt.height;
        p.count = p.total = static_cast<uint32_t>(opt.spp);
        rt::render_part(p, *job.scene, job.plan, opt, terminal_progress_bar(opt.quiet));
    }
    if (!job.frames) {
        std::vector<const rt::RenderPart*> parts;
        for (const rt::RenderPart& p : job.tiles) parts.push_back(&p);
        const rt::RenderState state =
            rt::merge_parts(parts, opt.width, opt.height, static_cast<uint32_t>(opt.spp));
        write_outputs(state.image(), opt.output, {}, opt.scene,
                      exr_output(opt, state, *job.scene, job.plan));
    }
    if (!opt.quiet) print_summary(job, ranks, rt::seconds_since(t0), bytes);
    return 0;
}

// --progressive: run_progressive() with each pass's tiles handed out to the workers, so the
// error against time is reported as raytrace reports it (and with --spp N, the same image).
int run_progressive_mpi(Job& job, int ranks) {
    const Options& opt = job.opt;
    const std::optional<rt::Image> reference = load_reference(opt, job.desc, *job.scene);
    double bytes = 0;
    Master m(job, ranks, &bytes);
    rt::RenderState state;
    auto pass = [&](rt::RenderState& s, const rt::RenderSettings& settings, int spp) {
        if (ranks == 1) return rt::render_samples(s, *job.scene, job.plan, settings, spp);
        const uint32_t first = s.samples.empty() ? 0 : s.samples[0];  // uniform passes
        for (rt::RenderPart& p : job.tiles) {
            p.first = first, p.count = static_cast<uint32_t>(spp);
            p.total = first + static_cast<uint32_t>(spp);
        }
        m.run_items([&](int t) {
            rt::add_part_samples(s, job.tiles[static_cast<size_t>(t)]);
            job.tiles[static_cast<size_t>(t)].blocks.clear();
        });
        ++s.passes;
        return true;
    };
    if (!opt.quiet) print_pass_header("uniform", reference.has_value());
    std::vector<ProgressRun> runs = {
        {"uniform",
         rt::run_progressive(
             state, *job.scene, job.plan, opt, opt.progressive, reference ? &*reference : nullptr,
             [&](const rt::PassRecord& r) {
                 if (!opt.quiet) print_pass(r);
             },
             nullptr, pass)}};
    if (ranks > 1) m.finish();
    if (!opt.quiet) print_progress_summary(runs, opt.progressive.target_relmse);
    std::vector<TextFile> texts;
    if (!opt.progressive.report.empty())
        texts.emplace_back(opt.progressive.report, progress_csv(runs));
    if (!opt.progressive.plot.empty())
        texts.emplace_back(opt.progressive.plot,
                           progress_svg(runs, "Error against render time: " + opt.scene));
    write_outputs(state.image(), opt.output, texts, opt.scene,
                  exr_output(opt, state, *job.scene, job.plan));
    if (!opt.quiet)
        std::printf("mpi       %d ranks, %.2f MB of results\nwrote     %s\n", ranks, bytes / 1e6,
                    opt.output.c_str());
    return 0;
}

int run(Job& job, int rank, int ranks) {
    RankInfo me;
    int len = 0;
    MPI_Get_processor_name(me.host, &len);
    me.pid = static_cast<int>(::getpid());
    g_ranks.resize(static_cast<size_t>(ranks));
    MPI_Gather(&me, sizeof me, MPI_BYTE, g_ranks.data(), sizeof me, MPI_BYTE, 0, MPI_COMM_WORLD);
    if (!load(job, rank)) return 1;
    job.plan = rt::make_render_plan(*job.scene, job.opt);
    job.settings = job.opt;
    if (job.opt.progressive.enabled) job.settings.centre_first_sample = false;  // as its passes
    job.frames = job.opt.animation.frames > 0;
    make_tiles(job);
    if (rank != 0) {
        worker(job, rank);
        return 0;
    }
    return job.opt.progressive.enabled ? run_progressive_mpi(job, ranks) : run_image(job, ranks);
}

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    std::signal(SIGTERM, [](int) { g_stopped = 1; });
    Job job;
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--tile-timeout" && i + 1 < argc) {
            job.tile_timeout_s = parse_tile_timeout(argv[++i]);
            continue;
        }
        args.push_back(a);
    }
    int code = 0;
    try {
        job.opt = parse_options(args);
        if (job.opt.split.part || job.opt.progressive.adaptive ||
            (job.opt.progressive.enabled && job.opt.animation.frames > 0))
            throw UsageError(
                "raytrace-mpi renders an image (also --progressive) or --frames: not .part, "
                "--adaptive or a progressive sequence");
        if (!(job.tile_timeout_s > 0 && job.tile_timeout_s <= kMaxTileTimeout))
            throw UsageError("--tile-timeout takes seconds, more than 0 and at most " +
                             std::to_string(static_cast<int>(kMaxTileTimeout)) + " (a week)");
        // A frame arrives from its worker without the scene at its time on rank 0.
        if (job.opt.exr.aovs.any() && job.opt.animation.frames > 0)
            throw UsageError("raytrace-mpi --frames writes no AOVs: use raytrace --frames --aov");
    } catch (const UsageError& e) {
        if (rank == 0) std::cerr << "raytrace-mpi: " << e.what() << "\n(see raytrace-mpi --help)\n";
        code = 2;
    }
    if (code == 0 && job.opt.version) {
        if (rank == 0) std::cout << rtapp::version_text("raytrace-mpi", true) << "\n";
    } else if (code == 0 && job.opt.help) {
        if (rank == 0)
            std::cout << "usage: mpirun -n N raytrace-mpi SCENE [raytrace's options] "
                         "[--tile-timeout S]\n\n"
                      << usage_text();
    } else if (code == 0) {
        const std::string first =
            job.opt.animation.frames > 0 ? rtapp::frame_path(job.opt.output, 0) : job.opt.output;
        if (rank == 0 && !rtapp::isa_usable("raytrace-mpi"))
            code = 2;
        else if (rank == 0 && !probe_outputs({first}))
            code = 1;
        MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
        if (code == 0) {
            try {
                code = run(job, rank, ranks);
            } catch (const std::exception& e) {
                std::cerr << "raytrace-mpi: error: rank " << rank << ": " << e.what() << "\n";
                MPI_Abort(MPI_COMM_WORLD, 1);
            }
        }
    }
    MPI_Finalize();
    return code;
}
