// Scene files: JSON as documented in docs/scene_format.md.
#pragma once

#include <string>
#include <string_view>

#include <tripsitter/core/result.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::scene {

// What was wrong and where. line and column are 1-based; 0 when the error has no place in the text
// (a file that cannot be opened).
struct SceneError {
  std::string source;  // file path or "<name>"
  int line = 0;
  int column = 0;
  std::string message;

  // "source:line:column: message", or "source: message" without a place.
  std::string to_string() const;
};

using SceneResult = core::Result<Scene, SceneError>;

// Parses a scene from JSON text. `source` names the text in errors. Every limit of scene.h is checked
// before anything of that size is allocated.
SceneResult parse_scene_json(std::string_view text, std::string_view source);

// Reads and parses a scene file.
SceneResult load_scene_file(const std::string& path);

// A built-in scene name (builtin.h) or else a path to a scene file.
SceneResult resolve_scene(const std::string& name_or_path);

}  // namespace tripsitter::scene
