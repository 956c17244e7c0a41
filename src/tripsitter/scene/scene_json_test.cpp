#include <tripsitter/scene/scene_json.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <tripsitter/scene/builtin.h>

#ifndef TRIPSITTER_SOURCE_DIR
#error "compile with -DTRIPSITTER_SOURCE_DIR=\"/path/to/repo\""
#endif

namespace tripsitter::scene {
namespace {

using core::Vec3d;

const std::string kSourceDir = TRIPSITTER_SOURCE_DIR;

// The example of docs/scene_format.md and scenes/three_materials.json.
constexpr const char* kExample = R"({
  "camera": {"lookfrom": [0, 0, -10], "lookat": [0, 0, 0], "vup": [0, 1, 0],
             "vfov": 60, "defocus_angle": 0, "focus_dist": 10},
  "render": {"width": 640, "height": 480, "spp": 1, "max_depth": 50},
  "spheres": [
    {"center": [0, 0, 0], "radius": 1, "material": {"type": "lambertian", "albedo": [0.8, 0.3, 0.3]}},
    {"center": [2, 0, 0], "radius": 0.5, "material": {"type": "metal", "albedo": [0.8, 0.8, 0.8], "fuzz": 0.1}},
    {"center": [-2, 0, 0], "radius": 0.5, "material": {"type": "dielectric", "ior": 1.5}}
  ]
})";

void ExpectVecEq(const Vec3d& a, const Vec3d& b) {
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
}

// Every field equal (exactly: the loader must not change a value).
void ExpectSceneEq(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  ExpectVecEq(a.camera.lookfrom, b.camera.lookfrom);
  ExpectVecEq(a.camera.lookat, b.camera.lookat);
  ExpectVecEq(a.camera.vup, b.camera.vup);
  EXPECT_EQ(a.camera.vfov, b.camera.vfov);
  EXPECT_EQ(a.camera.defocus_angle, b.camera.defocus_angle);
  EXPECT_EQ(a.camera.focus_dist, b.camera.focus_dist);
  EXPECT_EQ(a.render.width, b.render.width);
  EXPECT_EQ(a.render.height, b.render.height);
  EXPECT_EQ(a.render.spp, b.render.spp);
  EXPECT_EQ(a.render.max_depth, b.render.max_depth);
  EXPECT_EQ(a.units_per_world, b.units_per_world);
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    SCOPED_TRACE("sphere " + std::to_string(i));
    ExpectVecEq(a.spheres[i].center, b.spheres[i].center);
    EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius);
    EXPECT_EQ(a.spheres[i].material.type, b.spheres[i].material.type);
    ExpectVecEq(a.spheres[i].material.albedo, b.spheres[i].material.albedo);
    EXPECT_EQ(a.spheres[i].material.fuzz, b.spheres[i].material.fuzz);
    EXPECT_EQ(a.spheres[i].material.ior, b.spheres[i].material.ior);
  }
}

Scene Parse(std::string_view text) {
  SceneResult r = parse_scene_json(text, "<test>");
  if (!r.ok()) ADD_FAILURE() << r.error().to_string();
  return r.ok() ? std::move(r).value() : Scene{};
}

// A scene written back as JSON with every field given.
std::string ToJson(const Scene& s) {
  using nlohmann::json;
  auto vec = [](const Vec3d& v) { return json::array({v.x, v.y, v.z}); };
  json spheres = json::array();
  for (const Sphere& sp : s.spheres) {
    spheres.push_back({{"center", vec(sp.center)},
                       {"radius", sp.radius},
                       {"material",
                        {{"type", material_name(sp.material.type)},
                         {"albedo", vec(sp.material.albedo)},
                         {"fuzz", sp.material.fuzz},
                         {"ior", sp.material.ior}}}});
  }
  json j = {{"name", s.name},
            {"camera",
             {{"lookfrom", vec(s.camera.lookfrom)},
              {"lookat", vec(s.camera.lookat)},
              {"vup", vec(s.camera.vup)},
              {"vfov", s.camera.vfov},
              {"defocus_angle", s.camera.defocus_angle},
              {"focus_dist", s.camera.focus_dist}}},
            {"render",
             {{"width", s.render.width},
              {"height", s.render.height},
              {"spp", s.render.spp},
              {"max_depth", s.render.max_depth}}},
            {"spheres", spheres}};
  if (s.units_per_world != 0) j["units_per_world"] = s.units_per_world;
  return j.dump(1);
}

