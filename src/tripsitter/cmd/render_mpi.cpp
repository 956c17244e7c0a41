// `tripsitter render --mode path` started by Open MPI's mpirun: the ranks share the work and rank 0 writes
// (docs/mpi.md). Built only with MPI.
#include <unistd.h>

#include <csignal>
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include <tripsitter/cluster/job.h>
#include <tripsitter/cluster/share.h>
#include <tripsitter/core/progress.h>
#include <tripsitter/modes/animation.h>

#include "render.h"

namespace tripsitter::cmd {
namespace {

// mpirun stops the other ranks with SIGTERM when one rank dies or the job is interrupted. Rank 0 then says
// that nothing more is written, and nothing is half-written: write_png writes beside its file and renames.
void on_stopped(int) {
  // The newline ends a progress bar line that may be showing.
  static const char kMessage[] =
      "\ntripsitter: mpirun stopped rank 0 before the job finished (a rank failed, or the job was interrupted); "
      "nothing more is written\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  ::_exit(kExitInternal);
}

// While it lives, rank 0 reports a stop as above.
class StopNotice {
 public:
  explicit StopNotice(bool enabled) : enabled_(enabled) {
    if (enabled_) previous_ = std::signal(SIGTERM, on_stopped);
  }
  ~StopNotice() {
    if (enabled_) std::signal(SIGTERM, previous_);
  }
  StopNotice(const StopNotice&) = delete;
  StopNotice& operator=(const StopNotice&) = delete;

 private:
  bool enabled_;
  void (*previous_)(int) = SIG_DFL;
};

std::string on_ranks(const cluster::Job& job) {
  return " on " + std::to_string(job.size()) + (job.size() == 1 ? " MPI rank" : " MPI ranks");
}

// A still: rank r of K traces rows r, r + K, ...; rank 0 gathers them, reports and writes.
int run_still(const cluster::Job& job, const RenderOptions& o, const scene::Scene& scene) {
  return run_path_still(o, scene, [&job](const auto& path_scene, const auto& camera, const auto& s, const auto& on_samples,
                                         render::Aovs* aovs) {
    return cluster::render_path_shared(job, path_scene, camera, s, on_samples, aovs);
  }, job.is_root(), on_ranks(job));
}

// An animation: frame i is rendered whole by rank i % K; rank 0 writes the frames in order (and feeds ffmpeg).
// Every rank moves the camera through every frame, so each frame's camera is the one a single process uses.
int run_frames(const cluster::Job& job, const RenderOptions& o, const scene::Scene& scene) {
  const modes::SourceConfig config = source_config(o, scene);
  const std::unique_ptr<modes::FrameSource> source = modes::make_frame_source(scene, config);
  cluster::FrameExchange exchange(job);
  std::unique_ptr<display::VideoPipe> video;
  if (job.is_root()) video = open_video(o, config.width, config.height);
  core::ProgressBar bar("animation", static_cast<std::uint64_t>(o.frames), "frames", !o.quiet && job.is_root(),
                        std::cerr);
  const auto owns = [&exchange](int i) { return exchange.owns(i); };
  modes::animate(*source, o.frames, o.orbit, owns, [&](int i, const modes::Frame* drawn) {
    modes::Frame frame = modes::PathFrame{};
    core::ImageRgb8& rgb = std::get<modes::PathFrame>(frame).rgb;
    if (drawn != nullptr) {
      job.test_kill_point();
      const core::ImageRgb8& traced = std::get<modes::PathFrame>(*drawn).rgb;
      if (!job.is_root()) {
        exchange.send(traced);
        return;
      }
      rgb = traced;
    } else if (job.is_root()) {
      rgb = exchange.receive(i, config.width, config.height);
    } else {
      return;
    }
    write_quietly(frame_path(o.out, i), frame, o);
    if (video) video->add(rgb);
    bar.add(1);
  });
  if (!job.is_root()) return kExitOk;
  bar.finish();
  if (video) video->finish(std::cerr);
  std::cerr << "wrote " << o.frames << " frames" << on_ranks(job) << ", " << frame_path(o.out, 0) << " to "
            << frame_path(o.out, o.frames - 1) << "\n";
  return kExitOk;
}

}  // namespace

int run_render_mpi(const RenderOptions& o) {
  cluster::Job job;
  // Every rank checks the options and loads the scene; rank 0, which writes, checks the output paths. The
  // ranks agree before any work: on bad input all stop, the lowest rank that found it says why, exit 2.
  std::optional<scene::Scene> scene;
  std::exception_ptr problem;
  try {
    check_options(o);
    if (o.frames > 0 && display::is_exr(o.out))
      throw InputError("--out " + o.out + ": under mpirun an animation's frames travel to rank 0 as 8-bit RGB, so "
                       "they cannot be written as EXR; write PNG frames, or run without mpirun");
    if (job.is_root()) check_outputs(o);
    scene = load_scene(o.scene);
  } catch (...) {
    problem = std::current_exception();
  }
  const int failed = job.first_failed_rank(problem != nullptr);
  if (failed >= 0) {
    if (failed != job.rank()) return kExitBadInput;
    // Said here, before the Job's MPI_Finalize lets the other ranks exit: mpirun stops every rank as soon as one
    // exits non-zero, which could cut off a message written later.
    const std::string who = job.is_root() ? "" : "rank " + std::to_string(job.rank()) + ": ";
    try {
      std::rethrow_exception(problem);
    } catch (const InputError& e) {
      std::cerr << "tripsitter: " << who << e.what() << std::endl;
      return kExitBadInput;
    } catch (const std::exception& e) {
      std::cerr << "tripsitter: internal error: " << who << e.what() << std::endl;
      return kExitInternal;
    }
  }

  const StopNotice notice(job.is_root());
  try {
    return o.frames > 0 ? run_frames(job, o, *scene) : run_still(job, o, *scene);
  } catch (const std::exception& e) {
    // Past the agreement other ranks may be waiting for this one: stop the whole job.
    const bool bad_input = dynamic_cast<const InputError*>(&e) != nullptr;
    std::cerr << "tripsitter: " << (bad_input ? "" : "internal error: ") << "rank " << job.rank() << ": " << e.what()
              << "\n";
    job.abort(bad_input ? kExitBadInput : kExitInternal);
  }
}

}  // namespace tripsitter::cmd
