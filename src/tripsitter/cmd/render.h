// The pieces of `tripsitter render` that its MPI mode (render_mpi.cpp, built only with MPI) shares with the
// plain command (render.cpp).
#pragma once

#include <cstdint>
#include <cstdio>
#include <iostream>
#include <functional>
#include <string>

#include <tripsitter/core/image.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/camera.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/scene/scene.h>

#include "common.h"

namespace tripsitter::cmd {

struct RenderOptions {
  std::string scene = "demo";
  std::string mode = "hw";
  std::string preset = "wide";
  int workers = 0;
  int bounces = -1;
  std::string wire = "v2";
  int width = 0;   // 0: 640 in hw mode, the scene's render.width in normal mode
  int height = 0;
  std::string out = "tripsitter.png";
  std::string vcd;
  int lines = 525;
  std::string link_input;
  std::size_t transfer_bytes = link::SpiConfig{}.max_transfer_bytes;
  std::int64_t spi_hz = link::SpiConfig{}.clock_hz;
  bool compare = false;
  // path mode; 0 means the scene's render settings
  int spp = 0;
  int depth = 0;
  std::uint64_t seed = 1;
  int threads = 0;
  bool quiet = false;
  // animation
  int frames = 0;
  double orbit = 0;
  std::string video;
};

// Options that contradict each other or name unknown things; throws InputError before any work.
void check_options(const RenderOptions& o);
// Output files that could not be written where asked (a missing directory); throws InputError before any work.
void check_outputs(const RenderOptions& o);

// The path tracer's settings: the command line's, else the scene's.
render::PathSettings path_settings(const RenderOptions& o, const scene::Scene& scene);
// A path-traced still from start to end: the BVH built, `trace` run under a progress bar, the summary line
// (ended by `where`: "" or " on 4 MPI ranks") and the image file. A process that only helps (an MPI rank other
// than 0) passes writes = false: no bar, no summary, no file.
using PathTrace = std::function<render::ImageRgbF(const render::PathScene&, const render::ThinLensCamera&,
                                                  const render::PathSettings&,
                                                  const std::function<void(std::uint64_t)>& on_samples)>;
int run_path_still(const RenderOptions& o, const scene::Scene& scene, const PathTrace& trace, bool writes,
                   const std::string& where);
// One frame of a path-traced animation: the scene's camera moved to where the host's camera is now.
core::ImageRgb8 render_path_frame(const render::PathScene& scene, scene::CameraSettings camera, const host::Camera& at,
                                  const render::PathSettings& s);

// "DIR/frame_%04d.png" with frame 7 is "DIR/frame_0007.png". REQUIRES a pattern accepted by check_options.
std::string frame_path(const std::string& pattern, int frame);

template <class Image>
void write_quietly(const std::string& path, const Image& image) {
  auto written = display::write_png(path, image);
  if (!written) throw InputError(written.error().message);
}

template <class Image>
void write_image(const std::string& path, const Image& image) {
  write_quietly(path, image);
  std::cerr << "wrote " << path << " (" << image.width << "x" << image.height << ")\n";
}

// ffmpeg fed raw RGB frames through a pipe; nothing when ffmpeg is not installed. The video appears under its
// name only when finish() succeeds.
class VideoPipe {
 public:
  VideoPipe(const std::string& path, int width, int height);
  ~VideoPipe();
  VideoPipe(const VideoPipe&) = delete;
  VideoPipe& operator=(const VideoPipe&) = delete;
  void add(const core::ImageRgb8& frame);
  void finish();

 private:
  FILE* pipe_ = nullptr;
  std::string path_, partial_;
};

// `tripsitter render` started by Open MPI's mpirun in path mode: the ranks share the work (docs/mpi.md).
// Defined only in builds with MPI.
int run_render_mpi(const RenderOptions& o);

}  // namespace tripsitter::cmd
