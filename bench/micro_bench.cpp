// Google Benchmark micro-benchmarks of the kernels. Run: build/release/bench/micro_bench
#include <benchmark/benchmark.h>

#include <bit>
#include <cmath>
#include <random>

#include <tripsitter/board/board.h>
#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/controller.h>
#include <tripsitter/device/sqrt_unit.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/render/denoise.h>
#include <tripsitter/render/interactive.h>
#include <tripsitter/render/normal.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/render/primary.h>
#include <tripsitter/render/temporal.h>
#include <tripsitter/scene/builtin.h>

namespace {

using namespace tripsitter;

void BM_SqrtUnit(benchmark::State& state) {
  const device::SqrtUnit unit(static_cast<int>(state.range(0)));
  std::mt19937_64 rng(1);
  std::vector<core::UInt128> inputs(1024);
  for (auto& v : inputs) v = rng() >> 2;
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(unit(inputs[i++ & 1023]));
}
BENCHMARK(BM_SqrtUnit)->Arg(8)->Arg(16)->Arg(24);

// One device line (640 pixels) of a random world of N spheres.
void BM_DeviceLine(benchmark::State& state) {
  const device::DevicePreset preset = device::wide_preset();
  device::Device dev(preset, link::WireVersion::kV2);
  host::Host h(scene::random_spheres(static_cast<int>(state.range(0)), 1), board::formats_of(preset),
               link::WireVersion::kV2);
  dev.transfer(h.update().bytes);
  dev.run_frame([](const device::VgaSample&) {});
  const device::Controller controller(preset);
  std::array<core::Rgb444, device::kLineWidth> line;
  int row = 0;
  for (auto _ : state) {
    controller.render_line(row, dev.scene(), line);
    row = (row + 1) % 480;
  }
  state.SetItemsProcessed(state.iterations() * device::kLineWidth);
}
BENCHMARK(BM_DeviceLine)->Arg(1)->Arg(16)->Arg(64);

// One 640x480 frame of a random world of N spheres, as the host sends it, drawn by `draw`.
template <class Draw>
void normal_frame(benchmark::State& state, const Draw& draw) {
  host::Host h(scene::random_spheres(static_cast<int>(state.range(0)), 1), board::formats_of(device::wide_preset()),
               link::WireVersion::kV2);
  const std::vector<scene::Sphere> view = h.view();
  for (auto _ : state) benchmark::DoNotOptimize(draw(view));
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}

void BM_NormalReferenceFrame(benchmark::State& state) {
  normal_frame(state, [](const auto& spheres) { return render::render_normal(spheres, 640, 480); });
}
BENCHMARK(BM_NormalReferenceFrame)->Arg(1)->Arg(16)->Arg(64)->Unit(benchmark::kMillisecond);

// The window's normal mode: the same frame by render_normal_fast, on one thread.
void BM_NormalFastFrame(benchmark::State& state) {
  normal_frame(state, [](const auto& spheres) { return render::render_normal_fast(spheres, 640, 480, 0, 1); });
}
BENCHMARK(BM_NormalFastFrame)->Arg(1)->Arg(16)->Arg(64)->Arg(488)->Unit(benchmark::kMillisecond);

// One frame of a path-tracing preset through the whole board (host -> link -> device -> VGA capture), random-N, the
// device on one thread. The camera orbits half a degree back and forth, so that every frame is a new world's first
// and no pixel stops at 255 samples.
void board_path_frame(benchmark::State& state, const device::DevicePreset& preset) {
  board::BoardConfig config;
  config.preset = preset;
  config.device_threads = 1;
  board::Board b(scene::random_spheres(static_cast<int>(state.range(0)), 1), config);
  double step = 0.5;
  for (auto _ : state) {
    b.host().camera().orbit(step);
    step = -step;
    benchmark::DoNotOptimize(b.show());
  }
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}

// The path preset: the single-thread figure of `tripsitter bench`'s hw_path_fps_64.
void BM_BoardPathFrame(benchmark::State& state) { board_path_frame(state, device::path_preset()); }
BENCHMARK(BM_BoardPathFrame)->Arg(64)->Unit(benchmark::kMillisecond);

// The artix path preset's sphere units (docs/device.md, "Path tracing on the artix datapath"): the single-thread
// figure of `tripsitter bench --scene random-64 --mode hw --preset artix-path`.
void BM_BoardArtixPathFrame(benchmark::State& state) { board_path_frame(state, device::artix_path_preset()); }
BENCHMARK(BM_BoardArtixPathFrame)->Arg(64)->Unit(benchmark::kMillisecond);

// The artix units' filter (device/artix_batch.h) as a bounced ray's walk calls it: random-64 as the host sends it
// to the artix path preset (a root and its leaves), each ray leaving a sphere's surface in a random direction
// testing the root's children's bounds and every leaf's spheres, one run after another, the caller branching on
// each entry's byte as the walk does. Items are calls.
void BM_ArtixFilterRuns(benchmark::State& state) {
  const device::DevicePreset preset = device::artix_path_preset();
  device::Device dev(preset, link::WireVersion::kV3);
  host::Host h(scene::random_spheres(64, 1), board::formats_of(preset), link::WireVersion::kV3);
  dev.transfer(h.update().bytes);
  dev.run_frame([](const device::VgaSample&) {});
  device::artix::UnitWorld world = device::artix::prepare_world(dev.scene());
  device::artix::add_fast_search(world);
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<std::int64_t> component(-(1 << 16), 1 << 16);
  std::vector<device::artix::UnitRay> rays(1024);
  for (auto& ray : rays) {
    const auto& s = world.spheres[rng() % world.spheres.size()];
    const auto n = device::artix::unit_direction({component(rng), component(rng), component(rng)});
    for (std::size_t k = 0; k < 3; ++k) ray.o[k] = s.c[k] + ((n[k] * s.r) >> device::artix::kDirectionFrac);
    ray.d = device::artix::unit_direction({component(rng), component(rng), component(rng)});
  }
  std::vector<std::uint8_t> meets(device::artix::meets_room(world.spheres.size()));
  std::size_t i = 0;
  std::int64_t calls = 0, met = 0;
  const auto run = [&](const device::artix::UnitRay& ray, const device::artix::SphereBlock& block, int first, int n) {
    if (n == 0) return;
    device::artix::meets_line(ray, block, static_cast<std::size_t>(first), static_cast<std::size_t>(n), meets.data());
    for (int j = 0; j < n; ++j)
      if (meets[static_cast<std::size_t>(j)] != 0) ++met;
    ++calls;
  };
  for (auto _ : state) {
    const device::artix::UnitRay& ray = rays[i++ & 1023];
    for (const device::artix::UnitNode& node : world.nodes) {
      run(ray, world.sphere_block, node.first_sphere, node.spheres);
      run(ray, world.bound_block, node.first_child, node.children);
    }
  }
  benchmark::DoNotOptimize(met);
  state.SetItemsProcessed(calls);
  state.counters["runs_per_ray"] = static_cast<double>(calls) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ArtixFilterRuns);

void BM_DecodeV2(benchmark::State& state) {
  host::Host h(scene::random_spheres(static_cast<int>(state.range(0)), 1), board::formats_of(device::wide_preset()),
               link::WireVersion::kV2);
  const auto bytes = h.update().bytes;
  for (auto _ : state) benchmark::DoNotOptimize(link::decode_frame(link::WireVersion::kV2, bytes, 4096));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_DecodeV2)->Arg(64)->Arg(4096);

}  // namespace

