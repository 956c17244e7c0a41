// The device as the rest of the board sees it: the link's endpoint (ready line, transfers) in, the VGA connector
// out. Two back-ends show the same pixels: the C++ model (device.h, Device) and the Verilated RTL
// (rtl/device/rtl_device.h), which the board, `render`'s device alone and the device program take in its place.
#pragma once

#include <functional>
#include <span>

#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/vga_signal.h>
#include <tripsitter/link/spi.h>

namespace tripsitter::device {

struct FrameStats;

class Backend : public link::Endpoint {
 public:
  // The host went away (the stream transport): a frame cut short is dropped and counted.
  virtual void end_of_stream() = 0;
  // One whole frame of 800 x 525 pixel clocks from a start of vertical blanking, where a waiting world is swapped
  // in, to the end of the last visible line: `line_sink` gets each line's samples in order. The model is at such a
  // start whenever it is not inside a frame; the RTL, whose transfers take clock cycles, first runs to the next one
  // (the samples it passes on the way are not shown). Returns the statistics of the frame.
  virtual FrameStats run_frame_lines(const std::function<void(std::span<const VgaSample>)>& line_sink) = 0;
  virtual const ReceiverStats& receiver_stats() const = 0;
  // A good world is in scene memory's front copy (the frames show it).
  virtual bool has_world() const = 0;
  // Scene memory's front copy and, with a path-tracing preset, frame memory, as the last frame left them; null
  // where the back-end cannot read them out (the RTL) or has none.
  virtual const SceneMemory* scene_memory() const = 0;
  virtual const FrameMemory* frame_memory() const = 0;
};

}  // namespace tripsitter::device
