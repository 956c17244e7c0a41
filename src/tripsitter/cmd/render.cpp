// tripsitter render: one frame as the monitor shows it.
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <system_error>

#include <tripsitter/board/board.h>
#include <tripsitter/display/png.h>
#include <tripsitter/display/vcd.h>
#include <tripsitter/core/progress.h>
#include <tripsitter/render/normal.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/scene/builtin.h>

#include "commands.h"
#include "common.h"
#include "render.h"

namespace tripsitter::cmd {
namespace {

// Fails before any work is done when a file could not be written there.
void check_output_path(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw InputError(path + ": directory " + parent.string() + " does not exist");
}

// Exactly one integer conversion (%d, %4d, %04d, ...) and no other %, except %%.
void check_pattern(const std::string& pattern) {
  int conversions = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < pattern.size() && (std::isdigit(static_cast<unsigned char>(pattern[j])) != 0)) ++j;
    if (j >= pattern.size() || pattern[j] != 'd' || j - i > 4)
      throw InputError("--out " + pattern + ": with --frames it needs one %d (or %04d) for the frame number");
    ++conversions;
    i = j;
  }
  if (conversions != 1 || pattern.size() > 2000)
    throw InputError("--out " + pattern + ": with --frames it needs exactly one %d (or %04d) for the frame number");
}

// The VCD file is opened before rendering, so a bad path fails before any work; it is removed again if
// the render fails.
class VcdCapture {
 public:
  VcdCapture(const std::string& path, int lines) : path_(path), limit_(std::int64_t{lines} * 800) {
    if (path.empty()) return;
    file_.open(path, std::ios::binary | std::ios::trunc);
    if (!file_) throw InputError(path + ": cannot open for writing");
    writer_ = std::make_unique<display::VcdWriter>(file_);
  }
  ~VcdCapture() {
    if (!path_.empty() && !kept_) {
      file_.close();
      std::remove(path_.c_str());
    }
  }
  std::function<void(const device::VgaSample&)> probe() {
    if (!writer_) return {};
    return [this](const device::VgaSample& s) {
      if (static_cast<std::int64_t>(writer_->samples()) < limit_) writer_->sample(s);
    };
  }
  void keep() {
    if (path_.empty()) return;
    writer_->finish();
    file_.close();
    if (!file_) throw InputError(path_ + ": write failed");
    kept_ = true;
    std::cerr << "wrote " << path_ << " (" << writer_->samples() << " pixel clocks)\n";
  }

 private:
  std::string path_;
  std::int64_t limit_;
  std::ofstream file_;
  std::unique_ptr<display::VcdWriter> writer_;
  bool kept_ = false;
};

void report(const board::ShownFrame& f) {
  std::cerr << "device: " << f.device.late_pixels << " late pixels on " << f.device.late_lines << " lines\n"
            << "link: " << f.link_bytes << " bytes, " << f.link_seconds * 1e3 << " ms at the SPI clock\n"
            << "host: " << f.saturations.total() << " saturated values\n";
  if (f.spheres_dropped > 0) std::cerr << "host: " << f.spheres_dropped << " spheres beyond scene memory were not sent\n";
}

// Samples of a whole image.
std::uint64_t samples_of(const render::PathSettings& s) {
  return s.row_samples() * static_cast<std::uint64_t>(s.height);
}

