// Scene files. The text is parsed by nlohmann's SAX parser straight into a Scene: the handler below knows
// the format (docs/scene_format.md), so every key, type and range is checked the moment it is read, no JSON
// tree is ever built, and no error can hide behind a value of unexpected size or depth.
//
// Positions. nlohmann reports no positions to a SAX handler, so the text is handed to the parser through
// TrackingIterator, which publishes how many bytes the lexer has consumed. When a callback arrives, the
// token it is about has just been read; scanning back over that token's text from the consumed count
// gives its first byte, which is what errors point at (converted to line:column only when one occurs).
//
// Depth. The format nests four levels at most (root / spheres / sphere / material or vector). Every
// container is checked against the format as it opens, so any deeper one is rejected the moment it opens:
// "[[[[..." a hundred thousand levels deep fails at its first byte, and nothing recurses (the parser
// itself keeps its nesting on a heap vector).
#include <tripsitter/scene/scene_json.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::scene {
namespace {

using Json = nlohmann::json;

constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{256} << 20;

// ------------------------------------------------------------------------------------------------
// Positions in the text

// An input iterator over the text that stores, in a cursor shared with the handler, how far the parser has
// read. nlohmann's lexer reads each byte exactly once through it (a byte it "ungets" is not read again).
class TrackingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackingIterator(const char* p, const char** cursor) : p_(p), cursor_(cursor) {}

  reference operator*() const { return *p_; }
  TrackingIterator& operator++() {
    *cursor_ = ++p_;
    return *this;
  }
  TrackingIterator operator++(int) {
    TrackingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const TrackingIterator& o) const { return p_ == o.p_; }

 private:
  const char* p_;
  const char** cursor_;
};

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_number_char(char c) { return is_digit(c) || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E'; }

// First byte of the number token that ends at text[end - 1] or, when the lexer has also read the byte after
// the number to see that it ended, at text[end - 2].
std::size_t number_start(std::string_view text, std::size_t end) {
  if (end > 0 && !is_number_char(text[end - 1])) --end;
  std::size_t start = end;
  while (start > 0 && is_number_char(text[start - 1])) --start;
  // Only malformed text puts a number straight after a literal ("true1"): skip the literal's 'e'.
  while (start < end && text[start] != '-' && !is_digit(text[start])) ++start;
  return start;
}

// Opening quote of the string token whose closing quote is text[end - 1]: the nearest quote before it that is
// not escaped, i.e. not preceded by an odd number of backslashes.
std::size_t string_start(std::string_view text, std::size_t end) {
  for (std::size_t i = end - 1; i-- > 0;) {
    if (text[i] != '"') continue;
    std::size_t backslashes = 0;
    while (backslashes < i && text[i - 1 - backslashes] == '\\') ++backslashes;
    if (backslashes % 2 == 0) return i;
  }
  return 0;
}

// First byte of the complete token (string, number, literal or structural character) ending at text[end - 1].
std::size_t token_start(std::string_view text, std::size_t end) {
  const char last = text[end - 1];
  if (last == '"') return string_start(text, end);
  if (is_digit(last)) return number_start(text, end);
  if (last >= 'a' && last <= 'z') {  // true, false, null
    std::size_t start = end - 1;
    while (start > 0 && text[start - 1] >= 'a' && text[start - 1] <= 'z') --start;
    return start;
  }
  return end - 1;
}

// Start of the bad literal whose mismatching byte is text[at]: nlohmann's lexer reads a literal byte by byte
// until one differs from "true", "false" or "null", so the bytes before `at` are a proper prefix of one.
std::size_t literal_start(std::string_view text, std::size_t at) {
  for (const std::string_view word : {"true", "false", "null"}) {
    for (std::size_t k = word.size() - 1; k >= 1; --k) {
      if (at >= k && text.substr(at - k, k) == word.substr(0, k)) return at - k;
    }
  }
  return at;
}

// 1-based line and column of a byte offset. Columns count characters (UTF-8 code points, so any byte but a
// continuation byte 10xxxxxx), as editors do; a byte-order mark at the start is not counted.
void line_column(std::string_view text, std::size_t offset, int* line, int* column) {
  offset = std::min(offset, text.size());
  std::size_t lines = 0, line_start = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++lines;
      line_start = i + 1;
    }
  }
  std::size_t chars = 0;
  for (std::size_t i = line_start; i < offset; ++i) chars += (static_cast<unsigned char>(text[i]) & 0xC0) != 0x80;
  constexpr std::size_t kIntMax = std::numeric_limits<int>::max();
  *line = static_cast<int>(std::min(lines + 1, kIntMax));
  *column = static_cast<int>(std::min(chars + 1, kIntMax));
}

