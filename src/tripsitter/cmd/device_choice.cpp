#include "device_choice.h"

#include "common.h"

#ifdef TRIPSITTER_WITH_RTL
#include <rtl_device.h>
#endif

namespace tripsitter::cmd {
namespace {

std::string rtl_builds_text() {
#ifdef TRIPSITTER_WITH_RTL
  return "this program has the RTL for " + rtl::rtl_builds();
#else
  return "this program was built without the RTL (Verilator was not found when it was configured)";
#endif
}

}  // namespace

void add_device_option(CLI::App& cmd, DeviceChoice& choice) {
  cmd.add_option("--device", choice.name,
                 "hw: which device draws the frames: model (the C++ model) or rtl (the Verilated RTL of rtl/, pin for "
                 "pin, much slower; " + rtl_builds_text() + ")")
      ->capture_default_str();
}

bool wants_rtl(const DeviceChoice& choice) {
  if (choice.name != "model" && choice.name != "rtl")
    throw InputError("--device " + choice.name + ": expected model or rtl");
  return choice.name == "rtl";
}

std::function<std::unique_ptr<device::Backend>()> device_maker(const DeviceChoice& choice,
                                                               const device::DevicePreset& preset,
                                                               link::WireVersion wire) {
  if (!wants_rtl(choice)) return {};
#ifdef TRIPSITTER_WITH_RTL
  rtl::RtlOptions options;
  options.spi_hz = choice.spi_hz;
  options.vcd = choice.vcd;
  options.vcd_worker = choice.vcd_worker;
  options.vcd_lines = choice.vcd_lines;
  auto made = rtl::make_rtl_device(preset, wire, options);
  if (!made) throw InputError("--device rtl: " + made.error());
  // The maker hands over the device it holds, once (a board makes its device once).
  auto held = std::make_shared<std::unique_ptr<device::Backend>>(std::move(made).value());
  return [held]() { return std::move(*held); };
#else
  (void)preset;
  (void)wire;
  throw InputError("--device rtl: " + rtl_builds_text());
#endif
}

}  // namespace tripsitter::cmd
