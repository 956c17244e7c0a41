// The artix preset's line (docs/device.md, "The artix preset"): the world as its sphere units read it, the camera
// rays' cull by screen-space tiles, and the units' cycle schedule of a line.
//
// Cull. As a world is written to scene memory each sphere gets the columns and rows whose planes through the
// camera meet it (core::screen_bounds, exact in integers) for a radius grown by r / 1024 + 4 raw units and then
// by one column and one row on each side: more than the units' rounding can add to a sphere (a direction within
// 2^-15 radians of the exact ray, the radius within 2^-14 of r), so a culled pair is a miss and the cull changes
// no colour. A sphere wholly behind the camera plane, with that radius, is culled everywhere. While a line is
// shown the cull engine lists, for each tile of the next line, the spheres whose rows hold it and whose columns
// meet the tile, in the order sent.
//
// Schedule. See DeviceUnits (preset.h). A pass of a ray testing n spheres keeps its unit's issue port for
// max(n, min_pass) cycles; its closest hit is known hit_latency cycles after its last pair; a reflected ray
// joins the unit's queue reflect_latency cycles after that (unit_finish_cycles: a shared bounce stage may delay
// the hit's entry), and a pixel's colour is in the line buffer
// shade_latency cycles after its last pass's hit is known. When its port is free the unit takes the oldest
// waiting reflected ray that is known, else its next camera ray, else it waits for the oldest reflected ray.
// A pixel whose colour is not in the line buffer by the lead time (3200 cycles) is black, as on the board.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/screen.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_batch.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/ball_tree.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/controller.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>

namespace tripsitter::device::artix {

// The fast model's search for rays that are not the camera's (ball_tree.h), each sphere counted with the units'
// reach r + 2^(max(e, 0) + 1) + 1: a sphere the units hit has its centre within that reach of the ray's line (the
// units' f = oc - b d is at least the distance to the line, and F's floors and r^2's rounding add less than
// 2^(max(e, 0) + 1)), and in front of the origin.
BallTree build_balls(std::span<const UnitSphere> spheres);

// A node of the world's hierarchy as the walker reads it (scene_memory.h's HierarchyNode): its bound prepared as a
// sphere the units test (the root's is never tested).
struct UnitNode {
  UnitSphere bound;
  int first_child = 0;
  int children = 0;
  int first_sphere = 0;
  int spheres = 0;
};

// The world as the units read it: each sphere with its per-world constants and its cull bounds, the hierarchy the
// world carries (empty if none), and what the fast model adds (empty until it builds them: the plain model does
// without): the balls, for bounced rays in a world without a hierarchy, and the spheres and the hierarchy's bounds
// as blocks for the filter (artix_batch.h), which the walk then uses.
struct UnitWorld {
  std::vector<UnitSphere> spheres;
  std::vector<core::ScreenBounds> bounds;  // inclusive; empty (lo > hi) when culled everywhere
  std::vector<UnitNode> nodes;
  BallTree balls;
  SphereBlock sphere_block;  // spheres[i] is entry i
  SphereBlock bound_block;   // nodes[i].bound is entry i
};
// The fast model's additions for `world` (balls or blocks, as above).
void add_fast_search(UnitWorld& world);

// closest_hit(ray, spheres, excluded), the same hit, found through the balls.
Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, const BallTree& balls, int excluded);
// REQUIRES scene memory in formats the preset validated (coordinates of at most 22 bits, radii of at most 21;
// the hierarchy's bounds too, as the receiver checks them).
UnitWorld prepare_world(const SceneMemory& scene);

// The closest hit of a ray that is not the camera's over every sphere but `excluded`, found by walking the
// world's hierarchy (REQUIRES world.nodes not empty) level by level, as the units do: the first pass tests the
// root's spheres and the bounds of its children, each later pass the spheres and the children's bounds of the
// nodes whose bound the previous pass entered (a bound is entered when the ray meets it ahead of its origin: the
// far root b + s 2^e above 0). The closest sphere hit wins, ties to the one sent first (closest_hit's rule), so a
// hierarchy whose bounds hold what the units hit gives closest_hit's answer. Appends the pairs each pass issued
// (every pass has at least one) to `passes`. With the world's blocks (add_fast_search) it filters each node's
// spheres and bounds before the units' arithmetic: the same answer.
Hit walk_closest_hit(const UnitRay& ray, const UnitWorld& world, int excluded, std::vector<int>& passes);

// The cull bounds of one sphere (the header's rule).
core::ScreenBounds cull_bounds(const UnitSphere& s);

// One row's tile lists: the spheres of tile t are spheres[start[t] .. start[t + 1]), ascending.
struct RowTiles {
  std::vector<int> start;
  std::vector<int> spheres;
  std::span<const int> list(int tile) const {
    const auto t = static_cast<std::size_t>(tile);
    return std::span<const int>(spheres).subspan(static_cast<std::size_t>(start[t]),
                                                 static_cast<std::size_t>(start[t + 1] - start[t]));
  }
};
RowTiles row_tiles(const UnitWorld& world, int row, int tile_columns);

// closest_hit(ray, spheres, list, excluded) through the filter (artix_batch.h): block entries first ..
// first + list.size() - 1 are the list's spheres in its order (the fast model's tile lists).
Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, std::span<const int> list,
                const SphereBlock& block, int first, int excluded);

