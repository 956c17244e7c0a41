// Rays of the float renderers.
#pragma once

#include <tripsitter/core/vec.h>

namespace tripsitter::render {

using core::Vec3f;

struct Ray {
  Vec3f origin;
  Vec3f dir;  // need not be unit length
  Vec3f at(float t) const { return origin + dir * t; }
};

}  // namespace tripsitter::render
