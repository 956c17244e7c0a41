// What the report's tests share (report_test.cpp, browser_test.cpp): a fresh directory per test, reading a file
// whole, and what they read out of HTML: the src and href attributes of markup, a number-valued attribute of a tag,
// and CSS url(...). Plain string scanning: std::regex trips GCC 12's -Wmaybe-uninitialized under the sanitizer
// presets.
#pragma once

#include <cctype>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::explore::test {

// Each test gets a fresh, empty directory, dir_, removed afterwards.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = std::filesystem::temp_directory_path() /
           ("tripsitter_explore_test_" + std::to_string(rd()) + std::to_string(rd()));
    ASSERT_TRUE(std::filesystem::create_directory(dir_)) << dir_;
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  std::filesystem::path dir_;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Attribute {
  std::string name;   // "src" or "href", in lower case
  std::string value;  // without its quotes
  std::string text;   // as written, for messages
};

inline bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

inline std::string lowered(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Every src= and href= of `markup` (an attribute name after white space), with a double-quoted, single-quoted or
// bare value, in any case.
inline std::vector<Attribute> link_attributes(const std::string& markup) {
  const std::string low = lowered(markup);
  std::vector<Attribute> out;
  for (const std::string name : {"src", "href"}) {
    for (std::size_t at = low.find(name); at != std::string::npos; at = low.find(name, at + 1)) {
      if (at == 0 || !is_space(low[at - 1])) continue;
      std::size_t i = at + name.size();
      while (i < low.size() && is_space(low[i])) ++i;
      if (i >= low.size() || low[i] != '=') continue;
      ++i;
      while (i < low.size() && is_space(low[i])) ++i;
      if (i >= low.size()) continue;
      std::size_t begin = i, end = 0;
      if (low[i] == '"' || low[i] == '\'') {
        begin = i + 1;
        end = low.find(low[i], begin);
        if (end == std::string::npos) end = low.size();
      } else {
        end = begin;
        while (end < low.size() && !is_space(low[end]) && low[end] != '>') ++end;
      }
      out.push_back({name, markup.substr(begin, end - begin), markup.substr(at, std::min(end + 1, markup.size()) - at)});
    }
  }
  return out;
}

// The whole of the first tag of `html` that starts with `open` ("<body"), or empty.
inline std::string first_tag(const std::string& html, const std::string& open) {
  const std::size_t at = html.find(open);
  if (at == std::string::npos) return {};
  const std::size_t end = html.find('>', at);
  return end == std::string::npos ? std::string() : html.substr(at, end + 1 - at);
}

// The value of `name="N"` in `tag`, when it is a whole non-negative number.
inline std::optional<int> number_attribute(const std::string& tag, const std::string& name) {
  const std::string key = name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return std::nullopt;
  std::size_t i = at + key.size();
  const std::size_t first = i;
  int value = 0;
  while (i < tag.size() && std::isdigit(static_cast<unsigned char>(tag[i])) != 0) value = value * 10 + (tag[i++] - '0');
  if (i == first || i >= tag.size() || tag[i] != '"') return std::nullopt;
  return value;
}

// Whether `text` (lower case) has a CSS url( : the word url, then optional white space and a parenthesis.
inline bool has_css_url(const std::string& text) {
  for (std::size_t at = text.find("url"); at != std::string::npos; at = text.find("url", at + 1)) {
    if (at > 0 && (std::isalnum(static_cast<unsigned char>(text[at - 1])) != 0 || text[at - 1] == '_')) continue;
    std::size_t i = at + 3;
    while (i < text.size() && is_space(text[i])) ++i;
    if (i < text.size() && text[i] == '(') return true;
  }
  return false;
}

}  // namespace tripsitter::explore::test
