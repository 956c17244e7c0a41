// One point of a sweep measured: its configuration run through the board (host, link and the device's bit-exact
// fast model, modes/frame_source.h), then compared with the float renderer of the same world.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include <tripsitter/core/image.h>
#include <tripsitter/explore/point.h>
#include <tripsitter/render/device_view.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::explore {

struct EvaluateSettings {
  int reference_spp = 64;  // the float path tracer's samples per pixel, for the path preset's error
  std::uint64_t seed = 1;  // the reference's
  bool thumbnail = true;   // keep the monitor's frame, scaled to 160 x 120, as PNG
};

// The path preset's references, shared among the points of a sweep: the float path tracer of the world in scene
// memory depends only on that world, the depth and the samples per pixel, so points that change only the workers,
// spp, SPI or frame memory share one. Safe to use from several threads; a reference is rendered once.
class ReferenceCache {
 public:
  using Key = std::tuple<std::string, int, int, std::uint64_t>;  // world (as text), depth, spp, seed
  // The reference of `key`, rendered by `render` the first time it is asked for.
  std::shared_ptr<const core::ImageRgbF> get(const Key& key, const std::function<core::ImageRgbF()>& render);
  std::size_t size() const;

 private:
  struct Entry {
    std::once_flag once;
    std::shared_ptr<const core::ImageRgbF> image;
  };
  mutable std::mutex mutex_;
  std::map<Key, std::shared_ptr<Entry>> entries_;
};

// The monitor's refresh rate, frames per second (25 MHz / (800 x 525)).
double refresh_hz();

// Runs `config` over `scene` (a scene the configuration's name loads) on the calling thread alone, and measures
// it (point.h). REQUIRES config to come from expand() (sweep.h).
Point evaluate(const Configuration& config, const scene::Scene& scene, const EvaluateSettings& settings,
               ReferenceCache& references);

}  // namespace tripsitter::explore
