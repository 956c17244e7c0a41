// The display's error value for files it writes and reads (PNG, VCD, video), and the one way it writes a whole
// file so that a failure leaves nothing half written.
#pragma once

#include <span>
#include <string>

#include <tripsitter/core/result.h>

namespace tripsitter::display {

struct IoError {
  std::string message;  // names the path and what went wrong
};

// Writes `bytes` to a new file beside `path` ("<path>.tmp-XXXXXXXX", created exclusively) and renames it onto
// `path`, so `path` is either as it was or the whole of `bytes`, and no temporary file stays behind. The error
// reads "<what> '<path>': <reason>".
core::Result<bool, IoError> write_file_beside_and_rename(const std::string& path, std::span<const char> bytes,
                                                         const std::string& what);

}  // namespace tripsitter::display
