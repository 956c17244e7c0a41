// tripsitter render: one frame as the monitor shows it.
#include <algorithm>
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
#include <variant>

#include <nlohmann/json.hpp>

#include <tripsitter/board/capture.h>
#include <tripsitter/core/progress.h>
#include <tripsitter/core/screen.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/resources.h>
#include <tripsitter/display/monitor.h>
#include <tripsitter/display/png.h>
#include <tripsitter/display/vcd.h>
#include <tripsitter/modes/animation.h>
#include <tripsitter/modes/device_compare.h>
#include <tripsitter/render/aov.h>
#include <tripsitter/scene/builtin.h>

#include "commands.h"
#include "common.h"
#include "options.h"
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

// --device with the RTL's settings from render's options: the SPI clock, the VCD and its lines.
DeviceChoice rtl_choice(const RenderOptions& o) {
  DeviceChoice c = o.device;
  c.spi_hz = o.source.board.spi.clock_hz;
  c.vcd = o.vcd;
  c.vcd_lines = o.lines;
  return c;
}

// The --vcd file, opened before rendering so that a bad path fails before any work; null without --vcd.
// With --device rtl the RTL writes its own (rtl_device.h): null here too.
std::unique_ptr<display::VcdFile> open_vcd(const RenderOptions& o) {
  if (o.vcd.empty() || wants_rtl(o.device)) return nullptr;
  auto file = display::VcdFile::open(o.vcd, static_cast<std::uint64_t>(o.lines) * device::kVga640x480.h_total());
  if (!file) throw InputError(file.error().message);
  return std::move(file).value();
}

void keep(display::VcdFile* vcd, const std::string& path) {
  if (vcd == nullptr) {
    if (!path.empty()) std::cerr << "wrote " << path << " (the RTL's pins and outputs at every clock)\n";
    return;
  }
  auto kept = vcd->keep();
  if (!kept) throw InputError(kept.error().message);
  std::cerr << "wrote " << path << " (" << kept.value() << " pixel clocks)\n";
}

// What a path frame's pixels cost the hardware (device/resources.h): operations per pixel, DSP slices, frame memory.
void report_resources(const modes::HwFrame& f, const device::DevicePreset& preset) {
  const auto spheres = static_cast<std::int64_t>(f.scene_memory != nullptr ? f.scene_memory->geometry.size() : 0);
  const device::Operations ops = device::path_operations_per_pixel(
      preset, f.device.path, spheres, std::uint64_t{core::kScreenWidth} * core::kScreenHeight);
  const device::Resources r = device::resources(preset);
  std::fprintf(stderr,
               "device: per pixel of the last frame %.1f multiplies, %.1f additions, %.2f square roots, %.2f divisions, "
               "%.2f random draws\n",
               ops.total_multiplies(), ops.additions, ops.square_roots, ops.divisions, ops.random_draws);
  std::fprintf(stderr,
               "device: %d DSP48E1 slices per worker and %d shared: %d workers fit the XC7A100T's %d (this run has %d); "
               "frame memory %.1f Mbit (%s)\n",
               r.dsp_per_worker, r.dsp_shared, r.workers_fitting, device::kBoardDsp, preset.workers,
               static_cast<double>(r.frame_memory_bits) / 1e6,
               !r.frame_memory_part.empty() ? "external: more than the 4.9 Mbit of block RAM"
               : r.frame_memory_in_bram     ? "in the block RAM"
                                            : "in the block RAM, whose 4.9 Mbit cannot hold it");
  if (!r.frame_memory_part.empty())
    std::fprintf(stderr,
                 "device: frame memory in %s, %d pins: a line's reads and writes are %.1f%% of what its pins carry in "
                 "a line, done in %.1f%% of the line at worst\n",
                 r.frame_memory_part.c_str(), r.frame_memory_pins, 100 * r.frame_memory_demand,
                 100 * r.frame_memory_busy);
}

