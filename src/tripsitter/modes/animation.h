// An animation: the camera circles its target while a source draws frame after frame.
#pragma once

#include <functional>

#include <tripsitter/modes/frame_source.h>

namespace tripsitter::modes {

// Frames 0 .. frames-1, the camera orbiting by orbit_deg over the whole animation (frame i at i * orbit_deg /
// frames, so 360 loops), each handed to on_frame(i, frame) in order. A frame for which draws(i) is false is not
// drawn (frame is null) but the camera moves through it all the same, so a frame's view never depends on which
// frames were drawn (MPI ranks each draw a share). Empty draws: every frame is drawn.
void animate(FrameSource& source, int frames, double orbit_deg, const std::function<bool(int)>& draws,
             const std::function<void(int, const Frame* frame)>& on_frame);

}  // namespace tripsitter::modes