// ---------------------------------------------------------------------------------------------
// Valid scenes

TEST(SceneJson, ExampleLoadsWithExactValues) {
  const Scene s = Parse(kExample);
  EXPECT_EQ(s.name, "");
  ExpectVecEq(s.camera.lookfrom, {0, 0, -10});
  ExpectVecEq(s.camera.lookat, {0, 0, 0});
  ExpectVecEq(s.camera.vup, {0, 1, 0});
  EXPECT_EQ(s.camera.vfov, 60);
  EXPECT_EQ(s.camera.defocus_angle, 0);
  EXPECT_EQ(s.camera.focus_dist, 10);
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.spp, 1);
  EXPECT_EQ(s.render.max_depth, 50);
  EXPECT_EQ(s.units_per_world, 0);
  ASSERT_EQ(s.spheres.size(), 3u);

  ExpectVecEq(s.spheres[0].center, {0, 0, 0});
  EXPECT_EQ(s.spheres[0].radius, 1);
  EXPECT_EQ(s.spheres[0].material.type, MaterialType::kLambertian);
  ExpectVecEq(s.spheres[0].material.albedo, {0.8, 0.3, 0.3});

  ExpectVecEq(s.spheres[1].center, {2, 0, 0});
  EXPECT_EQ(s.spheres[1].radius, 0.5);
  EXPECT_EQ(s.spheres[1].material.type, MaterialType::kMetal);
  ExpectVecEq(s.spheres[1].material.albedo, {0.8, 0.8, 0.8});
  EXPECT_EQ(s.spheres[1].material.fuzz, 0.1);

  ExpectVecEq(s.spheres[2].center, {-2, 0, 0});
  EXPECT_EQ(s.spheres[2].radius, 0.5);
  EXPECT_EQ(s.spheres[2].material.type, MaterialType::kDielectric);
  ExpectVecEq(s.spheres[2].material.albedo, {1, 1, 1});
  EXPECT_EQ(s.spheres[2].material.ior, 1.5);
}

TEST(SceneJson, OmittedFieldsTakeTheDefaultsOfSceneH) {
  const Scene s = Parse(R"({"spheres": [{"center": [1, 2, 3], "radius": 4}]})");
  Scene expected;
  expected.spheres.push_back({{1, 2, 3}, 4, Material{}});
  ExpectSceneEq(s, expected);
  EXPECT_EQ(s.spheres[0].material.type, MaterialType::kLambertian);
  ExpectVecEq(s.spheres[0].material.albedo, {0.5, 0.5, 0.5});

  ExpectSceneEq(Parse(R"({"spheres": [], "camera": {}, "render": {}})"), Scene{});
  ExpectSceneEq(Parse(R"({"spheres": []})"), Scene{});
}

TEST(SceneJson, MaterialDefaultsDependOnTheType) {
  const Scene s = Parse(R"({"spheres": [
    {"center": [0, 0, 0], "radius": 1, "material": {"type": "metal"}},
    {"center": [0, 0, 0], "radius": 1, "material": {"type": "dielectric"}},
    {"center": [0, 0, 0], "radius": 1, "material": {"albedo": [0.1, 0.2, 0.3], "type": "dielectric", "ior": 2.4}},
    {"center": [0, 0, 0], "radius": 1, "material": {"type": "lambertian"}}]})");
  ASSERT_EQ(s.spheres.size(), 4u);
  EXPECT_EQ(s.spheres[0].material.type, MaterialType::kMetal);
  ExpectVecEq(s.spheres[0].material.albedo, {0.5, 0.5, 0.5});
  EXPECT_EQ(s.spheres[0].material.fuzz, 0);
  ExpectVecEq(s.spheres[1].material.albedo, {1, 1, 1});
  EXPECT_EQ(s.spheres[1].material.ior, 1.5);
  ExpectVecEq(s.spheres[2].material.albedo, {0.1, 0.2, 0.3});  // given before the type: kept
  EXPECT_EQ(s.spheres[2].material.ior, 2.4);
  ExpectVecEq(s.spheres[3].material.albedo, {0.5, 0.5, 0.5});
}

