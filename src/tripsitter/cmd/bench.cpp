// tripsitter bench: the fixed benchmark suite (hw_fps_N, hw_path_fps_64, primary_mrays_N, path_msamples_field,
// path_msamples_field_brute_force, path_fps_field),
// or one scene file in one mode. Every figure is the median of several timed runs, on one thread and on all.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/core/parallel.h>
#include <tripsitter/frontend/app.h>
#include <tripsitter/modes/frame_source.h>
#include <tripsitter/modes/path_quality.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/render/primary.h>
#include <tripsitter/scene/builtin.h>
#if defined(TRIPSITTER_HAVE_EMBREE)
#include <tripsitter/render/embree.h>
#endif

#include "commands.h"
#include "common.h"
#include "options.h"

namespace tripsitter::cmd {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct BenchOptions {
  double seconds = 1.0;  // per run, at least
  int runs = 3;          // the median of these is reported
  bool json = false;
  bool embree = true;
  std::string scene;     // --scene: one file (or built-in name) instead of the suite
  modes::Mode mode = modes::Mode::kNormal;
  int threads = 0;       // --threads: only this count (0: 1 and all)
  std::string preset = "wide";  // --scene with --mode hw
  bool quality = true;           // the suite's path_relmse_field_* figures
  std::string cache = TRIPSITTER_BENCH_CACHE;  // where their references are kept
  std::string pictures;          // where their pictures are written (empty: nowhere)
  int row_step = 1;              // the window's --row-step in path_fps_field and path_relmse_field_*
};

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Median over `runs` runs of (work units done / seconds), each run repeating `unit()` (which returns the work
// it did) for at least `seconds`.
template <class F>
double median_rate(const BenchOptions& o, F&& unit) {
  std::vector<double> rates;
  for (int run = 0; run < o.runs; ++run) {
    const auto start = Clock::now();
    double work = 0, elapsed = 0;
    do {
      work += unit();
      elapsed = seconds_since(start);
    } while (elapsed < o.seconds);
    rates.push_back(work / elapsed);
  }
  std::sort(rates.begin(), rates.end());
  return rates[rates.size() / 2];
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

json machine() {
  json m;
  m["cpu"] = cpu_model();
  m["hardware_threads"] = core::thread_count(0);
#if defined(__x86_64__) || defined(__i386__)
  m["avx2"] = __builtin_cpu_supports("avx2") != 0;
  m["fma"] = __builtin_cpu_supports("fma") != 0;
  m["avx512f"] = __builtin_cpu_supports("avx512f") != 0;
#endif
#if defined(__clang__)
  m["compiler"] = "clang " + std::string(__clang_version__);
#else
  m["compiler"] = "g++ " + std::string(__VERSION__);
#endif
  m["render_simd"] = render::simd_instruction_set();
#if defined(NDEBUG)
  m["assertions"] = false;
#else
  m["assertions"] = true;
#endif
#if defined(TRIPSITTER_HAVE_EMBREE)
  m["embree"] = render::embree_version();
#else
  m["embree"] = nullptr;
#endif
  return m;
}

// Prints figures as they are measured (a table, or progress on stderr when the result is JSON) and keeps
// them for the JSON object.
class Report {
 public:
  explicit Report(const BenchOptions& o) : o_(o) {
    doc_["machine"] = machine();
    doc_["runs"] = o.runs;
    doc_["seconds_per_run"] = o.seconds;
    if (o.json) return;
    const json& m = doc_["machine"];
    std::printf("machine: %s, %d hardware threads", m["cpu"].get<std::string>().c_str(), m["hardware_threads"].get<int>());
    if (m.contains("avx2"))
      std::printf(" (AVX2 %s, FMA %s, AVX-512 %s)", m["avx2"].get<bool>() ? "yes" : "no", m["fma"].get<bool>() ? "yes" : "no",
                  m["avx512f"].get<bool>() ? "yes" : "no");
    std::printf("\ncompiler: %s%s; render library: %s; Embree: %s\n", m["compiler"].get<std::string>().c_str(),
                m["assertions"].get<bool>() ? " (assertions on: not an optimised build)" : "",
                m["render_simd"].get<std::string>().c_str(),
                m["embree"].is_null() ? "not built in" : m["embree"].get<std::string>().c_str());
    std::printf("each figure: median of %d runs of at least %.2f s\n", o.runs, o.seconds);
  }

  void note(const std::string& key, const json& value) { doc_[key] = value; }

  void add(const std::string& figure, int threads, double value, const std::string& unit,
           std::optional<std::pair<double, std::string>> embree = std::nullopt) {
    json& f = doc_[figure];
    f["unit"] = unit;
    const std::string t = "threads_" + std::to_string(threads);
    f[t] = value;
    if (embree) {
      f["embree_" + t] = embree->first;
      f["embree_mode_" + t] = embree->second;
      f["ratio_" + t] = value / embree->first;
    }
    if (o_.json) {
      std::cerr << figure << " on " << threads << " thread(s): " << value << " " << unit << "\n";
      return;
    }
    if (!table_started_) add_header();
    std::printf("%-24s %7d %12.2f  %-10s", figure.c_str(), threads, value, unit.c_str());
    if (embree) std::printf(" %12.2f  %-16s %8.2f", embree->first, embree->second.c_str(), value / embree->first);
    std::printf("\n");
    std::fflush(stdout);
  }

  // A picture's error against its reference (modes/path_quality.h): relMSE as the value, the rest beside it.
  void add_quality(const std::string& figure, int threads, const modes::QualityFigure& q) {
    json& f = doc_[figure];
    f["unit"] = "relMSE";
    const std::string t = "threads_" + std::to_string(threads);
    f[t] = q.error.relmse;
    f["bias_" + t] = q.error.bias;
    f["block_relmse_" + t] = q.error.block_relmse;
    f["frames_" + t] = q.frames;
    f["seconds_" + t] = q.seconds;
    f["mean_spp_" + t] = q.mean_samples;
    if (o_.json) {
      std::cerr << figure << " on " << threads << " thread(s): relMSE " << q.error.relmse << ", bias " << q.error.bias
                << "\n";
      return;
    }
    if (!table_started_) add_header();
    std::printf("%-24s %7d %12.5f  %-10s bias %+.4f, 8x8 blocks %.5f; %d frames in %.2f s, %.1f spp\n", figure.c_str(),
                threads, q.error.relmse, "relMSE", q.error.bias, q.error.block_relmse, q.frames, q.seconds,
                q.mean_samples);
    std::fflush(stdout);
  }
  void finish() {
    if (o_.json) std::cout << doc_.dump(2) << "\n";
  }

 private:
  void add_header() {
    std::printf("\n%-24s %7s %12s  %-10s %12s  %-16s %8s\n", "figure", "threads", "value", "unit", "Embree",
                "Embree's best", "ours/Embree");
    table_started_ = true;
  }
  const BenchOptions& o_;
  json doc_;
  bool table_started_ = false;
};

std::vector<int> thread_counts(const BenchOptions& o) {
  if (o.threads > 0) return {o.threads};
  const int all = core::thread_count(0);
  return all > 1 ? std::vector<int>{1, all} : std::vector<int>{1};
}

// hw: frames through host -> link -> device -> VGA capture. A path-tracing preset would stop tracing a still world's
// pixels once frame memory holds 255 samples each, so there the camera orbits 0.5 degrees back and forth between
// frames: every frame is the first of a world of new content, each pixel traced at the preset's samples per frame
// (what a moving camera costs; a still one costs the same until its pixels are full).
void bench_hw(const BenchOptions& o, Report& r, const std::string& figure, const scene::Scene& scene,
              const device::DevicePreset& preset = device::wide_preset()) {
  for (int t : thread_counts(o)) {
    modes::SourceConfig config;
    config.board.preset = preset;
    config.board.device_threads = t;
    const std::unique_ptr<modes::FrameSource> board = modes::make_frame_source(scene, config);
    double step = 0.5;
    r.add(figure, t, median_rate(o, [&] {
            if (preset.path) {
              board->steer().orbit(step);
              step = -step;
            }
            board->draw();
            return 1.0;
          }),
          "frames/s");
  }
}

// Primary rays at 640x480, and Embree on the same rays where it is built in.
void bench_primary(const BenchOptions& o, Report& r, const std::string& figure, const render::PathScene& scene,
                   const scene::CameraSettings& camera_settings) {
  constexpr int kW = 640, kH = 480;
  const render::ThinLensCamera camera(camera_settings, kW, kH);
  const double mrays = kW * kH / 1e6;
  for (int t : thread_counts(o)) {
    const render::PrimarySettings s{.width = kW, .height = kH, .threads = t};
    const double ours = median_rate(o, [&] { render::render_primary(scene, camera, s); return mrays; });
    std::optional<std::pair<double, std::string>> best;
#if defined(TRIPSITTER_HAVE_EMBREE)
    if (o.embree) {
      const render::EmbreeScene embree(scene, t);
      for (auto packet : {render::EmbreePacket::k1, render::EmbreePacket::k8, render::EmbreePacket::k16}) {
        const double theirs = median_rate(o, [&] { embree.render_primary(camera, s, packet); return mrays; });
        if (!best || theirs > best->first) best = {theirs, render::to_string(packet)};
      }
    }
#endif
    r.add(figure, t, ours, "Mrays/s", best);
  }
}

// Path tracing at the scene's size and depth, one sample per pixel per pass: the passes take seeds 1, 2, 3, ...
// Where Embree is built in, the same path tracer (same paths, same shading) runs with Embree finding the hits.
double path_rate(const BenchOptions& o, const render::PathSettings& settings,
                 const std::function<void(const render::PathSettings&)>& pass) {
  std::uint64_t seed = 1;
  return median_rate(o, [&] {
    render::PathSettings s = settings;
    s.seed = seed++;
    pass(s);
    return static_cast<double>(s.width) * s.height / 1e6;
  });
}

void bench_path(const BenchOptions& o, Report& r, const std::string& figure, const render::PathScene& scene,
                const scene::Scene& sc) {
  const render::ThinLensCamera camera(sc.camera, sc.render.width, sc.render.height);
  for (int t : thread_counts(o)) {
    const render::PathSettings s{.width = sc.render.width, .height = sc.render.height, .spp = 1,
                                 .max_depth = sc.render.max_depth, .seed = 1, .threads = t, .sky = {}};
    const double ours = path_rate(o, s, [&](const render::PathSettings& p) { render::render_path(scene, camera, p); });
    std::optional<std::pair<double, std::string>> embree_rate;
#if defined(TRIPSITTER_HAVE_EMBREE)
    if (o.embree) {
      const render::EmbreeScene embree(scene, t);
      embree_rate = {path_rate(o, s, [&](const render::PathSettings& p) { render::render_path(scene, embree, camera, p); }),
                     render::to_string(render::EmbreePacket::k1)};
    }
#endif
    r.add(figure, t, ours, "Msamples/s", embree_rate);
  }
}

// The straightforward tracer: the same path tracer testing every sphere for every ray, on one thread. At 160x90,
// since it is slow; samples per second do not depend on the size.
void bench_path_brute_force(const BenchOptions& o, Report& r, const std::string& figure, const scene::Scene& sc) {
  const render::PathScene scene(sc.spheres);
  const render::BruteForceQuery brute_force(scene);
  const render::PathSettings s{.width = 160, .height = 90, .spp = 1, .max_depth = sc.render.max_depth, .seed = 1,
                               .threads = 1, .sky = {}};
  const render::ThinLensCamera camera(sc.camera, s.width, s.height);
  r.add(figure, 1, path_rate(o, s, [&](const render::PathSettings& p) { render::render_path(scene, brute_force, camera, p); }),
        "Msamples/s");
}

// The window's path mode without the window, as a person uses it while moving: E held (the camera orbits its
// target at the window's 45 degrees per second, advanced by 1/60 s per frame), each frame traced, reprojected,
// denoised and encoded (render/interactive.h).
void bench_path_interactive(const BenchOptions& o, Report& r, const std::string& figure, const scene::Scene& sc) {
  for (int t : thread_counts(o)) {
    frontend::AppConfig config;
    config.scene = sc;
    config.source.mode = modes::Mode::kPath;
    config.source.threads = t;
    config.source.row_step = o.row_step;
    frontend::App app(config);
    app.handle({frontend::Input::Kind::kKeyDown, host::Key::kE});
    r.add(figure, t, median_rate(o, [&] { app.advance(1.0 / 60); return 1.0; }), "frames/s");
  }
}

// path_relmse_field_*: the window's path mode against a converged reference of `field` at 640x480 (rendered once
// and kept in the cache), on all threads; and the plain path tracer for comparison (docs/denoiser.md).
void bench_path_quality(const BenchOptions& o, Report& r, const scene::Scene& field) {
  modes::QualitySettings q;
  q.threads = o.threads;
  q.row_step = o.row_step;
  q.max_depth = field.render.max_depth;
  q.cache_dir = o.cache;
  q.pictures_dir = o.pictures;
  q.say = [](const std::string& s) { std::cerr << s << std::endl; };
  modes::PathQuality quality(field, q);
  const int t = core::thread_count(o.threads);
  const modes::Reference& ref = quality.reference();
  r.note("path_reference_field", {{"spp", q.reference_spp}, {"noise_relmse", ref.noise_relmse}, {"cached", ref.cached},
                                  {"orbit_spp", q.orbit_reference_spp}, {"orbit_noise_relmse", quality.orbit_noise_relmse()},
                                  {"cache", o.cache}, {"row_step", o.row_step}});
  if (!o.json)
    std::printf("reference: field at %d spp (relMSE floor %.5f), orbit frames at %d spp (floor %.5f), in %s\n",
                q.reference_spp, ref.noise_relmse, q.orbit_reference_spp, quality.orbit_noise_relmse(),
                o.cache.empty() ? "memory only" : o.cache.c_str());
  r.add_quality("path_relmse_field_1frame", t, quality.still(true, 1, 0, "path_relmse_field_1frame"));
  r.add_quality("path_relmse_field_0.25s", t, quality.still(true, 0, 0.25, "path_relmse_field_0.25s"));
  r.add_quality("path_relmse_field_1s", t, quality.still(true, 0, 1.0, "path_relmse_field_1s"));
  // The same after a fixed number of frames: what the loop's code gives, whatever the machine's speed that minute.
  r.add_quality("path_relmse_field_16frames", t, quality.still(true, 16, 0, "path_relmse_field_16frames"));
  r.add_quality("path_relmse_field_orbit", t, quality.orbit(true, true, "path_relmse_field_orbit"));
  r.add_quality("plain_relmse_field_64spp", t, quality.plain(64, render::SamplerKind::kSobol, "plain_relmse_field_64spp"));
  r.add_quality("plain_relmse_field_1s", t, quality.still(false, 0, 1.0, "plain_relmse_field_1s"));
  r.add_quality("plain_relmse_field_10s", t, quality.still(false, 0, 10.0, "plain_relmse_field_10s"));
  r.add_quality("plain_relmse_field_orbit", t, quality.orbit(false, false, "plain_relmse_field_orbit"));
}

int run_suite(const BenchOptions& o) {
  Report r(o);
  for (int n : {1, 16, 64, 256}) bench_hw(o, r, "hw_fps_" + std::to_string(n), scene::random_spheres(n, 1));
  // The path preset on hw_fps_64's world (lambertian, fuzzed metal and dielectric spheres), 1 sample per pixel per
  // frame, 4 rays per path.
  bench_hw(o, r, "hw_path_fps_64", scene::random_spheres(64, 1), device::path_preset());
  const scene::Scene field = *scene::builtin("field");
  for (int n : {1, 16, 488, 10000, 1000000}) {
    const scene::Scene sc = n == 488 ? field : scene::random_spheres(n, 1);
    const render::PathScene scene(sc.spheres);
    bench_primary(o, r, "primary_mrays_" + std::to_string(n), scene, sc.camera);
  }
  {
    scene::Scene sc = field;
    sc.render = {640, 360, 1, 50};
    bench_path(o, r, "path_msamples_field", render::PathScene(sc.spheres), sc);
    bench_path_brute_force(o, r, "path_msamples_field_brute_force", sc);
  }
  bench_path_interactive(o, r, "path_fps_field", field);
  if (o.quality) bench_path_quality(o, r, field);
  r.finish();
  return kExitOk;
}

int run_scene(const BenchOptions& o, modes::Mode mode) {
  // Loaded before anything is printed, so that a bad scene file gives its error alone.
  auto start = Clock::now();
  const scene::Scene sc = load_scene(o.scene);
  const double load = seconds_since(start);
  const device::DevicePreset preset = load_preset(o.preset, 0);  // an unknown name fails before anything is printed
  Report r(o);
  r.note("scene", {{"name", o.scene}, {"spheres", sc.spheres.size()}, {"mode", std::string(modes::mode_name(mode))}, {"load_seconds", load}});
  if (!o.json) std::printf("scene %s: %zu spheres, loaded in %.3f s\n", o.scene.c_str(), sc.spheres.size(), load);
  if (mode == modes::Mode::kHw) {
    if (preset.path) r.note("preset", {{"name", preset.name}, {"spp", preset.path->spp}, {"depth", preset.path->depth}});
    else r.note("preset", {{"name", preset.name}});
    bench_hw(o, r, "hw_fps", sc, preset);
  } else {
    start = Clock::now();
    const render::PathScene scene(sc.spheres);
    const double build = seconds_since(start);
    r.note("build_seconds", build);
    if (!o.json) std::printf("BVH built in %.3f s\n", build);
    if (mode == modes::Mode::kNormal) bench_primary(o, r, "primary_mrays", scene, sc.camera);
    else bench_path(o, r, "path_msamples", scene, sc);
  }
  r.finish();
  return kExitOk;
}

}  // namespace

void add_bench_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Measures speed. Without --scene, the fixed suite: hw_fps_N (device model, host -> link -> device -> VGA, "
      "N = 1, 16, 64, 256 spheres), hw_path_fps_64 (the same with the path preset: random-64's lambertian, metal and "
      "dielectric spheres path-traced on the device, 1 sample per pixel per frame, 4 rays per path), primary_mrays_N (one primary ray per pixel, normal shading, 640x480, N = 1, 16, "
      "488 (field), 10000, 1000000; compared with Embree where built in), path_msamples_field (path tracer, field, "
      "640x360, depth 50; compared with the same path tracer over Embree's hits where built in), "
      "path_msamples_field_brute_force (the same path tracer testing every sphere for every ray, 1 thread only) and "
      "path_fps_field (the window's path mode, 640x480, 1 sample per pixel per frame), each on "
      "1 thread and on all");
  cmd->add_option("--seconds", o->seconds, "Minimum time per run")->capture_default_str()->check(CLI::Range(0.0, 600.0));
  cmd->add_option("--runs", o->runs, "Runs per figure; the median is reported")->capture_default_str()->check(CLI::Range(1, 101));
  cmd->add_flag("--json", o->json, "Print one JSON object (a key per figure, the machine first) instead of the table");
  cmd->add_flag("!--no-embree", o->embree, "Do not measure Embree, even where it is built in");
  add_scene_option(*cmd, o->scene, "measured instead of the suite: loading and BVH build timed apart from the frames");
  add_mode_option(*cmd, o->mode,
                  "with --scene: hw (device model, frames/s), normal (primary rays at 640x480, Mrays/s, with Embree) or "
                  "path (path tracer at the scene's size and depth, Msamples/s, with the path tracer over Embree)");
  cmd->add_option("--threads", o->threads, "Only this many threads (default: 1 and all)")->check(CLI::Range(1, 1024));
  cmd->add_flag("!--no-quality", o->quality, "Suite: skip the path_relmse_field_* figures (the first run renders their references, minutes)");
  cmd->add_option("--cache", o->cache, "Suite: where the references of path_relmse_field_* are kept (empty: not kept)")
      ->capture_default_str();
  add_preset_option(*cmd, o->preset,
                    "with --scene and --mode hw; with path, 1 sample per pixel per frame and the camera orbiting 0.5 "
                    "degrees back and forth, so that no pixel stops at 255 samples");
  cmd->add_option("--pictures", o->pictures,
                  "Suite: write the pictures path_relmse_field_* and plain_relmse_field_* measure, and their references, "
                  "as PNG files in this directory");
  cmd->add_option("--row-step", o->row_step,
                  "Suite: path_fps_field and path_relmse_field_* with the window's --row-step N (paths on 1 row of "
                  "every N per frame; the plain_relmse_field_* figures trace every row)")
      ->capture_default_str()->check(CLI::Range(1, 8));
  cmd->callback([o, cmd, &run] {
    const bool mode_given = cmd->count("--mode") > 0;
    const bool preset_given = cmd->count("--preset") > 0;
    const bool row_step_given = cmd->count("--row-step") > 0;
    run = [o, mode_given, preset_given, row_step_given] {
      const modes::Mode mode = o->mode;
      if (o->scene.empty() && mode_given) throw InputError("--mode needs --scene FILE");
      if (preset_given && (o->scene.empty() || mode != modes::Mode::kHw))
        throw InputError("--preset needs --scene FILE and --mode hw");
      if (!o->scene.empty() && row_step_given) throw InputError("--row-step is for the suite (no --scene)");
      return o->scene.empty() ? run_suite(*o) : run_scene(*o, mode);
    };
  });
}

}  // namespace tripsitter::cmd
