// ts_artix_pkg: the facts of the artix preset that every block of its RTL shares, in one place. The C++ model
// states the same facts in src/tripsitter/device/preset.cpp (artix_preset(), DeviceUnits in preset.h) and
// src/tripsitter/device/artix_kernel.h; artix_pkg_test.cpp reads this file and holds each value to the model's,
// so a value changed on one side only fails the build's tests. docs/device.md, "The artix preset", explains the
// arithmetic; docs/rtl.md the blocks.
// Each block uses some of the values: the package as a whole is waived from Verilator's unused-parameter warning.
/* verilator lint_off UNUSEDPARAM */
package ts_artix_pkg;
  // ---- Scene memory: the formats of x, y, z (signed) and the radius (unsigned), and the capacity ----------------
  localparam int Frac = 4;
  localparam int CoordW = 22;
  localparam int RadiusW = 21;
  localparam int MaxSpheres = 256;
  localparam int SphereAW = 8;         // a sphere's index: 0 .. MaxSpheres - 1

  // ---- The units and the line (DeviceUnits, lead_cycles, max_bounces) -----------------------------------------
  localparam int Units = 9;            // sphere units of the preset (the top's N may differ)
  localparam int MaxBounces = 3;
  localparam int LeadCycles = 3200;    // a line's work: the whole line before it is shown
  localparam int LineWidth = 640;
  localparam int TileColumns = 32;     // camera rays are culled per tile of this many columns
  localparam int Tiles = LineWidth / TileColumns;
  localparam int MinPass = 3;          // cycles a pass holds its unit's issue port at least
  localparam int HitLatency = 40;      // from the cycle after a pass's last pair to its closest hit known
  localparam int SceneReadCycles = 2;  // from a pair's issue to its sphere's fields at the unit (of HitLatency)
  localparam int ReflectLatency = 20;  // from a hit known to the reflected ray in its unit's queue
  localparam int ShadeLatency = 12;    // from the last hit known to the colour in the line buffer
  localparam int WalkLead = 1;         // artix-path: cycles a walk's later level holds the port before its first slot
  localparam int WalkWait = 1;         // artix-path: from a walk level's hits known to its next level in the queue
  localparam int Paths = 32;           // artix-path: paths a unit holds at once
  localparam int BounceLatency = 51;   // artix-path: from a hit at its unit's stage port to the next ray in its queue
  localparam int PixelLatency = 2;     // artix-path: from a sample's end at its unit's pixel port to its entry final

  // ---- The arithmetic (artix_kernel.h) ------------------------------------------------------------------------
  localparam int DirFrac = 17;         // unit directions and normals: times 2^17
  localparam int DirW = 18;            // ... saturated to 18 bits signed: |d_k| <= 2^17 - 1
  localparam int ScaledRadiusBits = 17;  // r / 2^e in [2^16, 2^17): e = bitlen(r) - 17, in -16..4
  localparam int SeedFirst = 200;      // the camera's reciprocal square root: seed i - SeedFirst for n >> 9 = i
  localparam int SeedLast = 512;
  localparam int SeedEntries = SeedLast - SeedFirst + 1;

  // ---- Register widths, signed unless said (docs/device.md, "The artix preset": the model's checks) ----------
  localparam int OriginW = 24;         // a ray's origin: 0 or a hit point, |o_k| < 2^23
  localparam int OcW = 25;             // oc = c - o, |oc_k| < 2^24: the pre-adder's output
  localparam int BdW = 44;             // b d = d.oc, times 2^17: |bd| < |oc| 2^17 < 2^42.8
  localparam int BW = 25;              // b = bd / 2^17 rounded, |b| < 2^24: the multiplier's A operand
  localparam int FW = 48;              // f = (oc << 17) - b d, |f_k| < 2^47: the post-adder's P
  localparam int ExpW = 6;             // e, -16..4
  localparam int R2sW = 34;            // r^2 / 4^e rounded, unsigned, below 2^34
  localparam int RinvW = 19;           // 2^(34 + e) / r rounded, unsigned, in (2^17, 2^18]
  localparam int DiscW = 37;           // r2s - F.F: above -3 2^34, below 2^34
  localparam int SqrtW = 17;           // floor(sqrt(disc)), unsigned, below 2^17
  localparam int TdW = 45;             // t d = bd - (s << (17 + e)), times 2^17
  localparam int HitFW = 39;           // a hit's f_k, signed: at a hit |f| <= r 2^17 < 2^38
endpackage
/* verilator lint_on UNUSEDPARAM */
