#include <tripsitter/explore/evaluate.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <variant>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/resources.h>
#include <tripsitter/device/vga_signal.h>
#include <tripsitter/display/png.h>
#include <tripsitter/explore/sweep.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/modes/device_compare.h>
#include <tripsitter/modes/frame_source.h>

namespace tripsitter::explore {
namespace {

constexpr int kThumbnailScale = 4;  // 640 x 480 to 160 x 120

// The mean of each kThumbnailScale x kThumbnailScale block.
core::ImageRgb8 thumbnail_of(const core::ImageRgb8& image) {
  core::ImageRgb8 out(image.width / kThumbnailScale, image.height / kThumbnailScale);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < kThumbnailScale; ++dy)
          for (int dx = 0; dx < kThumbnailScale; ++dx)
            sum += image.pixels[3 * (static_cast<std::size_t>(y * kThumbnailScale + dy) * static_cast<std::size_t>(image.width) +
                                     static_cast<std::size_t>(x * kThumbnailScale + dx)) +
                                static_cast<std::size_t>(c)];
        out.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(out.width) + static_cast<std::size_t>(x)) +
                   static_cast<std::size_t>(c)] = static_cast<std::uint8_t>((sum + kThumbnailScale * kThumbnailScale / 2) /
                                                                            (kThumbnailScale * kThumbnailScale));
      }
  return out;
}

// The world in scene memory as text: the reference cache's key.
std::string world_key(const modes::HwFrame& frame, int frac_bits) {
  std::string key = std::to_string(frac_bits);
  for (const scene::Sphere& s : modes::scene_memory_spheres(*frame.scene_memory, frac_bits)) {
    char buf[256];
    std::snprintf(buf, sizeof buf, ";%a,%a,%a,%a,%d,%a,%a,%a,%a,%a", s.center.x, s.center.y, s.center.z, s.radius,
                  static_cast<int>(s.material.type), s.material.albedo.x, s.material.albedo.y, s.material.albedo.z,
                  s.material.fuzz, s.material.ior);
    key += buf;
  }
  return key;
}

}  // namespace

std::shared_ptr<const core::ImageRgbF> ReferenceCache::get(const Key& key,
                                                             const std::function<core::ImageRgbF()>& render) {
  std::shared_ptr<Entry> entry;
  {
    const std::lock_guard lock(mutex_);
    auto& slot = entries_[key];
    if (!slot) slot = std::make_shared<Entry>();
    entry = slot;
  }
  std::call_once(entry->once, [&] { entry->image = std::make_shared<const core::ImageRgbF>(render()); });
  return entry->image;
}

std::size_t ReferenceCache::size() const {
  const std::lock_guard lock(mutex_);
  return entries_.size();
}

double refresh_hz() {
  const device::VgaMode& vga = device::kVga640x480;
  return static_cast<double>(device::kPixelClockHz) / (static_cast<double>(vga.h_total()) * vga.v_total());
}

Point evaluate(const Configuration& config, const scene::Scene& scene, const EvaluateSettings& settings,
               ReferenceCache& references) {
  const DeviceSetup setup = setup_of(config);
  modes::SourceConfig source;
  source.mode = modes::Mode::kHw;
  source.board.preset = setup.preset;
  source.board.wire = *link::wire_by_name(setup.wire);
  source.board.spi = setup.spi;
  source.board.device_threads = 1;
  source.threads = 1;
  const std::unique_ptr<modes::FrameSource> board = modes::make_frame_source(scene, source);
  const modes::Frame* shown = &board->draw();
  for (int i = 1; i < config.frames; ++i) shown = &board->draw();
  const modes::HwFrame& frame = std::get<modes::HwFrame>(*shown);

  Point point;
  point.config = config;
  Measurement& m = point.m;
  const device::FrameStats& d = frame.device;
  const device::DevicePreset& preset = setup.preset;
  m.late_pixels = d.late_pixels;
  m.late_lines = d.late_lines;
  m.line_load = static_cast<double>(d.worst_line_cycles) / preset.lead_cycles;
  m.link_bits = 8 * static_cast<std::uint64_t>(frame.link_bytes);
  m.link_ms = 1e3 * frame.link_seconds;
  m.link_transfers = (frame.link_bytes + static_cast<std::uint64_t>(config.transfer_bytes) - 1) /
                     static_cast<std::uint64_t>(config.transfer_bytes);
  m.fps = refresh_hz() / std::max(1.0, m.line_load);
  if (frame.link_seconds > 0) m.fps = std::min(m.fps, 1.0 / frame.link_seconds);
  m.saturations = frame.saturations.total();
  m.spheres = frame.scene_memory != nullptr ? frame.scene_memory->geometry.size() : 0;
  m.spheres_dropped = frame.spheres_dropped;
  const std::uint64_t pixels = std::uint64_t{core::kScreenWidth} * core::kScreenHeight;
  m.pixels = pixels;

  modes::PathComparisonSettings compare;
  compare.reference_spp = settings.reference_spp;
  compare.seed = settings.seed;
  compare.threads = 1;
  std::shared_ptr<const core::ImageRgbF> reference;
  if (device::traces_paths(preset, source.board.wire)) {
    reference = references.get(
        {world_key(frame, preset.frac_bits()), preset.path->depth, settings.reference_spp, settings.seed},
        [&] { return modes::device_path_reference(frame, preset, compare); });
    compare.reference = reference.get();
  }
  const modes::DeviceComparison c = modes::compare_device(scene, source, frame, compare);
  device::Operations ops;
  if (const auto* path = std::get_if<modes::PathComparison>(&c)) {
    m.relmse = path->figures.relmse;
    m.bias = path->figures.mean_relative_bias;
    m.reference_spp = path->reference_spp;
    m.pixels = path->pixels_compared;
    ops = device::path_operations_per_pixel(preset, d.path, static_cast<std::int64_t>(m.spheres), pixels);
  } else {
    const core::ImageDiff& diff = std::get<core::ImageDiff>(c);
    m.pixels = diff.pixels;
    m.differing = diff.differing;
    m.over_one_level = diff.over_one_level;
    m.max_levels = diff.max_level_difference;
    ops = device::mirror_operations_per_pixel(preset, static_cast<std::int64_t>(m.spheres), d.reflections, pixels);
  }
  m.multiplies = ops.total_multiplies();
  m.additions = ops.additions;
  m.square_roots = ops.square_roots;
  m.divisions = ops.divisions;
  m.random_draws = ops.random_draws;

  const device::Resources r = device::resources(preset);
  m.dsp_per_worker = r.dsp_per_worker;
  m.dsp_shared = r.dsp_shared;
  m.dsp = r.dsp_per_worker * preset.workers + r.dsp_shared;
  m.luts = r.luts;
  m.bram_kbit = static_cast<double>(r.bram_bits) / 1024.0;
  m.sram_bits_per_cycle = r.frame_memory_bits_per_cycle;

  if (settings.thumbnail) {
    auto png = display::encode_png(thumbnail_of(core::to_rgb8(frame.vga)));
    if (png) point.thumbnail_png = std::move(png).value();
  }
  return point;
}

}  // namespace tripsitter::explore
