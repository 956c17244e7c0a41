// The artix shading, reflection and tint block (ts_artix_shade_reflect.sv) held to the model: for a pass's closest
// hit, artix::reflect and the tint's products when the model reflects, else core::tint_colour of
// artix::normal_colour (of the background on a miss), each exactly in the cycle the line's schedule counts on
// (ReflectLatency, ShadeLatency - 1 after the hit is known). Cases: spheres at the formats' limits (centres of 22
// bits, radii 1 .. 2^21 - 1, every scale e) hit by camera rays, by rays from random origins and by rays reflected
// along chains of metals; random bounces and reachable tints; events back to back (every 3 cycles) and sparse,
// with garbage at the ports between them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_shade_reflect.h>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

// ts_artix_pkg's widths (the Verilated ports' types follow them) and the block's TAG_W; the bounce cut-off and the
// latencies are the preset's, which TheBlocksFactsAreThePresets holds these to.
constexpr int kOriginW = 24, kDirW = 18, kBdW = 44, kFW = 48, kSqrtW = 17, kTdW = 45, kExpW = 6, kRinvW = 19;
constexpr int kMaxBounces = 3, kTintW = 8 * kMaxBounces, kTagW = 10;
constexpr int kReflectLatency = 20, kShadeLatency = 12, kMinPass = 3;

std::int64_t signed_bits(std::int64_t v, int width) {
  return static_cast<std::int64_t>(sign_extend(static_cast<UInt128>(v), width));
}

// One pass's end as the block takes it, and what the model makes of it.
struct Event {
  artix::UnitRay ray;
  bool hit = false;
  artix::Quadratic q;
  artix::UnitSphere s;
  int bounces = 0;
  std::array<std::int64_t, 3> tint{1, 1, 1};
  int tag = 0;
  // The model (artix::trace_pixel_with's loop body).
  bool reflects() const { return hit && s.metal && bounces < kMaxBounces; }
  artix::UnitRay reflected() const { return artix::reflect(ray, s, q.td); }
  std::array<std::int64_t, 3> next_tint() const {
    std::array<std::int64_t, 3> t{};
    for (std::size_t k = 0; k < 3; ++k) t[k] = tint[k] * s.albedo[k];
    return t;
  }
  core::Rgb444 colour() const {
    std::int64_t scale = 1;
    for (int i = 0; i < bounces; ++i) scale *= 255;
    const core::Rgb444 base = hit ? artix::normal_colour(ray, s) : core::kBackground;
    return core::tint_colour(artix::TintArith{}, base, tint, scale);
  }
};

// What came out, and in which cycle.
struct RayOut {
  artix::UnitRay ray;
  int bounces = 0;
  std::array<std::int64_t, 3> tint{};
  int tag = 0;
};
struct ColourOut {
  int colour = 0;
  int tag = 0;
};

class ShadeReflect {
 public:
  explicit ShadeReflect(std::uint64_t garbage_seed)
      : top_(std::make_unique<Vts_artix_shade_reflect>()), rng_(garbage_seed) {
    top_->rst = 1;
    tick();
    tick();
    top_->rst = 0;
  }
  // One cycle: the event at the ports (or garbage without in_valid), the outputs of this cycle recorded.
  void cycle(const Event* e) {
    if (e != nullptr) {
      drive(*e);
      top_->in_valid = 1;
    } else {
      garbage();
      top_->in_valid = 0;
    }
    top_->eval();
    if (top_->out_ray_valid) rays_[now_] = read_ray();
    if (top_->out_colour_valid)
      colours_[now_] = {static_cast<int>(top_->out_colour), static_cast<int>(top_->out_colour_tag)};
    tick();
  }
  std::int64_t now() const { return now_; }
  const std::map<std::int64_t, RayOut>& rays() const { return rays_; }
  const std::map<std::int64_t, ColourOut>& colours() const { return colours_; }

