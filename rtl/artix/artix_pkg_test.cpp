// The artix RTL's package (ts_artix_pkg.sv) against the C++ model: every fact the package states about the
// preset, its units' schedule and its arithmetic equals the value in device/preset.cpp, preset.h and
// artix_kernel.h, so a change on one side alone fails here. The package is read as text: each
// `localparam int Name = expression;` (integers and earlier names joined by + - * /, left to right) is evaluated.
#include <cstdint>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

std::map<std::string, std::int64_t> read_package(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::map<std::string, std::int64_t> values;
  const std::regex line(R"(^\s*localparam\s+int\s+(\w+)\s*=\s*([^;]+);)");
  std::string text;
  while (std::getline(in, text)) {
    std::smatch m;
    if (!std::regex_search(text, m, line)) continue;
    std::istringstream expr(m[2].str());
    std::int64_t value = 0;
    char op = '+';
    std::string token;
    while (expr >> token) {
      if (token.size() == 1 && std::string("+-*/").find(token[0]) != std::string::npos) {
        op = token[0];
        continue;
      }
      std::int64_t operand = 0;
      if (std::isdigit(static_cast<unsigned char>(token[0]))) {
        operand = std::stoll(token);
      } else {
        const auto it = values.find(token);
        if (it == values.end()) throw std::runtime_error(path + ": " + m[1].str() + " uses unknown " + token);
        operand = it->second;
      }
      value = op == '+' ? value + operand : op == '-' ? value - operand : op == '*' ? value * operand : value / operand;
    }
    values[m[1].str()] = value;
  }
  return values;
}

int bits_for(std::int64_t values) {  // index bits of `values` entries
  int b = 0;
  while ((std::int64_t{1} << b) < values) ++b;
  return b;
}

TEST(ArtixPackage, StatesThePresetsFacts) {
  const auto pkg = read_package(TS_ARTIX_PKG);
  const auto at = [&](const char* name) {
    const auto it = pkg.find(name);
    if (it == pkg.end()) throw std::runtime_error(std::string("ts_artix_pkg.sv has no ") + name);
    return it->second;
  };
  const device::DevicePreset p = device::artix_preset();
  ASSERT_TRUE(p.units.has_value());
  EXPECT_EQ(at("Frac"), p.x.frac_bits);
  for (const auto* f : {&p.x, &p.y, &p.z}) {
    EXPECT_EQ(at("CoordW"), f->total_bits);
    EXPECT_EQ(at("Frac"), f->frac_bits);
  }
  EXPECT_EQ(at("RadiusW"), p.radius.total_bits);
  EXPECT_EQ(at("Frac"), p.radius.frac_bits);
  EXPECT_EQ(at("MaxSpheres"), p.max_spheres);
  EXPECT_EQ(at("SphereAW"), bits_for(p.max_spheres));
  EXPECT_EQ(at("Units"), p.workers);
  EXPECT_EQ(at("MaxBounces"), p.max_bounces);
  EXPECT_EQ(at("LeadCycles"), p.lead_cycles);
  EXPECT_EQ(at("LineWidth"), device::kLineWidth);
  EXPECT_EQ(at("TileColumns"), p.units->tile_columns);
  EXPECT_EQ(at("Tiles"), device::kLineWidth / p.units->tile_columns);
  EXPECT_EQ(at("MinPass"), p.units->min_pass);
  EXPECT_EQ(at("HitLatency"), p.units->hit_latency);
  EXPECT_EQ(at("ReflectLatency"), p.units->reflect_latency);
  EXPECT_EQ(at("ShadeLatency"), p.units->shade_latency);
  EXPECT_EQ(at("WalkLead"), p.units->walk_lead);
  EXPECT_EQ(at("WalkWait"), p.units->walk_wait);
  EXPECT_EQ(at("Paths"), device::artix_path_preset().units->paths);
  EXPECT_EQ(at("BounceLatency"), device::artix_path_preset().units->reflect_latency);
  EXPECT_EQ(at("PixelLatency"), device::artix_path_preset().units->shade_latency);
  EXPECT_EQ(at("DirFrac"), artix::kDirectionFrac);
  EXPECT_EQ(std::int64_t{1} << (at("DirW") - 1), artix::kDirectionMax + 1);
  EXPECT_EQ(at("ScaledRadiusBits"), artix::kScaledRadiusBits);
  EXPECT_EQ(at("SeedFirst"), artix::kSeedFirst);
  EXPECT_EQ(at("SeedLast"), artix::kSeedLast);
  EXPECT_EQ(at("SeedEntries"), artix::kSeedEntries);
  EXPECT_EQ(at("CoordW"), artix::kMaxCoordinateBits);
  EXPECT_EQ(at("RadiusW"), artix::kMaxRadiusBits);
  // The registers' widths are the kernel's checked ranges (artix_kernel.h).
  EXPECT_EQ(at("OriginW"), artix::kOriginBits);
  EXPECT_EQ(at("OcW"), artix::kOcBits);
  EXPECT_EQ(at("BW"), artix::kBBits);
  EXPECT_EQ(at("FW"), artix::kFBits);
}

TEST(ArtixPackage, ReadingFailsOnAnUnknownName) {
  // The reader itself: a package that uses a name it never defined is an error, not a zero.
  const std::string path = testing::TempDir() + "bad_pkg.sv";
  std::ofstream(path) << "package p;\n  localparam int A = B + 1;\nendpackage\n";
  EXPECT_THROW(read_package(path), std::runtime_error);
}

}  // namespace
}  // namespace tripsitter::rtl