// ------------------------------------------------------------------------------------------------
// Text for messages

// Shortest text that reads back as v: plain decimals for ordinary magnitudes (100000, 0.25), else
// scientific (1e+20).
std::string format_number(double v) {
  char buf[400];  // a fixed-notation double can take 300+ characters; only ordinary ones are printed so
  const bool plain = std::abs(v) >= 1e-4 && std::abs(v) < 1e15;
  const auto r = plain ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed)
                       : std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// Text from the input made safe to print: control and non-ASCII bytes as \xNN, at most `max` bytes of it
// (the last ones when `keep_end`, else the first ones).
std::string printable(std::string_view s, std::size_t max = 40, bool keep_end = false) {
  std::string_view part = s;
  if (s.size() > max) part = keep_end ? s.substr(s.size() - max) : s.substr(0, max);
  std::string out = (s.size() > max && keep_end) ? "..." : "";
  for (const char c : part) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7F) {
      static constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    } else {
      out += c;
    }
  }
  if (s.size() > max && !keep_end) out += "...";
  return out;
}

// ------------------------------------------------------------------------------------------------
// The format

enum class Kind : std::uint8_t { kNull, kBoolean, kNumber, kString, kObject, kArray };

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::kNull: return "null";
    case Kind::kBoolean: return "a boolean";
    case Kind::kNumber: return "a number";
    case Kind::kString: return "a string";
    case Kind::kObject: return "an object";
    case Kind::kArray: return "an array";
  }
  return "?";
}

// What a slot of the format takes.
enum class Expect : std::uint8_t { kNumber, kInteger, kString, kObject, kVector, kArray };

const char* expect_name(Expect expect) {
  switch (expect) {
    case Expect::kNumber: return "a number";
    case Expect::kInteger: return "an integer";
    case Expect::kString: return "a string";
    case Expect::kObject: return "an object";
    case Expect::kVector: return "an array of 3 numbers";
    case Expect::kArray: return "an array";
  }
  return "?";
}

Kind kind_of(Expect expect) {
  switch (expect) {
    case Expect::kNumber:
    case Expect::kInteger: return Kind::kNumber;
    case Expect::kString: return Kind::kString;
    case Expect::kObject: return Kind::kObject;
    case Expect::kVector:
    case Expect::kArray: return Kind::kArray;
  }
  return Kind::kNull;
}

enum class Field : std::uint8_t {
  kName, kCamera, kRender, kUnitsPerWorld, kSpheres,                // top level
  kLookfrom, kLookat, kVup, kVfov, kDefocusAngle, kFocusDist,        // camera
  kWidth, kHeight, kSpp, kMaxDepth,                                  // render
  kCenter, kRadius, kMaterial,                                       // sphere
  kType, kAlbedo, kFuzz, kIor,                                       // material
  kCount
};

struct FieldSpec {
  std::string_view key;
  Field field;
  Expect expect;
  bool required = false;
};

