#include <gtest/gtest.h>
#include <tripsitter/display/vcd.h>
#include <tripsitter/device/vga.h>

#include <cstdint>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace tripsitter::display {
namespace {

using device::VgaSample;

// A small reader of the VCD subset the writer may use, strict about the grammar (IEEE 1364-2005 18.2).
struct Var {
  std::string type;
  int width = 0;
  std::string id;
  std::string name;
};
struct Change {
  std::uint64_t time = 0;
  std::string id;
  std::uint32_t value = 0;
};
struct Dump {
  std::string timescale;
  std::vector<std::string> scopes;  // "module vga"
  std::vector<Var> vars;
  int upscopes = 0;
  std::vector<std::uint64_t> times;  // every #time, in order
  std::vector<Change> changes;
  std::vector<std::string> dumpvars_ids;  // ids given values inside $dumpvars
  std::uint64_t dumpvars_time = 0;
  int dumpvars_blocks = 0;
};

// Returns false (with a gtest failure) on anything outside the grammar.
bool parse_vcd(const std::string& text, Dump& dump) {
  std::istringstream in(text);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  std::size_t i = 0;
  auto until_end = [&](std::vector<std::string>& body) {
    body.clear();
    while (i < tokens.size() && tokens[i] != "$end") body.push_back(tokens[i++]);
    if (i == tokens.size()) return false;
    ++i;  // $end
    return true;
  };

  // Declarations.
  bool definitions_ended = false;
  std::vector<std::string> body;
  while (i < tokens.size() && !definitions_ended) {
    const std::string kw = tokens[i++];
    if (!until_end(body)) {
      ADD_FAILURE() << kw << " without $end";
      return false;
    }
    if (kw == "$date" || kw == "$version" || kw == "$comment") continue;
    if (kw == "$timescale") {
      if (body.size() != 1) {
        ADD_FAILURE() << "bad $timescale";
        return false;
      }
      dump.timescale = body[0];
    } else if (kw == "$scope") {
      if (body.size() != 2) {
        ADD_FAILURE() << "bad $scope";
        return false;
      }
      dump.scopes.push_back(body[0] + " " + body[1]);
    } else if (kw == "$upscope") {
      if (!body.empty()) {
        ADD_FAILURE() << "bad $upscope";
        return false;
      }
      ++dump.upscopes;
    } else if (kw == "$var") {
      if (body.size() != 4) {
        ADD_FAILURE() << "bad $var";
        return false;
      }
      dump.vars.push_back(Var{body[0], std::stoi(body[1]), body[2], body[3]});
    } else if (kw == "$enddefinitions") {
      if (!body.empty()) {
        ADD_FAILURE() << "bad $enddefinitions";
        return false;
      }
      definitions_ended = true;
    } else {
      {
        ADD_FAILURE() << "unknown declaration " << kw;
        return false;
      }
    }
  }
  if (!definitions_ended) {
    ADD_FAILURE() << "no $enddefinitions";
    return false;
  }

  std::map<std::string, int> width_of;
  for (const Var& v : dump.vars) width_of[v.id] = v.width;
  auto known = [&](const std::string& id, int width) {
    const auto it = width_of.find(id);
    if (it == width_of.end()) {
      ADD_FAILURE() << "undeclared id " << id;
      return false;
    }
    if (it->second != width) {
      ADD_FAILURE() << "width mismatch for " << id;
      return false;
    }
    return true;
  };

  // Simulation commands and value changes.
  bool have_time = false, in_dumpvars = false;
  std::uint64_t now = 0;
  while (i < tokens.size()) {
    const std::string t = tokens[i++];
    if (t[0] == '#') {
      if (in_dumpvars) {
        ADD_FAILURE() << "time inside $dumpvars";
        return false;
      }
      const std::uint64_t time = std::stoull(t.substr(1));
      if (have_time && time <= now) {
        ADD_FAILURE() << "time not increasing at " << t;
        return false;
      }
      now = time;
      have_time = true;
      dump.times.push_back(time);
    } else if (t == "$dumpvars") {
      if (!have_time || in_dumpvars) {
        ADD_FAILURE() << "misplaced $dumpvars";
        return false;
      }
      in_dumpvars = true;
      ++dump.dumpvars_blocks;
      dump.dumpvars_time = now;
    } else if (t == "$end") {
      if (!in_dumpvars) {
        ADD_FAILURE() << "stray $end";
        return false;
      }
      in_dumpvars = false;
    } else if (t[0] == '0' || t[0] == '1') {
      const std::string id = t.substr(1);
      if (!have_time || !known(id, 1)) {
        ADD_FAILURE() << "bad scalar change " << t;
        return false;
      }
      dump.changes.push_back(Change{now, id, t[0] == '1' ? 1u : 0u});
      if (in_dumpvars) dump.dumpvars_ids.push_back(id);
    } else if (t[0] == 'b') {
      if (i == tokens.size() || t.size() < 2 || t.size() > 5) {
        ADD_FAILURE() << "bad vector " << t;
        return false;
      }
      std::uint32_t value = 0;
      for (std::size_t k = 1; k < t.size(); ++k) {
        if (t[k] != '0' && t[k] != '1') {
          ADD_FAILURE() << "bad vector digit in " << t;
          return false;
        }
        value = value * 2 + static_cast<std::uint32_t>(t[k] - '0');
      }
      const std::string id = tokens[i++];
      if (!have_time || !known(id, 4)) return false;
      dump.changes.push_back(Change{now, id, value});
      if (in_dumpvars) dump.dumpvars_ids.push_back(id);
    } else {
      {
        ADD_FAILURE() << "unexpected token " << t;
        return false;
      }
    }
  }
  if (in_dumpvars) {
    ADD_FAILURE() << "$dumpvars without $end";
    return false;
  }
  return true;
}

// Rebuilds the sample sequence: sample k holds the values of the latest changes at or before k * period.
std::vector<VgaSample> reconstruct(const Dump& dump, std::uint64_t period, std::uint64_t count) {
  std::map<std::string, std::string> id_of;
  for (const Var& v : dump.vars) id_of[v.name] = v.id;
  std::map<std::string, std::uint32_t> value;
  std::vector<VgaSample> samples;
  std::size_t next = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    while (next < dump.changes.size() && dump.changes[next].time <= k * period) {
      value[dump.changes[next].id] = dump.changes[next].value;
      ++next;
    }
    VgaSample s;
    s.hsync_n = value.at(id_of.at("hsync_n")) != 0;
    s.vsync_n = value.at(id_of.at("vsync_n")) != 0;
    s.colour = core::Rgb444::from_channels(static_cast<int>(value.at(id_of.at("r"))),
                                           static_cast<int>(value.at(id_of.at("g"))),
                                           static_cast<int>(value.at(id_of.at("b"))));
    samples.push_back(s);
  }
  EXPECT_EQ(next, dump.changes.size()) << "changes after the last sample";
  return samples;
}

