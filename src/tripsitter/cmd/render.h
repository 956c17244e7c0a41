// The pieces of `tripsitter render` that its MPI mode (render_mpi.cpp, built only with MPI) shares with the
// plain command (render.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <tripsitter/display/io.h>
#include <tripsitter/display/video.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/modes/frame_source.h>
#include <tripsitter/render/sampler.h>
#include <tripsitter/scene/scene.h>

#include "common.h"
#include "device_choice.h"

namespace tripsitter::cmd {

// The frame source's settings as the options give them (source: the mode, the wire and SPI link, threads, and in
// path mode seed, sampler and denoiser), and what source_config makes of the rest.
struct RenderOptions {
  modes::SourceConfig source;
  std::string scene = "demo";
  std::string preset = "wide";
  int workers = 0;
  int bounces = -1;
  int width = 0;   // 0: 640 in hw mode, the scene's render.width in normal mode
  int height = 0;
  std::string out = "tripsitter.png";
  std::string vcd;
  int lines = 525;
  std::string link_input;
  bool compare = false;
  DeviceChoice device;     // hw: the C++ model or the RTL (its SPI clock, VCD and lines are set from the options here)
  bool json = false;       // --compare's figures as one JSON object on stdout
  int reference_spp = 0;   // --compare with a path-tracing preset: the float reference's samples (0: the default)
  int accumulate = 0;      // hw with a path-tracing preset: frames of the still world (0: one)
  // path mode; 0 means the scene's render settings
  int spp = 0;
  int depth = 0;
  bool quiet = false;
  std::string aov;  // path stills: write the feature buffers here as PNG files
  display::ExrPixel exr_pixel = display::ExrPixel::kHalf;  // --out FILE.exr (depth is always float)
  // animation
  int frames = 0;
  double orbit = 0;
  std::string video;
};

// Options that contradict each other or name unknown things; throws InputError before any work.
void check_options(const RenderOptions& o);
// Output files that could not be written where asked (a missing directory); throws InputError before any work.
void check_outputs(const RenderOptions& o);

// The frame source's settings: the command line's, else the scene's (size, samples, depth).
// REQUIRES check_options(o) passed.
modes::SourceConfig source_config(const RenderOptions& o, const scene::Scene& scene);
// A path-traced still from start to end: the BVH built, `trace` run under a progress bar, the summary line
// (ended by `where`: "" or " on 4 MPI ranks") and the image file. A process that only helps (an MPI rank other
// than 0) passes writes = false: no bar, no summary, no file.
int run_path_still(const RenderOptions& o, const scene::Scene& scene, const modes::PathTrace& trace, bool writes,
                   const std::string& where);

// "DIR/frame_%04d.png" with frame 7 is "DIR/frame_0007.png". REQUIRES a pattern accepted by check_options.
std::string frame_path(const std::string& pattern, int frame);

// The frame to `path`: PNG, or OpenEXR for a .exr name (modes::write_image); throws InputError when it cannot
// be written.
void write_quietly(const std::string& path, const modes::Frame& frame, const RenderOptions& o);
// The same, and says so on stderr.
void write_image(const std::string& path, const modes::Frame& frame, const RenderOptions& o);

// The --video pipe for frames of width x height, or null without --video; throws InputError for a path the
// pipe cannot take.
std::unique_ptr<display::VideoPipe> open_video(const RenderOptions& o, int width, int height);

// `tripsitter render` started by Open MPI's mpirun in path mode: the ranks share the work (docs/mpi.md).
// Defined only in builds with MPI.
int run_render_mpi(const RenderOptions& o);

}  // namespace tripsitter::cmd
