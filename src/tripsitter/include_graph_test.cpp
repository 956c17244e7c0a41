// The blocks' include graph, checked over the source tree: every `#include <tripsitter/BLOCK/...>` of every file
// under src/tripsitter/ must name the file's own block or one its block may include. CMake links each library
// with its dependencies only, but every target sees the whole of src/, so a header-only include across the
// graph (a device file including a renderer header) would otherwise build.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

namespace {

// A source file: its path under src/tripsitter/ ("device/device.h") and its text.
struct SourceFile {
  std::string path;
  std::string text;
};

// Block -> what its files may include besides their own block: a block ("core"), or one header of a block
// ("device/vga_signal.h").
using IncludeGraph = std::map<std::string, std::set<std::string>>;

struct IncludeRules {
  IncludeGraph code;   // every file of a block
  IncludeGraph tests;  // what a block's tests (*_test.cpp, *test_util.h) may include besides
};

IncludeRules include_rules() {
  IncludeGraph code = {
      {"core", {}},
      {"scene", {"core"}},
      {"link", {"core"}},
      {"transport", {"link", "core"}},
      {"host", {"core", "scene", "link"}},
      {"device", {"core", "link"}},
      {"display", {"core", "device/vga_signal.h"}},  // of the device, only the VGA signal's types
      {"render", {"core", "scene"}},
      {"cluster", {"render", "scene", "core"}},
      {"board", {"host", "link", "device", "display", "scene", "core"}},
      {"modes", {"board", "render", "host", "device", "display", "link", "scene", "core", "cluster"}},
      {"approx", {"device", "core"}},  // the approximations' benchmark: the device's code and its rivals
  };
  code["frontend"] = code["modes"];
  code["frontend"].insert("modes");
  code["explore"] = code["frontend"];
  std::set<std::string> every_block;
  for (const auto& [block, _] : code) every_block.insert(block);
  code["cmd"] = every_block;

  // Every block's tests may include the float renderer, the reference a frame is compared with, and the scenes
  // it renders (board/board_test.cpp: render/normal.h). Two exceptions besides: display's tests drive the
  // monitor and the VCD writer with the device's own VGA timing generator (monitor_test.cpp, vcd_test.cpp), and
  // the device's tests walk worlds with the hierarchy the host builds for them (device/test_util.h).
  IncludeGraph tests;
  for (const auto& [block, _] : code) tests[block] = {"render", "scene"};
  tests["display"].insert("device/vga.h");
  tests["device"].insert("host/hierarchy.h");
  return {code, tests};
}

bool is_test_file(const std::string& path) {
  return path.ends_with("_test.cpp") || path.ends_with("test_util.h");
}

// The block and header of a line `#include <tripsitter/BLOCK/HEADER>` (spaces allowed around '#' and before
// '<'); nothing for any other line. (Plain string parsing: GCC 12 warns inside <regex> under the sanitizers.)
std::optional<std::pair<std::string, std::string>> tripsitter_include(const std::string& line) {
  std::size_t at = line.find_first_not_of(" \t");
  if (at == std::string::npos || line[at] != '#') return std::nullopt;
  at = line.find_first_not_of(" \t", at + 1);
  constexpr std::string_view kInclude = "include";
  if (at == std::string::npos || line.compare(at, kInclude.size(), kInclude) != 0) return std::nullopt;
  at = line.find_first_not_of(" \t", at + kInclude.size());
  constexpr std::string_view kRoot = "<tripsitter/";
  if (at == std::string::npos || line.compare(at, kRoot.size(), kRoot) != 0) return std::nullopt;
  at += kRoot.size();
  const std::size_t slash = line.find('/', at), close = line.find('>', at);
  if (slash == std::string::npos || close == std::string::npos || slash >= close || slash == at) return std::nullopt;
  return std::pair{line.substr(at, slash - at), line.substr(slash + 1, close - slash - 1)};
}

// "file:line: block X includes block Y" for every include of the files that the graph does not allow; also
// library code including a test helper, which is not installed, and files of a block the graph does not know.
std::vector<std::string> include_violations(const std::vector<SourceFile>& files, const IncludeRules& rules) {
  std::vector<std::string> violations;
  for (const SourceFile& file : files) {
    const std::size_t slash = file.path.find('/');
    if (slash == std::string::npos) continue;  // directly in src/tripsitter/ (this test): in no block
    const std::string block = file.path.substr(0, slash);
    const auto allowed = rules.code.find(block);
    if (allowed == rules.code.end()) {
      violations.push_back(file.path + ": block " + block + " is not in the include graph");
      continue;
    }
    const std::set<std::string> none;
    const auto test_extras = rules.tests.find(block);
    const std::set<std::string>& extras =
        is_test_file(file.path) && test_extras != rules.tests.end() ? test_extras->second : none;
    std::istringstream lines(file.text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
      const auto include = tripsitter_include(line);
      if (!include) continue;
      const auto& [target, header] = *include;
      const std::string where = file.path + ":" + std::to_string(number) + ": block " + block + " includes ";
      if (!is_test_file(file.path) && is_test_file(header))
        violations.push_back(where + "test helper " + target + "/" + header);
      const auto allows = [&](const std::set<std::string>& set) {
        return set.contains(target) || set.contains(target + "/" + header);
      };
      if (target != block && !allows(allowed->second) && !allows(extras)) violations.push_back(where + "block " + target);
    }
  }
  return violations;
}

std::vector<SourceFile> read_tree(const std::filesystem::path& root) {
  std::vector<SourceFile> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp")) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    files.push_back({entry.path().lexically_relative(root).generic_string(), text.str()});
  }
  std::sort(files.begin(), files.end(), [](const SourceFile& a, const SourceFile& b) { return a.path < b.path; });
  return files;
}