 private:
  void tick() {
    top_->clk = 1;
    top_->eval();
    top_->clk = 0;
    top_->eval();
    ++now_;
  }
  void drive(const Event& e) {
    Vts_artix_shade_reflect& t = *top_;
    for (int k = 0; k < 3; ++k) {
      const auto i = static_cast<std::size_t>(k);
      set_bits(t.in_o, k * kOriginW, kOriginW, e.ray.o[i]);
      set_bits(t.in_d, k * kDirW, kDirW, e.ray.d[i]);
      set_bits(t.in_tint, k * kTintW, kTintW, e.tint[i]);
    }
    t.in_hit = e.hit;
    t.in_bounces = static_cast<CData>(e.bounces);
    t.in_tag = static_cast<SData>(e.tag);
    if (!e.hit) return;  // the quadratic's and the sphere's fields stay garbage: the block must ignore them
    set_bits(t.in_bd, 0, kBdW, e.q.bd);
    for (int k = 0; k < 3; ++k) set_bits(t.in_f, k * kFW, kFW, e.q.f[static_cast<std::size_t>(k)]);
    t.in_s = static_cast<IData>(e.q.s);
    set_bits(t.in_td, 0, kTdW, e.q.td);
    t.in_e = static_cast<CData>(e.s.e & 0x3f);
    t.in_r = static_cast<IData>(e.s.r);
    t.in_rinv = static_cast<IData>(e.s.rinv);
    t.in_metal = e.s.metal;
    t.in_albedo = static_cast<IData>(e.s.albedo[0] | (e.s.albedo[1] << 8) | (e.s.albedo[2] << 16));
  }
  void garbage() {
    Vts_artix_shade_reflect& t = *top_;
    auto any = [&](int bits) { return static_cast<std::int64_t>(rng_() & ((std::uint64_t{1} << bits) - 1)); };
    for (int k = 0; k < 3; ++k) {
      set_bits(t.in_o, k * kOriginW, kOriginW, any(kOriginW));
      set_bits(t.in_d, k * kDirW, kDirW, any(kDirW));
      set_bits(t.in_tint, k * kTintW, kTintW, any(kTintW));
      set_bits(t.in_f, k * kFW, kFW, any(kFW));
    }
    set_bits(t.in_bd, 0, kBdW, any(kBdW));
    set_bits(t.in_td, 0, kTdW, any(kTdW));
    t.in_hit = static_cast<CData>(any(1));
    t.in_s = static_cast<IData>(any(kSqrtW));
    t.in_e = static_cast<CData>(any(kExpW));
    t.in_r = static_cast<IData>(any(21));
    t.in_rinv = static_cast<IData>(any(kRinvW));
    t.in_metal = static_cast<CData>(any(1));
    t.in_albedo = static_cast<IData>(any(24));
    t.in_bounces = static_cast<CData>(any(2));
    t.in_tag = static_cast<SData>(any(kTagW));
  }
  RayOut read_ray() const {
    const Vts_artix_shade_reflect& t = *top_;
    RayOut r;
    for (int k = 0; k < 3; ++k) {
      const auto i = static_cast<std::size_t>(k);
      r.ray.o[i] = signed_bits(bits_of(t.out_ray_o, k * kOriginW, kOriginW), kOriginW);
      r.ray.d[i] = signed_bits(bits_of(t.out_ray_d, k * kDirW, kDirW), kDirW);
      r.tint[i] = bits_of(t.out_ray_tint, k * kTintW, kTintW);
    }
    r.bounces = t.out_ray_bounces;
    r.tag = t.out_ray_tag;
    return r;
  }

  std::unique_ptr<Vts_artix_shade_reflect> top_;
  std::mt19937_64 rng_;
  std::int64_t now_ = 0;
  std::map<std::int64_t, RayOut> rays_;
  std::map<std::int64_t, ColourOut> colours_;
};

