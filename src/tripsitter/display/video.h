// A video file made by ffmpeg (Debian's ffmpeg), fed raw RGB frames through a pipe. Without ffmpeg installed
// the pipe takes the frames and makes nothing, and says so when opened. The video appears under its name only
// when finish() succeeds: ffmpeg writes beside it, and a pipe closed early removes what it wrote.
#pragma once

#include <cstdio>
#include <memory>
#include <ostream>
#include <string>

#include <tripsitter/core/image.h>
#include <tripsitter/core/result.h>
#include <tripsitter/display/io.h>

namespace tripsitter::display {

class VideoPipe {
 public:
  // A pipe to a width x height video at 30 frames/s in `path` (the format follows its extension). Notes (no
  // ffmpeg installed) go to `log`. Fails on a path the shell command cannot carry (a single quote).
  static core::Result<std::unique_ptr<VideoPipe>, IoError> open(const std::string& path, int width, int height,
                                                                 std::ostream& log);
  ~VideoPipe();
  VideoPipe(const VideoPipe&) = delete;
  VideoPipe& operator=(const VideoPipe&) = delete;

  // REQUIRES a frame of the size given to open().
  void add(const core::ImageRgb8& frame);
  // Ends the video and gives it its name; says so on `log`. Throws std::runtime_error when ffmpeg failed.
  void finish(std::ostream& log);

 private:
  VideoPipe() = default;

  FILE* pipe_ = nullptr;
  std::string path_, partial_;
};

}  // namespace tripsitter::display
