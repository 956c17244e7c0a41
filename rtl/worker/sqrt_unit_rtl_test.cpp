// The square-root unit's RTL (ts_sqrt_unit.sv) against the C++ model, device::SqrtUnit::operator(), bit for bit:
// both forms (pipelined, one iteration per stage; iterative, one unit used N times), the presets' input widths,
// the widest input (126 bits), N = 1, 3, 4, 16 and 30, and exact latencies. The planted fault (the recurrence's
// comparison flipped, in the test-only copy of the unit that rtl/worker/CMakeLists.txt writes) must disagree with the
// model: the tests would catch it.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_sqrt_i16_126.h>
#include <Vts_sqrt_i16_126_bug.h>
#include <Vts_sqrt_i16_53.h>
#include <Vts_sqrt_i3_12.h>
#include <Vts_sqrt_p16_126.h>
#include <Vts_sqrt_p16_126_bug.h>
#include <Vts_sqrt_p16_95.h>
#include <Vts_sqrt_p1_6.h>
#include <Vts_sqrt_p30_126.h>
#include <Vts_sqrt_p4_24.h>

#include <tripsitter/device/sqrt_unit.h>

namespace tripsitter::rtl {
namespace {

// How a Verilated variant was built (its PARAMS in CMakeLists.txt).
struct Form {
  int iterations;
  int width;
  bool pipelined;
  int cycles_per_iteration;  // iterative only
  // Cycles from the input's acceptance to its root: lzc, shift, the iterations, rounding.
  int latency() const { return 3 + iterations * (pipelined ? 1 : cycles_per_iteration); }
};

// One Verilated square-root unit, clocked by hand: inputs are set, the model settles with the clock low (the
// acceptance is read then), and the rising edge moves everything on by a cycle.
template <class V>
class SqrtRtl {
 public:
  explicit SqrtRtl(Form form) : form_(form) {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<V>(&context_);
    top_->rst = 1;
    top_->in_valid = 0;
    top_->flush = 0;
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
  }

  // The roots of `inputs`, fed as fast as the unit takes them. Checks that each comes out exactly latency()
  // cycles after it was taken, once, in order, and (iterative) that the unit takes nothing while busy.
  std::vector<UInt128> run(const std::vector<UInt128>& inputs) {
    std::vector<UInt128> roots;
    std::vector<std::int64_t> taken;
    std::size_t next = 0;
    const std::int64_t limit = cycle_ + static_cast<std::int64_t>(inputs.size() + 2) * (form_.latency() + 2);
    while (roots.size() < inputs.size() && cycle_ < limit) {
      top_->in_valid = next < inputs.size();
      put(top_->in_value, next < inputs.size() ? inputs[next] : 0);
      top_->in_tag = static_cast<CData>(next);
      settle();
      if (form_.pipelined) {
        EXPECT_EQ(top_->in_ready, 1);
      }
      if (top_->in_valid && top_->in_ready) {
        if (!form_.pipelined && !taken.empty() && roots.size() < taken.size()) {
          ADD_FAILURE() << "the iterative unit took an input while busy, at cycle " << cycle_;
        }
        taken.push_back(cycle_);
        ++next;
      }
      tick();
      if (top_->out_valid) {
        const std::size_t i = roots.size();
        if (i >= taken.size()) {
          ADD_FAILURE() << "a root with no input, at cycle " << cycle_;
          break;
        }
        EXPECT_EQ(top_->out_tag, static_cast<CData>(i)) << "roots out of order at input " << i;
        EXPECT_EQ(cycle_ - taken[i], form_.latency()) << "latency of input " << i;
        roots.push_back(get(top_->out_root));
      }
    }
    EXPECT_EQ(roots.size(), inputs.size()) << "roots missing";
    return roots;
  }

  // Inputs taken, then a flush `after` cycles later: none of them may come out, and the unit works on.
  void flush_after(const std::vector<UInt128>& inputs, int after) {
    for (const UInt128 v : inputs) {
      top_->in_valid = 1;
      put(top_->in_value, v);
      settle();
      tick();
    }
    top_->in_valid = 0;
    for (int i = 0; i < after; ++i) {
      settle();
      tick();
      EXPECT_EQ(top_->out_valid, 0) << "a root came out early";
    }
    top_->flush = 1;
    settle();
    tick();
    top_->flush = 0;
    for (int i = 0; i < 2 * form_.latency(); ++i) {
      settle();
      tick();
      EXPECT_EQ(top_->out_valid, 0) << "a flushed input came out";
    }
  }