void check_round_trip(const std::vector<VgaSample>& samples, std::uint64_t period) {
  std::ostringstream out;
  VcdWriter writer(out, period);
  for (const VgaSample& s : samples) writer.sample(s);
  EXPECT_EQ(writer.samples(), samples.size());

  Dump dump;
  ASSERT_TRUE(parse_vcd(out.str(), dump));
  EXPECT_EQ(dump.timescale, "1ns");
  ASSERT_EQ(dump.vars.size(), 5u);
  EXPECT_EQ(dump.dumpvars_blocks, 1);
  EXPECT_EQ(dump.dumpvars_time, 0u);
  EXPECT_EQ(dump.dumpvars_ids.size(), 5u) << "$dumpvars gives every signal its initial value";
  for (std::uint64_t t : dump.times) EXPECT_EQ(t % period, 0u);

  // Only changes are written: one time stamp per sample that differs from the one before, plus time 0.
  std::size_t changed_samples = 0;
  for (std::size_t k = 1; k < samples.size(); ++k) changed_samples += samples[k] != samples[k - 1] ? 1 : 0;
  EXPECT_EQ(dump.times.size(), changed_samples + 1);

  const std::vector<VgaSample> back = reconstruct(dump, period, samples.size());
  ASSERT_EQ(back.size(), samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    ASSERT_EQ(back[k], samples[k]) << "sample " << k;
  }
}