constexpr FieldSpec kRootFields[] = {
    {"name", Field::kName, Expect::kString},
    {"camera", Field::kCamera, Expect::kObject},
    {"render", Field::kRender, Expect::kObject},
    {"units_per_world", Field::kUnitsPerWorld, Expect::kNumber},
    {"spheres", Field::kSpheres, Expect::kArray, true},
};
constexpr FieldSpec kCameraFields[] = {
    {"lookfrom", Field::kLookfrom, Expect::kVector},
    {"lookat", Field::kLookat, Expect::kVector},
    {"vup", Field::kVup, Expect::kVector},
    {"vfov", Field::kVfov, Expect::kNumber},
    {"defocus_angle", Field::kDefocusAngle, Expect::kNumber},
    {"focus_dist", Field::kFocusDist, Expect::kNumber},
};
constexpr FieldSpec kRenderFields[] = {
    {"width", Field::kWidth, Expect::kInteger},
    {"height", Field::kHeight, Expect::kInteger},
    {"spp", Field::kSpp, Expect::kInteger},
    {"max_depth", Field::kMaxDepth, Expect::kInteger},
};
constexpr FieldSpec kSphereFields[] = {
    {"center", Field::kCenter, Expect::kVector, true},
    {"radius", Field::kRadius, Expect::kNumber, true},
    {"material", Field::kMaterial, Expect::kObject},
};
constexpr FieldSpec kMaterialFields[] = {
    {"type", Field::kType, Expect::kString, true},
    {"albedo", Field::kAlbedo, Expect::kVector},
    {"fuzz", Field::kFuzz, Expect::kNumber},
    {"ior", Field::kIor, Expect::kNumber},
};

constexpr MaterialType kMaterialTypes[] = {MaterialType::kLambertian, MaterialType::kMetal,
                                           MaterialType::kDielectric};

// ------------------------------------------------------------------------------------------------
// The SAX handler

class SceneBuilder {
 public:
  SceneBuilder(std::string_view text, const char* const* cursor) : text_(text), cursor_(cursor) {
    stack_.reserve(8);  // the format nests 4 deep; references into the stack stay valid
    field_offset_.fill(kNone);
  }

  // SAX interface (nlohmann::json_sax). Returning false stops the parser; error_message() says why.
  bool null() { return scalar(Kind::kNull, consumed() - 4); }
  bool boolean(bool b) { return scalar(Kind::kBoolean, consumed() - (b ? 4 : 5)); }
  bool number_integer(Json::number_integer_t v) { return number(static_cast<double>(v)); }
  bool number_unsigned(Json::number_unsigned_t v) { return number(static_cast<double>(v)); }
  bool number_float(Json::number_float_t v, const Json::string_t&) { return number(v); }
  bool string(Json::string_t& s) { return scalar(Kind::kString, string_start(text_, consumed()), &s); }
  bool binary(Json::binary_t&) { return fail(consumed(), "unexpected binary value"); }  // binary formats only
  bool start_object(std::size_t) { return open(Kind::kObject, consumed() - 1); }
  bool start_array(std::size_t) { return open(Kind::kArray, consumed() - 1); }
  bool key(Json::string_t& k);
  bool end_object();
  bool end_array();
  bool parse_error(std::size_t position, const std::string& last_token, const Json::exception& ex);

  Scene& scene() { return scene_; }
  bool failed() const { return failed_; }
  std::size_t error_offset() const { return error_offset_; }
  const std::string& error_message() const { return error_message_; }

