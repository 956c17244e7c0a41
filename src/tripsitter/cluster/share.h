// The path tracer's work shared among the ranks of a Job (docs/mpi.md): the rows of a still, or the frames
// of an animation. Rank 0 ends up with everything and is the one that writes. The split never changes a
// value: every pixel, and every frame, is computed whole by one rank exactly as a single process computes
// it, and moving it to rank 0 is a copy. So rank 0's result is bit-identical whatever the number of ranks.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>

#include <tripsitter/cluster/job.h>
#include <tripsitter/core/image.h>
#include <tripsitter/render/path_tracer.h>

namespace tripsitter::cluster {

// Collective. Rank r of K traces rows r, r + K, r + 2K, ... with render::render_path_rows, on
// settings.threads threads of its own, and sends them to rank 0. Rank 0 returns the whole image, equal to
// render::render_path's; it calls on_samples(n) on the calling thread as the samples of any rank complete,
// so its progress is the whole job's. Other ranks return an image holding their own rows only and never
// call on_samples. With `aovs`, the feature buffers (render/aov.h) travel the same way: rank 0's are
// render::render_path's, other ranks' hold their own rows.
core::ImageRgbF render_path_shared(const Job& job, const render::PathScene& scene, const render::ThinLensCamera& camera,
                                     const render::PathSettings& settings,
                                     const std::function<void(std::uint64_t)>& on_samples = {},
                                     render::Aovs* aovs = nullptr);

// The frames of an animation dealt to the ranks: frame i belongs to rank i % K. Every rank walks through all
// frames in order; the owner of a frame renders it and, unless it is rank 0, sends it; rank 0 receives the
// others' frames in order. One frame per rank is in flight at a time, so memory stays flat.
class FrameExchange {
 public:
  explicit FrameExchange(const Job& job) : job_(job) {}
  // Waits until the last frame sent has been taken.
  ~FrameExchange();
  FrameExchange(const FrameExchange&) = delete;
  FrameExchange& operator=(const FrameExchange&) = delete;

  bool owns(int frame) const { return frame % job_.size() == job_.rank(); }
  // On a rank other than 0, for the next frame it owns: hands the frame to rank 0, once the previous one has
  // been taken.
  void send(core::ImageRgb8 image);
  // On rank 0, for the next frame it does not own: that frame (width x height), from its owner.
  core::ImageRgb8 receive(int frame, int width, int height);

 private:
  const Job& job_;
  core::ImageRgb8 sending_;
  MPI_Request request_ = MPI_REQUEST_NULL;
};

}  // namespace tripsitter::cluster