TEST(SceneJson, OptionalTopLevelFieldsAndNumberForms) {
  const Scene s = Parse(
      "\xEF\xBB\xBF"  // a byte-order mark is allowed
      R"({"name": "t\u00e9st \"q\"", "units_per_world": 32.5,
          "render": {"width": 1.28e3, "height": 720.0, "spp": 65536, "max_depth": 1024},
          "camera": {"vfov": 179.5, "defocus_angle": 0.5, "focus_dist": 1e-3, "lookfrom": [-1E2, 0.0, -0]},
          "spheres": [{"center": [1e300, -1e-300, 5], "radius": 1e-9,
                       "material": {"type": "metal", "fuzz": 1, "albedo": [0, 1, 0.25]}}]})");
  EXPECT_EQ(s.name, "t\xC3\xA9st \"q\"");
  EXPECT_EQ(s.units_per_world, 32.5);
  EXPECT_EQ(s.render.width, 1280);
  EXPECT_EQ(s.render.height, 720);
  EXPECT_EQ(s.render.spp, kMaxSpp);
  EXPECT_EQ(s.render.max_depth, kMaxDepth);
  EXPECT_EQ(s.camera.vfov, 179.5);
  EXPECT_EQ(s.camera.defocus_angle, 0.5);
  EXPECT_EQ(s.camera.focus_dist, 1e-3);
  ExpectVecEq(s.camera.lookfrom, {-100, 0, 0});
  ExpectVecEq(s.spheres.at(0).center, {1e300, -1e-300, 5});
  EXPECT_EQ(s.spheres[0].radius, 1e-9);
  EXPECT_EQ(s.spheres[0].material.fuzz, 1);
}

TEST(SceneJson, ScenesRoundTripThroughJson) {
  std::vector<Scene> scenes;
  for (const std::string& name : builtin_names()) scenes.push_back(*builtin(name));
  scenes.push_back(random_spheres(300, 7));
  for (const Scene& s : scenes) {
    SCOPED_TRACE(s.name);
    ExpectSceneEq(Parse(ToJson(s)), s);
  }
}

TEST(SceneJson, ShippedScenesLoad) {
  SceneResult three = load_scene_file(kSourceDir + "/scenes/three_materials.json");
  ASSERT_TRUE(three.ok()) << three.error().to_string();
  Scene expected = Parse(kExample);
  expected.name = "three_materials";  // from the file name: the file has no "name"
  ExpectSceneEq(three.value(), expected);

  // scenes/cluster.json is the built-in "cluster" written out.
  SceneResult cluster = load_scene_file(kSourceDir + "/scenes/cluster.json");
  ASSERT_TRUE(cluster.ok()) << cluster.error().to_string();
  ExpectSceneEq(cluster.value(), *builtin("cluster"));
}

TEST(SceneJson, DocumentedExampleLoads) {
  std::ifstream in(kSourceDir + "/docs/scene_format.md");
  ASSERT_TRUE(in) << "docs/scene_format.md";
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t begin = doc.find("```json\n");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin + 8);
  ASSERT_NE(end, std::string::npos);
  ExpectSceneEq(Parse(std::string_view(doc).substr(begin + 8, end - begin - 8)), Parse(kExample));
}

// ---------------------------------------------------------------------------------------------
// Malformed scenes: each fails with one message at an exact place.

struct BadCase {
  const char* what;
  std::string text;
  int line;
  int column;
  const char* message;  // a substring of the message
};

std::string Sphere1(const std::string& fields) { return R"({"spheres": [{"center": [0, 0, 0], )" + fields + "}]}"; }
std::string WithCamera(const std::string& fields) { return R"({"spheres": [], "camera": {)" + fields + "}}"; }
std::string WithRender(const std::string& fields) { return R"({"spheres": [], "render": {)" + fields + "}}"; }

