// tripsitter rom: the ROM image of the board that draws without its microcontroller (rtl/boards/, docs/rtl.md "The
// board"): the worlds of a camera path, encoded by the host for the device's formats on wire v2, as a $readmemh file.
#include <iostream>
#include <memory>
#include <sstream>

#include <tripsitter/board/board.h>
#include <tripsitter/display/io.h>
#include <tripsitter/host/host.h>
#include <tripsitter/host/rom_image.h>
#include <tripsitter/link/sequence.h>

#include "commands.h"
#include "common.h"
#include "options.h"

namespace tripsitter::cmd {
namespace {

struct RomOptions {
  std::string scene = "cluster";
  std::string preset = "artix";
  int worlds = 32;
  double orbit = 360;
  double walk = 0;
  bool walking = false;  // --walk given
  std::size_t capacity = host::kBoardRomBytes;
  std::string out;
};

// The ROM host sends its frames again and again as they are stored: wire v2, which shows every intact world, even
// one numbered lower than the last (v3 refuses it as a replay: docs/link_format.md, "Sessions and sequence numbers").
constexpr link::WireVersion kRomWire = link::WireVersion::kV2;

int run_rom(const RomOptions& o) {
  const device::DevicePreset preset = load_preset(o.preset, 0);
  if (device::traces_paths(preset, kRomWire))
    throw InputError("--preset " + o.preset + ": the board's device draws one world at a time, not path-traced frames");
  scene::Scene scene = load_scene(o.scene);
  host::Host host(std::move(scene), board::formats_of(preset), kRomWire);
  const host::CameraPath path{o.walking ? host::CameraPath::Kind::kWalk : host::CameraPath::Kind::kOrbit,
                              o.walking ? o.walk : o.orbit};
  const host::RomImage rom = host::make_rom_image(host, path, o.worlds, link::Numbering(kRomWire, 0));
  if (rom.bytes.size() > o.capacity)
    throw InputError(std::to_string(o.worlds) + " worlds of " + std::to_string(rom.spheres) + " spheres take " +
                     std::to_string(rom.bytes.size()) + " bytes, more than the ROM's " + std::to_string(o.capacity) +
                     " (--capacity): give fewer --worlds, or a larger ROM_BYTES to the board's top and --capacity");

  std::ostringstream what;
  what << "tripsitter rom --scene " << o.scene << " --preset " << o.preset << " --worlds " << o.worlds
       << (o.walking ? " --walk " : " --orbit ") << path.amount;
  std::ostringstream summary;
  summary << rom.worlds << (rom.worlds == 1 ? " world" : " worlds") << " of " << rom.spheres
          << " spheres on wire v2, numbered 1 to " << rom.worlds << ": " << rom.bytes.size() << " of " << o.capacity
          << " bytes";
  const std::string text =
      host::to_readmemh(rom.bytes, {what.str(), summary.str(), "layout: src/tripsitter/host/rom_image.h"});
  const auto written = display::write_file_beside_and_rename(o.out, text, "ROM image");
  if (!written) throw InputError(written.error().message);
  std::cerr << "wrote " << o.out << ": " << summary.str() << ", " << rom.saturations.total() << " saturated values\n";
  return kExitOk;
}

}  // namespace

void add_rom_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<RomOptions>();
  CLI::App* cmd = app.add_subcommand(
      "rom",
      "Write the ROM image of the board that draws without its microcontroller (rtl/boards/arty_a7/ts_arty_top.sv, "
      "STANDALONE = 1): the worlds of a camera path around or through a scene, each encoded by the host as a wire v2 "
      "frame for the preset's formats, behind a table of where each starts (src/tripsitter/host/rom_image.h), as a "
      "$readmemh file of one byte a line. The board's buttons step through the worlds");
  add_scene_option(*cmd, o->scene);
  add_preset_option(*cmd, o->preset, "the host rounds to its number formats (the board's device is artix)");
  cmd->add_option("--worlds", o->worlds, "Worlds on the path (N); the first is the scene's own view")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  CLI::Option* orbit =
      cmd->add_option("--orbit", o->orbit,
                      "Degrees the camera circles its target over the N worlds, DEG/N from one world to the next (as "
                      "link encode --orbit)")
          ->capture_default_str()
          ->check(CLI::Range(-36000.0, 36000.0));
  CLI::Option* walk = cmd->add_option("--walk", o->walk,
                                      "Instead of --orbit: scene units the camera moves forward over the N worlds "
                                      "(negative: backwards), DIST/N from one world to the next")
                          ->check(CLI::Range(-1.0e6, 1.0e6));
  walk->excludes(orbit);
  cmd->add_option("--capacity", o->capacity,
                  "Bytes the board's ROM holds (ts_arty_top's ROM_BYTES); a larger image is refused")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{16}, std::size_t{1} << 30));
  cmd->add_option("-o,--out", o->out, "The $readmemh file to write (written whole or not at all)")->required();
  cmd->callback([o, walk, &run] {
    o->walking = walk->count() > 0;
    run = [o] { return run_rom(*o); };
  });
}

}  // namespace tripsitter::cmd