// Random cases at the formats' limits.
class CaseDraw {
 public:
  explicit CaseDraw(std::uint64_t seed) : rng_(seed) {}
  std::int64_t between(std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_);
  }
  double real(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

  // A unit direction, times 2^17, uniform over the sphere.
  artix::Vec3i direction() {
    std::normal_distribution<double> normal(0, 1);
    double v[3], len = 0;
    do {
      len = 0;
      for (double& x : v) {
        x = normal(rng_);
        len += x * x;
      }
      len = std::sqrt(len);
    } while (len < 1e-3);
    artix::Vec3i d{};
    for (std::size_t k = 0; k < 3; ++k)
      d[k] = std::clamp<std::int64_t>(std::llround(v[k] / len * 131072.0), -artix::kDirectionMax, artix::kDirectionMax);
    return d;
  }
  // 1 .. 2^21 - 1: the smallest, the largest, around powers of two, and log-uniform.
  std::int64_t radius() {
    constexpr std::int64_t kMax = (std::int64_t{1} << 21) - 1;
    switch (between(0, 9)) {
      case 0: return between(1, 4);
      case 1: return kMax - between(0, 2);
      case 2: return std::clamp<std::int64_t>((std::int64_t{1} << between(0, 20)) + between(-1, 1), 1, kMax);
      default: return std::clamp<std::int64_t>(std::llround(std::exp2(real(0, 21))), 1, kMax);
    }
  }
  std::array<std::uint8_t, 3> albedo() {
    std::array<std::uint8_t, 3> a{};
    for (auto& x : a) {
      const auto kind = between(0, 5);
      x = static_cast<std::uint8_t>(kind == 0 ? 0 : kind == 1 ? 255 : between(0, 255));
    }
    return a;
  }
  // A sphere `ray` hits in front of its origin (centre within 22 bits signed), into `e`; false when the draw
  // missed or left the format.
  bool place(const artix::UnitRay& ray, bool metal, Event& e) {
    const std::int64_t r = radius();
    const double rr = static_cast<double>(r);
    const double dist = rr * (1.0 + std::exp2(real(-12, 8))) + static_cast<double>(between(0, 8));
    const double off = rr * real(0, 1.02);
    const artix::Vec3i w = direction();
    std::array<std::int64_t, 3> c{};
    for (std::size_t k = 0; k < 3; ++k) {
      const double v = static_cast<double>(ray.o[k]) +
                       (dist * static_cast<double>(ray.d[k]) + off * static_cast<double>(w[k])) / 131072.0;
      if (std::abs(v) >= 2097151.0) return false;
      c[k] = std::llround(v);
    }
    core::KernelSphere<std::int64_t> ks;
    ks.center = {c[0], c[1], c[2]};
    ks.radius = r;
    core::KernelSurface surface;
    surface.metal = metal;
    surface.albedo = albedo();
    e.ray = ray;
    e.s = artix::prepare_sphere(ks, surface);
    e.q = artix::quadratic(ray, e.s);
    e.hit = e.q.hit();
    return e.hit;
  }
  // The camera's ray of a random pixel, a ray from a random origin (a hit point's range), or one reflected along a
  // chain of one to three metals.
  artix::UnitRay ray() {
    artix::UnitRay ray;
    const auto kind = between(0, 2);
    if (kind == 1) {
      for (auto& o : ray.o) o = between(-(std::int64_t{1} << 22) + 1, (std::int64_t{1} << 22) - 1);
      ray.d = direction();
      return ray;
    }
    ray.d = artix::camera_direction(static_cast<int>(between(0, 639)), static_cast<int>(between(0, 479)));
    if (kind == 2) {
      for (auto links = between(1, 3); links > 0; --links) {
        Event e;
        int tries = 0;
        while (!place(ray, true, e))
          if (++tries > 50) return ray;
        ray = e.reflected();
      }
    }
    return ray;
  }
  // A hit of a metal or not.
  Event hit(bool metal) {
    while (true) {
      const artix::UnitRay r = ray();
      Event e;
      for (int tries = 0; tries < 20; ++tries)
        if (place(r, metal, e)) return e;
    }
  }
  // A pass that hit nothing: the ray only (the block gets garbage for the rest).
  Event miss() {
    Event e;
    e.ray = ray();
    return e;
  }
  // The pixel's state: `bounces` reflections so far and the tint they made (products of albedo bytes).
  void state(Event& e, int bounces) {
    e.bounces = bounces;
    e.tint = {1, 1, 1};
    for (int i = 0; i < bounces; ++i) {
      const auto a = albedo();
      for (std::size_t k = 0; k < 3; ++k) e.tint[k] *= a[k];
    }
  }
  // Any of the kinds: reflecting metals, metals at the bounce limit, other hits, misses.
  Event any() {
    Event e;
    switch (between(0, 5)) {
      case 0:
      case 1: e = hit(true); state(e, static_cast<int>(between(0, kMaxBounces - 1))); break;
      case 2: e = hit(true); state(e, kMaxBounces); break;
      case 3:
      case 4: e = hit(false); state(e, static_cast<int>(between(0, kMaxBounces))); break;
      default: e = miss(); state(e, static_cast<int>(between(0, kMaxBounces))); break;
    }
    return e;
  }

 private:
  std::mt19937_64 rng_;
};

