// Documents that stay true: every repository path README.md and docs/ name exists, every public header is on
// README's architecture map, and every file a source comment names exists. A file moved or renamed without its
// documents fails here, not in a newcomer's hands.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = TRIPSITTER_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// README.md and every page of docs/.
std::vector<fs::path> documents() {
  std::vector<fs::path> out{kRoot / "README.md"};
  for (const auto& e : fs::directory_iterator(kRoot / "docs"))
    if (e.path().extension() == ".md") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The blocks of src/tripsitter/ (its folders).
std::vector<std::string> blocks() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(kRoot / "src" / "tripsitter"))
    if (e.is_directory()) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// The text between each pair of backticks of a line.
std::vector<std::string> backticked(std::string_view line) {
  std::vector<std::string> out;
  for (std::size_t open = line.find('`'); open != std::string_view::npos;) {
    const std::size_t close = line.find('`', open + 1);
    if (close == std::string_view::npos) break;
    out.emplace_back(line.substr(open + 1, close - open - 1));
    open = line.find('`', close + 1);
  }
  return out;
}

// A quoted text that names a file or folder of the repository: a plain path (no spaces, wildcards or
// placeholders) under one of the repository's folders or one of src/tripsitter/'s blocks; the part before a
// ':' (a line number, a test name) is the path.
std::string repository_path(std::string text, const std::vector<std::string>& block_names) {
  text = text.substr(0, text.find(':'));
  while (!text.empty() && (text.back() == '.' || text.back() == ',' || text.back() == ';')) text.pop_back();
  if (text.empty() || text.find_first_of(" *<>{}$[]|") != std::string::npos || text.find("...") != std::string::npos ||
      text.find("NAME") != std::string::npos || text.find('/') == std::string::npos)
    return "";
  static const std::vector<std::string> kFolders{"src/", "rtl/", "scripts/", "docs/", "scenes/", "fuzz/",
                                                 "bench/", "examples/", "cmake/", ".ci/"};
  for (const std::string& f : kFolders)
    if (text.starts_with(f)) return text;
  for (const std::string& b : block_names)
    if (text.starts_with(b + "/")) return text;
  return "";
}

TEST(Documents, EveryRepositoryPathTheyNameExists) {
  const std::vector<std::string> block_names = blocks();
  for (const fs::path& doc : documents()) {
    const std::vector<std::string> lines = lines_of(read(doc));
    for (std::size_t n = 0; n < lines.size(); ++n)
      for (const std::string& q : backticked(lines[n])) {
        const std::string path = repository_path(q, block_names);
        if (path.empty()) continue;
        EXPECT_TRUE(fs::exists(kRoot / path) || fs::exists(kRoot / "src" / "tripsitter" / path))
            << doc.filename().string() << ":" << n + 1 << " names " << path << ", which does not exist";
      }
  }
}

// README's architecture map has a row per block, "| `block/` | ... |", naming its headers. The public headers are
// every library's (the blocks but cmd, the command line's own); tests' helpers (*test_util.h) are not public.
TEST(Documents, EveryPublicHeaderIsOnTheArchitectureMap) {
  const std::vector<std::string> readme = lines_of(read(kRoot / "README.md"));
  for (const std::string& block : blocks()) {
    if (block == "cmd") continue;
    const std::string head = "| `" + block + "/` |";
    const auto row = std::find_if(readme.begin(), readme.end(), [&](const std::string& l) { return l.starts_with(head); });
    ASSERT_NE(row, readme.end()) << "README.md's architecture map has no row for src/tripsitter/" << block << "/";
    for (const auto& e : fs::directory_iterator(kRoot / "src" / "tripsitter" / block)) {
      const std::string name = e.path().filename().string();
      if (e.path().extension() != ".h" || name.ends_with("test_util.h")) continue;
      EXPECT_NE(row->find("`" + name + "`"), std::string::npos)
          << "src/tripsitter/" << block << "/" << name << " is not on README.md's architecture map (row " << block << "/)";
    }
  }
}

// The file names in a comment: words ending in a source or document extension.
std::vector<std::string> named_files(std::string_view comment) {
  static const std::vector<std::string_view> kExtensions{".h", ".cpp", ".sv", ".md", ".sh", ".tsv"};
  std::vector<std::string> out;
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < comment.size(); ++i) {
    // A word's start; not after '.' (a path's extension) nor '*' (a pattern, *_test.cpp).
    if (!word_char(comment[i]) || (i > 0 && (word_char(comment[i - 1]) || comment[i - 1] == '.' || comment[i - 1] == '*')))
      continue;
    std::size_t end = i;
    while (end < comment.size() && word_char(comment[end])) ++end;
    for (std::string_view ext : kExtensions) {
      const std::size_t after = end + ext.size();
      if (comment.substr(end, ext.size()) == ext && (after == comment.size() || !word_char(comment[after])))
        out.emplace_back(comment.substr(i, after - i));
    }
    i = end;
  }
  return out;
}

// Every file name a comment of the sources cites (frame.h, ts_receiver.sv, docs' pages) is a file of the
// repository, but for the few that live elsewhere.
TEST(Documents, EveryFileACommentNamesExists) {
  static const std::set<std::string> kElsewhere{
      "SPEC.md", "STYLE.md",    // ../shared, beside the repository
      "verilated.h",            // Verilator's
      "report_page_text.cpp",   // generated in the build tree (src/tripsitter/explore/CMakeLists.txt)
  };
  std::set<std::string> files;
  std::vector<fs::path> sources;
  for (auto it = fs::recursive_directory_iterator(kRoot); it != fs::recursive_directory_iterator(); ++it) {
    const fs::directory_entry& e = *it;
    const std::string rel = fs::relative(e.path(), kRoot).string();
    if (e.is_directory() && (rel.starts_with("build") || rel.starts_with("."))) {
      it.disable_recursion_pending();  // build trees and .git
      continue;
    }
    if (!e.is_regular_file()) continue;
    files.insert(e.path().filename().string());
    const std::string ext = e.path().extension().string();
    if ((rel.starts_with("src/") || rel.starts_with("rtl/")) && (ext == ".h" || ext == ".cpp" || ext == ".sv"))
      sources.push_back(e.path());
  }
  std::sort(sources.begin(), sources.end());
  for (const fs::path& source : sources) {
    const std::vector<std::string> lines = lines_of(read(source));
    for (std::size_t n = 0; n < lines.size(); ++n) {
      const std::size_t comment = lines[n].find("//");
      if (comment == std::string::npos) continue;
      for (const std::string& name : named_files(std::string_view(lines[n]).substr(comment)))
        EXPECT_TRUE(files.contains(name) || kElsewhere.contains(name))
            << fs::relative(source, kRoot).string() << ":" << n + 1 << " names " << name << ", which is no file here";
    }
  }
}

}  // namespace