void report(const modes::HwFrame& f, int frames, const device::DevicePreset& preset) {
  std::cerr << "device: " << f.device.late_pixels << " late pixels on " << f.device.late_lines << " lines";
  if (f.device.demand_known)
    std::cerr << "; the busiest line needs " << f.device.worst_line_cycles << " of its " << preset.lead_cycles
              << " cycles" << (f.device.late_pixels > 0 && !preset.demand_exact() ? " or more" : "");
  std::cerr << "\n";
  if (f.frame_memory != nullptr && f.device.has_world && f.samples > 0) {
    std::cerr << "device: " << f.samples << " samples per pixel accumulated in frame memory over " << frames
              << (frames == 1 ? " frame" : " frames") << " (by pixels on time in every frame), " << f.device.rays
              << " rays in the last\n";
    report_resources(f, preset);
  }
  std::cerr << "link: " << f.link_bytes << " bytes, " << f.link_seconds * 1e3 << " ms at the SPI clock\n"
            << "host: " << f.saturations.total() << " saturated values\n";
  if (f.spheres_dropped > 0) std::cerr << "host: " << f.spheres_dropped << " spheres beyond scene memory were not sent\n";
}

// --compare of a path-tracing preset: frame memory's linear mean against the float path tracer of the device's
// rays, over the pixels with samples.
void print_path_comparison(const RenderOptions& o, const modes::SourceConfig& config, const modes::PathComparison& c,
                           int frames) {
  // By what the camera ray meets first: the sky, or a sphere of each material.
  std::vector<std::pair<std::string, modes::PartComparison>> parts{{"sky", c.sky}};
  for (auto type : {scene::MaterialType::kLambertian, scene::MaterialType::kMetal, scene::MaterialType::kDielectric})
    parts.emplace_back(scene::material_name(type), c.material[static_cast<std::size_t>(type)]);
  if (o.json) {
    nlohmann::json doc = {{"scene", o.scene},
                          {"preset", config.board.preset.name},
                          {"mean_relative_bias", c.figures.mean_relative_bias},
                          {"relmse", c.figures.relmse},
                          {"device_spp", c.device_spp},
                          {"device_spp_min", c.min_spp},
                          {"device_spp_max", c.max_spp},
                          {"reference_spp", c.reference_spp},
                          {"depth", c.depth},
                          {"seed", o.source.seed},
                          {"frames", frames},
                          {"spheres", c.spheres},
                          {"pixels", c.pixels},
                          {"pixels_compared", c.pixels_compared},
                          {"pixels_without_samples", c.pixels_without_samples},
                          {"late_pixels", c.late_pixels},
                          {"late_lines", c.late_lines}};
    for (const auto& [name, part] : parts)
      doc["by_first_hit"][name] = {{"pixels", part.pixels},
                                   {"mean_relative_bias", part.figures.mean_relative_bias},
                                   {"relmse", part.figures.relmse}};
    std::printf("%s\n", doc.dump(2).c_str());
    return;
  }
  std::printf("vs float path tracer of the device's rays (same sky, %d rays per path, %d samples per pixel, seed %llu):\n"
              "  mean relative bias %+.4f (%+.2f%%), relative MSE %.5f\n"
              "  over %zu of %zu pixels, each with %d to %d samples (%d per pixel on time in every frame); "
              "%zu pixels without samples left out\n",
              c.depth, c.reference_spp, static_cast<unsigned long long>(o.source.seed), c.figures.mean_relative_bias,
              100 * c.figures.mean_relative_bias, c.figures.relmse, c.pixels_compared, c.pixels, c.min_spp, c.max_spp,
              c.device_spp, c.pixels_without_samples);
  std::printf("  by what the camera ray meets first:\n");
  for (const auto& [name, part] : parts) {
    if (part.pixels == 0) continue;
    std::printf("    %-10s %7zu pixels: mean relative bias %+.4f (%+.2f%%), relative MSE %.5f\n", name.c_str(),
                part.pixels, part.figures.mean_relative_bias, 100 * part.figures.mean_relative_bias, part.figures.relmse);
  }
}

// --compare of a normal-shaded device: its VGA frame against the float renderer's, level by level.
void print_shaded_comparison(const RenderOptions& o, const modes::SourceConfig& config, const core::ImageDiff& d,
                             const modes::HwFrame& frame) {
  if (o.json) {
    const nlohmann::json doc = {{"scene", o.scene},
                                {"preset", config.board.preset.name},
                                {"pixels", d.pixels},
                                {"differing", d.differing},
                                {"over_one_level", d.over_one_level},
                                {"max_level_difference", d.max_level_difference},
                                {"late_pixels", frame.device.late_pixels},
                                {"late_lines", frame.device.late_lines}};
    std::printf("%s\n", doc.dump(2).c_str());
    return;
  }
  std::printf("vs float reference: %zu of %zu pixels differ (%.3f%%), %zu by more than one level, at most %d levels\n",
              d.differing, d.pixels, 100.0 * static_cast<double>(d.differing) / static_cast<double>(d.pixels),
              d.over_one_level, d.max_level_difference);
}

