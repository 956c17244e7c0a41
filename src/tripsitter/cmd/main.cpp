// tripsitter: the command-line front end. Parses, picks a subcommand, maps errors to exit codes
// (0 success, 2 bad input or usage, 1 internal failure).
#include <exception>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "common.h"

int main(int argc, char** argv) {
  using namespace tripsitter::cmd;
  CLI::App app{"TripSitter: the ray-tracing board of the 2023 report, as software.\n"
               "The host keeps a world of spheres and a camera, sends it over the SPI link to the device,\n"
               "whose fixed-point workers fill line buffers that drive a 640x480 VGA signal in 12-bit colour.",
               "tripsitter"};
  app.require_subcommand(1);
  Action run;
  add_render_command(app, run);
  add_run_command(app, run);
  add_link_command(app, run);
  add_bench_command(app, run);
  add_host_command(app, run);
  add_device_command(app, run);
  add_approx_command(app, run);
  add_explore_command(app, run);
  add_rom_command(app, run);
  // Under mpirun every rank parses the same arguments: rank 0 alone prints help and usage errors and gives the
  // job its exit code. The others end quietly with 0: mpirun stops every rank as soon as one exits non-zero,
  // which could kill rank 0 before it has said what was wrong.
  std::ostringstream elsewhere;
  std::ostream& out = mpirun_place().rank == 0 ? std::cout : elsewhere;
  std::ostream& err = mpirun_place().rank == 0 ? std::cerr : elsewhere;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    app.exit(e, out, err);
    return mpirun_place().rank == 0 ? kExitBadInput : kExitOk;
  }
  try {
    return run();
  } catch (const InputError& e) {
    std::cerr << "tripsitter: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "tripsitter: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
}