  // Records the first error; always false, for `return fail(...)` from the callbacks.
  bool fail(std::size_t offset, std::string message) {
    if (!failed_) {
      failed_ = true;
      error_offset_ = offset;
      error_message_ = std::move(message);
    }
    return false;
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  enum class Ctx : std::uint8_t { kRoot, kCamera, kRender, kSphere, kMaterial, kSpheres, kVector };

  // One open object or array.
  struct Frame {
    Ctx ctx;
    std::size_t offset;                   // of its '{' or '['
    std::span<const FieldSpec> fields{};  // objects: the keys it takes
    std::uint32_t seen = 0;               // objects: bit i set once fields[i] was given
    const FieldSpec* pending = nullptr;   // objects: the field of the last key, whose value comes next
    std::size_t count = 0;                // arrays: elements started so far
    Vec3d* vector = nullptr;              // kVector: where the numbers go
    bool unit_interval = false;           // kVector: each number in [0, 1] (colours)

    bool is_array() const { return ctx == Ctx::kSpheres || ctx == Ctx::kVector; }
  };

  std::size_t consumed() const { return static_cast<std::size_t>(*cursor_ - text_.data()); }

  // The path of the value inside the first `depth` open containers, e.g. "spheres[3].material.fuzz": each
  // object contributes the key being read, each array the index of the element being read.
  std::string path(std::size_t depth) const {
    std::string p;
    for (std::size_t i = 0; i < depth; ++i) {
      const Frame& f = stack_[i];
      if (f.is_array()) {
        p += '[' + std::to_string(f.count - 1) + ']';
      } else if (f.pending != nullptr) {
        if (!p.empty()) p += '.';
        p += f.pending->key;
      }
    }
    return p;
  }
  // "<path>: " for the value being read now, or for the innermost open container (empty at the top level).
  std::string value_prefix() const { return prefix(path(stack_.size())); }
  std::string container_prefix() const { return prefix(path(stack_.size() - 1)); }
  static std::string prefix(std::string p) { return p.empty() ? p : p + ": "; }

  bool number(double v);
  bool scalar(Kind kind, std::size_t offset, const std::string* text = nullptr);
  bool open(Kind kind, std::size_t offset);
  bool arrive(Kind kind, std::size_t offset, const FieldSpec** spec);
  bool assign(const FieldSpec& spec, std::size_t offset, double number, const std::string* text);
  bool require(bool ok, std::size_t offset, const char* range, double v) {
    return ok || fail(offset, value_prefix() + "must be " + range + ", found " + format_number(v));
  }
  bool integer(std::size_t offset, double v, int lo, int hi, int* out);
  bool check_camera(const Frame& camera);
  void push(Frame frame) { stack_.push_back(frame); }
  void push_vector(std::size_t offset, Vec3d* out, bool unit_interval = false) {
    push({.ctx = Ctx::kVector, .offset = offset, .vector = out, .unit_interval = unit_interval});
  }

  std::string_view text_;
  const char* const* cursor_;
  std::vector<Frame> stack_;
  Scene scene_;
  Sphere sphere_;              // the sphere being read
  bool albedo_given_ = false;  // of the material being read
  std::array<std::size_t, static_cast<std::size_t>(Field::kCount)> field_offset_{};  // where each was last given

  bool failed_ = false;
  std::size_t error_offset_ = 0;
  std::string error_message_;
};

bool SceneBuilder::number(double v) {
  const std::size_t offset = number_start(text_, consumed());
  const FieldSpec* spec = nullptr;
  if (!arrive(Kind::kNumber, offset, &spec)) return false;
  // nlohmann already turns an overflowing float into a parse error (see parse_error); be sure anyway.
  if (!std::isfinite(v)) return fail(offset, value_prefix() + "number out of range");
  Frame& top = stack_.back();
  if (top.ctx == Ctx::kVector) {
    if (top.unit_interval && !require(v >= 0 && v <= 1, offset, "in [0, 1]", v)) return false;
    (*top.vector)[static_cast<int>(top.count - 1)] = v;
    return true;
  }
  return assign(*spec, offset, v, nullptr);
}

// null, true, false or a string.
bool SceneBuilder::scalar(Kind kind, std::size_t offset, const std::string* text) {
  const FieldSpec* spec = nullptr;
  if (!arrive(kind, offset, &spec)) return false;
  return assign(*spec, offset, 0, text);  // arrive() lets through only string fields given a string
}

// Bookkeeping common to every value: counts array elements, checks that the value is of the kind its slot
// takes and remembers where it was given. `spec` becomes the field, or null for an array element.
bool SceneBuilder::arrive(Kind kind, std::size_t offset, const FieldSpec** spec) {
  *spec = nullptr;
  if (stack_.empty()) {
    if (kind == Kind::kObject) return true;
    return fail(offset, std::string("expected a JSON object at the top level, found ") + kind_name(kind));
  }
  Frame& top = stack_.back();
  Expect expect;
  if (top.ctx == Ctx::kSpheres) {
    if (top.count == kMaxSpheres) {
      return fail(offset, container_prefix() + "more than " + std::to_string(kMaxSpheres) + " spheres");
    }
    ++top.count;
    expect = Expect::kObject;
  } else if (top.ctx == Ctx::kVector) {
    if (top.count == 3) return fail(offset, container_prefix() + "expected an array of 3 numbers, found more");
    ++top.count;
    expect = Expect::kNumber;
  } else {
    *spec = top.pending;
    expect = top.pending->expect;
    field_offset_[static_cast<std::size_t>(top.pending->field)] = offset;
  }
  if (kind != kind_of(expect)) {
    return fail(offset, value_prefix() + "expected " + expect_name(expect) + ", found " + kind_name(kind));
  }
  return true;
}

bool SceneBuilder::open(Kind kind, std::size_t offset) {
  const FieldSpec* spec = nullptr;
  if (!arrive(kind, offset, &spec)) return false;
  if (stack_.empty()) {
    push({Ctx::kRoot, offset, kRootFields});
    return true;
  }
  if (stack_.back().ctx == Ctx::kSpheres) {
    sphere_ = Sphere{};
    push({Ctx::kSphere, offset, kSphereFields});
    return true;
  }
  switch (spec->field) {
    case Field::kCamera: push({Ctx::kCamera, offset, kCameraFields}); return true;
    case Field::kRender: push({Ctx::kRender, offset, kRenderFields}); return true;
    case Field::kSpheres: push({Ctx::kSpheres, offset}); return true;
    case Field::kMaterial:
      albedo_given_ = false;
      push({Ctx::kMaterial, offset, kMaterialFields});
      return true;
    case Field::kLookfrom: push_vector(offset, &scene_.camera.lookfrom); return true;
    case Field::kLookat: push_vector(offset, &scene_.camera.lookat); return true;
    case Field::kVup: push_vector(offset, &scene_.camera.vup); return true;
    case Field::kCenter: push_vector(offset, &sphere_.center); return true;
    case Field::kAlbedo:
      albedo_given_ = true;
      push_vector(offset, &sphere_.material.albedo, /*unit_interval=*/true);
      return true;
    default: return fail(offset, value_prefix() + "internal error: no container here");
  }
}

bool SceneBuilder::key(Json::string_t& k) {
  const std::size_t offset = string_start(text_, consumed());
  Frame& top = stack_.back();  // keys come only inside objects
  for (std::size_t i = 0; i < top.fields.size(); ++i) {
    if (top.fields[i].key != k) continue;
    if (top.seen & (1u << i)) return fail(offset, container_prefix() + "duplicate key \"" + printable(k) + "\"");
    top.seen |= 1u << i;
    top.pending = &top.fields[i];
    return true;
  }
  std::string keys;
  for (const FieldSpec& f : top.fields) keys += (keys.empty() ? "" : ", ") + std::string(f.key);
  return fail(offset, container_prefix() + "unknown key \"" + printable(k) + "\"; expected one of " + keys);
}

bool SceneBuilder::end_object() {
  const Frame& top = stack_.back();
  for (std::size_t i = 0; i < top.fields.size(); ++i) {
    if (top.fields[i].required && !(top.seen & (1u << i))) {
      return fail(top.offset,
                  container_prefix() + "missing required key \"" + std::string(top.fields[i].key) + "\"");
    }
  }
  switch (top.ctx) {
    case Ctx::kCamera:
      if (!check_camera(top)) return false;
      break;
    case Ctx::kSphere: scene_.spheres.push_back(sphere_); break;
    case Ctx::kMaterial:
      if (sphere_.material.type == MaterialType::kDielectric && !albedo_given_) sphere_.material.albedo = {1, 1, 1};
      break;
    default: break;
  }
  stack_.pop_back();
  return true;
}

bool SceneBuilder::end_array() {
  const Frame& top = stack_.back();
  if (top.ctx == Ctx::kVector && top.count < 3) {
    return fail(top.offset, container_prefix() + "expected an array of 3 numbers, found " + std::to_string(top.count));
  }
  stack_.pop_back();
  return true;
}

bool SceneBuilder::assign(const FieldSpec& spec, std::size_t offset, double v, const std::string* text) {
  RenderSettings& render = scene_.render;
  CameraSettings& camera = scene_.camera;
  // Stores v in `out` when `ok`, else reports that v must be in `range`.
  auto set = [&](bool ok, const char* range, double* out) {
    if (!require(ok, offset, range, v)) return false;
    *out = v;
    return true;
  };
  switch (spec.field) {
    case Field::kName: scene_.name = *text; return true;
    case Field::kUnitsPerWorld: return set(v > 0, "greater than 0", &scene_.units_per_world);
    case Field::kVfov: return set(v > 0 && v < 180, "in (0, 180) degrees", &camera.vfov);
    case Field::kDefocusAngle: return set(v >= 0 && v < 180, "in [0, 180) degrees", &camera.defocus_angle);
    case Field::kFocusDist: return set(v > 0, "greater than 0", &camera.focus_dist);
    case Field::kWidth: return integer(offset, v, 1, kMaxImageSide, &render.width);
    case Field::kHeight: return integer(offset, v, 1, kMaxImageSide, &render.height);
    case Field::kSpp: return integer(offset, v, 1, kMaxSpp, &render.spp);
    case Field::kMaxDepth: return integer(offset, v, 1, kMaxDepth, &render.max_depth);
    case Field::kRadius: return set(v > 0, "greater than 0", &sphere_.radius);
    case Field::kFuzz: return set(v >= 0 && v <= 1, "in [0, 1]", &sphere_.material.fuzz);
    case Field::kIor: return set(v > 0, "greater than 0", &sphere_.material.ior);
    case Field::kType: {
      std::string names;
      for (const MaterialType type : kMaterialTypes) {
        if (*text == material_name(type)) {
          sphere_.material.type = type;
          return true;
        }
        names += (names.empty() ? "" : ", ") + std::string(material_name(type));
      }
      return fail(offset,
                  value_prefix() + "unknown material type \"" + printable(*text) + "\"; expected one of " + names);
    }
    default: return fail(offset, value_prefix() + "internal error: no scalar here");
  }
}

bool SceneBuilder::integer(std::size_t offset, double v, int lo, int hi, int* out) {
  if (v != std::floor(v)) return fail(offset, value_prefix() + "expected an integer, found " + format_number(v));
  if (v < lo || v > hi) {
    return fail(offset, value_prefix() + "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", found " +
                            format_number(v));
  }
  *out = static_cast<int>(v);
  return true;
}

// Unit vector along v, scaled first so that no finite v overflows; false for the zero vector.
bool direction(const Vec3d& v, Vec3d* out) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0)) return false;
  *out = core::normalize(v / m);
  return true;
}

