// Helpers shared by the render tests: random points, and the statistics that hold a sampler to its distribution.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/vec.h>

namespace tripsitter::render::testing {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

// Uniform in [lo, hi), and in the box [lo, hi)^3.
inline float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
inline core::Vec3f uniform_in_box(std::mt19937& rng, float lo, float hi) {
  return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

// Samples the statistical tests draw (their tolerances are set for this many).
inline constexpr int kSamples = 200000;

// Counts of values in [0, 1) in equal bins, and Pearson's chi-square statistic against the uniform distribution.
class Histogram {
 public:
  explicit Histogram(int bins) : counts_(static_cast<std::size_t>(bins), 0) {}
  void add(double x) {
    ASSERT_GE(x, 0.0);
    ASSERT_LT(x, 1.0);
    ++counts_[static_cast<std::size_t>(x * static_cast<double>(counts_.size()))];
    ++total_;
  }
  double chi_square() const {
    const double expected = static_cast<double>(total_) / static_cast<double>(counts_.size());
    double sum = 0;
    for (const long c : counts_) sum += (static_cast<double>(c) - expected) * (static_cast<double>(c) - expected) / expected;
    return sum;
  }
  // The statistic's mean (bins - 1) plus 6 of its standard deviations: a uniform sampler stays below with
  // probability above 1 - 1e-6; a sampler a few per cent off in some bins over 10^5 samples and more does not.
  double bound() const {
    const double dof = static_cast<double>(counts_.size() - 1);
    return dof + 6 * std::sqrt(2 * dof);
  }

 private:
  std::vector<long> counts_;
  long total_ = 0;
};

// The angle of (x, y) as a fraction of a turn, in [0, 1).
inline double turn(double x, double y) {
  const double t = std::atan2(y, x) / (2 * std::numbers::pi) + 0.5;
  return t < 1.0 ? t : 0.0;
}

// x, or the largest double below 1 where x is 1 or more: for values of [0, 1] (or a rounding above), so that 1
// counts in the last bin.
inline double below_one(double x) { return std::min(x, std::nextafter(1.0, 0.0)); }

}  // namespace tripsitter::render::testing
