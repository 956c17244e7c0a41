// Value change dump of the VGA signal (IEEE 1364 VCD), for a waveform viewer such as GTKWave:
// hsync, vsync (1 bit each), r, g, b (4 bits each), one sample per 40 ns pixel clock.
#pragma once

#include <cstdint>
#include <ostream>

#include <tripsitter/device/vga.h>

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

}  // namespace tripsitter::display