// The camera needs a view direction and an up vector that is not along it.
bool SceneBuilder::check_camera(const Frame& camera) {
  const CameraSettings& c = scene_.camera;
  auto where = [&](Field f, Field g) {
    const std::size_t a = field_offset_[static_cast<std::size_t>(f)], b = field_offset_[static_cast<std::size_t>(g)];
    return a != kNone ? a : (b != kNone ? b : camera.offset);
  };
  const std::string p = container_prefix();
  const Vec3d d = c.lookat - c.lookfrom;
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) {
    return fail(where(Field::kLookat, Field::kLookfrom), p + "lookfrom and lookat are too far apart");
  }
  Vec3d forward, up;
  if (!direction(d, &forward)) {
    return fail(where(Field::kLookat, Field::kLookfrom), p + "lookfrom and lookat are the same point");
  }
  if (!direction(c.vup, &up) || core::length(core::cross(forward, up)) < 1e-9) {
    return fail(where(Field::kVup, Field::kVup), p + "vup must not be zero or parallel to the view direction "
                                                     "lookat - lookfrom");
  }
  return true;
}

bool SceneBuilder::parse_error(std::size_t position, const std::string& last_token, const Json::exception& ex) {
  if (ex.id == 406) {  // a number too large for a double, e.g. 1e999 (nlohmann parses it to inf and stops)
    const std::size_t offset = number_start(text_, std::min(position, text_.size()));
    const FieldSpec* spec = nullptr;
    if (!arrive(Kind::kNumber, offset, &spec)) return false;  // a number where none belongs says so first
    return fail(offset, value_prefix() + "number " + printable(last_token) + " is out of range");
  }
  // nlohmann counts the bytes it has read; position - 1 is the byte it stopped at, position beyond the text
  // means it hit the end. Lexer errors ("invalid literal", "invalid string: ...") point at the byte that broke
  // the token; unexpected tokens point at the token's first byte.
  std::string what = ex.what();  // "[json.exception.parse_error.101] parse error at line 1, column 4: ..."
  const std::size_t column = what.find(", column ");
  if (column != std::string::npos && what.find(": ", column) != std::string::npos) {
    what.erase(0, what.find(": ", column) + 2);
  }
  std::size_t offset = position > text_.size() ? text_.size() : (position > 0 ? position - 1 : 0);
  const std::size_t last_read = what.find("; last read: '");
  if (last_read == std::string::npos) {
    if (offset < text_.size()) offset = token_start(text_, offset + 1);
  } else {
    // nlohmann's last_token is exact for strings and numbers, but after a structural character it also holds
    // stale bytes, so a bad literal is cut from the text instead (and pointed at from its start).
    std::string token = last_token;
    if (last_read >= 15 && what.compare(last_read - 15, 15, "invalid literal") == 0) {
      const std::size_t start = literal_start(text_, offset);
      token = text_.substr(start, offset - start + 1);
      offset = start;
    }
    // Keep the end of what was read, nearest to the error; a runaway string may be megabytes long.
    what = printable(what.substr(0, last_read), 200) + "; last read: '" + printable(token, 32, true) + "'";
  }
  if (offset < text_.size() && text_[offset] == '\0') what = "unexpected NUL byte (is this a binary file?)";
  return fail(offset, printable(what, 300));
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Public interface

std::string SceneError::to_string() const {
  if (line == 0) return source + ": " + message;
  return source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
}

SceneResult parse_scene_json(std::string_view text, std::string_view source) {
  auto error = [&](std::size_t offset, std::string message) {
    SceneError e{std::string(source), 0, 0, std::move(message)};
    line_column(text, offset, &e.line, &e.column);
    return e;
  };
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    return error(0, "empty input; expected a JSON object");
  }

  const char* cursor = text.data();
  SceneBuilder builder(text, &cursor);
  const TrackingIterator first(text.data(), &cursor), last(text.data() + text.size(), &cursor);
  const bool ok = Json::sax_parse(first, last, &builder);
  if (!ok || builder.failed()) {
    if (!builder.failed()) builder.fail(static_cast<std::size_t>(cursor - text.data()), "parse stopped");  // unexpected
    return error(builder.error_offset(), builder.error_message());
  }
  // nlohmann takes a NUL byte for the end of the input, so a valid document followed by a NUL and anything
  // at all parses; no NUL may appear anywhere in JSON text.
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    return error(nul, "unexpected NUL byte (is this a binary file?)");
  }
  return std::move(builder.scene());
}

