// The RTL's promises, kept by the test suite (docs/rtl.md, "Proofs" and "Lint"): every proof of rtl/*/proofs.tsv
// closes as its row says (scripts/prove.sh), every planted violation is caught by the property named beside it, and
// every module is lint-clean (scripts/lint_rtl.sh). One test a proof, so a failure names the block.
#include <array>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>

namespace {

struct Proof {
  std::string name;
  std::string mode;  // induction or bmc
  int plants = 0;
};

// GoogleTest names a parameter by its proof.
void PrintTo(const Proof& proof, std::ostream* os) { *os << proof.name; }

struct ScriptRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs a script of the repository, from its root, with its work in this test's own folder.
ScriptRun run(const std::string& arguments, const std::string& work) {
  const std::string command = "cd '" + std::string(TRIPSITTER_SOURCE_DIR) + "' && FORMAL_BUILD_DIR='" +
                              std::string(TRIPSITTER_FORMAL_DIR) + "/" + work + "' " + arguments + " 2>&1";
  ScriptRun result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, '\t');) fields.push_back(field);
  return fields;
}

// The proofs of rtl/*/proofs.tsv, with how many planted violations each has, as scripts/prove.sh --list gives them
// (the script is the one reader of the manifests' format); none when it fails (RtlProofs.TheManifestsRead).
std::vector<Proof> manifest() {
  std::vector<Proof> proofs;
  const ScriptRun list = run("scripts/prove.sh --list", "list");
  if (list.exit_code != 0) return proofs;
  std::istringstream in(list.output);
  for (std::string line; std::getline(in, line);) {
    const auto fields = split_tabs(line);
    if (fields.size() == 6 && fields[0] == "proof") proofs.push_back({fields[1], fields[4], 0});
    if (fields.size() == 4 && fields[0] == "plant") {
      for (auto& p : proofs) p.plants += p.name == fields[1];
    }
  }
  return proofs;
}

// The lines of scripts/prove.sh's output that report on a property of `proof` (its name is the first column).
std::vector<std::string> property_lines(const std::string& output, const std::string& proof) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(proof + " ", 0) == 0) lines.push_back(line);
  }
  return lines;
}

class Proofs : public testing::TestWithParam<Proof> {};

TEST_P(Proofs, EveryPropertyHoldsAsTheRowSays) {
  const Proof& proof = GetParam();
  const ScriptRun r = run("scripts/prove.sh " + proof.name, proof.name);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto lines = property_lines(r.output, proof.name);
  ASSERT_FALSE(lines.empty()) << r.output;
  const std::string expected = proof.mode == "induction" ? "proven (k-induction" : "bounded to depth";
  for (const auto& line : lines) EXPECT_NE(line.find(expected), std::string::npos) << line;
}

TEST_P(Proofs, EveryPlantedViolationIsCaught) {
  const Proof& proof = GetParam();
  ASSERT_GT(proof.plants, 0) << "every proof has a planted violation that makes it fail";
  const ScriptRun r = run("scripts/prove.sh --planted " + proof.name, proof.name + "-planted");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto lines = property_lines(r.output, proof.name);
  EXPECT_EQ(lines.size(), static_cast<std::size_t>(proof.plants)) << r.output;
  for (const auto& line : lines) EXPECT_NE(line.find(" caught: "), std::string::npos) << line;
}

TEST(RtlProofs, TheManifestsRead) {
  const ScriptRun list = run("scripts/prove.sh --list", "list");
  EXPECT_EQ(list.exit_code, 0) << list.output;
  EXPECT_FALSE(manifest().empty()) << list.output;
}

INSTANTIATE_TEST_SUITE_P(Rtl, Proofs, testing::ValuesIn(manifest()),
                         [](const testing::TestParamInfo<Proof>& info) { return info.param.name; });

TEST(RtlLint, EveryModuleIsCleanUnderVerilatorAndYosys) {
  const ScriptRun r = run("scripts/lint_rtl.sh", "lint");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(": clean"), std::string::npos) << r.output;
}

}  // namespace