using Violations = std::vector<std::string>;

TEST(IncludeGraph, SourceTreeFollowsTheGraph) {
  const std::vector<SourceFile> files = read_tree(std::filesystem::path(TRIPSITTER_SOURCE_DIR) / "src" / "tripsitter");
  ASSERT_GT(files.size(), 100u) << "the source tree was not found under " << TRIPSITTER_SOURCE_DIR;
  std::ostringstream report;
  for (const std::string& v : include_violations(files, include_rules())) report << v << "\n";
  EXPECT_EQ(report.str(), "") << "includes across the graph of the blocks (include_graph_test.cpp, include_rules)";
}

TEST(IncludeGraph, PlantedViolationIsReported) {
  const std::vector<SourceFile> files = {
      {"device/worker.h", "#pragma once\n\n#include <tripsitter/core/fixed.h>\n#include <tripsitter/render/normal.h>\n"}};
  EXPECT_EQ(include_violations(files, include_rules()), Violations{"device/worker.h:4: block device includes block render"});
}

TEST(IncludeGraph, AllowedIncludesPass) {
  const std::vector<SourceFile> files = {
      {"device/device.h", "#include <tripsitter/device/vga.h>\n#include <tripsitter/link/spi.h>\n"},
      {"board/board.h", "#include <tripsitter/display/monitor.h>\n#include <tripsitter/host/host.h>\n"},
      {"cmd/main.cpp", "#include <tripsitter/frontend/run.h>\n#include <tripsitter/transport/stream.h>\n"},
      {"include_graph_test.cpp", "#include <tripsitter/render/normal.h>\n"},  // in no block
  };
  EXPECT_EQ(include_violations(files, include_rules()), Violations{});
}

TEST(IncludeGraph, DisplaySeesOnlyTheVgaSignalOfTheDevice) {
  const std::vector<SourceFile> files = {
      {"display/monitor.h", "#include <tripsitter/device/vga_signal.h>\n#include <tripsitter/device/vga.h>\n"}};
  EXPECT_EQ(include_violations(files, include_rules()),
            Violations{"display/monitor.h:2: block display includes block device"});
}

TEST(IncludeGraph, TestsMayAlsoIncludeTheReferences) {
  const std::vector<SourceFile> files = {
      {"device/device_test.cpp", "#include <tripsitter/render/normal.h>\n#include <tripsitter/scene/builtin.h>\n"},
      {"device/worker_test.cpp", "#include <tripsitter/host/host.h>\n"},
      {"device/device.cpp", "#include <tripsitter/scene/scene.h>\n"},
      {"display/monitor_test.cpp", "#include <tripsitter/device/vga.h>\n#include <tripsitter/device/device.h>\n"},
  };
  EXPECT_EQ(include_violations(files, include_rules()),
            (Violations{"device/worker_test.cpp:1: block device includes block host",
                        "device/device.cpp:1: block device includes block scene",
                        "display/monitor_test.cpp:2: block display includes block device"}));
}

TEST(IncludeGraph, LibraryCodeMayNotIncludeTestHelpers) {
  const std::vector<SourceFile> files = {{"board/board.cpp", "#include <tripsitter/device/test_util.h>\n"},
                                         {"board/soak_test.cpp", "#include <tripsitter/device/test_util.h>\n"}};
  EXPECT_EQ(include_violations(files, include_rules()),
            Violations{"board/board.cpp:1: block board includes test helper device/test_util.h"});
}

TEST(IncludeGraph, UnknownBlocksAreReported) {
  const std::vector<SourceFile> files = {{"gpu/kernel.h", "#include <tripsitter/core/vec.h>\n"},
                                         {"core/vec.h", "#include <tripsitter/gpu/kernel.h>\n"}};
  EXPECT_EQ(include_violations(files, include_rules()),
            (Violations{"gpu/kernel.h: block gpu is not in the include graph", "core/vec.h:1: block core includes block gpu"}));
}

}  // namespace
