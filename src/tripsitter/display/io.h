// The display's error value for files it writes and reads (PNG, VCD, video).
#pragma once

#include <string>

namespace tripsitter::display {

struct IoError {
  std::string message;  // names the path and what went wrong
};

}  // namespace tripsitter::display
