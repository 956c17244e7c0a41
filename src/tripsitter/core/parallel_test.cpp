#include <tripsitter/core/parallel.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

TEST(ParallelFor, CallsEveryIndexOnce) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> calls(1000);
    parallel_for(0, 1000, threads, [&](int i) { calls[static_cast<std::size_t>(i)].fetch_add(1); });
    for (const auto& c : calls) ASSERT_EQ(c.load(), 1) << threads;
  }
}

TEST(ParallelFor, EmptyAndOffsetRanges) {
  int calls = 0;
  parallel_for(5, 5, 2, [&](int) { ++calls; });
  parallel_for(7, 3, 2, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
  std::atomic<int> sum{0};
  parallel_for(10, 20, 4, [&](int i) { sum += i; });
  EXPECT_EQ(sum.load(), 145);
}

TEST(ParallelFor, RethrowsTheFirstException) {
  EXPECT_THROW(parallel_for(0, 100, 2,
                            [](int i) {
                              if (i == 37) throw std::runtime_error("boom");
                            }),
               std::runtime_error);
}

TEST(ParallelFor, ThreadCountDefaultsToTheHardware) {
  EXPECT_EQ(thread_count(3), 3);
  EXPECT_GE(thread_count(0), 1);
}

}  // namespace
}  // namespace tripsitter::core
