// The device drives one whole frame of VGA signal and the monitor captures it: "run the device, feed the
// monitor, take the frame", the one way every part of the system (the board, render's device alone, the device
// program) gets a picture out of the device.
#pragma once

#include <functional>

#include <tripsitter/core/image.h>
#include <tripsitter/device/backend.h>
#include <tripsitter/device/device.h>
#include <tripsitter/display/monitor.h>

namespace tripsitter::board {

struct CapturedFrame {
  device::FrameStats stats;  // the world it shows, its late pixels and lines
  core::Image444 image;      // as the monitor captured it
};

// One frame from a start of vertical blanking to the end of the last visible line (Backend::run_frame_lines), every
// sample into the monitor and, when given, into `probe` (a VCD trace). REQUIRES the monitor locked to the device
// or fresh.
CapturedFrame capture_frame(device::Backend& device, display::VgaMonitor& monitor,
                            const std::function<void(const device::VgaSample&)>& probe = {});

}  // namespace tripsitter::board