const std::vector<BadCase>& BadCases() {
  static const std::vector<BadCase> cases = {
      // Syntax.
      {"trailing comma", R"({"spheres": [],})", 1, 16, "unexpected '}'; expected string literal"},
      {"missing colon", R"({"spheres" []})", 1, 12, "unexpected '['; expected ':'"},
      {"unclosed object", R"({"spheres": [])", 1, 15, "unexpected end of input"},
      {"missing comma on line 4", "{\n  \"spheres\": [],\n  \"name\": \"x\"\n  \"render\": {}\n}", 4, 3,
       "unexpected string literal; expected '}'"},
      {"bad escape", R"({"name": "a\qb"})", 1, 13, "invalid string"},
      {"newline in string", "{\"name\": \"ab\ncd\"}", 1, 13, "control character U+000A"},
      {"bad number", R"({"spheres": [], "units_per_world": 1.x})", 1, 38, "expected digit after '.'"},
      {"two numbers", R"({"spheres": [], "units_per_world": 1 2})", 1, 38, "unexpected number literal; expected '}'"},
      {"bad literal", R"({"spheres": [], "name": nul})", 1, 25, "invalid literal; last read: 'nul}'"},
      {"garbage after the object", "{\"spheres\": []}\n x", 2, 2, "invalid literal; last read: 'x'"},
      {"single quotes", R"({'spheres': []})", 1, 2, "invalid literal"},
      {"empty text", "", 1, 1, "empty input"},
      {"only whitespace", " \n\t\r\n ", 1, 1, "empty input"},
      {"not json", "not json", 1, 1, "invalid literal; last read: 'no'"},
      {"binary garbage", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff", 17), 1, 1, "invalid literal"},
      {"NUL inside", std::string("{\"spheres\": [\0]}", 16), 1, 14, "NUL byte"},
      {"NUL after the object", std::string("{\"spheres\": []}\0\xff\xfe junk", 22), 1, 16, "NUL byte"},
      {"deep arrays", std::string(100000, '['), 1, 1, "expected a JSON object at the top level, found an array"},
      {"deep arrays in spheres", "{\"spheres\": " + std::string(100000, '['), 1, 14,
       "spheres[0]: expected an object, found an array"},
      {"deep arrays in a vector", "{\"camera\": {\"lookfrom\": " + std::string(100000, '['), 1, 26,
       "camera.lookfrom[0]: expected a number, found an array"},
      {"deep objects", "{\"camera\": {\"lookfrom\": " + [] {
         std::string s;
         for (int i = 0; i < 100000; ++i) s += "{\"a\": ";
         return s;
       }(),
       1, 25, "camera.lookfrom: expected an array of 3 numbers, found an object"},
      // Shape.
      {"top level array", "[]", 1, 1, "expected a JSON object at the top level, found an array"},
      {"top level number", " 42", 1, 2, "expected a JSON object at the top level, found a number"},
      {"top level 1e999", "1e999", 1, 1, "expected a JSON object at the top level, found a number"},
      {"missing spheres", R"({"name": "x"})", 1, 1, "missing required key \"spheres\""},
      {"missing radius", "{\"spheres\": [\n  {\"center\": [0, 0, 0]}\n]}", 2, 3,
       "spheres[0]: missing required key \"radius\""},
      {"missing center", R"({"spheres": [{"radius": 1}]})", 1, 14, "spheres[0]: missing required key \"center\""},
      {"missing material type", Sphere1(R"("radius": 1, "material": {"albedo": [1, 1, 1]})"), 1, 61,
       "spheres[0].material: missing required key \"type\""},
      {"spheres not an array", R"({"spheres": {}})", 1, 13, "spheres: expected an array, found an object"},
      {"sphere not an object", R"({"spheres": [{"center": [0, 0, 0], "radius": 1}, 7]})", 1, 50,
       "spheres[1]: expected an object, found a number"},
      {"unknown top level key", R"({"spheres": [], "camra": {}})", 1, 17,
       "unknown key \"camra\"; expected one of name, camera, render, units_per_world, spheres"},
      {"unknown sphere key", Sphere1(R"("radius": 1, "color": [1, 0, 0])"), 1, 49, "spheres[0]: unknown key \"color\""},
      {"unknown material key", Sphere1(R"("radius": 1, "material": {"type": "metal", "fuz": 0.1})"), 1, 79,
       "spheres[0].material: unknown key \"fuz\"; expected one of type, albedo, fuzz, ior"},
      {"unknown camera key", WithCamera(R"("fov": 60)"), 1, 28, "camera: unknown key \"fov\""},
      {"duplicate key", Sphere1(R"("radius": 1, "radius": 2)"), 1, 49, "spheres[0]: duplicate key \"radius\""},
      // Types.
      {"wrong type on line 3", "{\n  \"camera\": {\n      \"vfov\": \"wide\"\n  },\n  \"spheres\": []\n}", 3, 15,
       "camera.vfov: expected a number, found a string"},
      {"null", WithCamera(R"("focus_dist": null)"), 1, 42, "camera.focus_dist: expected a number, found null"},
      {"boolean", WithRender(R"("spp": true)"), 1, 35, "render.spp: expected an integer, found a boolean"},
      {"name not a string", R"({"spheres": [], "name": 5})", 1, 25, "name: expected a string, found a number"},
      {"render not an object", R"({"spheres": [], "render": 5})", 1, 27, "render: expected an object, found a number"},
      {"material type not a string", Sphere1(R"("radius": 1, "material": {"type": 1})"), 1, 70,
       "spheres[0].material.type: expected a string, found a number"},
      {"material not an object", Sphere1(R"("radius": 1, "material": "metal")"), 1, 61,
       "spheres[0].material: expected an object, found a string"},
      {"spp 1.5", WithRender(R"("spp": 1.5)"), 1, 35, "render.spp: expected an integer, found 1.5"},
      // Vectors.
      {"vector of 2", R"({"spheres": [{"center": [0, 0], "radius": 1}]})", 1, 25,
       "spheres[0].center: expected an array of 3 numbers, found 2"},
      {"vector of 4", R"({"spheres": [{"center": [0, 0, 0, 0], "radius": 1}]})", 1, 35,
       "spheres[0].center: expected an array of 3 numbers, found more"},
      {"empty vector", WithCamera(R"("vup": [])"), 1, 35, "camera.vup: expected an array of 3 numbers, found 0"},
      {"vector element a string", WithCamera(R"("lookat": [0, 0, "1"])"), 1, 45,
       "camera.lookat[2]: expected a number, found a string"},
      {"vector not an array", WithCamera(R"("lookfrom": 5)"), 1, 40,
       "camera.lookfrom: expected an array of 3 numbers, found a number"},
      {"-1e999 in a vector", R"({"spheres": [{"center": [0, -1e999, 0], "radius": 1}]})", 1, 29,
       "spheres[0].center[1]: number -1e999 is out of range"},
      // Ranges.
      {"1e999", R"({"spheres": [], "units_per_world": 1e999})", 1, 36, "units_per_world: number 1e999 is out of range"},
      {"units_per_world 0", R"({"spheres": [], "units_per_world": 0})", 1, 36,
       "units_per_world: must be greater than 0, found 0"},
      {"negative radius", Sphere1(R"("radius": -1)"), 1, 46, "spheres[0].radius: must be greater than 0, found -1"},
      {"zero radius", Sphere1(R"("radius": 0)"), 1, 46, "spheres[0].radius: must be greater than 0, found 0"},
      {"radius in the second sphere",
       R"({"spheres": [{"center": [0, 0, 0], "radius": 1}, {"center": [0, 0, 0], "radius": -0.5}]})", 1, 82,
       "spheres[1].radius: must be greater than 0, found -0.5"},
      {"albedo 2", Sphere1(R"("radius": 1, "material": {"type": "lambertian", "albedo": [0.5, 2, 0.5]})"), 1, 100,
       "spheres[0].material.albedo[1]: must be in [0, 1], found 2"},
      {"albedo negative", Sphere1(R"("radius": 1, "material": {"type": "metal", "albedo": [-0.1, 0, 0]})"), 1, 90,
       "spheres[0].material.albedo[0]: must be in [0, 1], found -0.1"},
      {"fuzz 1.5", Sphere1(R"("radius": 1, "material": {"type": "metal", "fuzz": 1.5})"), 1, 87,
       "spheres[0].material.fuzz: must be in [0, 1], found 1.5"},
      {"ior 0", Sphere1(R"("radius": 1, "material": {"type": "dielectric", "ior": 0})"), 1, 91,
       "spheres[0].material.ior: must be greater than 0, found 0"},
      {"unknown material", Sphere1(R"("radius": 1, "material": {"type": "glass"})"), 1, 70,
       "spheres[0].material.type: unknown material type \"glass\"; expected one of lambertian, metal, dielectric"},
      {"vfov 180", WithCamera(R"("vfov": 180)"), 1, 36, "camera.vfov: must be in (0, 180) degrees, found 180"},
      {"vfov 0", WithCamera(R"("vfov": 0)"), 1, 36, "camera.vfov: must be in (0, 180) degrees, found 0"},
      {"defocus_angle 180", WithCamera(R"("defocus_angle": 180)"), 1, 45,
       "camera.defocus_angle: must be in [0, 180) degrees, found 180"},
      {"defocus_angle -1", WithCamera(R"("defocus_angle": -1)"), 1, 45, "camera.defocus_angle: must be in [0, 180)"},
      {"focus_dist 0", WithCamera(R"("focus_dist": 0)"), 1, 42, "camera.focus_dist: must be greater than 0, found 0"},
      {"width 0", WithRender(R"("width": 0)"), 1, 37, "render.width: must be in 1..16384, found 0"},
      {"width 100000", WithRender(R"("width": 100000)"), 1, 37, "render.width: must be in 1..16384, found 100000"},
      {"height 1e20", WithRender(R"("height": 1e20)"), 1, 38, "render.height: must be in 1..16384, found 1e+20"},
      {"spp 70000", WithRender(R"("spp": 70000)"), 1, 35, "render.spp: must be in 1..65536, found 70000"},
      {"max_depth 0", WithRender(R"("max_depth": 0)"), 1, 41, "render.max_depth: must be in 1..1024, found 0"},
      {"max_depth 2000", WithRender(R"("max_depth": 2000)"), 1, 41, "render.max_depth: must be in 1..1024"},
      // Camera geometry.
      {"lookfrom equals lookat", WithCamera(R"("lookfrom": [1, 2, 3], "lookat": [1, 2, 3])"), 1, 61,
       "camera: lookfrom and lookat are the same point"},
      {"lookfrom equals the default lookat", WithCamera(R"("lookfrom": [0, 0, 0])"), 1, 40,
       "camera: lookfrom and lookat are the same point"},
      {"vup along the view direction", WithCamera(R"("lookfrom": [0, -5, 0], "vup": [0, 2, 0])"), 1, 59,
       "camera: vup must not be zero or parallel to the view direction"},
      {"default vup along the view direction", WithCamera(R"("lookfrom": [0, 10, 0])"), 1, 27,
       "camera: vup must not be zero or parallel"},
      {"zero vup", WithCamera(R"("vup": [0, 0, 0])"), 1, 35, "camera: vup must not be zero"},
      {"lookfrom and lookat too far apart", WithCamera(R"("lookfrom": [-1e308, 0, 0], "lookat": [1e308, 0, 0])"),
       1, 66, "camera: lookfrom and lookat are too far apart"},
      // Positions count lines and characters.
      {"CRLF line ends", "{\r\n  \"spheres\": 5\r\n}", 2, 14, "spheres: expected an array, found a number"},
      {"non-ASCII before the error", "{\"name\": \"\xC3\xA9\xC3\xA9\", \"spheres\": 5}", 1, 27,
       "spheres: expected an array, found a number"},
      {"after a byte-order mark", "\xEF\xBB\xBF{\"spheres\": 5}", 1, 13, "spheres: expected an array"},
      {"unknown key with control bytes", std::string("{\"a\\u0001\": 1}"), 1, 2, "unknown key \"a\\x01\""},
  };
  return cases;
}

class BadScene : public testing::TestWithParam<std::size_t> {};

TEST_P(BadScene, FailsWithPositionAndMessage) {
  const BadCase& c = BadCases()[GetParam()];
  SCOPED_TRACE(c.what);
  const SceneResult r = parse_scene_json(c.text, "bad.json");
  ASSERT_FALSE(r.ok());
  const SceneError& e = r.error();
  EXPECT_EQ(e.source, "bad.json");
  EXPECT_EQ(e.line, c.line) << e.to_string();
  EXPECT_EQ(e.column, c.column) << e.to_string();
  EXPECT_NE(e.message.find(c.message), std::string::npos) << e.to_string();
  EXPECT_LT(e.message.size(), 400u) << e.to_string();
}

INSTANTIATE_TEST_SUITE_P(Table, BadScene, testing::Range<std::size_t>(0, BadCases().size()),
                         [](const testing::TestParamInfo<std::size_t>& info) {
                           std::string name;
                           for (const char ch : std::string(BadCases()[info.param].what)) {
                             name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           }
                           return name;
                         });

// The keys the parser accepts in one kind of object, as its "unknown key" message lists them.
std::vector<std::string> keys_of(const std::string& document_with_unknown_key) {
  const SceneResult r = parse_scene_json(document_with_unknown_key, "s");
  EXPECT_FALSE(r.ok());
  if (r.ok()) return {};
  const std::string& m = r.error().message;
  const std::string tail = "expected one of ";
  const auto at = m.find(tail);
  EXPECT_NE(at, std::string::npos) << m;
  if (at == std::string::npos) return {};
  std::vector<std::string> keys;
  std::stringstream list(m.substr(at + tail.size()));
  for (std::string key; std::getline(list, key, ',');) keys.push_back(key.substr(key.find_first_not_of(' ')));
  return keys;
}

// A message with every array index written as [] ("spheres[1].radius: ..." is "spheres[].radius: ...").
std::string without_indices(std::string message) {
  for (std::size_t open = message.find('['); open != std::string::npos; open = message.find('[', open + 1)) {
    std::size_t close = open + 1;
    while (close < message.size() && std::isdigit(static_cast<unsigned char>(message[close])) != 0) ++close;
    if (close < message.size() && message[close] == ']') message.erase(open + 1, close - open - 1);
  }
  return message;
}

// Every key of every object has a bad case in the table: a key the parser learns without a case fails here.
TEST(SceneJson, TableHasABadCaseForEveryKey) {
  struct Object {
    std::string unknown_key_document;
    std::string path;  // the object's place in a message: "" (top level), "camera", "spheres[]", ...
  };
  const std::vector<Object> objects = {
      {R"({"spheres": [], "zzz": 1})", ""},
      {WithCamera(R"("zzz": 1)"), "camera"},
      {WithRender(R"("zzz": 1)"), "render"},
      {Sphere1(R"("radius": 1, "zzz": 1)"), "spheres[]"},
      {Sphere1(R"("radius": 1, "material": {"type": "metal", "zzz": 1})"), "spheres[].material"},
  };
  std::size_t keys = 0;
  for (const Object& object : objects) {
    for (const std::string& key : keys_of(object.unknown_key_document)) {
      ++keys;
      // A message about the key's value ("camera.vfov: ...", "spheres[].center[]: ...") or its absence.
      const std::string value = (object.path.empty() ? "" : object.path + ".") + key;
      const std::string missing = (object.path.empty() ? "" : object.path + ": ") + "missing required key \"" + key + "\"";
      const auto& cases = BadCases();
      EXPECT_TRUE(std::any_of(cases.begin(), cases.end(), [&](const BadCase& c) {
        const std::string m = without_indices(c.message);
        return m.starts_with(value + ":") || m.starts_with(value + "[") || m.starts_with(missing);
      })) << "no bad case for key \"" << key << "\" of " << (object.path.empty() ? "the top level" : object.path);
    }
  }
  EXPECT_EQ(keys, 22u);  // the five objects' keys were read from the parser
}

TEST(SceneJson, RunawayStringIsReportedBriefly) {
  const std::string text = "{\"name\": \"" + std::string(1 << 20, 'a');
  const SceneResult r = parse_scene_json(text, "s");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().line, 1);
  EXPECT_EQ(r.error().column, static_cast<int>(text.size()) + 1);
  EXPECT_NE(r.error().message.find("missing closing quote; last read: '...aaaa"), std::string::npos)
      << r.error().message;
  EXPECT_LT(r.error().message.size(), 300u);
}

