// One frame source per mode: each owns the host's camera (the controls move it) and makes the picture seen from
// it. `render` (stills, animations, MPI), `run` (the window) and `bench` take their frames from here, so that a
// mode is chosen once and takes one road through the code. Each mode's frame is its own type (Frame).
//
//   hw      the board (board.h): the host quantises and encodes, the link carries the bytes, the device draws a
//           VGA frame and the monitor captures it;
//   normal  the host's view (host/view.h) rendered by the float reference of the device's shading
//           (render/normal.h), nothing encoded;
//   path    the path tracer (render/path_tracer.h) from the scene's thin-lens camera; once the camera has been
//           steered, from the host camera's position and target: the window's source refines a picture
//           (render/interactive.h), the stills' source traces a whole one at a time.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <variant>

#include <tripsitter/board/board.h>
#include <tripsitter/core/image.h>
#include <tripsitter/core/result.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/display/io.h>
#include <tripsitter/host/camera.h>
#include <tripsitter/host/host.h>
#include <tripsitter/modes/mode.h>
#include <tripsitter/render/aov.h>
#include <tripsitter/render/interactive.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::modes {

// How the path tracer makes one picture (render::render_path by default; MPI shares the rows among ranks).
// It fills the feature buffers when given them.
using PathTrace = std::function<core::ImageRgbF(const render::PathScene&, const render::ThinLensCamera&,
                                                  const render::PathSettings&,
                                                  const std::function<void(std::uint64_t)>& on_samples,
                                                  render::Aovs* aovs)>;

// What a source needs; each mode reads its own fields.
struct SourceConfig {
  Mode mode = Mode::kHw;
  // hw: the board as it is built. normal: of it, the device's mirror bounces and scene memory (preset) and the
  // wire (the float reference renders the world the device would hold).
  board::BoardConfig board;
  std::function<void(const device::VgaSample&)> probe;  // hw: sees every VGA sample (a VCD trace)
  // normal and path (hw is always the monitor's 640x480)
  int width = 640;
  int height = 480;
  int threads = 0;                     // 0: all hardware threads
  // path
  int spp = 1;                         // samples per pixel of a picture
  int max_depth = 50;                  // bounces along one path
  std::uint64_t seed = 1;
  bool progressive = false;            // each draw adds a pass to the picture (the window: render/interactive.h)
  render::SamplerKind sampler = render::SamplerKind::kSobol;
  bool denoise = false;                // filter the picture (render/denoise.h); the window's default is on
  bool aovs = false;                   // path stills: fill Frame::aovs (render --aov, EXR layers)
  bool reuse = true;                   // progressive: reproject the history when the camera moves (else start over)
  int row_step = 1;                    // progressive: paths on 1 row of every row_step per draw
  PathTrace trace;                     // empty: render::render_path on this process's threads
  std::function<void(std::uint64_t)> on_samples;  // progress: samples traced so far
};

// The path tracer's settings of a picture at config.spp samples per pixel.
render::PathSettings path_settings(const SourceConfig& config);

// hw: the board's picture, the device's frame and the world it shows as the host sent it.
struct HwFrame {
  core::Image444 vga;  // the 12-bit picture the monitor captured
  device::FrameStats device;
  host::Saturations saturations;
  std::size_t link_bytes = 0;
  double link_seconds = 0;          // at the SPI clock
  std::size_t spheres_dropped = 0;  // beyond scene memory, never sent
  int samples = 0;                  // with a path-tracing preset: samples per pixel in frame memory
  // The device's memories as this frame left them, valid until the next draw(): scene memory, the world the
  // frame shows in raw fixed point; and with a path-tracing preset frame memory, each pixel's accumulated
  // samples (null for the other presets). modes/device_compare.h reads them.
  const device::SceneMemory* scene_memory = nullptr;
  const device::FrameMemory* frame_memory = nullptr;
};

// normal: the float reference's 12-bit picture.
struct NormalFrame {
  core::Image444 vga;
};

// path: the picture in linear light, its sRGB encoding and its feature buffers.
struct PathFrame {
  core::ImageRgb8 rgb;      // sRGB-encoded
  core::ImageRgbF linear;   // before the encoding
  const render::Aovs* aovs = nullptr;  // progressive: always; stills: with SourceConfig::aovs or denoise
  int samples = 0;          // samples per pixel (progressive: frames since the camera last moved)
  double mean_samples = 0;  // samples per pixel, mean over the picture (progressive: reprojected share included)
};

// One picture and what it cost, of the source's mode.
using Frame = std::variant<HwFrame, NormalFrame, PathFrame>;

// The picture in 8-bit RGB: the sRGB one, or the 12-bit one with each channel expanded.
core::ImageRgb8 rgb8(const Frame& frame);
// The picture's width and height in pixels.
struct PictureSize {
  int width = 0;
  int height = 0;
};
PictureSize picture_size(const Frame& frame);

// Writes the frame's picture to `path` (display/io.h's write_image: PNG, or OpenEXR for a .exr name); an EXR
// file holds a path frame's linear light with its feature buffers as layers. A 12-bit picture has no linear
// light: for a .exr name the error says so and nothing is written.
core::Result<bool, display::IoError> write_image(const std::string& path, const Frame& frame,
                                                display::ExrPixel pixel = display::ExrPixel::kHalf);

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  Mode mode() const { return mode_; }
  // The host's camera as it is.
  virtual const host::Camera& camera() const = 0;
  // The host's camera, to move it: the next draw shows the new view (a progressive source starts over).
  virtual host::Camera& steer() = 0;
  // R: world and camera as loaded.
  virtual void reset() = 0;

  // The picture from the camera as it is now. The frame lives until the next call.
  virtual const Frame& draw() = 0;
  // Whether another draw() would improve the picture although nothing moved (a progressive path source still
  // refining; the hw source with a path-tracing preset while the device's frame memory still accumulates).
  virtual bool refining() const { return false; }
  // The denoiser of a path source (render/denoise.h): on or off; false where the mode has none.
  virtual bool set_denoise(bool /*on*/) { return false; }
  virtual bool denoise() const { return false; }

 protected:
  explicit FrameSource(Mode mode) : mode_(mode) {}

 private:
  Mode mode_;
};

// The source of config.mode for the scene. REQUIRES the scene's camera to be valid (scene_json.h) and the
// preset to validate.
std::unique_ptr<FrameSource> make_frame_source(const scene::Scene& scene, const SourceConfig& config);

}  // namespace tripsitter::modes