// The path tracer's bounced rays as it makes them: every ray a 160x90 one-sample render of `field` asks of a
// HitQuery (render_path's HitQuery form traces them one at a time), recorded, without the camera rays. Their
// order keeps the render's: each round of a group's live paths together, so neighbours start near each other.
class RecordingQuery final : public render::HitQuery {
 public:
  explicit RecordingQuery(const render::Bvh& bvh) : bvh_(bvh) {}
  bool intersect(const render::Ray& ray, float t_min, float t_max, render::SphereHit& hit) const override {
    rays_.push_back(ray);
    return bvh_.intersect(ray, t_min, t_max, hit);
  }
  std::vector<render::Ray>& rays() const { return rays_; }

 private:
  const render::Bvh& bvh_;
  mutable std::vector<render::Ray> rays_;
};

std::vector<render::Ray> bounced_rays_of_field(const render::PathScene& scene, const scene::Scene& field) {
  const render::PathSettings s{.width = 160, .height = 90, .spp = 1, .max_depth = 50, .seed = 1, .threads = 1, .sky = {}};
  const render::ThinLensCamera camera(field.camera, s.width, s.height);
  const RecordingQuery recorder(scene.bvh());
  render::render_path(scene, recorder, camera, s);
  // Camera rays start on the lens, within 0.1 of lookfrom (its radius is 0.05); no sphere comes that near.
  std::vector<render::Ray> bounced;
  const render::Vec3f lens{static_cast<float>(field.camera.lookfrom.x), static_cast<float>(field.camera.lookfrom.y),
                   static_cast<float>(field.camera.lookfrom.z)};
  for (const render::Ray& r : recorder.rays()) {
    const render::Vec3f d = r.origin - lens;
    if (core::dot(d, d) > 0.01f) bounced.push_back(r);
  }
  return bounced;
}

