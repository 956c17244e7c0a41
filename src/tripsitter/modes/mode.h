// The three ways TripSitter makes a picture, parsed once from the command line and dispatched once, by
// make_frame_source (frame_source.h).
#pragma once

#include <string_view>

namespace tripsitter::modes {

enum class Mode {
  kHw,      // the board: host -> link -> device -> VGA signal -> monitor, bit-exact fixed point, 640x480
  kNormal,  // the float reference of the device's shading (normal maps, metal mirrors), any size
  kPath,    // the float path tracer with the scene's materials and thin-lens camera, any size
};

// "hw", "normal", "path": the names the command line takes (cmd/options.h parses them).
std::string_view mode_name(Mode mode);

}  // namespace tripsitter::modes
