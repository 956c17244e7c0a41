// Value change dump of the VGA signal (IEEE 1364 VCD), for a waveform viewer such as GTKWave:
// hsync, vsync (1 bit each), r, g, b (4 bits each), one sample per 40 ns pixel clock.
#pragma once

#include <cstdint>
#include <fstream>
#include <memory>
#include <ostream>
#include <string>

#include <tripsitter/core/result.h>
#include <tripsitter/display/io.h>

#include <tripsitter/device/vga_signal.h>

namespace tripsitter::display {

class VcdWriter {
 public:
  // Writes the header to `out`, which must outlive the writer. Time unit 1 ns.
  explicit VcdWriter(std::ostream& out, std::uint64_t pixel_period_ns = 40);
  // One pixel clock; only changed signals are written.
  void sample(const device::VgaSample& s);
  // Writes the time at which the last sample ends, so a viewer shows it for its full period. Call once,
  // after the last sample.
  void finish();
  std::uint64_t samples() const { return samples_; }

 private:
  std::ostream& out_;
  std::uint64_t period_ns_;
  std::uint64_t samples_ = 0;
  bool first_ = true;
  device::VgaSample last_;
};

// A VCD trace written to a file. It is opened before any work, so that a bad path fails first; it takes at most
// `max_samples` samples (later ones are dropped); and it is removed again unless keep() is called, so a render
// that fails leaves no trace behind.
class VcdFile {
 public:
  static core::Result<std::unique_ptr<VcdFile>, IoError> open(const std::string& path, std::uint64_t max_samples);
  ~VcdFile();
  VcdFile(const VcdFile&) = delete;
  VcdFile& operator=(const VcdFile&) = delete;

  void sample(const device::VgaSample& s) {
    if (writer_.samples() < max_samples_) writer_.sample(s);
  }
  // Finishes the trace and keeps the file; returns the samples written.
  core::Result<std::uint64_t, IoError> keep();

 private:
  VcdFile(std::string path, std::uint64_t max_samples);

  std::string path_;
  std::uint64_t max_samples_;
  std::ofstream file_;
  VcdWriter writer_;
  bool kept_ = false;
};

}  // namespace tripsitter::display