// --frames N --orbit DEG: the camera circles its target by DEG over the N frames (frame i at i * DEG / N,
// so 360 loops), each frame through the same path as a still.
int run_animation(const RenderOptions& o, scene::Scene scene, const device::DevicePreset& preset,
                  link::WireVersion wire) {
  const bool path_mode = o.mode == "path";
  const int width = o.mode == "hw" ? 640 : (o.width != 0 ? o.width : scene.render.width);
  const int height = o.mode == "hw" ? 480 : (o.height != 0 ? o.height : scene.render.height);
  std::unique_ptr<render::PathScene> path_scene;
  if (path_mode) path_scene = std::make_unique<render::PathScene>(scene.spheres);
  const scene::CameraSettings camera = scene.camera;
  const render::PathSettings settings = path_settings(o, scene);
  board::Board b(std::move(scene), {preset, wire, {o.transfer_bytes, o.spi_hz}});
  VideoPipe video(o.video, width, height);
  core::ProgressBar bar("animation", static_cast<std::uint64_t>(o.frames), "frames", !o.quiet, std::cerr);
  for (int i = 0; i < o.frames; ++i) {
    if (i > 0) b.host().camera().orbit(o.orbit / o.frames);
    const std::string file = frame_path(o.out, i);
    core::ImageRgb8 rgb;
    if (o.mode == "hw") {
      const board::ShownFrame shown = b.show();
      write_quietly(file, shown.image);
      rgb = core::to_rgb8(shown.image);
    } else if (o.mode == "normal") {
      const core::Image444 img =
          render::render_normal_fast(b.host().update().view_spheres, width, height, preset.max_bounces, o.threads);
      write_quietly(file, img);
      rgb = core::to_rgb8(img);
    } else {
      rgb = render_path_frame(*path_scene, camera, b.host().camera(), settings);
      write_quietly(file, rgb);
    }
    video.add(rgb);
    bar.add(1);
  }
  bar.finish();
  video.finish();
  std::cerr << "wrote " << o.frames << " frames, " << frame_path(o.out, 0) << " to " << frame_path(o.out, o.frames - 1)
            << "\n";
  return kExitOk;
}

int run_render(const RenderOptions& o) {
  const MpirunPlace place = mpirun_place();
#ifdef TRIPSITTER_WITH_MPI
  if (place.size > 0 && o.mode == "path") return run_render_mpi(o);
  const std::string refusal = "--mode " + o.mode + " under mpirun: only --mode path shares its work among MPI ranks; run " +
                              o.mode + " without mpirun";
#else
  const std::string refusal = "this tripsitter was built without MPI, so under mpirun each of the " +
                              std::to_string(place.size) +
                              " ranks would render the whole image on its own; run it without mpirun, or build it "
                              "with MPI (docs/mpi.md)";
#endif
  // Every rank refuses alike; rank 0 says why.
  if (place.size > 1) {
    if (place.rank != 0) return kExitBadInput;
    throw InputError(refusal);
  }
  check_options(o);
  check_outputs(o);
  const link::WireVersion wire = parse_wire(o.wire);
  const device::DevicePreset preset = load_preset(o.preset, o.workers, o.bounces);

  if (!o.link_input.empty()) {
    // The device alone, fed raw link bytes as a real host would send them.
    const std::vector<std::uint8_t> bytes = read_bytes(o.link_input);
    VcdCapture vcd(o.vcd, o.lines);
    device::Device dev(preset, wire);
    display::VgaMonitor monitor;
    const std::span<const std::uint8_t> all(bytes);
    for (std::size_t at = 0; at < all.size(); at += o.transfer_bytes)
      dev.transfer(all.subspan(at, std::min(o.transfer_bytes, all.size() - at)));
    dev.end_of_stream();
    auto probe = vcd.probe();
    const device::FrameStats stats = dev.run_frame([&](const device::VgaSample& s) {
      monitor.sample(s);
      if (probe) probe(s);
    });
    const auto& rx = dev.receiver_stats();
    std::cerr << "device: " << rx.worlds_accepted << " worlds accepted, " << rx.worlds_missing
              << " missing (sequence numbers skipped), " << rx.frames_rejected
              << " frames rejected, " << rx.garbage_runs << " runs of garbage (" << rx.bytes_dropped
              << " bytes dropped)\n";
    if (!stats.has_world)
      throw InputError(o.link_input + ": no intact world in " + std::to_string(bytes.size()) + " bytes" +
                       (rx.last_error.empty() ? "" : " (last error: " + rx.last_error + ")"));
    auto frame = monitor.take_frame();
    if (!frame) throw std::logic_error("monitor did not capture a frame");
    std::cerr << "device: showing world " << stats.sequence << ", " << stats.late_pixels << " late pixels on "
              << stats.late_lines << " lines\n";
    write_image(o.out, *frame);
    vcd.keep();
    return kExitOk;
  }

  scene::Scene scene = load_scene(o.scene);
  if (o.frames > 0) return run_animation(o, std::move(scene), preset, wire);
  if (o.mode == "path") {
    return run_path_still(o, scene, [](const auto& path_scene, const auto& camera, const auto& s, const auto& on_samples) {
      return render::render_path(path_scene, camera, s, on_samples);
    }, true, "");
  }
  if (o.mode == "normal") {
    host::Host host(scene, board::formats_of(preset), wire);
    const auto& world = host.update();
    const int width = o.width != 0 ? o.width : scene.render.width;
    const int height = o.height != 0 ? o.height : scene.render.height;
    write_image(o.out, render::render_normal_fast(world.view_spheres, width, height, preset.max_bounces, o.threads));
    return kExitOk;
  }
  VcdCapture vcd(o.vcd, o.lines);
  board::Board b(std::move(scene), {preset, wire, {o.transfer_bytes, o.spi_hz}});
  const board::ShownFrame shown = b.show(vcd.probe());
  report(shown);
  if (o.compare) {
    const core::ImageDiff d =
        core::diff(shown.image, render::render_normal(b.host().ready().view_spheres, 640, 480, preset.max_bounces));
    std::printf("vs float reference: %zu of %zu pixels differ (%.3f%%), %zu by more than one level, at most %d levels\n",
                d.differing, d.pixels, 100.0 * static_cast<double>(d.differing) / static_cast<double>(d.pixels),
                d.over_one_level, d.max_level_difference);
  }
  write_image(o.out, shown.image);
  vcd.keep();
  return kExitOk;
}

}  // namespace

