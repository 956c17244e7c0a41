// The device drives one whole frame of VGA signal and the monitor captures it: "run the device, feed the
// monitor, take the frame", the one way every part of the system (the board, render's device alone, the device
// program) gets a picture out of the device.
#pragma once

#include <functional>

#include <tripsitter/core/image.h>
#include <tripsitter/device/device.h>
#include <tripsitter/display/monitor.h>

namespace tripsitter::board {

struct CapturedFrame {
  device::FrameStats stats;  // the world it shows, its late pixels and lines
  core::Image444 image;      // as the monitor captured it
};

// One frame from the start of vertical blanking to the end of the last visible line, every sample into the
// monitor and, when given, into `probe` (a VCD trace). REQUIRES the device at the start of vertical blanking
// (as after reset or an earlier capture) and the monitor locked to it or fresh.
CapturedFrame capture_frame(device::Device& device, display::VgaMonitor& monitor,
                            const std::function<void(const device::VgaSample&)>& probe = {});

}  // namespace tripsitter::board
