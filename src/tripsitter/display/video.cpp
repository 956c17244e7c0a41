#include <tripsitter/display/video.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace tripsitter::display {

core::Result<std::unique_ptr<VideoPipe>, IoError> VideoPipe::open(const std::string& path, int width, int height,
                                                                   std::ostream& log) {
  std::unique_ptr<VideoPipe> video(new VideoPipe);
  // The command goes through the shell, with the path in single quotes.
  if (path.find('\'') != std::string::npos) return IoError{path + ": a quote in the file name"};
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    log << "ffmpeg is not installed (Debian: apt-get install ffmpeg): writing the PNG frames only, no " << path << "\n";
    return video;
  }
  // ffmpeg writes "DIR/NAME.partial.EXT" (it picks the format by the extension), renamed once it has finished,
  // so a render that stops part-way never leaves a short video under the asked name.
  const std::filesystem::path p(path);
  video->partial_ = (p.parent_path() / (p.stem().string() + ".partial" + p.extension().string())).string();
  const std::string cmd = "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " + std::to_string(width) + "x" +
                          std::to_string(height) + " -r 30 -i - -pix_fmt yuv420p '" + video->partial_ + "'";
  video->pipe_ = popen(cmd.c_str(), "w");
  if (video->pipe_ == nullptr) throw std::runtime_error("cannot start ffmpeg");
  video->path_ = path;
  return video;
}

VideoPipe::~VideoPipe() {
  if (pipe_ == nullptr) return;
  pclose(pipe_);
  std::error_code ignored;
  std::filesystem::remove(partial_, ignored);
}

void VideoPipe::add(const core::ImageRgb8& frame) {
  if (pipe_ != nullptr) std::fwrite(frame.pixels.data(), 1, frame.pixels.size(), pipe_);
}

void VideoPipe::finish(std::ostream& log) {
  if (pipe_ == nullptr) return;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  std::error_code ec;
  if (status == 0) std::filesystem::rename(partial_, path_, ec);
  if (status != 0 || ec) {
    std::filesystem::remove(partial_, ec);
    throw std::runtime_error("ffmpeg failed writing " + path_);
  }
  log << "wrote " << path_ << "\n";
}

}  // namespace tripsitter::display
