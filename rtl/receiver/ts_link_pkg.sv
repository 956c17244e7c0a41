// ts_link_pkg: the link's wire facts that the receiver's blocks share, in one place. The C++ states the same facts in
// src/tripsitter/link/frame.h and frame.cpp (the framed wires' sizes, magics, header layouts and sphere record),
// sequence.h (the ring of ended sessions) and wire_v1.h/.cpp (the v1 word's fields); link_pkg_test.cpp reads this
// file and holds each value to the C++'s, so a value changed on one side only fails the tests. The formats are
// explained in docs/link_format.md.
//
// Yosys 0.23 cannot parse `import ts_link_pkg::*;`: the blocks write ts_link_pkg::Name, and every source list reads
// this file before them. Each block uses some of the values: the package is waived from the unused-parameter warning.
/* verilator lint_off UNUSEDPARAM */
package ts_link_pkg;
  // ---- The framed wires (frame.h): v2 and v3 differ only in their headers ------------------------------------------
  localparam int V2Magic = 32'h5453_5732;      // "TSW2", first byte in the top bits
  localparam int V3Magic = 32'h5453_5733;      // "TSW3"
  localparam int V2Version = 2;
  localparam int V3Version = 3;
  localparam int V2HeaderBytes = 20;
  localparam int V3HeaderBytes = 28;
  localparam int SphereBytes = 24;
  localparam int FrameTrailerBytes = 4;        // CRC-32 of header and payload
  localparam int MaxFracBits = 30;

  // ---- Where a header keeps its fields (frame.cpp, Layout): both begin with magic, version, frac_bits, reserved ----
  localparam int VersionAt = 4;
  localparam int FracBitsAt = 5;
  localparam int ReservedAt = 6;
  localparam int ReservedEnd = 8;
  localparam int V2SequenceAt = 8;
  localparam int V2CountAt = 12;
  localparam int V2LengthAt = 16;
  localparam int V3SessionAt = 8;
  localparam int V3SequenceAt = 12;
  localparam int V3CountAt = 16;
  localparam int V3LengthAt = 20;
  localparam int V3HeaderCrcAt = 24;           // the CRC-32 of the 24 header bytes before it

  // ---- One sphere record (frame.cpp): big-endian fields at these offsets ------------------------------------------
  localparam int SphereXAt = 0;
  localparam int SphereYAt = 4;
  localparam int SphereZAt = 8;
  localparam int SphereRadiusAt = 12;
  localparam int SphereMaterialAt = 16;
  localparam int SphereAlbedoAt = 17;
  localparam int SphereFuzzAt = 20;
  localparam int SphereIorAt = 22;
  localparam int MaterialLambertian = 0;
  localparam int MaterialMetal = 1;
  localparam int MaterialDielectric = 2;

  // ---- v3's hierarchy (frame.h, docs/link_format.md "The hierarchy"): the header's content byte, a node record ---
  localparam int ContentAt = 6;                // the first reserved byte: 0 spheres only, 1 a hierarchy follows
  localparam int ContentHierarchy = 1;
  localparam int NodeBytes = 24;
  localparam int NodeXAt = 0;
  localparam int NodeYAt = 4;
  localparam int NodeZAt = 8;
  localparam int NodeRadiusAt = 12;
  localparam int NodeFirstChildAt = 16;        // 16 bits
  localparam int NodeChildrenAt = 18;          // 8 bits
  localparam int NodeSphereCountAt = 19;       // 8 bits
  localparam int NodeFirstSphereAt = 20;       // 32 bits
  localparam int MaxHierarchyDepth = 8;        // levels below the root

  // ---- The sequence rules (sequence.h, SequenceRules) -----------------------------------------------------------
  localparam int RetiredSessions = 16;         // ended sessions remembered, so that their frames are refused

  // ---- The v1 word (wire_v1.h/.cpp): each field `W` bits whose least significant bit sits at `Shift` -------------
  localparam int V1WordBytes = 8;
  localparam int V1Frac = 3;                   // x, y, z carry 3 fractional bits
  localparam int V1XShift = 48;
  localparam int V1XW = 16;
  localparam int V1YShift = 33;
  localparam int V1YW = 15;
  localparam int V1ZShift = 18;
  localparam int V1ZW = 15;
  localparam int V1RShift = 12;                // the radius is 2^r pixel units
  localparam int V1RW = 6;
  localparam int V1ColourShift = 0;            // RGB444
  localparam int V1ColourW = 12;
endpackage
/* verilator lint_on UNUSEDPARAM */
