// ts_artix_cull: one sphere's cull bounds, the columns and rows whose planes through the camera meet it. C++
// model: artix::cull_bounds (src/tripsitter/device/artix_units.cpp) with core::screen_bounds (core/screen.h), bit
// for bit; docs/device.md, "The artix preset", says why the bounds are safe. It uses only the centre c and the
// radius r of a sphere:
//     grown = r + (r >> 10) + 4;  culled everywhere when c_z + grown <= 0;
//     else the hull of the columns (f = 320, offset o = col - 320) and of the rows (o = row - 240) whose plane meets
//     the sphere of radius grown, (f c - o c_z)^2 <= grown^2 (f^2 + o^2), with c = c_x or c_y; culled when no
//     column meets; then one column and one row more on each side, clamped to the screen.
// One of these serves the device, fed sphere by sphere as a world enters.
//
// The method: the plane test is the sign of a quadratic in the offset,
//     G(o) = grown^2 (f^2 + o^2) - (f c - o c_z)^2 = A o^2 + B o + C >= 0,
//     A = grown^2 - c_z^2,  B = 2 f c c_z,  C = f^2 (grown^2 - c^2),
// and a pencil's planes are tested in order by forward differences, exactly, with adders only: G(o + 1) = G(o) + D,
// D(o + 1) = D(o) + 2A, D(0) = A + B; the same going down with B negated (G(-o) is the quadratic A o^2 - B o + C).
// Four such engines, from the middle outwards: columns up (o = 0..319) and down (0..-320), rows up (0..239) and down
// (0..-240), each a pencil's half, so every column and row is tested, once or (o = 0) twice, whatever shape the set
// of meeting planes has (an interval, or two pieces when it wraps through z = 0: the hull is from the first to the
// last). The lowest meeting column is the last one the down engine meets, else the first the up engine meets, and
// so on.
//
// The setup, A, A + B, A - B and C per pencil, is 24 multiply-accumulate steps on one 25 x 18 signed multiplier
// (one DSP48E1), each adding (x y) 2^s, s in {0, 7, 17, 24}, to an accumulator or starting it. x = xa + xb, xa one of
// grown, -grown, 4 c_x, 4 c_y and xb one of c_x, c_y, c_z; y is 25 or a 17-bit piece of a value (the low piece
// zero-extended, or the high one, signed, weighing 2^17), negated when the step says (|y| < 2^17, so it fits). A
// product (grown - c) y is taken as -((c - grown) y), so that x is only ever a sum.
//     W = 25 (grown + c)                         (one step per pencil, for C: f^2 = 25 2^12)
//     A = (grown - c_z)(grown + c_z)             (two steps)
//     C = ((grown - c) W) 2^12                   (two steps per pencil; the shift is wiring)
//     A +- B = A +- (5 c)(c_z) 2^7               (four steps each; f = 320 = 5 2^6)
// The sums are taken modulo 2^AccW (two's complement sums are exact modulo their width), so only the results need to
// fit. Each result is loaded where it goes by adding it to a register cleared before the setup: the adder that steps
// an engine also loads it. C goes into both D registers of its pencil, and the cycle after into G (G += D) while D
// is cleared again for A + B or A - B, so G's adder never chooses its addend.
//
// Timing: a sphere taken with start in cycle t (while ready) gives its bounds and a one-cycle done in cycle
// t + Latency (352: the start cycle, 1 for grown, 27 of setup, 321 of scan, 2 for the hull and the margin); ready is
// low from t + 1 to t + Latency - 1, so one sphere every 352 cycles. The bounds hold until the next done. The world
// arrives at 64 clocks a byte or slower in 24-byte records, so a sphere's record takes at least 1,536 cycles, and
// the last sphere's geometry is known about 512 cycles before the frame may be accepted: 352 fits both.
//
// Ports: c_k signed, CoordW bits (|c_k| <= 2^21), r unsigned, RadiusW bits, 1 .. 2^21 - 1. Out: `empty` when the
// sphere is culled everywhere (then the bounds are 0), else col_lo <= col_hi in 0..639 and row_lo <= row_hi in
// 0..479, inclusive.
//
// Widths (|c_k| <= 2^21, grown <= 2^21 + 2050 < 2^21.0015):
//   grown          22 bits unsigned
//   grown + c      24 bits signed: in [4 - 2^21, 2^22 + 2050]; c - grown is in [-2^22 - 2050, 2^21 - 5]
//   x              25 bits signed (the multiplier's A): grown + c, c - grown, or 5 c, |5 c| <= 5 2^21 < 2^23.33
//   y              18 bits signed (the multiplier's B): a low piece < 2^17, or a high piece of grown + c_z (7
//                  bits), c_z (5) or W (11), or 25; or its negation
//   W              28 bits signed: |W| < 25 2^22.001 < 2^26.65
//   acc            53 bits signed: |A +- B| < 2^42.01 + 640 2^42 < 2^51.34, |(grown - c) W| < 25 2^42.01 < 2^46.7
//   A              44 bits signed: -2^42 <= A < 2^42.01
//   G              62 bits signed: grown^2 (f^2 + o^2) <= 2^42.01 204800 < 2^59.65, (f c - o c_z)^2 <= (640 2^21)^2
//                  = 2^60.65, for |o| <= 320
//   D              60 bits signed: C while the setup runs, |C| < 102400 2^42.01 < 2^58.65; in the scan
//                  |A (2 o + 1)| + |B| <= 641 2^42.01 + 640 2^42 < 2^52.34
// An engine's registers after its last test are never read, so what they overflow to does not matter.
//
// The package's facts are named ts_artix_pkg::X, not imported: Yosys 0.23 cannot parse `import`.
module ts_artix_cull (
    input  logic                                   clk,
    input  logic                                   rst,
    input  logic                                   start,   // take the sphere at the ports; only while ready
    output logic                                   ready,
    input  logic signed [ts_artix_pkg::CoordW-1:0] cx,
    input  logic signed [ts_artix_pkg::CoordW-1:0] cy,
    input  logic signed [ts_artix_pkg::CoordW-1:0] cz,
    input  logic [ts_artix_pkg::RadiusW-1:0]       r,
    output logic                                   done,    // one cycle: the bounds below are the sphere's
    output logic                                   empty,
    output logic [9:0]                             col_lo,
    output logic [9:0]                             col_hi,
    output logic [8:0]                             row_lo,
    output logic [8:0]                             row_hi
);
  localparam int CoordW = ts_artix_pkg::CoordW;
  localparam int RadiusW = ts_artix_pkg::RadiusW;
  localparam int GrownW = RadiusW + 1;
  localparam int SumW = CoordW + 2;
  localparam int XW = 25;
  localparam int YW = 18;
  localparam int PieceW = YW - 1;
  localparam int MW = XW + YW;
  localparam int WW = 28;
  localparam int AccW = 53;
  localparam int AW = 44;
  localparam int GW = 62;
  localparam int DW = 60;
  localparam int Steps = 24;
  localparam int SetupCycles = Steps + 3;        // the last step's result is loaded 3 cycles after its issue
  localparam int LastK = 320;                    // the scan: k = 0..320, the offsets +-k
  localparam int ColCentre = 320;
  localparam int RowCentre = 240;
  localparam int LastCol = 639;
  localparam int LastRow = 479;

  // ---- the setup's program -------------------------------------------------------------------------------------
  // x = xa + xb
  localparam logic [1:0] XaGrown = 2'd0, XaMinusGrown = 2'd1, XaFourCx = 2'd2, XaFourCy = 2'd3;
  localparam logic [1:0] XbCx = 2'd0, XbCy = 2'd1, XbCz = 2'd2;
  // y: 25, or a piece of grown + c_z, c_z, W_x or W_y
  localparam logic [2:0] Y25 = 3'd0, YVz = 3'd1, YCz = 3'd2, YWx = 3'd3, YWy = 3'd4;
  localparam logic Lo = 1'b0, Hi = 1'b1;
  localparam logic [1:0] Sh0 = 2'd0, Sh7 = 2'd1, Sh17 = 2'd2, Sh24 = 2'd3;
  localparam logic Pos = 1'b0, Neg = 1'b1;
  localparam logic More = 1'b0, First = 1'b1;   // First: the term starts a new sum
  // where a finished sum goes (given on its last term)
  localparam logic [3:0] ToNone = 4'd0, ToWx = 4'd1, ToWy = 4'd2, ToA = 4'd3, ToColUp = 4'd4, ToColDown = 4'd5,
                         ToRowUp = 4'd6, ToRowDown = 4'd7, ToColC = 4'd8, ToRowC = 4'd9;
  localparam int CtlW = 2 + 2 + 3 + 1 + 2 + 1 + 1 + 4;

  // The step's fields; nothing outside the setup's first Steps cycles. A product (grown - c) y is taken as
  // -((c - grown) y), so that the pre-adder only adds; the sign goes to y.
  function automatic logic [CtlW-1:0] program_step(input logic [4:0] s);
    unique case (s)
      //                     xa            xb    y     piece shift  sign first  to
      5'd0:  program_step = {XaGrown,      XbCx, Y25,  Lo,   Sh0,   Pos, First, ToWx};
      5'd1:  program_step = {XaGrown,      XbCy, Y25,  Lo,   Sh0,   Pos, First, ToWy};
      5'd2:  program_step = {XaMinusGrown, XbCz, YVz,  Lo,   Sh0,   Neg, First, ToNone};
      5'd3:  program_step = {XaMinusGrown, XbCz, YVz,  Hi,   Sh17,  Neg, More,  ToA};
      5'd4:  program_step = {XaMinusGrown, XbCx, YWx,  Lo,   Sh0,   Neg, First, ToNone};
      5'd5:  program_step = {XaMinusGrown, XbCx, YWx,  Hi,   Sh17,  Neg, More,  ToColC};
      5'd6:  program_step = {XaMinusGrown, XbCy, YWy,  Lo,   Sh0,   Neg, First, ToNone};
      5'd7:  program_step = {XaMinusGrown, XbCy, YWy,  Hi,   Sh17,  Neg, More,  ToRowC};
      5'd8:  program_step = {XaMinusGrown, XbCz, YVz,  Lo,   Sh0,   Neg, First, ToNone};
      5'd9:  program_step = {XaMinusGrown, XbCz, YVz,  Hi,   Sh17,  Neg, More,  ToNone};
      5'd10: program_step = {XaFourCx,     XbCx, YCz,  Lo,   Sh7,   Pos, More,  ToNone};
      5'd11: program_step = {XaFourCx,     XbCx, YCz,  Hi,   Sh24,  Pos, More,  ToColUp};
      5'd12: program_step = {XaMinusGrown, XbCz, YVz,  Lo,   Sh0,   Neg, First, ToNone};
      5'd13: program_step = {XaMinusGrown, XbCz, YVz,  Hi,   Sh17,  Neg, More,  ToNone};
      5'd14: program_step = {XaFourCx,     XbCx, YCz,  Lo,   Sh7,   Neg, More,  ToNone};
      5'd15: program_step = {XaFourCx,     XbCx, YCz,  Hi,   Sh24,  Neg, More,  ToColDown};
      5'd16: program_step = {XaMinusGrown, XbCz, YVz,  Lo,   Sh0,   Neg, First, ToNone};
      5'd17: program_step = {XaMinusGrown, XbCz, YVz,  Hi,   Sh17,  Neg, More,  ToNone};
      5'd18: program_step = {XaFourCy,     XbCy, YCz,  Lo,   Sh7,   Pos, More,  ToNone};
      5'd19: program_step = {XaFourCy,     XbCy, YCz,  Hi,   Sh24,  Pos, More,  ToRowUp};
      5'd20: program_step = {XaMinusGrown, XbCz, YVz,  Lo,   Sh0,   Neg, First, ToNone};
      5'd21: program_step = {XaMinusGrown, XbCz, YVz,  Hi,   Sh17,  Neg, More,  ToNone};
      5'd22: program_step = {XaFourCy,     XbCy, YCz,  Lo,   Sh7,   Neg, More,  ToNone};
      5'd23: program_step = {XaFourCy,     XbCy, YCz,  Hi,   Sh24,  Neg, More,  ToRowDown};
      default: program_step = {XaGrown,    XbCx, Y25,  Lo,   Sh0,   Pos, First, ToNone};
    endcase
  endfunction

  // ---- control: the only state with a reset --------------------------------------------------------------------
  typedef enum logic [2:0] {Idle, Grow, Setup, Scan, Hull, Out} phase_e;
  phase_e    phase_q;
  logic [8:0] count_q;  // the setup's step, then the scan's k
  logic [3:0] to1_q, to2_q, to3_q;
  logic       done_q;

  always_ff @(posedge clk) begin
    if (rst) begin
      phase_q <= Idle;
      done_q <= 1'b0;
    end else begin
      done_q <= 1'b0;
      unique case (phase_q)
        Idle:  if (start) phase_q <= Grow;
        Grow:  phase_q <= Setup;
        Setup: if (count_q == 9'(SetupCycles - 1)) phase_q <= Scan;
        Scan:  if (count_q == 9'(LastK)) phase_q <= Hull;
        Hull:  phase_q <= Out;
        Out: begin
          phase_q <= Idle;
          done_q <= 1'b1;
        end
        default: phase_q <= Idle;
      endcase
    end
  end

  always_ff @(posedge clk) begin
    if (phase_q == Grow || (phase_q == Setup && count_q == 9'(SetupCycles - 1))) count_q <= '0;
    else count_q <= count_q + 9'd1;
  end

  assign ready = phase_q == Idle;
  assign done = done_q;

  // ---- the sphere and grown ------------------------------------------------------------------------------------
  // grown and the sums taken from it follow the sphere's registers: right from the cycle after Grow (grown) and the
  // setup's second cycle (the others), before any step reads them, and steady while the sphere is worked on.
  logic signed [CoordW-1:0] cx_q, cy_q, cz_q;
  logic [RadiusW-1:0]       r_q;
  logic [GrownW-1:0]        grown_q;
  logic signed [SumW-1:0]   vz_q;  // grown + c_z
  logic signed [XW-1:0]     minus_grown_q;
  always_ff @(posedge clk) begin
    if (ready && start) begin
      cx_q <= cx;
      cy_q <= cy;
      cz_q <= cz;
      r_q <= r;
    end
    grown_q <= GrownW'(r_q) + GrownW'(r_q[RadiusW-1:10]) + GrownW'(4);
    vz_q <= SumW'($signed({1'b0, grown_q})) + SumW'(cz_q);
    minus_grown_q <= XW'(0) - XW'($signed({1'b0, grown_q}));
  end

  // ---- the setup: 24 steps on one multiplier -------------------------------------------------------------------
  logic [1:0] c_xa, c_xb, c_shift;
  logic       c_hi, c_neg, c_first;
  logic [2:0] c_y;
  logic [3:0] c_to;
  assign {c_xa, c_xb, c_y, c_hi, c_shift, c_neg, c_first, c_to} =
      program_step(phase_q == Setup && count_q < 9'(Steps) ? count_q[4:0] : 5'd31);

  logic signed [WW-1:0] wx_q, wy_q;
  logic signed [XW-1:0] xa, xb;
  logic signed [WW-1:0] y_source;
  always_comb begin
    unique case (c_xa)
      XaFourCx: xa = XW'(cx_q) <<< 2;
      XaFourCy: xa = XW'(cy_q) <<< 2;
      XaMinusGrown: xa = minus_grown_q;
      default:  xa = XW'($signed({1'b0, grown_q}));
    endcase
    unique case (c_xb)
      XbCy:    xb = XW'(cy_q);
      XbCz:    xb = XW'(cz_q);
      default: xb = XW'(cx_q);
    endcase
    unique case (c_y)
      YVz:     y_source = WW'(vz_q);
      YCz:     y_source = WW'(cz_q);
      YWx:     y_source = wx_q;
      YWy:     y_source = wy_q;
      default: y_source = WW'(25);
    endcase
    if (c_y == Y25) y = YW'(25);
    else if (c_hi) y = YW'(y_source >>> PieceW);
    else y = {1'b0, y_source[PieceW-1:0]};
  end

  // Stage 1: the multiplier's operands (x = xa + xb is the DSP48E1's pre-adder: Yosys packs it, with its register);
  // 2: the product; 3: the sum; 4: the sum loaded where it goes.
  logic signed [XW-1:0]  x1_q;
  logic signed [YW-1:0]  y, y1_q;
  logic [1:0]            shift1_q, shift2_q;
  logic                  first1_q, first2_q;
  logic signed [MW-1:0]  m2_q;
  logic signed [AccW-1:0] acc3_q;
  always_ff @(posedge clk) begin
    x1_q <= xa + xb;
    y1_q <= c_neg ? -y : y;  // |y| < 2^17: its negation fits
    shift1_q <= c_shift;
    first1_q <= c_first;

    m2_q <= x1_q * y1_q;
    shift2_q <= shift1_q;
    first2_q <= first1_q;
  end

  logic signed [AccW-1:0] term, base;
  always_comb begin
    unique case (shift2_q)
      Sh7:     term = AccW'(m2_q) <<< 7;
      Sh17:    term = AccW'(m2_q) <<< 17;
      Sh24:    term = AccW'(m2_q) <<< 24;
      default: term = AccW'(m2_q);
    endcase
    base = first2_q ? '0 : acc3_q;
  end
  always_ff @(posedge clk) acc3_q <= base + term;

  // The destination codes are control: reset, so that no stale code loads an engine during a scan.
  logic [3:0] to4_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      to1_q <= ToNone;
      to2_q <= ToNone;
      to3_q <= ToNone;
      to4_q <= ToNone;
    end else begin
      to1_q <= c_to;
      to2_q <= to1_q;
      to3_q <= to2_q;
      to4_q <= to3_q;
    end
  end

  // ---- the engines ---------------------------------------------------------------------------------------------
  // All cleared before the setup; every value is loaded by adding it to a zero, so that the adder that steps a
  // register also loads it and no multiplexer follows a carry chain. G's adder has no choice of addend at all: C
  // goes into the pencil's two D registers first, and the cycle after into G (G += D) while D is cleared for A + B
  // and A - B. The addend of the four D registers is one shared choice: 2A while scanning, else the setup's value.
  logic signed [AW-1:0] a_q;
  logic signed [GW-1:0] g_cu_q, g_cd_q, g_ru_q, g_rd_q;  // columns up, down; rows up, down
  logic signed [DW-1:0] d_cu_q, d_cd_q, d_ru_q, d_rd_q;
  wire scan = phase_q == Scan;
  wire load_c = to3_q == ToColC || to3_q == ToRowC;
  wire move_col = to4_q == ToColC;
  wire move_row = to4_q == ToRowC;
  wire signed [DW-1:0] setup_value = load_c ? DW'(acc3_q) <<< 12 : DW'(acc3_q);  // f^2 = 25 2^12: W holds the 25
  wire signed [DW-1:0] addend = scan ? DW'(a_q) <<< 1 : setup_value;
  always_ff @(posedge clk) begin
    if (to3_q == ToWx) wx_q <= WW'(acc3_q);
    if (to3_q == ToWy) wy_q <= WW'(acc3_q);
    if (to3_q == ToA) a_q <= AW'(acc3_q);
  end
  always_ff @(posedge clk) begin
    if (phase_q == Grow) begin
      g_cu_q <= '0;
      g_cd_q <= '0;
      g_ru_q <= '0;
      g_rd_q <= '0;
    end else begin
      if (scan || move_col) begin
        g_cu_q <= g_cu_q + GW'(d_cu_q);
        g_cd_q <= g_cd_q + GW'(d_cd_q);
      end
      if (scan || move_row) begin
        g_ru_q <= g_ru_q + GW'(d_ru_q);
        g_rd_q <= g_rd_q + GW'(d_rd_q);
      end
    end
  end
  always_ff @(posedge clk) begin
    if (phase_q == Grow || move_col) begin
      d_cu_q <= '0;
      d_cd_q <= '0;
    end else begin
      if (scan || to3_q == ToColC || to3_q == ToColUp) d_cu_q <= d_cu_q + addend;
      if (scan || to3_q == ToColC || to3_q == ToColDown) d_cd_q <= d_cd_q + addend;
    end
    if (phase_q == Grow || move_row) begin
      d_ru_q <= '0;
      d_rd_q <= '0;
    end else begin
      if (scan || to3_q == ToRowC || to3_q == ToRowUp) d_ru_q <= d_ru_q + addend;
      if (scan || to3_q == ToRowC || to3_q == ToRowDown) d_rd_q <= d_rd_q + addend;
    end
  end

  // ---- the tests: in scan cycle k each engine's G is its pencil's at offset +-k ------------------------------------
  // Per engine: whether a plane met, and the k of the first and of the last that did.
  logic       cu_met_q, cd_met_q, ru_met_q, rd_met_q;
  logic [8:0] cu_first_q, cu_last_q, cd_first_q, cd_last_q;
  logic [7:0] ru_first_q, ru_last_q, rd_first_q, rd_last_q;
  wire [8:0] k = count_q;
  wire cu_meets = !g_cu_q[GW-1] && k <= 9'(ColCentre - 1);
  wire cd_meets = !g_cd_q[GW-1];
  wire ru_meets = !g_ru_q[GW-1] && k <= 9'(RowCentre - 1);
  wire rd_meets = !g_rd_q[GW-1] && k <= 9'(RowCentre);
  always_ff @(posedge clk) begin
    if (!scan) begin
      cu_met_q <= 1'b0;
      cd_met_q <= 1'b0;
      ru_met_q <= 1'b0;
      rd_met_q <= 1'b0;
    end else begin
      if (cu_meets) begin
        if (!cu_met_q) cu_first_q <= k;
        cu_last_q <= k;
        cu_met_q <= 1'b1;
      end
      if (cd_meets) begin
        if (!cd_met_q) cd_first_q <= k;
        cd_last_q <= k;
        cd_met_q <= 1'b1;
      end
      if (ru_meets) begin
        if (!ru_met_q) ru_first_q <= k[7:0];
        ru_last_q <= k[7:0];
        ru_met_q <= 1'b1;
      end
      if (rd_meets) begin
        if (!rd_met_q) rd_first_q <= k[7:0];
        rd_last_q <= k[7:0];
        rd_met_q <= 1'b1;
      end
    end
  end

  // ---- the hull, then the margin -------------------------------------------------------------------------------
  logic [9:0] col_lo_q, col_hi_q;
  logic [8:0] row_lo_q, row_hi_q;
  logic       met_q;
  always_ff @(posedge clk) begin
    col_lo_q <= cd_met_q ? 10'(ColCentre) - 10'(cd_last_q) : 10'(ColCentre) + 10'(cu_first_q);
    col_hi_q <= cu_met_q ? 10'(ColCentre) + 10'(cu_last_q) : 10'(ColCentre) - 10'(cd_first_q);
    row_lo_q <= rd_met_q ? 9'(RowCentre) - 9'(rd_last_q) : 9'(RowCentre) + 9'(ru_first_q);
    row_hi_q <= ru_met_q ? 9'(RowCentre) + 9'(ru_last_q) : 9'(RowCentre) - 9'(rd_first_q);
    // In front of the camera plane (grown + c_z > 0), some column and some row meet.
    met_q <= !vz_q[SumW-1] && vz_q != '0 && (cu_met_q || cd_met_q) && (ru_met_q || rd_met_q);
  end

  always_ff @(posedge clk) begin
    if (phase_q == Out) begin
      empty <= !met_q;
      col_lo <= !met_q || col_lo_q == '0 ? '0 : col_lo_q - 10'd1;
      col_hi <= !met_q ? '0 : col_hi_q == 10'(LastCol) ? col_hi_q : col_hi_q + 10'd1;
      row_lo <= !met_q || row_lo_q == '0 ? '0 : row_lo_q - 9'd1;
      row_hi <= !met_q ? '0 : row_hi_q == 9'(LastRow) ? row_hi_q : row_hi_q + 9'd1;
    end
  end
endmodule