void check_options(const RenderOptions& o) {
  if (o.mode != "hw" && o.mode != "normal" && o.mode != "path")
    throw InputError("--mode must be hw, normal or path, not '" + o.mode + "'");
  if (o.mode != "path" && (o.spp != 0 || o.depth != 0))
    throw InputError("--spp and --depth need --mode path (hw and normal trace one ray per pixel)");
  parse_wire(o.wire);
  load_preset(o.preset, o.workers, o.bounces);
  if (o.mode == "hw" && ((o.width != 0 && o.width != 640) || (o.height != 0 && o.height != 480)))
    throw InputError("--mode hw draws the VGA monitor's 640x480 only; other sizes need --mode normal or path");
  if (o.mode != "hw" && !o.vcd.empty()) throw InputError("--vcd needs --mode hw (the float renderers have no VGA signal)");
  if (o.mode != "hw" && !o.link_input.empty()) throw InputError("--link-input needs --mode hw");
  if (o.compare && (o.mode != "hw" || !o.link_input.empty()))
    throw InputError("--compare needs --mode hw with a scene (it renders the same world in float)");
  if (o.frames == 0 && (o.orbit != 0 || !o.video.empty())) throw InputError("--orbit and --video need --frames N");
  if (o.frames > 0 && (!o.vcd.empty() || !o.link_input.empty() || o.compare))
    throw InputError("--frames renders an animation: --vcd, --link-input and --compare are for one frame");
  if (o.frames > 0) check_pattern(o.out);
}

void check_outputs(const RenderOptions& o) {
  if (o.frames == 0) {
    check_output_path(o.out);
  } else {
    check_output_path(frame_path(o.out, 0));
    if (!o.video.empty()) check_output_path(o.video);
  }
  if (!o.vcd.empty()) check_output_path(o.vcd);
}

render::PathSettings path_settings(const RenderOptions& o, const scene::Scene& scene) {
  render::PathSettings s;
  s.width = o.width != 0 ? o.width : scene.render.width;
  s.height = o.height != 0 ? o.height : scene.render.height;
  s.spp = o.spp != 0 ? o.spp : scene.render.spp;
  s.max_depth = o.depth != 0 ? o.depth : scene.render.max_depth;
  s.seed = o.seed;
  s.threads = o.threads;
  return s;
}