 private:
  void settle() {
    top_->clk = 0;
    top_->eval();
  }
  void tick() {
    rising_edge(*top_);
    ++cycle_;
  }

  Form form_;
  VerilatedContext context_;
  std::unique_ptr<V> top_;
  std::int64_t cycle_ = 0;
};

// The model's root of every input, compared with the RTL's; the first mismatch is reported with both values.
// Returns the number of mismatches.
template <class V>
int mismatches(Form form, const std::vector<UInt128>& inputs, bool report = true) {
  SqrtRtl<V> rtl(form);
  const std::vector<UInt128> roots = rtl.run(inputs);
  const device::SqrtUnit model(form.iterations);
  int bad = 0;
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const auto expected = static_cast<UInt128>(model(inputs[i]));
    if (roots[i] == expected) continue;
    if (bad++ == 0 && report) {
      ADD_FAILURE() << "N=" << form.iterations << " width " << form.width << ": sqrt(" << to_string(inputs[i])
                    << ") is " << to_string(roots[i]) << " in the RTL, " << to_string(expected) << " in the model";
    }
  }
  return bad;
}

// Every input below `count`.
std::vector<UInt128> every_input_below(std::uint64_t count) {
  std::vector<UInt128> v;
  v.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) v.push_back(i);
  return v;
}

// Around every power of two below 2^width (so every power of four, where the normalising shift changes, and
// every odd power, where it does not): 2^b - 4 .. 2^b + 4.
std::vector<UInt128> around_powers_of_two(int width) {
  std::vector<UInt128> v;
  for (int b = 0; b < width; ++b) {
    for (int d = -4; d <= 4; ++d) {
      const Int128 x = (Int128{1} << b) + d;
      if (x >= 0 && static_cast<UInt128>(x) < (UInt128{1} << width)) v.push_back(static_cast<UInt128>(x));
    }
  }
  v.push_back((UInt128{1} << width) - 1);
  return v;
}

// Random inputs of 1..width bits, each length equally likely.
std::vector<UInt128> random_inputs(int width, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<UInt128> v;
  for (int i = 0; i < count; ++i) {
    const int bits = 1 + static_cast<int>(rng() % static_cast<std::uint64_t>(width));
    const UInt128 r = UInt128{rng()} << 64 | rng();
    v.push_back((r >> (128 - bits)) | (UInt128{1} << (bits - 1)));
  }
  return v;
}

// Both sides of the recurrence's leaf boundaries (docs/device.md, "Closed form"): inputs whose normalised
// register M is (2j)^2 - 1, (2j)^2 or (2j)^2 + 1, at random normalising exponents e >= N.
std::vector<UInt128> leaf_boundaries(int n, int width, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<UInt128> v;
  const std::uint64_t lo = std::uint64_t{1} << (n - 2), hi = std::uint64_t{1} << (n - 1);  // 2j in [2^(N-1), 2^N)
  for (int i = 0; i < count; ++i) {
    const std::uint64_t j = lo + rng() % (hi - lo);
    const UInt128 m = UInt128{2 * j} * (2 * j);
    const int e = n + static_cast<int>(rng() % static_cast<std::uint64_t>((width + 1) / 2 - n + 1));
    const UInt128 base = m << (2 * (e - n));
    for (int d = -1; d <= 1; ++d) {
      const UInt128 x = base + static_cast<UInt128>(static_cast<Int128>(d));
      if (x < (UInt128{1} << width)) v.push_back(x);
    }
  }
  return v;
}

std::vector<UInt128> concat(std::initializer_list<std::vector<UInt128>> parts) {
  std::vector<UInt128> v;
  for (const auto& p : parts) v.insert(v.end(), p.begin(), p.end());
  return v;
}

constexpr Form kP16W126{16, 126, true, 1};
constexpr Form kI16W126{16, 126, false, 2};
constexpr Form kP16W95{16, 95, true, 1};    // the wide preset's worker: D < 2^95
constexpr Form kI16W53{16, 53, false, 2};   // the board-2023 preset's worker: D < 2^53
constexpr Form kP4W24{4, 24, true, 1};
constexpr Form kI3W12{3, 12, false, 1};
constexpr Form kP1W6{1, 6, true, 1};
constexpr Form kP30W126{30, 126, true, 1};

