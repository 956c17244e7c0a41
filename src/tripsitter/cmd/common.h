// Shared pieces of the tripsitter subcommands: exit codes, option checks, scene and preset lookup.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <tripsitter/device/preset.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::cmd {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitBadInput = 2;

// Bad input or usage: reported on stderr, exit code 2, no output written.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A built-in scene name or a scene file; throws InputError with file:line:column on failure.
scene::Scene load_scene(const std::string& name_or_path);

// The named preset with the overrides given on the command line (workers, spp and depth 0 and bounces -1: not
// given). spp and depth apply to a path-tracing preset only (InputError otherwise).
device::DevicePreset load_preset(const std::string& name, int workers, int bounces = -1, int spp = 0, int depth = 0);

// All bytes of a file, or of standard input for "-"; throws InputError.
std::vector<std::uint8_t> read_bytes(const std::string& path);

// Where this process stands in a job started by Open MPI's mpirun, read from the OMPI_COMM_WORLD_RANK and
// OMPI_COMM_WORLD_SIZE variables it sets: size 0 when mpirun did not start it.
struct MpirunPlace {
  int rank = 0;
  int size = 0;
};
MpirunPlace mpirun_place();

// "a, b, c"
std::string join(const std::vector<std::string>& items);

}  // namespace tripsitter::cmd