// --compare: modes::compare_device decides what the frame is compared with; a path reference shows its progress.
void compare(const RenderOptions& o, const scene::Scene& scene, const modes::SourceConfig& config,
             const modes::HwFrame& frame, int frames) {
  modes::PathComparisonSettings settings;
  settings.reference_spp = o.reference_spp > 0 ? o.reference_spp : modes::default_reference_spp(frame.samples);
  settings.seed = o.source.seed;
  settings.threads = o.source.threads;
  const auto row_samples = static_cast<std::uint64_t>(core::kScreenWidth) * static_cast<std::uint64_t>(settings.reference_spp);
  std::optional<core::ProgressBar> bar;
  if (device::traces_paths(config.board.preset, config.board.wire)) {
    bar.emplace("reference", row_samples * core::kScreenHeight, "samples", !o.quiet, std::cerr);
    settings.on_row = [&](int) { bar->add(row_samples); };
  }
  const modes::DeviceComparison c = modes::compare_device(scene, config, frame, settings);
  if (bar) bar->finish();
  if (const auto* path = std::get_if<modes::PathComparison>(&c))
    print_path_comparison(o, config, *path, frames);
  else
    print_shaded_comparison(o, config, std::get<core::ImageDiff>(c), frame);
}

// --aov DIR: the feature buffers as albedo.png, normal.png and depth.png (render/aov.h says how each is drawn).
void write_aovs(const std::string& dir, const render::Aovs& aovs) {
  for (const auto& [name, image] : {std::pair{"albedo", render::albedo_image(aovs)}, std::pair{"normal", render::normal_image(aovs)},
                                    std::pair{"depth", render::depth_image(aovs)}}) {
    const std::string path = (std::filesystem::path(dir) / (std::string(name) + ".png")).string();
    auto written = display::write_png(path, image);
    if (!written) throw InputError(written.error().message);
  }
  std::cerr << "wrote albedo.png, normal.png and depth.png in " << dir << "\n";
}

// Samples of a whole image.
std::uint64_t samples_of(const render::PathSettings& s) {
  return s.row_samples() * static_cast<std::uint64_t>(s.height);
}

// --frames N --orbit DEG: the camera circles its target by DEG over the N frames, each frame through the same
// road as a still.
int run_animation(const RenderOptions& o, const scene::Scene& scene) {
  const modes::SourceConfig config = source_config(o, scene);
  const std::unique_ptr<modes::FrameSource> source = modes::make_frame_source(scene, config);
  const std::unique_ptr<display::VideoPipe> video = open_video(o, config.width, config.height);
  core::ProgressBar bar("animation", static_cast<std::uint64_t>(o.frames), "frames", !o.quiet, std::cerr);
  modes::animate(*source, o.frames, o.orbit, {}, [&](int i, const modes::Frame* frame) {
    write_quietly(frame_path(o.out, i), *frame, o);
    if (video) video->add(modes::rgb8(*frame));
    bar.add(1);
  });
  bar.finish();
  if (video) video->finish(std::cerr);
  std::cerr << "wrote " << o.frames << " frames, " << frame_path(o.out, 0) << " to " << frame_path(o.out, o.frames - 1)
            << "\n";
  return kExitOk;
}