// Runs `events` with the gaps given (cycles from one event to the next, each >= MinPass) and checks every output
// against the model, in its exact cycle and nowhere else. Returns the number of mismatches (the first ten reported).
int run_and_compare(std::vector<Event> events, const std::vector<int>& gaps, std::uint64_t seed) {
  ShadeReflect block(seed);
  std::map<std::int64_t, std::size_t> at;  // the cycle of each event
  std::int64_t next = block.now() + 5;
  for (std::size_t i = 0; i < events.size(); ++i) {
    events[i].tag = static_cast<int>(i % (1u << kTagW));
    at[next] = i;
    next += gaps[i];
  }
  const std::int64_t end = next + kReflectLatency + 5;
  while (block.now() < end) {
    const auto it = at.find(block.now());
    block.cycle(it == at.end() ? nullptr : &events[it->second]);
  }
  int bad = 0;
  auto report = [&bad]() { return ++bad <= 10; };
  std::size_t rays = 0, colours = 0;
  for (const auto& [k, i] : at) {
    const Event& e = events[i];
    if (e.reflects()) {
      ++rays;
      const auto out = block.rays().find(k + kReflectLatency);
      if (out == block.rays().end()) {
        if (report()) ADD_FAILURE() << "event " << i << ": no ray in cycle K + " << kReflectLatency;
        continue;
      }
      const artix::UnitRay want = e.reflected();
      const auto tint = e.next_tint();
      const RayOut& got = out->second;
      if ((got.ray.o != want.o || got.ray.d != want.d || got.bounces != e.bounces + 1 || got.tint != tint ||
           got.tag != e.tag) && report()) {
        ADD_FAILURE() << "event " << i << " (e " << e.s.e << ", r " << e.s.r << ", bounces " << e.bounces
                      << "): ray o (" << got.ray.o[0] << ", " << got.ray.o[1] << ", " << got.ray.o[2] << ") d ("
                      << got.ray.d[0] << ", " << got.ray.d[1] << ", " << got.ray.d[2] << ") tint (" << got.tint[0]
                      << ", " << got.tint[1] << ", " << got.tint[2] << ") bounces " << got.bounces << " tag "
                      << got.tag << "; the model's o (" << want.o[0] << ", " << want.o[1] << ", " << want.o[2]
                      << ") d (" << want.d[0] << ", " << want.d[1] << ", " << want.d[2] << ") tint (" << tint[0]
                      << ", " << tint[1] << ", " << tint[2] << ") bounces " << e.bounces + 1 << " tag " << e.tag;
      }
    } else {
      ++colours;
      const auto out = block.colours().find(k + kShadeLatency - 1);
      if (out == block.colours().end()) {
        if (report()) ADD_FAILURE() << "event " << i << ": no colour in cycle K + " << kShadeLatency - 1;
        continue;
      }
      const int want = e.colour().packed;
      if ((out->second.colour != want || out->second.tag != e.tag) && report()) {
        ADD_FAILURE() << "event " << i << " (hit " << e.hit << ", e " << e.s.e << ", r " << e.s.r << ", bounces "
                      << e.bounces << ", tint " << e.tint[0] << " " << e.tint[1] << " " << e.tint[2] << "): colour "
                      << std::hex << out->second.colour << ", the model's " << want << std::dec << "; tag "
                      << out->second.tag << " for " << e.tag;
      }
    }
  }
  // Nothing else came out: every output pulse is one of the events'.
  EXPECT_EQ(block.rays().size(), rays);
  EXPECT_EQ(block.colours().size(), colours);
  return bad;
}

std::vector<int> back_to_back(std::size_t n) { return std::vector<int>(n, kMinPass); }

