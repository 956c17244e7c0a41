#include <tripsitter/device/device.h>

#include <algorithm>
#include <stdexcept>

namespace tripsitter::device {
namespace {

DevicePreset checked(const DevicePreset& preset) {
  if (auto why = preset.validate()) throw std::invalid_argument("device preset '" + preset.name + "': " + *why);
  return preset;
}

}  // namespace

Device::Device(const DevicePreset& preset, link::WireVersion wire, int threads, DeviceModel model)
    : preset_(checked(preset)), wire_(wire), receiver_(preset_, wire),
      controller_(preset_),
      ahead_(model == DeviceModel::kPlain ? nullptr : std::make_unique<FrameLines>(preset_, threads)),
      memory_(preset_.path ? std::make_unique<FrameMemory>() : nullptr) {
  if (preset_.path) {
    path_frame_.spp = preset_.path->spp;
    path_frame_.depth = preset_.path->depth;
    path_frame_.dither = preset_.path->dither;
  }
  // Out of reset at the start of vertical blanking.
  while (vga_.line() != vga_.mode().v_visible) vga_.tick();
}

void Device::next_path_frame(bool swapped) {
  if (!path_traced()) return;
  if (swapped && scene_.content != shown_content_) {
    shown_content_ = scene_.content;
    path_frame_.epoch = static_cast<std::uint8_t>((path_frame_.epoch + 1) % kEpochs);
    path_frame_.frame = 0;
    surfaces_.resize(scene_.surfaces.size());
    for (std::size_t i = 0; i < surfaces_.size(); ++i) surfaces_[i] = path_surface(scene_.surfaces[i]);
    path_frame_.surfaces = surfaces_;
  } else {
    ++path_frame_.frame;
  }
  building_.samples_per_pixel =
      static_cast<int>(std::min<std::uint64_t>(kMaxSamples / path_frame_.spp * path_frame_.spp,
                                               (std::uint64_t{path_frame_.frame} + 1) * static_cast<std::uint64_t>(path_frame_.spp)));
}

void Device::start_line(int line) {
  const VgaMode& mode = vga_.mode();
  if (line == mode.v_visible) {
    // Vertical blanking: a waiting world becomes scene memory, fixed until the next blanking.
    const bool swapped = receiver_.swap_if_pending(scene_);
    building_ = FrameStats{};
    building_.sequence = scene_.sequence;
    building_.has_world = scene_.valid;
    next_path_frame(swapped);
    if (ahead_) ahead_->start(scene_, path_traced() ? &path_frame_ : nullptr, memory_.get());
  }
  const int next = (line + 1) % mode.v_total();
  if (next < mode.v_visible) {
    auto& back = line_buffers_[static_cast<std::size_t>(1 - front_)];
    LineResult r;
    if (ahead_) {
      const FrameLines::Line& computed = ahead_->line(next);
      back = computed.pixels;
      r.late_pixels = computed.late_pixels;
      r.reflections = computed.reflections;
      r.demand_cycles = computed.demand_cycles;
      r.rays = computed.rays;
      building_.path += computed.counters;
    } else if (path_traced()) {
      r = controller_.render_path_line(next, scene_, path_frame_, memory_->row(next), back, building_.path);
    } else {
      r = controller_.render_line(next, scene_, back);
    }
    building_.rays += static_cast<std::uint64_t>(r.rays);
    building_.reflections += static_cast<std::uint64_t>(r.reflections);
    building_.worst_line_cycles = std::max(building_.worst_line_cycles, r.demand_cycles);
    if (r.late_pixels > 0) {
      building_.late_pixels += r.late_pixels;
      ++building_.late_lines;
      total_late_pixels_ += static_cast<std::uint64_t>(r.late_pixels);
      ++total_late_lines_;
    }
  }
}

VgaSample Device::tick() {
  const int col = vga_.column();
  const int line = vga_.line();
  if (col == 0) start_line(line);
  const core::Rgb444 colour =
      vga_.visible() ? line_buffers_[static_cast<std::size_t>(front_)][static_cast<std::size_t>(col)] : core::kBlack;
  const VgaSample s = vga_.sample(colour);
  if (col == vga_.mode().h_total() - 1) front_ = 1 - front_;  // end of line: the buffers swap
  vga_.tick();
  return s;
}

FrameStats Device::run_frame(const std::function<void(const VgaSample&)>& sink) {
  return run_frame_lines([&](std::span<const VgaSample> line) {
    for (const VgaSample& s : line) sink(s);
  });
}

// Line by line, the same samples tick() would give: syncs from the counters, colours from the front
// buffer, the buffers swapping at each line's end.
FrameStats Device::run_frame_lines(const std::function<void(std::span<const VgaSample>)>& line_sink) {
  const VgaMode& mode = vga_.mode();
  if (vga_.line() != mode.v_visible || vga_.column() != 0)
    throw std::logic_error("run_frame: the device is not at the start of vertical blanking");
  std::vector<VgaSample> samples(static_cast<std::size_t>(mode.h_total()));
  for (int i = 0; i < mode.v_total(); ++i) {
    const int line = vga_.line();
    start_line(line);
    const bool vsync_n = vga_.vsync_n();
    const auto& front = line_buffers_[static_cast<std::size_t>(front_)];
    const int shown = line < mode.v_visible ? mode.h_visible : 0;
    for (int col = 0; col < mode.h_total(); ++col)
      samples[static_cast<std::size_t>(col)] = {vga_.hsync_n_at(col), vsync_n,
                                                col < shown ? front[static_cast<std::size_t>(col)] : core::kBlack};
    front_ = 1 - front_;
    vga_.tick_line();
    line_sink(samples);
  }
  return building_;
}

}  // namespace tripsitter::device