TEST(SqrtUnitRtl, PipelinedSixteenIterationsWidest) {
  const auto inputs = concat({every_input_below(1u << 20), around_powers_of_two(126), random_inputs(126, 200000, 1),
                              leaf_boundaries(16, 126, 30000, 2)});
  EXPECT_EQ(mismatches<Vts_sqrt_p16_126>(kP16W126, inputs), 0);
}

TEST(SqrtUnitRtl, IterativeSixteenIterationsWidest) {
  const auto inputs = concat({every_input_below(4096), around_powers_of_two(126), random_inputs(126, 12000, 3),
                              leaf_boundaries(16, 126, 2000, 4)});
  EXPECT_EQ(mismatches<Vts_sqrt_i16_126>(kI16W126, inputs), 0);
}

TEST(SqrtUnitRtl, ThePresetsWidths) {
  EXPECT_EQ(mismatches<Vts_sqrt_p16_95>(kP16W95, concat({every_input_below(1u << 16), around_powers_of_two(95),
                                                         random_inputs(95, 100000, 5), leaf_boundaries(16, 95, 10000, 6)})),
            0);
  EXPECT_EQ(mismatches<Vts_sqrt_i16_53>(kI16W53, concat({around_powers_of_two(53), random_inputs(53, 8000, 7),
                                                         leaf_boundaries(16, 53, 1000, 8)})),
            0);
}

TEST(SqrtUnitRtl, SmallIterationCountsEveryInput) {
  EXPECT_EQ(mismatches<Vts_sqrt_p4_24>(kP4W24, every_input_below(1u << 24)), 0);  // every input of 24 bits
  EXPECT_EQ(mismatches<Vts_sqrt_i3_12>(kI3W12, every_input_below(1u << 12)), 0);
  EXPECT_EQ(mismatches<Vts_sqrt_p1_6>(kP1W6, every_input_below(1u << 6)), 0);
}

TEST(SqrtUnitRtl, ThirtyIterations) {
  EXPECT_EQ(mismatches<Vts_sqrt_p30_126>(kP30W126, concat({every_input_below(1u << 16), around_powers_of_two(126),
                                                           random_inputs(126, 100000, 9), leaf_boundaries(30, 126, 20000, 10)})),
            0);
}

TEST(SqrtUnitRtl, FlushDropsEverythingInFlight) {
  const device::SqrtUnit model(16);
  const std::vector<UInt128> after{2, UInt128{1} << 30, 12345};
  std::vector<UInt128> expected;
  for (const UInt128 v : after) expected.push_back(static_cast<UInt128>(model(v)));
  {
    SqrtRtl<Vts_sqrt_p16_126> rtl(kP16W126);
    rtl.flush_after({5, 7, 1000000}, 4);
    EXPECT_EQ(rtl.run(after), expected);
  }
  {
    SqrtRtl<Vts_sqrt_i16_126> rtl(kI16W126);
    rtl.flush_after({9}, 10);
    EXPECT_EQ(rtl.run(after), expected);
  }
}

// The planted fault: with the comparison flipped, the unit must disagree with the model on most random inputs
// (so every comparison above, and the worker's tests, would fail), in both forms; the first disagreement shows.
TEST(SqrtUnitRtl, ThePlantedFaultIsCaught) {
  const auto inputs = random_inputs(126, 2000, 11);
  const int pipelined = mismatches<Vts_sqrt_p16_126_bug>(kP16W126, inputs, false);
  const int iterative = mismatches<Vts_sqrt_i16_126_bug>(kI16W126, inputs, false);
  EXPECT_GT(pipelined, 1900) << "the planted fault went unnoticed by the pipelined unit's comparison";
  EXPECT_GT(iterative, 1900) << "the planted fault went unnoticed by the iterative unit's comparison";
  EXPECT_EQ(pipelined, iterative);
  const device::SqrtUnit model(16);
  SqrtRtl<Vts_sqrt_p16_126_bug> planted(kP16W126);
  const auto roots = planted.run({1000000});
  EXPECT_NE(roots.at(0), static_cast<UInt128>(model(1000000)))
      << "planted sqrt(1000000) = " << to_string(roots.at(0)) << ", model " << to_string(model(1000000));
}

}  // namespace
}  // namespace tripsitter::rtl