TEST(ArtixShadeReflectRtl, TheBlocksFactsAreThePresets) {
  const device::DevicePreset preset = device::artix_preset();
  ASSERT_TRUE(preset.units.has_value());
  EXPECT_EQ(preset.max_bounces, kMaxBounces);
  EXPECT_EQ(preset.units->reflect_latency, kReflectLatency);
  EXPECT_EQ(preset.units->shade_latency, kShadeLatency);
  EXPECT_EQ(preset.units->min_pass, kMinPass);
}

// Whether channel k's numerator 7 (Q_k + R) in the model's normal_colour is negative (scaled_normal in
// artix_kernel.cpp: the channel is 0 there without a quotient), for the draw's coverage.
bool numerator_negative(const Event& e, std::size_t k) {
  const std::int64_t beta = ((e.q.bd & 0x1ffff) ^ 0x10000) - 0x10000;
  const int z = std::max(0, -e.s.e);
  const std::int64_t f = e.q.f[k] - ((beta * e.ray.d[k]) >> 17);
  const std::int64_t q = -((f << z) + ((e.q.s * e.ray.d[k]) << (e.s.e + z)));
  return q + (e.s.r << (17 + z)) < 0;
}

TEST(ArtixShadeReflectRtl, ReflectsAndShadesAsTheModelBackToBack) {
  CaseDraw draw(1);
  std::vector<Event> events;
  for (int i = 0; i < 20000; ++i) events.push_back(draw.any());
  // The draw covers what it claims: every scale, each kind and bounce count, the channels' extremes.
  std::set<int> scales, colour_values;
  std::set<std::pair<bool, int>> kinds;  // (reflects, bounces)
  int misses = 0, limit_metals = 0, saturated_normals = 0, negative_numerators = 0;
  for (const Event& e : events) {
    if (e.hit) scales.insert(e.s.e);
    kinds.insert({e.reflects(), e.bounces});
    misses += !e.hit;
    limit_metals += e.hit && e.s.metal && e.bounces == kMaxBounces;
    if (e.hit && !e.reflects()) {
      const core::Rgb444 c = artix::normal_colour(e.ray, e.s);
      colour_values.insert({c.r(), c.g(), c.b()});
      for (std::size_t k = 0; k < 3; ++k) negative_numerators += numerator_negative(e, k);
    }
    if (e.reflects()) {
      const artix::Vec3i n = artix::normal(e.ray, e.s);
      for (const auto nk : n) saturated_normals += std::abs(nk) == artix::kDirectionMax;
    }
  }
  EXPECT_EQ(scales.size(), 21u);  // e = -16 .. 4
  for (int b = 0; b <= kMaxBounces; ++b) EXPECT_TRUE(kinds.count({false, b})) << b;
  for (int b = 0; b < kMaxBounces; ++b) EXPECT_TRUE(kinds.count({true, b})) << b;
  EXPECT_TRUE(colour_values.count(0) && colour_values.count(14));
  EXPECT_GT(misses, 100);
  EXPECT_GT(limit_metals, 100);
  EXPECT_GT(saturated_normals, 0);
  EXPECT_GT(negative_numerators, 0);
  EXPECT_EQ(run_and_compare(events, back_to_back(events.size()), 11), 0);
}

TEST(ArtixShadeReflectRtl, SparseEventsWithGarbageBetween) {
  CaseDraw draw(2);
  std::vector<Event> events;
  std::vector<int> gaps;
  for (int i = 0; i < 6000; ++i) {
    events.push_back(draw.any());
    gaps.push_back(static_cast<int>(draw.between(0, 3) == 0 ? draw.between(kMinPass, 30) : draw.between(kMinPass, 6)));
  }
  EXPECT_EQ(run_and_compare(events, gaps, 12), 0);
}

TEST(ArtixShadeReflectRtl, MissesGiveTheTintedBackground) {
  CaseDraw draw(3);
  std::vector<Event> events;
  for (int i = 0; i < 400; ++i) {
    Event e = draw.miss();
    draw.state(e, i % (kMaxBounces + 1));
    events.push_back(e);
  }
  // The background untinted, and dimmed to black by a zero albedo.
  EXPECT_EQ(events[0].colour().packed, core::kBackground.packed);
  events[1].bounces = 1;
  events[1].tint = {0, 0, 0};
  EXPECT_EQ(events[1].colour().packed, 0);
  EXPECT_EQ(run_and_compare(events, back_to_back(events.size()), 13), 0);
}