// One ray at a time (Bvh::intersect); items are rays.
void BM_BvhBouncedRaysField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const std::vector<render::Ray> rays = bounced_rays_of_field(scene, field);
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    render::SphereHit hit;
    hits += scene.intersect(rays[i], render::kRayEpsilon, INFINITY, hit) ? 1 : 0;
    i = i + 1 == rays.size() ? 0 : i + 1;
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations());
  state.counters["rays_per_sample"] = static_cast<double>(rays.size()) / (160 * 90);
}
BENCHMARK(BM_BvhBouncedRaysField);

// The same rays eight neighbours at a time in one packet (Bvh::intersect_packet); items are rays.
void BM_BvhBouncedRaysPacketField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const std::vector<render::Ray> rays = bounced_rays_of_field(scene, field);
  const std::size_t packets = rays.size() / render::Bvh::kWidth;
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    render::Ray packet[render::Bvh::kWidth];
    for (int k = 0; k < render::Bvh::kWidth; ++k) packet[k] = rays[i * render::Bvh::kWidth + static_cast<std::size_t>(k)];
    render::SphereHit packet_hits[render::Bvh::kWidth];
    hits += static_cast<std::size_t>(
        std::popcount(scene.bvh().intersect_packet(packet, render::kRayEpsilon, INFINITY, packet_hits)));
    i = i + 1 == packets ? 0 : i + 1;
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations() * render::Bvh::kWidth);
}
BENCHMARK(BM_BvhBouncedRaysPacketField);

// The field camera's rays (lens jitter included) in packets of a row's eight pixels (Bvh::intersect_packet);
// items are rays.
void BM_BvhIntersectPacketField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const render::ThinLensCamera camera(field.camera, 640, 360);
  render::Rng rng(9);
  std::vector<render::Ray> rays;
  for (int row = 0; row < 360; row += 45)
    for (int col = 0; col < 640; ++col) rays.push_back(camera.ray(col, row, rng));
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    render::Ray packet[render::Bvh::kWidth];
    for (auto& r : packet) r = rays[i++ % rays.size()];
    render::SphereHit packet_hits[render::Bvh::kWidth];
    hits += static_cast<std::size_t>(std::popcount(scene.bvh().intersect_packet(packet, render::kRayEpsilon, INFINITY, packet_hits)));
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations() * render::Bvh::kWidth);
}
BENCHMARK(BM_BvhIntersectPacketField);

// A whole primary-ray frame, 640x480, one thread, over random-N.
void BM_PrimaryFrame(benchmark::State& state) {
  const scene::Scene sc = scene::random_spheres(static_cast<int>(state.range(0)), 1);
  const render::PathScene scene(sc.spheres);
  const render::ThinLensCamera camera(sc.camera, 640, 480);
  for (auto _ : state) benchmark::DoNotOptimize(render::render_primary(scene, camera, {.width = 640, .height = 480, .threads = 1}));
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_PrimaryFrame)->Arg(1)->Arg(488)->Arg(10000)->Unit(benchmark::kMillisecond);

// One path-traced sample per pixel of field at 160x90 (a slice of path_msamples_field), one thread.
void BM_PathField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const render::ThinLensCamera camera(field.camera, 160, 90);
  std::uint64_t seed = 1;
  for (auto _ : state) {
    const render::PathSettings s{.width = 160, .height = 90, .spp = 1, .max_depth = 50, .seed = seed++, .threads = 1, .sky = {}};
    benchmark::DoNotOptimize(render::render_path(scene, camera, s));
  }
  state.SetItemsProcessed(state.iterations() * 160 * 90);
}
BENCHMARK(BM_PathField)->Unit(benchmark::kMillisecond);