SceneResult load_scene_file(const std::string& path) {
  auto error = [&](std::string message) { return SceneError{path, 0, 0, std::move(message)}; };
  const std::string too_large = "file is larger than the limit of 256 MiB";
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };

  std::unique_ptr<std::FILE, Closer> file(std::fopen(path.c_str(), "rb"));
  if (!file) return error("cannot open: " + std::error_code(errno, std::generic_category()).message());
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return error("cannot open: is a directory");
  std::string text;
  if (const std::uintmax_t size = std::filesystem::file_size(path, ec); !ec) {  // regular files only
    if (size > kMaxFileBytes) return error(too_large);
    text.reserve(static_cast<std::size_t>(size));
  }
  // Read in blocks, checking the limit again: a pipe or device has no size up front.
  std::vector<char> block(1 << 16);
  std::size_t n;
  while ((n = std::fread(block.data(), 1, block.size(), file.get())) > 0) {
    if (text.size() + n > kMaxFileBytes) return error(too_large);
    text.append(block.data(), n);
  }
  if (std::ferror(file.get())) {
    return error("cannot read: " + std::error_code(errno, std::generic_category()).message());
  }

  SceneResult result = parse_scene_json(text, path);
  if (result.ok() && result.value().name.empty()) result.value().name = std::filesystem::path(path).stem().string();
  return result;
}

SceneResult resolve_scene(const std::string& name_or_path) {
  if (std::optional<Scene> scene = builtin(name_or_path)) return std::move(*scene);
  std::error_code ec;
  if (!std::filesystem::exists(name_or_path, ec)) {
    std::string names;
    for (const std::string& name : builtin_names()) names += (names.empty() ? "" : ", ") + name;
    return SceneError{name_or_path, 0, 0,
                      "no built-in scene of that name and no such file; the built-in scenes are " + names +
                          " and random-N (N random spheres)"};
  }
  return load_scene_file(name_or_path);
}

}  // namespace tripsitter::scene
