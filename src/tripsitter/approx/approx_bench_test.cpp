#include <tripsitter/approx/approx_bench.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/device/frame_memory.h>

namespace tripsitter::approx_bench {
namespace {

using device::AccumEntry;
using device::display_colour;
using device::display_mean;
using device::kMaxSamples;
using device::kSampleBits;

const std::vector<Operation>& operations() {
  static const std::vector<Operation> ops = evaluate();
  return ops;
}

const Candidate& chosen(const Operation& op) {
  for (const Candidate& c : op.candidates)
    if (c.chosen) return c;
  throw std::logic_error(op.name + " has no chosen candidate");
}

TEST(ApproxBench, EveryOperationHasThreeCandidatesAndOneChosen) {
  ASSERT_EQ(operations().size(), 7u);
  for (const Operation& op : operations()) {
    EXPECT_GE(op.candidates.size(), 3u) << op.name;
    int chosen = 0;
    for (const Candidate& c : op.candidates) chosen += c.chosen ? 1 : 0;
    EXPECT_EQ(chosen, 1) << op.name;
  }
}

// The bounds docs/device.md states for what the device runs, in the output's last place.
TEST(ApproxBench, ChosenCandidatesStayWithinTheirBounds) {
  const std::vector<double> bounds = {
      1.0,   // a unit vector's component
      4.0,   // a direction at the sphere units' 2^17 (the artix path preset)
      0.5,   // the square root: correctly rounded on the tracer's inputs
      0.5,   // the hit point: exact division
      0.75,  // the display's mean
      1.75,  // the fifth power
      0.5,   // sin and cos: a table of rounded values
  };
  ASSERT_EQ(operations().size(), bounds.size());
  for (std::size_t i = 0; i < bounds.size(); ++i) {
    const Candidate& c = chosen(operations()[i]);
    EXPECT_LE(c.error.worst, bounds[i]) << operations()[i].name << ": " << c.name;
    EXPECT_GT(c.error.mean, 0.0) << operations()[i].name;  // measured at all
  }
}

// The candidates that round an exact result once are within half a unit: the benchmark's references and its
// models of exact hardware agree.
TEST(ApproxBench, ExactCandidatesAreWithinHalfAUnit) {
  int exact = 0;
  for (const Operation& op : operations()) {
    for (const Candidate& c : op.candidates) {
      if (c.name.find("exact") == std::string::npos) continue;
      ++exact;
      EXPECT_LE(c.error.worst, 0.5) << c.name;
    }
  }
  EXPECT_EQ(exact, 4);
}

TEST(ApproxBench, ACandidatesSlicesAreItsMultipliesSlices) {
  Candidate c;
  c.multiplies = {{16, 16}, {26, 17, 3}};
  EXPECT_EQ(c.multiply_count(), 4);
  EXPECT_EQ(c.dsp(), 1 + 3 * 2);
}

// The display's mean, which the benchmark measures, is what display_colour shows: an entry of count 1 shows its sum
// exactly, so (sum, count) and (display_mean(sum, count), 1) give the same colour at all 16 dither thresholds,
// which pins the gamma table's entry they index.
TEST(ApproxBench, TheMeanIsTheDisplays) {
  std::mt19937 rng(5);
  for (int count = 1; count <= kMaxSamples; ++count) {
    const auto largest = static_cast<std::uint32_t>(count * ((1 << kSampleBits) - 1));
    for (int i = 0; i < 16; ++i) {
      AccumEntry entry{{0, largest, 0}, static_cast<std::uint8_t>(count), 0};
      if (i > 0)
        for (std::uint32_t& sum : entry.sum) sum = rng() % (largest + 1);
      AccumEntry one{{}, 1, 0};
      for (std::size_t k = 0; k < 3; ++k) one.sum[k] = display_mean(entry.sum[k], count);
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row)
          ASSERT_EQ(display_colour(entry, col, row, true), display_colour(one, col, row, true))
              << "count " << count << ", sums " << entry.sum[0] << " " << entry.sum[1] << " " << entry.sum[2];
    }
  }
}

TEST(ApproxBench, TheTableIsTheSameEveryTime) {
  EXPECT_EQ(markdown(evaluate()), markdown(operations()));
}

// docs/device.md holds exactly what `tripsitter approx` prints, between its markers.
TEST(ApproxBench, TheDocumentHoldsTheTable) {
  const std::filesystem::path doc = std::filesystem::path(TRIPSITTER_SOURCE_DIR) / "docs" / "device.md";
  std::ifstream in(doc, std::ios::binary);
  ASSERT_TRUE(in) << doc;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const std::string begin = "<!-- approximations table: begin -->\n", end = "<!-- approximations table: end -->";
  const std::size_t from = s.find(begin), to = s.find(end);
  ASSERT_NE(from, std::string::npos) << doc << " has no " << begin;
  ASSERT_NE(to, std::string::npos) << doc << " has no " << end;
  ASSERT_LT(from, to);
  EXPECT_EQ(s.substr(from + begin.size(), to - from - begin.size()), markdown(operations()))
      << "docs/device.md's approximations table is out of date: put the output of `tripsitter approx` between "
         "the markers";
}

}  // namespace
}  // namespace tripsitter::approx_bench