// core::tint_colour gives the base colour itself without reflections (a scale of 1), whatever the tint says.
TEST(ArtixShadeReflectRtl, WithoutReflectionsTheTintIsNotApplied) {
  CaseDraw draw(7);
  std::vector<Event> events;
  for (int i = 0; i < 400; ++i) {
    Event e = i % 4 == 0 ? draw.miss() : draw.hit(false);
    e.bounces = 0;
    for (auto& t : e.tint) t = draw.between(0, (std::int64_t{1} << kTintW) - 1);
    if (e.hit) {
      EXPECT_EQ(e.colour().packed, artix::normal_colour(e.ray, e.s).packed);
    }
    events.push_back(e);
  }
  EXPECT_EQ(run_and_compare(events, back_to_back(events.size()), 15), 0);
}

TEST(ArtixShadeReflectRtl, AMetalAtTheBounceLimitIsShaded) {
  CaseDraw draw(4);
  std::vector<Event> events;
  for (int i = 0; i < 400; ++i) {
    Event e = draw.hit(true);
    draw.state(e, kMaxBounces);
    ASSERT_FALSE(e.reflects());
    events.push_back(e);
  }
  EXPECT_EQ(run_and_compare(events, back_to_back(events.size()), 14), 0);
}

// Each kind alone, then both interleaved: the output valid is high in exactly one cycle, K + 20 for a ray and
// K + 11 for a colour, and low in every other.
TEST(ArtixShadeReflectRtl, OutputsComeExactlyAtTheirLatencies) {
  CaseDraw draw(5);
  Event ray = draw.hit(true);
  draw.state(ray, 0);
  Event colour = draw.hit(false);
  draw.state(colour, 1);
  ASSERT_TRUE(ray.reflects());
  ASSERT_FALSE(colour.reflects());
  for (const Event* e : {&ray, &colour}) {
    ShadeReflect block(21);
    const std::int64_t k = block.now() + 7;
    while (block.now() < k + 40) block.cycle(block.now() == k ? e : nullptr);
    const auto& rays = block.rays();
    const auto& colours = block.colours();
    if (e == &ray) {
      ASSERT_EQ(rays.size(), 1u);
      EXPECT_EQ(rays.begin()->first, k + kReflectLatency);
      EXPECT_TRUE(colours.empty());
    } else {
      ASSERT_EQ(colours.size(), 1u);
      EXPECT_EQ(colours.begin()->first, k + kShadeLatency - 1);
      EXPECT_TRUE(rays.empty());
    }
  }
  // A colour event 9 cycles after a ray event: both come out in the same cycle, K + 20.
  ShadeReflect block(22);
  const std::int64_t k = block.now() + 7;
  while (block.now() < k + 40) {
    const std::int64_t t = block.now();
    block.cycle(t == k ? &ray : t == k + 9 ? &colour : nullptr);
  }
  ASSERT_EQ(block.rays().size(), 1u);
  ASSERT_EQ(block.colours().size(), 1u);
  EXPECT_EQ(block.rays().begin()->first, k + kReflectLatency);
  EXPECT_EQ(block.colours().begin()->first, k + 9 + kShadeLatency - 1);
}

// The model's values fit the block's ports and registers on the draw (the widths are derived from the model's own
// checks; this would name a value that escaped them).
TEST(ArtixShadeReflectRtl, TheModelsValuesFitThePorts) {
  CaseDraw draw(6);
  for (int i = 0; i < 20000; ++i) {
    Event e = draw.hit(true);
    const artix::UnitRay out = e.reflected();
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_LT(std::abs(out.o[k]), std::int64_t{1} << (kOriginW - 1));
      ASSERT_LE(std::abs(out.d[k]), artix::kDirectionMax);
      // A hit's f in the sphere's scale fits 18 bits, so f itself 39 (the block keeps f's low 39 bits).
      ASSERT_LT(std::abs(e.q.f[k]), std::int64_t{1} << 38);
    }
    ASSERT_GE(e.s.e, -16);
    ASSERT_LE(e.s.e, 4);
    ASSERT_LE(e.s.rinv, std::int64_t{1} << 18);
  }
}

}  // namespace
}  // namespace tripsitter::rtl
