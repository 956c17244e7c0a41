// The link's RTL package (ts_link_pkg.sv) against the C++ link: every fact the package states about the wires equals
// what src/tripsitter/link/ says, so a change on one side alone fails here. The constants frame.h and wire_v1.h
// publish are compared directly; the header and sphere-record offsets, which frame.cpp keeps to itself, are compared
// with where encode_frame puts each field of a frame built to make every field recognisable; the v1 fields with the
// bits encode_v1_word sets for each field alone. The package is read as text: each `localparam int Name = value;`
// (a decimal or 32'h hexadecimal literal).
#include <cstdint>
#include <fstream>
#include <map>
#include <regex>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/wire_v1.h>

namespace tripsitter::rtl {
namespace {

using link::WireVersion;

std::map<std::string, std::int64_t> read_package(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::map<std::string, std::int64_t> values;
  const std::regex line(R"(^\s*localparam\s+int\s+(\w+)\s*=\s*(32'h([0-9A-Fa-f_]+)|([0-9]+))\s*;)");
  std::string text;
  while (std::getline(in, text)) {
    std::smatch m;
    if (!std::regex_search(text, m, line)) continue;
    if (m[3].matched) {
      std::string hex = m[3].str();
      std::erase(hex, '_');
      values[m[1].str()] = std::stoll(hex, nullptr, 16);
    } else {
      values[m[1].str()] = std::stoll(m[4].str());
    }
  }
  return values;
}

class LinkPackage : public ::testing::Test {
 protected:
  std::int64_t at(const char* name) const {
    const auto it = pkg_.find(name);
    if (it == pkg_.end()) throw std::runtime_error(std::string("ts_link_pkg.sv has no ") + name);
    return it->second;
  }
  std::map<std::string, std::int64_t> pkg_ = read_package(TS_LINK_PKG);
};

std::uint32_t be32(std::span<const std::uint8_t> bytes, std::size_t at) {
  return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) | (std::uint32_t{bytes[at + 2]} << 8) |
         std::uint32_t{bytes[at + 3]};
}
// Any integer as the package's values are held, so that comparisons are of one signedness.
template <class T>
std::int64_t I(T v) {
  return static_cast<std::int64_t>(v);
}

std::uint32_t magic_of(const std::array<std::uint8_t, 4>& magic) { return be32(magic, 0); }

// A world whose every header field and sphere field has a value no other field has.
link::World recognisable_world() {
  link::World w;
  w.session = 0x5E55'1011;
  w.sequence = 0x0005'E9A0;
  w.frac_bits = 7;
  link::WireSphere s;
  s.x = 0x0102'0304;
  s.y = 0x1112'1314;
  s.z = 0x2122'2324;
  s.radius = 0x3132'3334;
  s.material = link::kMaterialDielectric;
  s.albedo = {0x41, 0x42, 0x43};
  s.fuzz = 0x5152;
  s.ior = 0x6162;
  w.spheres = {s, s, s};
  return w;
}

TEST_F(LinkPackage, StatesTheFramedWiresFacts) {
  EXPECT_EQ(at("V2Magic"), I(magic_of(link::kV2Magic)));
  EXPECT_EQ(at("V3Magic"), I(magic_of(link::kV3Magic)));
  EXPECT_EQ(at("V2Version"), I(link::kV2Version));
  EXPECT_EQ(at("V3Version"), I(link::kV3Version));
  EXPECT_EQ(at("V2HeaderBytes"), I(link::kV2HeaderBytes));
  EXPECT_EQ(at("V3HeaderBytes"), I(link::kV3HeaderBytes));
  EXPECT_EQ(at("V2HeaderBytes"), I(link::frame_header_bytes(WireVersion::kV2)));
  EXPECT_EQ(at("V3HeaderBytes"), I(link::frame_header_bytes(WireVersion::kV3)));
  EXPECT_EQ(at("SphereBytes"), I(link::kSphereBytes));
  EXPECT_EQ(at("FrameTrailerBytes"), I(link::kFrameTrailerBytes));
  EXPECT_EQ(at("V3HeaderBytes") + 5 * at("SphereBytes") + at("FrameTrailerBytes"),
            I(link::frame_bytes(WireVersion::kV3, 5)));
  EXPECT_EQ(at("MaxFracBits"), I(link::kMaxFracBits));
  EXPECT_EQ(at("MaterialLambertian"), I(link::kMaterialLambertian));
  EXPECT_EQ(at("MaterialMetal"), I(link::kMaterialMetal));
  EXPECT_EQ(at("MaterialDielectric"), I(link::kMaterialDielectric));
  EXPECT_EQ(at("RetiredSessions"), I(link::SequenceRules::kRetiredSessions));
}

// Each header field where encode_frame writes it, on both wires.
TEST_F(LinkPackage, HeaderOffsetsAreWhereTheEncoderPutsEachField) {
  const link::World w = recognisable_world();
  for (const WireVersion wire : {WireVersion::kV2, WireVersion::kV3}) {
    const bool v3 = wire == WireVersion::kV3;
    SCOPED_TRACE(v3 ? "v3" : "v2");
    const std::vector<std::uint8_t> f = link::encode_frame(wire, w);
    const auto field = [&](const char* v2_name, const char* v3_name) {
      return static_cast<std::size_t>(at(v3 ? v3_name : v2_name));
    };
    EXPECT_EQ(I(f.at(static_cast<std::size_t>(at("VersionAt")))), I(v3 ? link::kV3Version : link::kV2Version));
    EXPECT_EQ(I(f.at(static_cast<std::size_t>(at("FracBitsAt")))), I(w.frac_bits));
    // The reserved bytes are zero and the next field begins where they end.
    EXPECT_EQ(at("ReservedAt"), I(at("FracBitsAt") + 1));
    for (auto i = static_cast<std::size_t>(at("ReservedAt")); i < static_cast<std::size_t>(at("ReservedEnd")); ++i)
      EXPECT_EQ(I(f.at(i)), 0) << "reserved byte " << i;
    EXPECT_EQ(I(field("V2SequenceAt", "V3SessionAt")), at("ReservedEnd"));
    if (v3) {
      EXPECT_EQ(be32(f, field("", "V3SessionAt")), w.session);
    }
    EXPECT_EQ(be32(f, field("V2SequenceAt", "V3SequenceAt")), w.sequence);
    EXPECT_EQ(I(be32(f, field("V2CountAt", "V3CountAt"))), I(w.spheres.size()));
    EXPECT_EQ(I(be32(f, field("V2LengthAt", "V3LengthAt"))), I(w.spheres.size() * link::kSphereBytes));
    if (v3) {
      const auto crc_at = static_cast<std::size_t>(at("V3HeaderCrcAt"));
      EXPECT_EQ(be32(f, crc_at), core::crc32(std::span(f).first(crc_at)));
      EXPECT_EQ(I(crc_at + 4), I(link::kV3HeaderBytes));  // the header CRC is the header's last field
    } else {
      EXPECT_EQ(I(field("V2LengthAt", "") + 4), I(link::kV2HeaderBytes));  // the length is v2's last field
    }
  }
}

// Each field of a sphere record where encode_frame writes it (the second record, so the offsets are from its start).
TEST_F(LinkPackage, SphereRecordOffsetsAreWhereTheEncoderPutsEachField) {
  const link::World w = recognisable_world();
  const link::WireSphere& s = w.spheres[1];
  const std::vector<std::uint8_t> f = link::encode_frame(WireVersion::kV3, w);
  const std::size_t rec = link::kV3HeaderBytes + link::kSphereBytes;
  const auto off = [&](const char* name) { return rec + static_cast<std::size_t>(at(name)); };
  EXPECT_EQ(be32(f, off("SphereXAt")), static_cast<std::uint32_t>(s.x));
  EXPECT_EQ(be32(f, off("SphereYAt")), static_cast<std::uint32_t>(s.y));
  EXPECT_EQ(be32(f, off("SphereZAt")), static_cast<std::uint32_t>(s.z));
  EXPECT_EQ(be32(f, off("SphereRadiusAt")), s.radius);
  EXPECT_EQ(I(f.at(off("SphereMaterialAt"))), I(s.material));
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(I(f.at(off("SphereAlbedoAt") + k)), I(s.albedo[k]));
  EXPECT_EQ(I((f.at(off("SphereFuzzAt")) << 8) | f.at(off("SphereFuzzAt") + 1)), I(s.fuzz));
  EXPECT_EQ(I((f.at(off("SphereIorAt")) << 8) | f.at(off("SphereIorAt") + 1)), I(s.ior));
  EXPECT_EQ(at("SphereIorAt") + 2, at("SphereBytes"));  // ior is the record's last field
}

// v3's hierarchy: the content byte, and each field of a node record where encode_frame writes it (the second node,
// so the offsets are from its start).
TEST_F(LinkPackage, NodeRecordOffsetsAreWhereTheEncoderPutsEachField) {
  link::World w;
  w.frac_bits = 4;
  w.spheres.push_back({0, 0, 6400, 100, link::kMaterialLambertian, {}, 0, 6144});
  w.spheres.push_back({300, 0, 6400, 100, link::kMaterialLambertian, {}, 0, 6144});
  w.nodes.push_back({0, 0, 0, 0, 1, 1, 0, 0});
  w.nodes.push_back({0x11223344, -0x5566778, 0x12345678, 0x7A6B5C4D, 0x0102, 0x03, 0x02, 0x0A0B0C0D});
  const link::WireNode& v = w.nodes[1];
  const std::vector<std::uint8_t> f = link::encode_frame(WireVersion::kV3, w);
  EXPECT_EQ(I(f.at(static_cast<std::size_t>(at("ContentAt")))), I(link::kContentHierarchy));
  EXPECT_EQ(at("ContentHierarchy"), I(link::kContentHierarchy));
  EXPECT_EQ(at("ContentAt"), at("ReservedAt"));
  EXPECT_EQ(at("NodeBytes"), I(link::kNodeBytes));
  EXPECT_EQ(at("MaxHierarchyDepth"), I(link::kMaxHierarchyDepth));
  const std::size_t rec = link::kV3HeaderBytes + 2 * link::kSphereBytes + link::kNodeBytes;
  const auto off = [&](const char* name) { return rec + static_cast<std::size_t>(at(name)); };
  EXPECT_EQ(be32(f, off("NodeXAt")), static_cast<std::uint32_t>(v.x));
  EXPECT_EQ(be32(f, off("NodeYAt")), static_cast<std::uint32_t>(v.y));
  EXPECT_EQ(be32(f, off("NodeZAt")), static_cast<std::uint32_t>(v.z));
  EXPECT_EQ(be32(f, off("NodeRadiusAt")), v.radius);
  EXPECT_EQ(I((f.at(off("NodeFirstChildAt")) << 8) | f.at(off("NodeFirstChildAt") + 1)), I(v.first_child));
  EXPECT_EQ(I(f.at(off("NodeChildrenAt"))), I(v.children));
  EXPECT_EQ(I(f.at(off("NodeSphereCountAt"))), I(v.sphere_count));
  EXPECT_EQ(be32(f, off("NodeFirstSphereAt")), v.first_sphere);
  EXPECT_EQ(at("NodeFirstSphereAt") + 4, at("NodeBytes"));  // first_sphere is the record's last field
}

// Each v1 field: the bits encode_v1_word sets for that field alone, all ones, are exactly the package's.
TEST_F(LinkPackage, V1FieldsAreWhereTheEncoderPutsThem) {
  EXPECT_EQ(at("V1WordBytes"), I(link::kV1WordBytes));
  EXPECT_EQ(at("V1Frac"), I(link::kV1X.frac_bits));
  EXPECT_EQ(at("V1Frac"), I(link::kV1Y.frac_bits));
  EXPECT_EQ(at("V1Frac"), I(link::kV1Z.frac_bits));
  EXPECT_EQ(at("V1XW"), I(link::kV1X.total_bits));
  EXPECT_EQ(at("V1YW"), I(link::kV1Y.total_bits));
  EXPECT_EQ(at("V1ZW"), I(link::kV1Z.total_bits));
  EXPECT_EQ((std::int64_t{1} << at("V1RW")) - 1, I(link::kV1RadiusLog2Max));
  const auto bits = [&](const char* shift, const char* width) {
    return ((std::uint64_t{1} << at(width)) - 1) << at(shift);
  };
  link::V1Sphere s;
  s.x_raw = -1;  // all ones in its field
  EXPECT_EQ(link::encode_v1_word(s), bits("V1XShift", "V1XW"));
  s = {};
  s.y_raw = -1;
  EXPECT_EQ(link::encode_v1_word(s), bits("V1YShift", "V1YW"));
  s = {};
  s.z_raw = -1;
  EXPECT_EQ(link::encode_v1_word(s), bits("V1ZShift", "V1ZW"));
  s = {};
  s.radius_log2 = static_cast<std::uint8_t>(link::kV1RadiusLog2Max);
  EXPECT_EQ(link::encode_v1_word(s), bits("V1RShift", "V1RW"));
  s = {};
  s.colour = 0xFFF;
  EXPECT_EQ(link::encode_v1_word(s), bits("V1ColourShift", "V1ColourW"));
}

// The reader itself: a name the package does not have is an error, not a silent zero.
TEST_F(LinkPackage, AnUnknownNameIsAnError) { EXPECT_THROW(at("NoSuchFact"), std::runtime_error); }

}  // namespace
}  // namespace tripsitter::rtl
