// The whole board in one process: host -> SPI link -> device -> VGA signal -> monitor.
// Every world the monitor shows has travelled as link bytes; nothing takes a shortcut around the wire.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include <tripsitter/core/image.h>
#include <tripsitter/device/backend.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/display/monitor.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::board {

struct BoardConfig {
  device::DevicePreset preset = device::wide_preset();
  link::WireVersion wire = link::WireVersion::kV3;
  link::SpiConfig spi;
  int device_threads = 0;  // threads the device model computes a frame's lines on (Device's `threads`)
  device::DeviceModel device_model = device::DeviceModel::kFast;  // kPlain: the reference model
  // The host's session on v3 (link/sequence.h): a board runs one host from power-on, so a fixed number keeps
  // its link bytes the same from run to run.
  std::uint32_t session = 1;
  // The device back-end in place of the C++ model (the Verilated RTL: rtl/device/rtl_device.h), made for `preset`
  // and `wire`; empty: device::Device with device_threads and device_model.
  std::function<std::unique_ptr<device::Backend>()> make_device{};
};

// What one shown frame cost and reported.
struct ShownFrame {
  core::Image444 image;                 // as captured from the VGA signal
  device::FrameStats device;            // late pixels and lines of the frame
  host::Saturations saturations;        // of the world it shows
  std::size_t link_bytes = 0;           // of that world
  double link_seconds = 0;              // at the SPI clock
  std::size_t spheres_dropped = 0;      // beyond scene memory, never sent
};

link::SceneFormats formats_of(const device::DevicePreset& preset);

class Board {
 public:
  Board(scene::Scene scene, BoardConfig config);

  host::Host& host() { return host_; }
  const host::Host& host() const { return host_; }
  device::Backend& device() { return *device_; }
  const link::SpiLink& link() const { return link_; }

  // The host rebuilds its world from the current camera and sends it when the device is ready; the device
  // runs until a whole frame of that world has gone out on the VGA signal, which the monitor captures.
  // `probe`, when given, sees every VGA sample (for VCD dumps).
  ShownFrame show(const std::function<void(const device::VgaSample&)>& probe = {});

 private:
  BoardConfig config_;
  host::Host host_;
  link::SpiLink link_;
  std::unique_ptr<device::Backend> device_;
  display::VgaMonitor monitor_;
};

}  // namespace tripsitter::board