int run_path_still(const RenderOptions& o, const scene::Scene& scene, const PathTrace& trace, bool writes,
                   const std::string& where) {
  const render::PathSettings s = path_settings(o, scene);
  const auto t0 = std::chrono::steady_clock::now();
  const render::PathScene path_scene(scene.spheres);
  const auto t1 = std::chrono::steady_clock::now();
  const render::ThinLensCamera camera(scene.camera, s.width, s.height);
  render::ImageRgbF image;
  {
    core::ProgressBar bar("path", samples_of(s), "samples", !o.quiet && writes, std::cerr);
    image = trace(path_scene, camera, s, [&](std::uint64_t n) { bar.add(n); });
  }
  if (!writes) return kExitOk;
  const double trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  if (!o.quiet) {
    std::fprintf(stderr, "path: %zu spheres, BVH built in %.3f s; %dx%d at %d spp in %.2f s (%.2f Msamples/s)%s\n",
                 path_scene.size(), std::chrono::duration<double>(t1 - t0).count(), s.width, s.height, s.spp,
                 trace_seconds, static_cast<double>(samples_of(s)) / trace_seconds / 1e6, where.c_str());
  }
  write_image(o.out, render::to_srgb8(image));
  return kExitOk;
}

core::ImageRgb8 render_path_frame(const render::PathScene& scene, scene::CameraSettings camera, const host::Camera& at,
                                  const render::PathSettings& s) {
  camera.lookfrom = at.position();
  camera.lookat = at.target();
  return render::to_srgb8(render::render_path(scene, render::ThinLensCamera(camera, s.width, s.height), s));
}

std::string frame_path(const std::string& pattern, int frame) {
  char buf[4096];
  std::snprintf(buf, sizeof buf, pattern.c_str(), frame);
  return buf;
}

VideoPipe::VideoPipe(const std::string& path, int width, int height) {
  if (path.empty()) return;
  // The command goes through the shell, with the path in single quotes.
  if (path.find('\'') != std::string::npos) throw InputError("--video " + path + ": a quote in the file name");
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    std::cerr << "ffmpeg is not installed (Debian: apt-get install ffmpeg): writing the PNG frames only, no " << path
              << "\n";
    return;
  }
  // ffmpeg writes "DIR/NAME.partial.EXT" (it picks the format by the extension), renamed once it has finished,
  // so a render that stops part-way never leaves a short video under the asked name.
  const std::filesystem::path p(path);
  partial_ = (p.parent_path() / (p.stem().string() + ".partial" + p.extension().string())).string();
  const std::string cmd = "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " + std::to_string(width) + "x" +
                          std::to_string(height) + " -r 30 -i - -pix_fmt yuv420p '" + partial_ + "'";
  pipe_ = popen(cmd.c_str(), "w");
  if (pipe_ == nullptr) throw std::runtime_error("cannot start ffmpeg");
  path_ = path;
}

VideoPipe::~VideoPipe() {
  if (pipe_ == nullptr) return;
  pclose(pipe_);
  std::error_code ignored;
  std::filesystem::remove(partial_, ignored);
}

void VideoPipe::add(const core::ImageRgb8& frame) {
  if (pipe_ != nullptr) std::fwrite(frame.pixels.data(), 1, frame.pixels.size(), pipe_);
}

void VideoPipe::finish() {
  if (pipe_ == nullptr) return;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  std::error_code ec;
  if (status == 0) std::filesystem::rename(partial_, path_, ec);
  if (status != 0 || ec) {
    std::filesystem::remove(partial_, ec);
    throw std::runtime_error("ffmpeg failed writing " + path_);
  }
  std::cerr << "wrote " << path_ << "\n";
}