// --link-input: the device alone, fed raw link bytes as a real host would send them.
int run_device_alone(const RenderOptions& o) {
  const std::vector<std::uint8_t> bytes = read_bytes(o.link_input);
  const std::unique_ptr<display::VcdFile> vcd = open_vcd(o);
  const device::DevicePreset preset = load_preset(o.preset, o.workers, o.bounces);
  const link::WireVersion wire = o.source.board.wire;
  const auto make_rtl = device_maker(rtl_choice(o), preset, wire);
  const std::unique_ptr<device::Backend> device =
      make_rtl ? make_rtl() : std::make_unique<device::Device>(preset, wire);
  device::Backend& dev = *device;
  display::VgaMonitor monitor;
  const std::span<const std::uint8_t> all(bytes);
  for (std::size_t at = 0; at < all.size(); at += o.source.board.spi.max_transfer_bytes)
    dev.transfer(all.subspan(at, std::min(o.source.board.spi.max_transfer_bytes, all.size() - at)));
  dev.end_of_stream();
  board::CapturedFrame captured = board::capture_frame(dev, monitor, [&vcd](const device::VgaSample& s) {
    if (vcd) vcd->sample(s);
  });
  const auto& rx = dev.receiver_stats();
  std::cerr << "device: " << rx.worlds_accepted << " worlds accepted, " << rx.worlds_missing
            << " missing (lost on the link), " << rx.worlds_replayed << " replayed, " << rx.frames_rejected
            << " frames rejected, " << rx.garbage_runs << " runs of garbage (" << rx.bytes_dropped
            << " bytes dropped)\n";
  if (!captured.stats.has_world)
    throw InputError(o.link_input + ": no intact world in " + std::to_string(bytes.size()) + " bytes" +
                     (rx.last_error.empty() ? "" : " (last error: " + rx.last_error + ")"));
  std::cerr << "device: showing world " << captured.stats.sequence << ", " << captured.stats.late_pixels
            << " late pixels on " << captured.stats.late_lines << " lines\n";
  modes::HwFrame frame;
  frame.vga = std::move(captured.image);
  write_image(o.out, std::move(frame), o);
  keep(vcd.get(), o.vcd);
  return kExitOk;
}

int run_render(const RenderOptions& o) {
  const MpirunPlace place = mpirun_place();
#ifdef TRIPSITTER_WITH_MPI
  if (place.size > 0 && o.source.mode == modes::Mode::kPath) return run_render_mpi(o);
  const std::string name(modes::mode_name(o.source.mode));
  const std::string refusal = "--mode " + name + " under mpirun: only --mode path shares its work among MPI ranks; run " +
                              name + " without mpirun";
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
  if (!o.link_input.empty()) return run_device_alone(o);

  const scene::Scene scene = load_scene(o.scene);
  if (o.frames > 0) return run_animation(o, scene);
  if (o.source.mode == modes::Mode::kPath) {
    return run_path_still(o, scene, {}, true, "");
  }
  const std::unique_ptr<display::VcdFile> vcd = open_vcd(o);
  modes::SourceConfig config = source_config(o, scene);
  if (vcd) config.probe = [&vcd](const device::VgaSample& s) { vcd->sample(s); };
  const std::unique_ptr<modes::FrameSource> source = modes::make_frame_source(scene, config);
  // --accumulate N: the still world N times; a path-tracing device adds each frame's samples to frame memory.
  const int frames = std::max(1, o.accumulate);
  const auto started = std::chrono::steady_clock::now();
  const modes::Frame* shown = &source->draw();
  for (int i = 1; i < frames; ++i) shown = &source->draw();
  const modes::Frame& frame = *shown;
  const auto* hw = std::get_if<modes::HwFrame>(&frame);
  if (hw != nullptr && !o.quiet) report(*hw, frames, config.board.preset);
  if (config.board.make_device && !o.quiet)
    std::cerr << "device (RTL): simulated in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()
              << " s, the world's transfer and the frames to its first one included\n";
  if (o.compare) compare(o, scene, config, std::get<modes::HwFrame>(frame), frames);
  write_image(o.out, frame, o);
  keep(vcd.get(), o.vcd);
  return kExitOk;
}

}  // namespace

