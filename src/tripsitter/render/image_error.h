// How far a picture is from a reference, in linear light: the figures `tripsitter bench` reports for the
// window's path mode (path_relmse_field_*) and that the tests of the sampler and the denoiser assert on.
#pragma once

#include <span>

#include <tripsitter/core/vec.h>

namespace tripsitter::render {

struct ImageError {
  // Relative mean squared error: the mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01).
  double relmse = 0;
  // Mean relative bias: the mean over pixels and channels of (x - ref) / (ref + 0.01). Noise averages out of
  // it; a picture darker or brighter than the reference does not.
  double bias = 0;
  // relMSE of the means of 8x8 blocks (partial blocks at the right and bottom edges as they are): most of the
  // noise averages out within a block, what is wrong over a region stays (blurred contact shadows, lost
  // reflections, light smeared across an edge).
  double block_relmse = 0;
};

// REQUIRES image and reference of width x height pixels, row-major.
ImageError image_error(std::span<const core::Vec3f> image, std::span<const core::Vec3f> reference, int width,
                       int height);

}  // namespace tripsitter::render