// Damaged copies of a valid scene: every one either loads or fails at a place inside the text (never
// crashes, which ASan/UBSan builds would show).
TEST(SceneJson, DamagedTextFailsCleanly) {
  const std::string good = kExample;
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  int failures = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string text = good;
    switch (next() % 4) {
      case 0: text.resize(next() % text.size()); break;                                   // truncated
      case 1: text[next() % text.size()] = static_cast<char>(next() >> 24); break;       // one byte changed
      case 2: text.erase(next() % text.size(), 1 + next() % 8); break;                    // bytes removed
      default: text.insert(next() % text.size(), 1, "{}[],:\"\\0e-. \n"[next() % 15]); break;  // one inserted
    }
    const SceneResult r = parse_scene_json(text, "t");
    if (r.ok()) continue;
    ++failures;
    const SceneError& e = r.error();
    const int lines = 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
    ASSERT_GE(e.line, 1) << e.to_string();
    ASSERT_LE(e.line, lines) << e.to_string();
    ASSERT_GE(e.column, 1) << e.to_string();
    ASSERT_LE(e.column, static_cast<int>(text.size()) + 1) << e.to_string();
    ASSERT_FALSE(e.message.empty());
    ASSERT_LT(e.message.size(), 400u) << e.to_string();
  }
  EXPECT_GT(failures, 1000);
}

