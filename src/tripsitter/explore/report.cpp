#include <tripsitter/explore/report.h>

#include <cctype>
#include <map>
#include <system_error>

#include <tripsitter/device/resources.h>

namespace tripsitter::explore {

// The page's template and Chart.js, compiled in by cmake/embed_text.cmake (report_page_text.cpp in the build
// tree): report_page.html, .css and .js beside this file, and Debian's chart.min.js.
namespace embedded {
std::string chart_js();
std::string page_html();
std::string page_css();
std::string page_js();
}  // namespace embedded

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// JSON text that can sit inside a <script> element: '<', '>' and '&' (which occur only inside strings) become
// \u escapes, so no scene name or caption can close the element ("</script>") or open an HTML comment in it.
// Invalid UTF-8 (a scene file's name) is replaced rather than thrown on.
std::string script_json(const Json& value) {
  const std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '<') {
      out += "\\u003c";
    } else if (c == '>') {
      out += "\\u003e";
    } else if (c == '&') {
      out += "\\u0026";
    } else {
      out += c;
    }
  }
  return out;
}

bool starts_with_nocase(const std::string& text, std::size_t at, const std::string& prefix) {
  if (text.size() - at < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(text[at + i])) != prefix[i]) return false;
  }
  return true;
}

// A script's text made safe inside <script>...</script>: "</script" becomes "<\/script" and "<!--" "<\!--" (the
// same string or regular expression to JavaScript, where alone they can occur). Chart.js 3.9.1 has neither, so it
// goes in verbatim, license comment and all.
std::string script_text(const std::string& js) {
  std::string out;
  out.reserve(js.size());
  for (std::size_t i = 0; i < js.size(); ++i) {
    if (js[i] == '<' && (starts_with_nocase(js, i, "</script") || starts_with_nocase(js, i, "<!--"))) {
      out += "<\\";  // then the '/' or '!' as they were
      continue;
    }
    out += js[i];
  }
  return out;
}

std::string html_text(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// What the page's script draws from: the sweep and summary as given, the board's limits, the columns, the points
// as rows of values in the columns' order (a third of the size of objects), and the thumbnails as data: URLs.
Json page_data(const Report& report) {
  Json data = Json::object();
  data["sweep"] = report.sweep.is_null() ? Json::object() : report.sweep;
  data["summary"] = report.summary.is_null() ? Json::object() : report.summary;
  data["board"] = {{"name", "XC7A100T"},
                   {"dsp", device::kBoardDsp},
                   {"bram_kbit", static_cast<double>(device::kBoardBramBits) / 1024.0}};
  data["columns"] = columns_json();
  Json rows = Json::array();
  std::map<int, const Point*> by_index;
  for (const Point& p : report.points) {
    const Json object = to_json(p);
    Json row = Json::array();
    for (const auto& [key, value] : object.items()) row.push_back(value);
    rows.push_back(std::move(row));
    by_index[p.index] = &p;
  }
  data["rows"] = std::move(rows);

  Json thumbnails = Json::array();
  const auto it = report.summary.find("thumbnails");
  if (report.summary.is_object() && it != report.summary.end() && it->is_array()) {
    for (const Json& entry : *it) {
      if (!entry.is_object() || !entry.contains("point") || !entry["point"].is_number_integer()) continue;
      const auto found = by_index.find(entry["point"].get<int>());
      if (found == by_index.end() || found->second->thumbnail_png.empty()) continue;
      Json t = Json::object();
      t["point"] = found->first;
      t["caption"] = entry.contains("caption") && entry["caption"].is_string() ? entry["caption"] : Json("");
      t["src"] = "data:image/png;base64," + base64(found->second->thumbnail_png);
      thumbnails.push_back(std::move(t));
    }
  }
  data["thumbnails"] = std::move(thumbnails);
  return data;
}

std::string page_title(const Report& report) {
  std::string title = "TripSitter explore";
  const auto it = report.sweep.is_object() ? report.sweep.find("scenes") : report.sweep.end();
  if (report.sweep.is_object() && it != report.sweep.end() && it->is_array() && !it->empty()) {
    std::string scenes;
    for (const Json& s : *it) {
      if (s.is_string()) scenes += (scenes.empty() ? "" : ", ") + s.get<std::string>();
    }
    if (!scenes.empty()) title += ": " + scenes;
  }
  return title;
}

}  // namespace

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (const int shift : {18, 12, 6, 0}) out += kAlphabet[(v >> shift) & 63];
  }
  if (const std::size_t rest = bytes.size() - i; rest > 0) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (rest == 2 ? std::uint32_t{bytes[i + 1]} << 8 : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string report_page(const Report& report) {
  // The template's @@NAME@@ markers, every one replaced; the inserted texts are not searched for markers.
  const std::map<std::string, std::string> values = {
      {"TITLE", html_text(page_title(report))},
      {"CSS", embedded::page_css()},
      {"CHART_JS", script_text(embedded::chart_js())},
      {"DATA", script_json(page_data(report))},
      {"PAGE_JS", script_text(embedded::page_js())},
  };
  const std::string html = embedded::page_html();
  std::string page;
  page.reserve(html.size() + 400'000);
  std::size_t at = 0;
  while (at < html.size()) {
    const std::size_t open = html.find("@@", at);
    const std::size_t close = open == std::string::npos ? std::string::npos : html.find("@@", open + 2);
    if (close == std::string::npos) {
      page.append(html, at, std::string::npos);
      break;
    }
    const auto value = values.find(html.substr(open + 2, close - open - 2));
    if (value == values.end()) {  // not a marker: keep the first "@@" and look again after it
      page.append(html, at, open + 2 - at);
      at = open + 2;
      continue;
    }
    page.append(html, at, open - at);
    page += value->second;
    at = close + 2;
  }
  return page;
}

core::Result<bool, display::IoError> write_report(const fs::path& dir, const Report& report) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) {
      const std::string reason = ec ? ec.message() : "a file of that name is not a directory";
      return display::IoError{"cannot create report directory '" + dir.string() + "': " + reason};
    }
  }

  std::string csv = csv_header() + "\n";
  for (const Point& p : report.points) csv += csv_row(p) + "\n";

  Json doc = Json::object();
  doc["sweep"] = report.sweep;
  doc["summary"] = report.summary;
  doc["columns"] = columns_json();
  Json points = Json::array();
  for (const Point& p : report.points) points.push_back(to_json(p));
  doc["points"] = std::move(points);
  const std::string json = doc.dump(1, ' ', false, Json::error_handler_t::replace) + "\n";

  // Each file beside its name, then renamed: each is its old self or the whole new text.
  const std::string page = report_page(report);
  for (const auto& [name, text] : {std::pair<const char*, const std::string&>{"points.csv", csv},
                                   std::pair<const char*, const std::string&>{"points.json", json},
                                   std::pair<const char*, const std::string&>{"index.html", page}}) {
    auto written = display::write_file_beside_and_rename((dir / name).string(), text, "cannot write report file");
    if (!written.ok()) return written.error();
  }
  return true;
}

}  // namespace tripsitter::explore
