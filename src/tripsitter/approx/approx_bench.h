// The benchmark that chose the path preset's approximations (docs/device.md, "Approximations"; `tripsitter
// approx` prints it). For every operation the path tracer needs beyond adds, multiplies and compares, several
// candidates, each measured against an exact reference over the inputs the tracer feeds it, with its cost on
// the device: cycles, multiplies (and the DSP48E1 slices they take) and table bits.
//
// The chosen candidates call the device's own code (approx.h, SqrtUnit, FixedArith), so the table measures what
// the device runs; the others are written here. Sampling uses fixed seeds and counts: the same build prints the
// same bytes, which docs/device.md holds between its table markers and approx_bench_test.cpp compares.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tripsitter::approx_bench {

// `count` multiplies of an a-bit by a b-bit unsigned operand (a sign, where there is one, aside).
struct Multiply {
  int a_bits = 0;
  int b_bits = 0;
  int count = 1;
};

// Absolute error in units of the output's last place.
struct Error {
  double worst = 0;
  double mean = 0;
};

struct Candidate {
  std::string name;
  bool chosen = false;
  Error error;
  int cycles = 0;          // latency at 100 MHz, a design estimate
  std::string cycles_why;  // one line
  std::vector<Multiply> multiplies;
  std::int64_t table_bits = 0;  // ROM

  int multiply_count() const;
  int dsp() const;  // DSP48E1 slices of all its multiplies
};

struct Operation {
  std::string name;
  std::string fed;  // what the tracer feeds it, how the benchmark samples that, and the output's unit
  std::vector<Candidate> candidates;
};

// A channel's mean on the display, sum over count (1..255) rounded as frame_memory.cpp's display_colour computes it:
// Every operation with every candidate, measured. Deterministic; about a quarter of a second in Release.
std::vector<Operation> evaluate();

// Per operation a line saying what it is fed, then a table of its candidates, the chosen one in bold.
std::string markdown(const std::vector<Operation>& operations);

// markdown(evaluate()): what `tripsitter approx` prints and docs/device.md holds.
std::string approximations_table();

}  // namespace tripsitter::approx_bench
