// The random streams' RTL (ts_path_rng.sv) against PathRng (src/tripsitter/device/path_rng.h), draw for draw: the
// seed hash's pipeline fed a key every cycle (and with gaps and junk between), each state out Latency cycles
// later with its tag; then streams loaded from it drawing 1,000 values each, every one PathRng's; and the one key
// whose hash is 0 (key 0: pixel 0, sample 0), whose stream starts from the stand-in state as PathRng's does.
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_rng.h>

#include <tripsitter/device/path_rng.h>

namespace tripsitter::rtl {
namespace {

using device::PathRng;

constexpr int kLatency = 4;  // ts_path_rng's seed pipeline

struct Key {
  std::uint32_t pixel = 0;   // 0 .. 307199
  std::uint32_t sample = 0;
};

// The first state of a key's stream, before its first draw: PathRng::for_sample's.
std::uint32_t first_state(const Key& k) {
  const std::uint32_t h = PathRng::hash(k.pixel + 307200u * k.sample);
  return h != 0 ? h : 0x9e3779b9u;
}

class RngRtl {
 public:
  RngRtl() {
    context_.randReset(2);
    top_ = std::make_unique<Vts_path_rng>(&context_);
    top_->rst = 1;
    top_->seed_valid = 0;
    top_->draw = 0;
    for (int i = 0; i < 3; ++i) rising_edge(*top_);
    top_->rst = 0;
  }
  Vts_path_rng& top() { return *top_; }

 private:
  VerilatedContext context_;
  std::unique_ptr<Vts_path_rng> top_;
};

std::vector<Key> random_keys(std::mt19937& rng, std::size_t n) {
  std::vector<Key> keys = {{0, 0}, {307199, 0}, {0, 13980}, {307199, 0xffffffffu}, {12345, 1}};
  while (keys.size() < n) {
    const auto pixel = static_cast<std::uint32_t>(rng() % 307200);
    const auto sample = static_cast<std::uint32_t>(rng() % 4 == 0 ? rng() : rng() % 64);
    keys.push_back({pixel, sample});
  }
  return keys;
}

TEST(PathRngRtl, TheSeedPipelineGivesEveryKeysStateAfterItsLatency) {
  std::mt19937 rng(41);
  const std::vector<Key> keys = random_keys(rng, 20000);
  RngRtl rtl;
  Vts_path_rng& top = rtl.top();
  struct Sent {
    std::int64_t cycle;
    std::uint32_t state;
    std::uint16_t tag;
  };
  std::deque<Sent> in_flight;
  std::size_t next = 0;
  int bad = 0;
  std::int64_t cycle = 0;
  while ((next < keys.size() || !in_flight.empty()) && cycle < 100000) {
    const bool send = next < keys.size() && rng() % 5 != 0;  // a gap one cycle in five, junk on the ports in it
    const Key k = send ? keys[next] : Key{static_cast<std::uint32_t>(rng() % 307200), static_cast<std::uint32_t>(rng())};
    top.seed_valid = send;
    top.seed_pixel = k.pixel;
    top.seed_sample = k.sample;
    top.seed_tag = static_cast<SData>(send ? next : rng());
    if (send) in_flight.push_back({cycle, first_state(k), static_cast<std::uint16_t>(next++)});
    rising_edge(top);
    ++cycle;
    if (top.seed_out_valid) {
      if (in_flight.empty()) {
        ++bad;
        ADD_FAILURE() << "a state came out that no key went in for, at cycle " << cycle;
        continue;
      }
      const Sent s = in_flight.front();
      in_flight.pop_front();
      EXPECT_EQ(cycle - s.cycle, kLatency);
      EXPECT_EQ(top.seed_out_tag, s.tag);
      if (top.seed_out_state != s.state && ++bad <= 5)
        ADD_FAILURE() << "key " << s.tag << ": state " << top.seed_out_state << ", the model's " << s.state;
    }
  }
  EXPECT_EQ(next, keys.size());
  EXPECT_TRUE(in_flight.empty());
  EXPECT_EQ(bad, 0);
}

// Loads the stream of `k` and draws `draws` values from it, one a cycle with a pause now and then, comparing each
// with PathRng's.
int draw_and_compare(Vts_path_rng& top, const Key& k, int draws, std::mt19937& rng) {
  top.seed_valid = 1;
  top.seed_pixel = k.pixel;
  top.seed_sample = k.sample;
  top.draw = 0;
  rising_edge(top);
  top.seed_valid = 0;
  for (int i = 0; i < kLatency; ++i) rising_edge(top);  // the state is loaded on the edge it comes out
  PathRng model = PathRng::for_sample(k.pixel, k.sample);
  int bad = 0;
  for (int d = 0; d < draws;) {
    top.draw = rng() % 8 != 0;  // no draw one cycle in eight: the stream holds its value
    rising_edge(top);
    if (!top.draw) continue;
    ++d;
    const std::uint32_t want = model.next();
    if (top.value != want && ++bad <= 3)
      ADD_FAILURE() << "pixel " << k.pixel << " sample " << k.sample << " draw " << d << ": " << top.value
                    << ", PathRng's " << want;
  }
  top.draw = 0;
  return bad;
}

TEST(PathRngRtl, StreamsDrawWhatPathRngDrawsDrawForDraw) {
  std::mt19937 rng(42);
  RngRtl rtl;
  int bad = 0;
  for (const Key& k : random_keys(rng, 200)) bad += draw_and_compare(rtl.top(), k, 1000, rng);
  EXPECT_EQ(bad, 0);
}

TEST(PathRngRtl, TheKeyWhoseHashIsZeroStartsFromTheStandIn) {
  // The hash is a bijection (xor-shifts and odd multipliers): invert it at 0, then find (pixel, sample) for the key.
  const auto unshift = [](std::uint32_t y, int s) {
    std::uint32_t x = y;
    for (int i = 0; i < 32 / s + 1; ++i) x = y ^ (x >> s);
    return x;
  };
  const auto inverse = [](std::uint32_t a) {  // of an odd a, mod 2^32 (Newton: x = x (2 - a x))
    std::uint32_t x = a;
    for (int i = 0; i < 5; ++i) x *= 2 - a * x;
    return x;
  };
  std::uint32_t key = unshift(0, 16);
  key *= inverse(0x846ca68bu);
  key = unshift(key, 15);
  key *= inverse(0x7feb352du);
  key = unshift(key, 16);
  ASSERT_EQ(PathRng::hash(key), 0u);
  EXPECT_EQ(key, 0u) << "the hash keeps 0: pixel 0's first sample of a world is the one";
  Key k;
  bool found = false;
  for (std::uint32_t s = 0; s < (1u << 22) && !found; ++s) {
    const std::uint32_t pixel = key - 307200u * s;
    if (pixel < 307200u) k = {pixel, s}, found = true;
  }
  ASSERT_TRUE(found);
  EXPECT_EQ(first_state(k), 0x9e3779b9u);
  std::mt19937 rng(43);
  RngRtl rtl;
  EXPECT_EQ(draw_and_compare(rtl.top(), k, 100, rng), 0);
}

}  // namespace
}  // namespace tripsitter::rtl
