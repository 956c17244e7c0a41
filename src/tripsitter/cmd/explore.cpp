// tripsitter explore: the design-space sweep (docs/explore.md). Device configurations over scenes, each run
// through the board's bit-exact model, written as a report a person opens (DIR/index.html) and files scripts
// read (DIR/points.csv, DIR/points.json).
#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <system_error>

#include <tripsitter/core/parallel.h>
#include <tripsitter/core/progress.h>
#include <tripsitter/explore/report.h>
#include <tripsitter/explore/runner.h>
#include <tripsitter/explore/summary.h>
#include <tripsitter/explore/sweep.h>

#include "commands.h"
#include "common.h"

namespace tripsitter::cmd {
namespace {

constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as a shell reports a program its Ctrl-C ended

struct ExploreOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> sweeps;
  std::string out;
  int threads = 0;
  int reference_spp = 64;
  std::uint64_t seed = 1;
  bool quiet = false;
  std::string command;  // the command with its scenes, sweeps and output, for the report
};

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted = true; }

std::string join_lines(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

int run_explore(const ExploreOptions& o) {
  const std::vector<std::string> scene_names = o.scenes.empty() ? explore::default_scenes() : o.scenes;
  const std::vector<std::string> specs = o.sweeps.empty() ? explore::default_sweeps() : o.sweeps;
  std::vector<explore::Sweep> sweeps;
  std::vector<explore::Configuration> configs;
  try {
    for (const auto& spec : specs) sweeps.push_back(explore::parse_sweep(spec));
    configs = explore::expand(sweeps, scene_names);
  } catch (const explore::SweepError& e) {
    throw InputError("--sweep: " + e.pointed());
  }
  std::map<std::string, scene::Scene> scenes;
  for (const auto& name : scene_names) scenes.emplace(name, load_scene(name));
  const std::filesystem::path dir(o.out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw InputError("--out " + o.out + ": cannot make that directory" + (ec ? " (" + ec.message() + ")" : ""));

  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  struct sigaction previous {};
  sigaction(SIGINT, &sa, &previous);
  std::cerr << "explore: " << configs.size() << " points over " << scene_names.size()
            << (scene_names.size() == 1 ? " scene (" : " scenes (")
            << join_lines(scene_names) << "), " << core::thread_count(o.threads)
            << " at once; Ctrl-C stops and keeps the points finished" << std::endl;

  core::ProgressBar bar("explore", configs.size(), "points", !o.quiet, std::cerr);
  explore::RunSettings settings;
  settings.threads = o.threads;
  settings.evaluate.reference_spp = o.reference_spp;
  settings.evaluate.seed = o.seed;
  settings.stop = &g_interrupted;
  settings.on_point = [&bar](const explore::Point&) { bar.add(1); };
  const explore::RunResult result = explore::run_sweep(configs, scenes, settings);
  bar.finish();
  sigaction(SIGINT, &previous, nullptr);

  const explore::Summary summary = explore::summarise(result.points);
  explore::Report report;
  report.points = result.points;
  report.summary = explore::to_json(summary);
  report.sweep = {{"command", o.command},
                  {"scenes", scene_names},
                  {"sweeps", specs},
                  {"points_planned", result.planned},
                  {"points_done", result.points.size()},
                  {"interrupted", result.interrupted},
                  {"seconds", result.seconds},
                  {"reference_spp", o.reference_spp},
                  {"seed", o.seed}};
  const auto written = explore::write_report(dir, report);
  if (!written) throw std::runtime_error(written.error().message);
  for (const std::string& line : explore::describe(summary, result.points)) std::cout << line << "\n";
  std::cerr << "wrote " << (dir / "index.html").string() << ", points.csv and points.json: " << result.points.size()
            << " of " << result.planned << " points in " << result.seconds << " s\n";
  if (result.interrupted) {
    std::cerr << "explore: interrupted; the report holds the " << result.points.size() << " points finished\n";
    return kExitInterrupted;
  }
  return kExitOk;
}

std::string parameters_help() {
  std::string text =
      "\nSweeps (docs/explore.md): --sweep 'name=values,name=values...', every combination of the values; a value is\n"
      "a number, a range a..b or a..b:step, or a word, and a parameter's values run on after commas until the next\n"
      "name=. Example: --sweep preset=board-2023,workers=1..64,fracbits=3,4,8. Parameters:\n";
  for (const auto& p : explore::parameters()) text += "  " + p.name + " (" + p.values + "): " + p.meaning + "\n";
  text += "Without --sweep:\n";
  for (const auto& s : explore::default_sweeps()) text += "  " + s + "\n";
  text += "Exit status: 0 done, 2 bad input, 1 internal failure, 130 interrupted (the report keeps the points done).";
  return text;
}

}  // namespace

void add_explore_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<ExploreOptions>();
  CLI::App* cmd = app.add_subcommand(
      "explore",
      "Sweep device configurations over scenes through the bit-exact model and write a report: DIR/index.html (charts, "
      "a table of every point, thumbnails; opens offline), DIR/points.csv and DIR/points.json");
  cmd->add_option("--scene", o->scenes, "Scenes: built-in names or scene files (repeat; default: demo and cluster)");
  cmd->add_option("--sweep", o->sweeps, "A sweep specification (repeat; default: the sweeps listed below)");
  cmd->add_option("--out", o->out, "Directory the report is written to (made if missing)")->required();
  cmd->add_option("--threads", o->threads, "Points measured at once (0: every core)")->check(CLI::Range(0, 1024));
  cmd->add_option("--reference-spp", o->reference_spp,
                  "Samples per pixel of the float path tracer the path preset's points are compared with")
      ->check(CLI::Range(1, 65536));
  cmd->add_option("--seed", o->seed, "Seed of that float path tracer");
  cmd->add_flag("--quiet", o->quiet, "No progress bar");
  cmd->footer(parameters_help());
  cmd->callback([o, &run] {
    o->command = "tripsitter explore";
    for (const auto& s : o->scenes) o->command += " --scene " + s;
    for (const auto& s : o->sweeps) o->command += " --sweep " + s;
    o->command += " --out " + o->out;
    run = [o] { return run_explore(*o); };
  });
}

}  // namespace tripsitter::cmd