// ---------------------------------------------------------------------------------------------
// Errors, files and names

TEST(SceneError, ToString) {
  EXPECT_EQ((SceneError{"a.json", 3, 15, "camera.vfov: bad"}).to_string(), "a.json:3:15: camera.vfov: bad");
  EXPECT_EQ((SceneError{"a.json", 0, 0, "cannot open: x"}).to_string(), "a.json: cannot open: x");
}

class SceneFiles : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(testing::TempDir()) /
           ("scene_json_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(SceneFiles, MissingFile) {
  const std::string path = (dir_ / "nope.json").string();
  const SceneResult r = load_scene_file(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().source, path);
  EXPECT_EQ(r.error().line, 0);
  EXPECT_EQ(r.error().column, 0);
  EXPECT_EQ(r.error().message, "cannot open: No such file or directory");
  EXPECT_EQ(r.error().to_string(), path + ": cannot open: No such file or directory");
}

TEST_F(SceneFiles, Directory) {
  const SceneResult r = load_scene_file(dir_.string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().line, 0);
  EXPECT_EQ(r.error().message, "cannot open: is a directory");
}

TEST_F(SceneFiles, TooLargeIsRejectedBeforeReading) {
  const std::string path = Write("huge.json", "{");
  std::filesystem::resize_file(path, (std::uintmax_t{256} << 20) + 1);  // sparse: costs no disk
  const SceneResult r = load_scene_file(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().line, 0);
  EXPECT_NE(r.error().message.find("256 MiB"), std::string::npos) << r.error().message;
}

