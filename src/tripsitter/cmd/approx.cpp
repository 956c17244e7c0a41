// tripsitter approx: the benchmark that chose the path preset's approximations, as the Markdown table
// docs/device.md holds ("Approximations").
#include <iostream>

#include <tripsitter/approx/approx_bench.h>

#include "commands.h"
#include "common.h"

namespace tripsitter::cmd {

void add_approx_command(CLI::App& app, Action& run) {
  app.add_subcommand("approx",
                     "Print the benchmark that chose the device's approximations (docs/device.md, Approximations) as "
                     "Markdown: per operation, every candidate's worst and mean error over the inputs the tracer "
                     "feeds it, its cycles, multiplies and table bits")
      ->callback([&run] {
        run = [] {
          std::cout << approx_bench::approximations_table();
          return std::cout.flush() ? kExitOk : kExitInternal;
        };
      });
}

}  // namespace tripsitter::cmd
