// Scenes that ship with TripSitter, selected by name (`--scene demo`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/scene/scene.h>

namespace tripsitter::scene {

// The names of the built-in scenes, in the order `--help` lists them. Besides these, builtin() knows the
// family random-N: random-1000 is random_spheres(1000, 1).
std::vector<std::string> builtin_names();

// The scene of that name, or nothing when there is none.
std::optional<Scene> builtin(std::string_view name);

// `count` (>= 0) spheres of random sizes and materials in front of the camera, reproducible from `seed`
// (used by the benchmarks and the randomised tests).
Scene random_spheres(int count, std::uint32_t seed);

}  // namespace tripsitter::scene
