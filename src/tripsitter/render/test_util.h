// Helpers shared by the render tests: the statistics that hold a sampler to its distribution.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::render::testing {

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
