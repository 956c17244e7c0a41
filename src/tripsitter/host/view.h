// The host's view transform as a pure function: the world's spheres and the camera in, the same spheres in the
// device's view space out, in floating point. Host::update quantises and encodes what this gives; the float
// renderers take it as it is and never encode.
//
// View space is the device's (SPEC.md section B): camera at the origin, x right, y down, z ahead, in pixel units;
// view_from_world = scale(units_per_world) * camera_from_world, one matrix for all centres.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <tripsitter/core/mat4.h>
#include <tripsitter/host/camera.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::host {

// Pixel units per world unit: the scene's units_per_world, or by default 320 / |lookat - lookfrom|, which puts
// the look-at point on the device's image plane.
double units_per_world(const scene::Scene& scene);

core::Mat4 view_from_world(const Camera& camera, double units_per_world);

// The spheres in view space, in the same order; materials unchanged, radii scaled.
std::vector<scene::Sphere> view_spheres(std::span<const scene::Sphere> world, const Camera& camera,
                                        double units_per_world);

// How many of a world's `count` spheres one world on `wire` carries: all of them on v1 (a stream of words), at
// most the device's scene memory (formats.max_spheres) on v2; the rest are never sent.
std::size_t spheres_carried(std::size_t count, const link::SceneFormats& formats, link::WireVersion wire);

}  // namespace tripsitter::host