void check_options(const RenderOptions& o) {
  using modes::Mode;
  const Mode mode = o.source.mode;
  if (mode == Mode::kNormal && (o.spp != 0 || o.depth != 0))
    throw InputError("--spp and --depth need --mode path, or --mode hw with a path preset (normal traces one ray per pixel)");
  const link::WireVersion wire = o.source.board.wire;
  const device::DevicePreset preset =
      load_preset(o.preset, o.workers, o.bounces, mode == Mode::kHw ? o.spp : 0, mode == Mode::kHw ? o.depth : 0);
  const bool traced = mode == Mode::kHw && device::traces_paths(preset, wire);
  if (mode == Mode::kHw && ((o.width != 0 && o.width != 640) || (o.height != 0 && o.height != 480)))
    throw InputError("--mode hw draws the VGA monitor's 640x480 only; other sizes need --mode normal or path");
  if (mode != Mode::kHw && !o.vcd.empty()) throw InputError("--vcd needs --mode hw (the float renderers have no VGA signal)");
  if (mode != Mode::kHw && !o.link_input.empty()) throw InputError("--link-input needs --mode hw");
  if (wants_rtl(o.device) && mode != Mode::kHw) throw InputError("--device rtl needs --mode hw (the RTL is the device)");
  if (o.device.vcd_worker >= 0 && (!wants_rtl(o.device) || o.vcd.empty()))
    throw InputError("--vcd-worker adds a worker's signals to the RTL's VCD: it needs --device rtl and --vcd FILE");
  if (o.compare && (mode != Mode::kHw || !o.link_input.empty()))
    throw InputError("--compare needs --mode hw with a scene (it renders the same world in float)");
  if (o.frames == 0 && (o.orbit != 0 || !o.video.empty())) throw InputError("--orbit and --video need --frames N");
  if (o.frames > 0 && (!o.vcd.empty() || !o.link_input.empty() || o.compare))
    throw InputError("--frames renders an animation: --vcd, --link-input and --compare are for one frame");
  if (o.json && !o.compare) throw InputError("--json prints --compare's figures: it needs --compare");
  if (o.reference_spp != 0 && !(o.compare && traced))
    throw InputError("--reference-spp sets the float path tracer --compare runs for a path-tracing device: it needs "
                     "--compare with --mode hw and a path preset (on a framed wire, v2 or v3)");
  if (o.accumulate != 0 && !traced)
    throw InputError("--accumulate needs --mode hw with a path-tracing preset (--preset path or artix-path) on a framed "
                     "wire (v2 or v3): only its frame memory accumulates the frames of a still world");
  if (o.accumulate != 0 && (o.frames > 0 || !o.link_input.empty()))
    throw InputError("--accumulate shows one still world for several frames: not with --frames or --link-input");
  if (!o.aov.empty() && o.frames > 0) throw InputError("--aov writes the feature buffers of a still: not with --frames");
  if (o.frames > 0) check_pattern(o.out);
  if (mode != Mode::kPath) {
    if (o.source.sampler != render::SamplerKind::kSobol) throw InputError("--sampler needs --mode path");
    if (o.source.denoise) throw InputError("--denoise needs --mode path (hw and normal pictures are not noisy)");
    if (!o.aov.empty()) throw InputError("--aov needs --mode path (the path tracer writes the feature buffers)");
    if (display::is_exr(o.out)) throw InputError("--out " + o.out + ": EXR files hold the path tracer's linear light; use --mode path, or a .png name");
  }
}

void check_outputs(const RenderOptions& o) {
  if (o.frames == 0) {
    check_output_path(o.out);
  } else {
    check_output_path(frame_path(o.out, 0));
    if (!o.video.empty()) check_output_path(o.video);
  }
  if (!o.vcd.empty()) check_output_path(o.vcd);
  if (!o.aov.empty() && !std::filesystem::is_directory(o.aov))
    throw InputError("--aov " + o.aov + ": not a directory (create it first)");
}

modes::SourceConfig source_config(const RenderOptions& o, const scene::Scene& scene) {
  modes::SourceConfig c = o.source;
  const bool monitor = c.mode == modes::Mode::kHw;
  c.board.preset = load_preset(o.preset, o.workers, o.bounces, monitor ? o.spp : 0, monitor ? o.depth : 0);
  if (monitor) c.board.make_device = device_maker(rtl_choice(o), c.board.preset, c.board.wire);
  c.width = monitor ? core::kScreenWidth : (o.width != 0 ? o.width : scene.render.width);
  c.height = monitor ? core::kScreenHeight : (o.height != 0 ? o.height : scene.render.height);
  c.spp = o.spp != 0 ? o.spp : scene.render.spp;
  c.max_depth = o.depth != 0 ? o.depth : scene.render.max_depth;
  c.aovs = !o.aov.empty() || display::is_exr(o.out);
  return c;
}

int run_path_still(const RenderOptions& o, const scene::Scene& scene, const modes::PathTrace& trace, bool writes,
                   const std::string& where) {
  modes::SourceConfig config = source_config(o, scene);
  const render::PathSettings s = modes::path_settings(config);
  std::optional<core::ProgressBar> bar;
  config.trace = trace;
  config.on_samples = [&bar](std::uint64_t n) { bar->add(n); };
  const auto t0 = std::chrono::steady_clock::now();
  const std::unique_ptr<modes::FrameSource> source = modes::make_frame_source(scene, config);  // builds the BVH
  const auto t1 = std::chrono::steady_clock::now();
  bar.emplace("path", samples_of(s), "samples", !o.quiet && writes, std::cerr);
  const modes::Frame& frame = source->draw();
  bar.reset();
  if (!writes) return kExitOk;
  const double trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  if (!o.quiet) {
    std::fprintf(stderr, "path: %zu spheres, BVH built in %.3f s; %dx%d at %d spp in %.2f s (%.2f Msamples/s)%s\n",
                 scene.spheres.size(), std::chrono::duration<double>(t1 - t0).count(), s.width, s.height, s.spp,
                 trace_seconds, static_cast<double>(samples_of(s)) / trace_seconds / 1e6, where.c_str());
  }
  write_image(o.out, frame, o);
  if (!o.aov.empty()) write_aovs(o.aov, *std::get<modes::PathFrame>(frame).aovs);
  return kExitOk;
}

