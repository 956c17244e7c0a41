// A slot of the path preset's sphere unit (ts_artix_sphere_unit.sv with PATH = 1) as its tests drive it: a sphere's
// pair, the far pair of the sphere the ray is in, a hierarchy's bound, or nothing (path_sphere_unit_rtl_test,
// path_walk_rtl_test).
#pragma once

#include <string>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_sphere_unit_path.h>

#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::rtl::sphere_unit {

struct Slot {
  enum Kind { kNone, kPair, kFar, kBound } kind = kNone;
  int index = 0;  // the sphere, or the bound's node
  bool operator==(const Slot&) const = default;
};

inline std::string describe(const Slot& s) {
  const char* kinds[] = {"none", "pair", "far", "bound"};
  return std::string(kinds[s.kind]) + " " + std::to_string(s.index);
}

// The unit's ports for `slot` of a pass of `ray`, first and/or end of it, with `fields` the sphere's or the bound's
// (the index rides in the carry too).
inline void drive(Vts_artix_sphere_unit_path& unit, const Slot& slot, bool first, bool end, const artix::UnitRay& ray,
                  const artix::UnitSphere& fields) {
  unit.in_first = first;
  unit.in_end = end;
  unit.in_pair = slot.kind == Slot::kPair || slot.kind == Slot::kFar;
  unit.in_far = slot.kind == Slot::kFar;
  unit.in_bound = slot.kind == Slot::kBound;
  unit.in_index = static_cast<CData>(slot.index);
  put(unit.in_o, pack3(ray.o, kOriginW));
  put(unit.in_d, pack3(ray.d, kDirW));
  put(unit.in_c, pack3(fields.c, kCoordW));
  put(unit.in_e, static_cast<UInt128>(fields.e) & 0x3f);
  put(unit.in_r2s, static_cast<UInt128>(fields.r2s));
  put(unit.in_carry, static_cast<UInt128>(slot.index));
}

}  // namespace tripsitter::rtl::sphere_unit