void add_render_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render one frame as the board's monitor shows it, to a PNG file");
  cmd->add_option("--scene", o->scene,
                  "Built-in scene name (" + join(scene::builtin_names()) + ", random-N) or JSON scene file")
      ->capture_default_str();
  cmd->add_option("--mode", o->mode,
                  "hw: host -> link -> device -> VGA capture, bit-exact fixed point (640x480 only);\n"
                  "normal: the float reference of the same rays and shading, mirrors included (any size);\n"
                  "path: the float path tracer with materials, bounces, samples and the scene's thin-lens camera,\n"
                  "      written sRGB-encoded")
      ->capture_default_str();
  cmd->add_option("--preset", o->preset, "Device preset (" + join(device::preset_names()) + ")")->capture_default_str();
  cmd->add_option("--workers", o->workers, "Number of device workers, 1..640 (default: the preset's)")
      ->check(CLI::Range(1, 640));
  cmd->add_option("--bounces", o->bounces,
                  "Device mirror bounces off metal spheres, 0..6 (default: the preset's); also used by --mode normal")
      ->check(CLI::Range(0, 6));
  cmd->add_option("--wire", o->wire, "Link protocol: v1 (the board's sphere word; the device shows the last sphere) or v2")
      ->capture_default_str();
  cmd->add_option("--width", o->width, "Image width, normal and path modes (default: the scene's render.width; hw is 640)")
      ->check(CLI::Range(1, scene::kMaxImageSide));
  cmd->add_option("--height", o->height, "Image height, normal and path modes (default: the scene's render.height; hw is 480)")
      ->check(CLI::Range(1, scene::kMaxImageSide));
  cmd->add_option("--out", o->out, "Output PNG file")->capture_default_str();
  cmd->add_option("--vcd", o->vcd, "Also dump the VGA signal (hsync, vsync, r, g, b) as a VCD file (hw only)");
  cmd->add_option("--lines", o->lines, "Lines of signal in the VCD, counted from the device's reset at the start of "
                                       "vertical blanking (line 480); 525 is one whole frame")
      ->capture_default_str()->check(CLI::Range(1, 525 * 4));
  cmd->add_option("--link-input", o->link_input,
                  "Feed the device raw link bytes from this file ('-' for stdin) instead of a scene; with v1, each 8 "
                  "bytes are one word, most significant byte first");
  cmd->add_option("--transfer-bytes", o->transfer_bytes, "Largest SPI transfer in bytes")
      ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30));
  cmd->add_option("--spi-hz", o->spi_hz, "SPI clock in Hz, for the link time report")
      ->capture_default_str()->check(CLI::Range(std::int64_t{1}, std::int64_t{1'000'000'000'000}));
  cmd->add_option("--spp", o->spp, "path only: samples per pixel (default: the scene's render.spp)")
      ->check(CLI::Range(1, scene::kMaxSpp));
  cmd->add_option("--depth", o->depth, "path only: most bounces along one path (default: the scene's render.max_depth)")
      ->check(CLI::Range(1, scene::kMaxDepth));
  cmd->add_option("--seed", o->seed, "path only: random seed; the same seed gives the same image on any thread count")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "normal and path modes: worker threads (default: all)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--quiet", o->quiet, "No progress bar or summary on stderr");
  cmd->add_option("--frames", o->frames,
                  "Render an animation of N frames; --out is then a pattern such as DIR/frame_%04d.png")
      ->check(CLI::Range(1, 1'000'000));
  cmd->add_option("--orbit", o->orbit, "With --frames: degrees the camera circles its target over the animation")
      ->check(CLI::Range(-36000.0, 36000.0));
  cmd->add_option("--video", o->video,
                  "With --frames: also pipe the frames to ffmpeg as this video file (30 frames/s); without ffmpeg, "
                  "says so and writes the PNGs only");
  cmd->add_flag("--compare", o->compare,
               "hw only: also render the same view-space world with the float reference and print how the two differ");
#ifdef TRIPSITTER_WITH_MPI
  cmd->footer("MPI: started by Open MPI's mpirun (mpirun -np K tripsitter render --mode path ...), the K ranks share\n"
              "the path tracer's work: rows of a still, frames of an animation. Rank 0 shows the progress and writes\n"
              "the output, which is the same bytes for any K. --threads is per rank. hw and normal modes refuse to\n"
              "run on more than one rank. See docs/mpi.md.");
#else
  cmd->footer("MPI: this build has none; under mpirun with more than one rank, render refuses to run (docs/mpi.md).");
#endif
  cmd->callback([o, &run] { run = [o] { return run_render(*o); }; });
}

}  // namespace tripsitter::cmd
