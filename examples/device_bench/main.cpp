// The whole board of TripSitter in a program of your own: the host sends the built-in demo scene over the SPI
// link, the device draws it on its VGA signal and the monitor captures one frame. Prints the frame's centre
// pixel (12-bit colour, 0xRGB) and the CRC-32 of its 8-bit RGB bytes; exits 1 if no world was shown.
#include <cstdio>

#include <tripsitter/board/board.h>
#include <tripsitter/core/crc32.h>
#include <tripsitter/core/image.h>
#include <tripsitter/scene/builtin.h>

int main() {
  using namespace tripsitter;
  board::Board board(*scene::builtin("demo"), board::BoardConfig{});
  const board::ShownFrame frame = board.show();
  const core::Image444& image = frame.image;
  const core::Rgb444 centre = image.at(image.width / 2, image.height / 2);
  std::printf("demo %dx%d: centre pixel 0x%03x, crc32 %08x\n", image.width, image.height,
              static_cast<unsigned>(centre.packed), static_cast<unsigned>(core::crc32(core::to_rgb8(image).pixels)));
  return frame.device.has_world ? 0 : 1;
}