// A line's work as chains of passes: a chain is a camera ray and the passes that follow it one after another (the
// mirror model's reflections; a path's bounces, each a walk of the hierarchy's levels), each pass waiting for the
// previous one's hit. Column c's chains are start[c] .. start[c + 1] - 1 (one a column in the mirror model, one a
// sample in the path tracer's, none for a pixel that traces nothing); chain k's passes are passes[chain_start[k]
// .. chain_start[k + 1]), at least one, the first the camera ray's.
struct LineChains {
  struct Pass {
    int tests = 0;       // the slots it issues (each a pair, but the sphere the ray leaves: its slot is spent)
    int lead = 0;        // cycles it holds the port before its first slot (a walk's later level: walk_lead)
    bool bounce = false; // its hit enters the bounce stage: a reflection, a path's bounce or its escape to the sky
                         // (the last level of a walk, unless the path is cut there); the next pass of its chain, or
                         // the chain's end, follows the stage (otherwise: the hit, as a walk's next level does)
  };
  std::vector<int> start;        // kLineWidth + 1 entries
  std::vector<int> chain_start;  // one entry a chain and one more
  std::vector<Pass> passes;
};

// The units' schedule of a line's chains: when each column's colour reaches the line buffer, in cycles from the
// start of the line's work. A pass keeps its unit's issue port lead + max(tests, min_pass) cycles and its hit is known
// hit_latency after. A bounce pass's hit then enters the bounce stage: the cycle it is known, or with
// shared_bounce the unit's first own cycle from then on that no earlier hit of the unit took; the next pass of its
// chain joins the unit's queue reflect_latency cycles after it enters (the next pass of another, a walk's next
// level: walk_wait cycles after the hit is known). A unit takes the queued pass known first (ties in the order
// queued) when one is known, else its next chain (its columns in order, a column's chains in order) if it holds
// fewer than `paths` chains (a chain is held from its first pass's start to its end; 0: no limit), else it waits
// for the queue or for a chain to end. A column's colour is there shade_latency after the end of its last chain to
// end: its last hit known, or the stage's output for a bounce pass (a column with no chains: shade_latency after the
// unit reaches it); a chain ends then (after the stage) or the cycle after its last hit (a cut). With pixel_port
// the ends go through the unit's pixel port (serve_pixel_port) and the column is final shade_latency after its
// last one there; a column with no chains is final from the start (0).
std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, const LineChains& work);

// A sample's end at its unit's pixel port (DeviceUnits::pixel_port): the cycle and its column.
struct PortEnd {
  std::int64_t cycle;
  int col;
};
// A unit's pixel port, a sample a cycle: `lit` (the bounce stage's ends, in order, at most one a cycle) go through
// in their cycle; each of `cut` (in the order cut) in the first cycle from its own that no light and no earlier
// cut took, written back into its `cycle`. ts_path_pixels is its RTL.
void serve_pixel_port(std::span<PortEnd> lit, std::span<PortEnd> cut);
// The mirror model's line: column c one chain of 1 + pixels[c].bounces passes.
std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, std::int64_t spheres,
                                             std::span<const core::PixelTrace> pixels,
                                             std::span<const int> camera_tests);
// The same schedule applied: fills `line` with the pixels on time and black for the late ones. The demand is
// exact (every pixel is traced).
LineResult schedule_units(const DevicePreset& preset, std::int64_t spheres, std::span<const core::PixelTrace> pixels,
                          std::span<const int> camera_tests, std::span<core::Rgb444> line);

// Row `row` of the world's frame: every pixel traced (artix_kernel.h), then scheduled. The plain model
// (`search` kAll) tests every sphere on every pass, the fast model (kTiles) only the camera ray's tile list on the
// first: the same colours, as the cull is conservative, and the same schedule, which counts the tile lists either
// way.
enum class Search { kAll, kTiles };
LineResult render_line(const DevicePreset& preset, const UnitWorld& world, int row, std::span<core::Rgb444> line,
                       Search search);

// Row `row` of a path frame as the units' work (the artix path preset): each pixel's entry and samples (path_pixel
// with artix_path.h's sample, the camera ray's search narrowed to its tile with kTiles) into `pixels`, the line's
// chains (one a sample) into `work`, and each ray with its closest hit, in the order traced, to `observe` when
// given (the RTL's tests follow each path with it). Adds what the units traced to `counters`.
using RayObserver = std::function<void(int col, const PathUnitRay& ray, const PathUnitHit& hit)>;
void path_line_chains(const DevicePreset& preset, const UnitWorld& world, int row, const PathFrame& frame,
                      std::span<const AccumEntry> memory, std::span<PathPixel> pixels, PathCounters& counters,
                      Search search, LineChains& work, const RayObserver* observe);

// Row `row` of a path frame on the units (the artix path preset): each pixel's entry and samples (path_pixel with
// artix_path.h's sample, the camera ray's search narrowed to its tile with kTiles), the line's chains (one a
// sample) scheduled. A bounced ray walks the world's hierarchy (walk_closest_hit: a pass a level) or, in a world
// without one, tests every sphere in one pass; kTiles finds the latter's hit through world.balls, which must then
// be built (build_balls). A pixel on time shows its colour and writes its entry, a late one is black and keeps its
// entry. Adds what the units traced to `counters` (every pixel, late or not).
LineResult render_path_line(const DevicePreset& preset, const UnitWorld& world, int row, const PathFrame& frame,
                            std::span<AccumEntry> memory, std::span<core::Rgb444> line, PathCounters& counters,
                            Search search);

}  // namespace tripsitter::device::artix