std::string frame_path(const std::string& pattern, int frame) {
  char buf[4096];
  std::snprintf(buf, sizeof buf, pattern.c_str(), frame);
  return buf;
}

void write_quietly(const std::string& path, const modes::Frame& frame, const RenderOptions& o) {
  auto written = modes::write_image(path, frame, o.exr_pixel);
  if (!written) throw InputError(written.error().message);
}

void write_image(const std::string& path, const modes::Frame& frame, const RenderOptions& o) {
  write_quietly(path, frame, o);
  const modes::PictureSize size = modes::picture_size(frame);
  std::cerr << "wrote " << path << " (" << size.width << "x" << size.height << ")\n";
}

std::unique_ptr<display::VideoPipe> open_video(const RenderOptions& o, int width, int height) {
  if (o.video.empty()) return nullptr;
  auto video = display::VideoPipe::open(o.video, width, height, std::cerr);
  if (!video) throw InputError("--video " + video.error().message);
  return std::move(video).value();
}

void add_render_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render one frame as the board's monitor shows it, to a PNG file");
  add_scene_option(*cmd, o->scene);
  add_mode_option(*cmd, o->source.mode,
                  "hw: host -> link -> device -> VGA capture, bit-exact fixed point (640x480 only);\n"
                  "normal: the float reference of the same rays and shading, mirrors included (any size);\n"
                  "path: the float path tracer with materials, bounces, samples and the scene's thin-lens camera,\n"
                  "      written sRGB-encoded");
  add_preset_option(*cmd, o->preset);
  cmd->add_option("--workers", o->workers,
                  "Number of device workers (the artix preset's sphere units), 1..640 (default: the preset's)")
      ->check(CLI::Range(1, 640));
  cmd->add_option("--bounces", o->bounces,
                  "Device mirror bounces off metal spheres, 0..6 (default: the preset's); also used by --mode normal")
      ->check(CLI::Range(0, 6));
  add_wire_option(*cmd, o->source.board.wire, "with v1 the device shows the last sphere");
  cmd->add_option("--width", o->width, "Image width, normal and path modes (default: the scene's render.width; hw is 640)")
      ->check(CLI::Range(1, scene::kMaxImageSide));
  cmd->add_option("--height", o->height, "Image height, normal and path modes (default: the scene's render.height; hw is 480)")
      ->check(CLI::Range(1, scene::kMaxImageSide));
  cmd->add_option("--out", o->out,
                  "Output file: PNG, or with --mode path FILE.exr (OpenEXR: linear RGB, with the feature buffers as "
                  "layers albedo.R/G/B, normal.X/Y/Z and Z)")
      ->capture_default_str();
  add_device_option(*cmd, o->device);
  cmd->add_option("--vcd", o->vcd,
                  "Also dump the VGA signal (hsync, vsync, r, g, b) as a VCD file (hw only); with --device rtl, the "
                  "RTL's pins and simulation outputs at every clock, from reset to --lines lines into the frame drawn");
  cmd->add_option("--vcd-worker", o->device.vcd_worker,
                  "With --device rtl and --vcd: also every signal inside this worker (0 to workers - 1)")
      ->check(CLI::Range(0, 639));
  cmd->add_option("--lines", o->lines, "Lines of signal in the VCD, counted from the device's reset at the start of "
                                       "vertical blanking (line 480); 525 is one whole frame. With --device rtl, "
                                       "counted from the start of the frame drawn")
      ->capture_default_str()->check(CLI::Range(1, 525 * 4));
  cmd->add_option("--link-input", o->link_input,
                  "Feed the device raw link bytes from this file ('-' for stdin) instead of a scene; with v1, each 8 "
                  "bytes are one word, most significant byte first");
  cmd->add_option("--transfer-bytes", o->source.board.spi.max_transfer_bytes, "Largest SPI transfer in bytes")
      ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30));
  cmd->add_option("--spi-hz", o->source.board.spi.clock_hz, "SPI clock in Hz, for the link time report; with --device rtl, SCLK on the "
                                         "RTL's pins (at most 12.5 MHz)")
      ->capture_default_str()->check(CLI::Range(std::int64_t{1}, std::int64_t{1'000'000'000'000}));
  cmd->add_option("--spp", o->spp,
                  "--mode path: samples per pixel (default: the scene's render.spp);\n"
                  "--mode hw --preset path or artix-path: samples per pixel the device adds to frame memory each frame, 1..255\n"
                  "(default 1); a pixel late in a frame gets none that frame, and one stops at 255")
      ->check(CLI::Range(1, scene::kMaxSpp));
  cmd->add_option("--depth", o->depth,
                  "--mode path: most bounces along one path (default: the scene's render.max_depth);\n"
                  "--mode hw --preset path or artix-path: rays per path on the device, 1..16 (default 4)")
      ->check(CLI::Range(1, scene::kMaxDepth));
  cmd->add_option("--seed", o->source.seed,
                  "--mode path: random seed; the same seed gives the same image on any thread count. With --compare and "
                  "--preset path or artix-path: the float reference's seed (the device's own random numbers do not take one)")
      ->capture_default_str();
  cmd->add_option("--threads", o->source.threads,
                  "normal and path modes, and --compare's float path tracer: worker threads (default: all)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--quiet", o->quiet, "No progress bar or summary on stderr");
  add_sampler_option(*cmd, o->source.sampler, "--mode path");
  cmd->add_flag("--denoise", o->source.denoise,
                "--mode path: filter the picture with the edge-avoiding a-trous denoiser, guided by the first hits' "
                "albedo, normal and depth (docs/denoiser.md); stills and animations");
  cmd->add_option("--aov", o->aov,
                  "--mode path, a still: also write the feature buffers (first hits' albedo, normal, depth) as "
                  "albedo.png, normal.png and depth.png in this existing directory");
  add_exr_pixel_option(*cmd, o->exr_pixel, "with --out FILE.exr");
  cmd->add_option("--frames", o->frames,
                  "Render an animation of N frames; --out is then a pattern such as DIR/frame_%04d.png")
      ->check(CLI::Range(1, 1'000'000));
  cmd->add_option("--orbit", o->orbit, "With --frames: degrees the camera circles its target over the animation")
      ->check(CLI::Range(-36000.0, 36000.0));
  cmd->add_option("--video", o->video,
                  "With --frames: also pipe the frames to ffmpeg as this video file (30 frames/s); without ffmpeg, "
                  "says so and writes the PNGs only");
  cmd->add_flag("--compare", o->compare,
               "hw only: also render the same view-space world in float and print how the two differ (stdout).\n"
               "Presets that trace one ray per pixel: against the float reference of the device's shading, pixels\n"
               "and 4-bit levels that differ. --preset path or artix-path: frame memory's accumulated linear mean (not the\n"
               "4-bit picture) against the float path tracer tracing the device's own rays from its scene memory\n"
               "(same sky, same rays per path, --reference-spp samples); prints the mean relative bias and the\n"
               "relative MSE over the pixels with samples (pixels late in every frame have none: left out, counted),\n"
               "and the same by what each pixel's camera ray meets first: sky, lambertian, metal, dielectric");
  cmd->add_flag("--json", o->json,
                "With --compare: print the figures as one JSON object on stdout instead (--preset path or artix-path: keys\n"
                "mean_relative_bias, relmse, device_spp, reference_spp, depth, late_pixels, pixels_without_samples,\n"
                "by_first_hit, ...; other presets: pixels, differing, over_one_level, max_level_difference, ...)");
  cmd->add_option("--reference-spp", o->reference_spp,
                  "With --compare and --preset path or artix-path: samples per pixel of the float path tracer (default: the larger "
                  "of 256 and 4 x the device's samples per pixel)")
      ->check(CLI::Range(1, scene::kMaxSpp));
  cmd->add_option("--accumulate", o->accumulate,
                  "--mode hw --preset path or artix-path: show the still world for N frames, so that frame memory accumulates up\n"
                  "to N x --spp samples per pixel (at most 255); writes, and with --compare compares, the last")
      ->check(CLI::Range(1, 1'000'000));
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
