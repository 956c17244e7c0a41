#include <tripsitter/modes/animation.h>

namespace tripsitter::modes {

void animate(FrameSource& source, int frames, double orbit_deg, const std::function<bool(int)>& draws,
             const std::function<void(int, const Frame* frame)>& on_frame) {
  for (int i = 0; i < frames; ++i) {
    if (i > 0) source.steer().orbit(orbit_deg / frames);
    on_frame(i, !draws || draws(i) ? &source.draw() : nullptr);
  }
}

}  // namespace tripsitter::modes