// The window's path mode per frame (render/interactive.h), its stages apart, field at 640x480, one thread.
// The camera of field orbited by `degrees` about its target.
render::ThinLensCamera orbited_field_camera(double degrees) {
  scene::CameraSettings c = scene::builtin("field")->camera;
  const double a = degrees * 3.14159265358979323846 / 180, ca = std::cos(a), sa = std::sin(a);
  const core::Vec3d d = c.lookfrom - c.lookat;
  c.lookfrom = c.lookat + core::Vec3d{d.x * ca + d.z * sa, d.y, -d.x * sa + d.z * ca};
  return render::ThinLensCamera(c, 640, 480);
}

// Reprojection: one pass added after a 0.75-degree move (a frame of the window's orbit), alternating two views.
void BM_ReprojectField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const render::ThinLensCamera cameras[2] = {orbited_field_camera(0), orbited_field_camera(0.75)};
  render::Aovs aovs[2];
  for (int k = 0; k < 2; ++k) render::render_primary_aovs(scene, cameras[k], {.width = 640, .height = 480, .threads = 1}, aovs[k]);
  const render::PathSettings s{.width = 640, .height = 480, .spp = 1, .max_depth = 50, .seed = 1, .threads = 1, .sky = {}};
  const core::ImageRgbF pass = render::render_path(scene, cameras[0], s);
  render::TemporalAccumulator history({.threads = 1});
  int k = 0;
  for (auto _ : state) {
    history.add(pass.pixels, aovs[k], cameras[k].pinhole());
    k ^= 1;
  }
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_ReprojectField)->Unit(benchmark::kMillisecond);

// The denoiser over a one-sample picture of field at the window's size: the filter's passes (the default 3, or
// 1 to 5) with a given variance, or the spatial variance estimate alone (passes 0), on 1 or 2 threads.
void BM_DenoiseField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const render::ThinLensCamera camera = orbited_field_camera(0);
  render::Aovs aovs;
  render::render_primary_aovs(scene, camera, {.width = 640, .height = 480, .threads = 1}, aovs);
  const render::PathSettings s{.width = 640, .height = 480, .spp = 1, .max_depth = 50, .seed = 1, .threads = 1, .sky = {}};
  const core::ImageRgbF pass = render::render_path(scene, camera, s);
  render::Denoiser denoiser;
  render::DenoiseSettings settings;
  settings.iterations = static_cast<int>(state.range(0));
  settings.threads = static_cast<int>(state.range(1));
  std::vector<float> variance(pass.pixels.size());
  std::vector<core::Vec3f> out(pass.pixels.size());
  denoiser.estimate_variance({.width = 640, .height = 480, .color = pass.pixels, .variance = {}, .aovs = &aovs},
                             settings.variance_radius, settings.threads, variance);
  for (auto _ : state) {
    if (settings.iterations == 0)
      denoiser.estimate_variance({.width = 640, .height = 480, .color = pass.pixels, .variance = {}, .aovs = &aovs},
                                 settings.variance_radius, settings.threads, variance);
    else
      denoiser.denoise({.width = 640, .height = 480, .color = pass.pixels, .variance = variance, .aovs = &aovs}, settings, out);
  }
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_DenoiseField)
    ->ArgNames({"passes", "threads"})
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// A whole frame of the window's loop while orbiting (feature buffers, paths, reprojection, variance, filter), one
// thread; the argument is the row step (paths on one row in that many).
void BM_InteractiveFrameField(benchmark::State& state) {
  const scene::Scene field = *scene::builtin("field");
  const render::PathScene scene(field.spheres);
  const render::PathSettings s{.width = 640, .height = 480, .spp = 1, .max_depth = 50, .seed = 1, .threads = 1, .sky = {}};
  render::InteractiveSettings settings;
  settings.row_step = static_cast<int>(state.range(0));
  render::InteractivePath loop(scene, s, settings);
  double degrees = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(loop.frame(orbited_field_camera(degrees)));
    degrees += 0.75;
  }
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_InteractiveFrameField)->ArgName("row_step")->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