TEST_F(SceneFiles, ErrorsNameTheFileAndPlace) {
  const std::string path =
      Write("bad.json", "{\n  \"spheres\": [\n    {\"center\": [0, 0, 0], \"radius\": 0}\n  ]\n}\n");
  const SceneResult r = load_scene_file(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().to_string(), path + ":3:37: spheres[0].radius: must be greater than 0, found 0");
}

TEST_F(SceneFiles, NameComesFromTheFileUnlessGiven) {
  EXPECT_EQ(load_scene_file(Write("my_scene.json", R"({"spheres": []})")).value().name, "my_scene");
  EXPECT_EQ(load_scene_file(Write("other.json", R"({"name": "given", "spheres": []})")).value().name, "given");
}

TEST_F(SceneFiles, ResolveBuiltinNamesFirstThenFiles) {
  for (const std::string& name : builtin_names()) {
    const SceneResult r = resolve_scene(name);
    ASSERT_TRUE(r.ok()) << r.error().to_string();
    ExpectSceneEq(r.value(), *builtin(name));
  }
  const SceneResult file = resolve_scene(kSourceDir + "/scenes/three_materials.json");
  ASSERT_TRUE(file.ok()) << file.error().to_string();
  EXPECT_EQ(file.value().spheres.size(), 3u);

  // A path is a file even when its file name is that of a built-in scene.
  const std::string demo_path = Write("demo", R"({"spheres": []})");
  EXPECT_EQ(resolve_scene(demo_path).value().spheres.size(), 0u);

  const std::string bad = Write("broken.json", R"({"spheres": 1})");
  const SceneResult broken = resolve_scene(bad);
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.error().to_string(), bad + ":1:13: spheres: expected an array, found a number");
}

TEST(ResolveScene, UnknownNameListsTheBuiltins) {
  const SceneResult r = resolve_scene("no-such-scene");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().source, "no-such-scene");
  EXPECT_EQ(r.error().line, 0);
  for (const std::string& name : builtin_names()) {
    EXPECT_NE(r.error().message.find(name), std::string::npos) << r.error().message;
  }
  EXPECT_NE(r.error().message.find("demo, cluster"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace tripsitter::scene