core::Rgb444 pattern(int x, int y) { return core::Rgb444::from_channels(x % 16, (x / 16) % 16, y % 16); }

TEST(VcdWriter, HeaderDeclaresTheSignals) {
  std::ostringstream out;
  VcdWriter writer(out);
  const std::string text = out.str();
  for (const char* line : {"$timescale 1ns $end\n", "$scope module vga $end\n", "$var wire 1 ! hsync_n $end\n",
                           "$var wire 1 \" vsync_n $end\n", "$var wire 4 # r $end\n", "$var wire 4 % g $end\n",
                           "$var wire 4 & b $end\n", "$upscope $end\n", "$enddefinitions $end\n"}) {
    EXPECT_NE(text.find(line), std::string::npos) << "missing " << line;
  }
  EXPECT_LT(text.find("$scope"), text.find("$var"));
  EXPECT_LT(text.find("$var"), text.find("$upscope"));
  EXPECT_LT(text.find("$upscope"), text.find("$enddefinitions"));

  Dump dump;
  ASSERT_TRUE(parse_vcd(text, dump));
  ASSERT_EQ(dump.scopes.size(), 1u);
  EXPECT_EQ(dump.scopes[0], "module vga");
  EXPECT_EQ(dump.upscopes, 1);
  ASSERT_EQ(dump.vars.size(), 5u);
  const char* names[] = {"hsync_n", "vsync_n", "r", "g", "b"};
  const int widths[] = {1, 1, 4, 4, 4};
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(dump.vars[k].type, "wire");
    EXPECT_EQ(dump.vars[k].name, names[k]);
    EXPECT_EQ(dump.vars[k].width, widths[k]);
    for (std::size_t j = 0; j < k; ++j) EXPECT_NE(dump.vars[k].id, dump.vars[j].id);
  }
  EXPECT_TRUE(dump.times.empty());
  EXPECT_EQ(writer.samples(), 0u);
}

TEST(VcdWriter, FirstSampleAndChanges) {
  std::ostringstream out;
  VcdWriter writer(out);
  const std::size_t header = out.str().size();
  writer.sample(VgaSample{true, true, core::Rgb444(0x5A3)});
  EXPECT_EQ(out.str().substr(header), "#0\n$dumpvars\n1!\n1\"\nb0101 #\nb1010 %\nb0011 &\n$end\n");
  const std::size_t after_first = out.str().size();
  writer.sample(VgaSample{true, true, core::Rgb444(0x5A3)});  // unchanged: nothing written
  EXPECT_EQ(out.str().size(), after_first);
  writer.sample(VgaSample{false, true, core::Rgb444(0x5A0)});  // sample 2 at 80 ns
  EXPECT_EQ(out.str().substr(after_first), "#80\n0!\nb0000 &\n");
  EXPECT_EQ(writer.samples(), 3u);
}

TEST(VcdWriter, RoundTripOfAWholeFrame) {
  device::VgaTimingGenerator gen;
  std::vector<VgaSample> samples;
  for (int i = 0; i < 800 * 525 + 1000; ++i) {
    samples.push_back(gen.sample(pattern(gen.column(), gen.line())));
    gen.tick();
  }
  check_round_trip(samples, 40);
}

TEST(VcdWriter, RoundTripOfRandomSamples) {
  std::mt19937 rng(99);
  std::bernoulli_distribution change(0.3);
  std::uniform_int_distribution<int> bit(0, 1), colour(0, 0xFFF);
  for (const std::uint64_t period : {std::uint64_t{40}, std::uint64_t{1}, std::uint64_t{7}}) {
    SCOPED_TRACE(::testing::Message() << "period " << period);
    std::vector<VgaSample> samples;
    VgaSample s{bit(rng) != 0, bit(rng) != 0, core::Rgb444(static_cast<std::uint16_t>(colour(rng)))};
    for (int i = 0; i < 20000; ++i) {
      if (change(rng)) s.hsync_n = bit(rng) != 0;
      if (change(rng)) s.vsync_n = bit(rng) != 0;
      if (change(rng)) s.colour = core::Rgb444(static_cast<std::uint16_t>(colour(rng)));
      samples.push_back(s);
    }
    check_round_trip(samples, period);
  }
}

}  // namespace
}  // namespace tripsitter::display
