// ts_artix_camera: the artix preset's camera rays, the unit direction of a pixel, one pixel a clock. C++ model:
// artix::camera_direction (src/tripsitter/device/artix_kernel.h/.cpp), bit for bit; docs/device.md, "The artix
// preset", gives the arithmetic. One of these serves the whole device, filling the units' direction buffers for the
// next line, so it is sized by its multipliers: four DSP48E1 for the reciprocal square root and two for the
// directions, none for the squares (a table) or for 320 g (two shifts and an add).
//
// The ray of pixel (col, row) is v = (x, y, 320), x = col - 320, y = row - 240; with n = x^2 + y^2 + 320^2 in
// [102400, 262400], the seed y0 = seed[(n >> 9) - SeedFirst] ~ 2^25 / sqrt(n) and one Newton step
//     e = (n y0^2) >> 30 ~ 2^20,   g = (y0 (3 2^20 + 1 - e)) >> 18 ~ 2^28 / sqrt(n),
// the direction is d_k = round(v_k g / 2^11) saturated to +-(2^17 - 1) (only the centre's z reaches 2^17).
//
// Timing: a pixel at the ports with in_valid in cycle t comes out with out_valid in cycle t + Latency (11), with
// the in_tag it came with; one pixel a cycle, any pattern of gaps. col must be 0..639 and row 0..479 when in_valid
// (the tables are not defined beyond); what the ports hold without in_valid is ignored. The block runs on a gated
// clock (ts_clock_gate) with an edge only while a pixel is at the ports or in the pipeline, or in reset: it
// works 640 cycles of a line's 3,200.
//
// Pipeline (stage k's registers hold a pixel k + 1 cycles after it was at the ports):
//   0   x, y and |x|, |y|                                       |x| <= 320, |y| <= 240: 9 bits
//   1   |x|^2, |y|^2 from one table of squares (two reads)       17 bits
//   2   n = x^2 + y^2 + 320^2                                    19 bits, below 2^18.01
//   3   y0 = seed[(n >> 9) - SeedFirst] (a 313-entry table)      17 bits, in [2^16, 2^17)
//   4   sq = y0^2                                                DSP 18 x 18; below 2^34
//   5   lo = n sq[16:0]                                          DSP 25 x 18; below 2^36
//   6   hi = n sq[33:17] + (lo >> 17) = (n sq) >> 17             DSP 25 x 18 and its post-adder; below 2^35.01
//   7   h = 3 2^20 + 1 - (hi >> 13)                              22 bits: e = 2^20 (1 +- 2^-8), so h = 2^21 +- 2^12
//   8   g = (y0 h) >> 18                                         DSP 25 x 18; g < 2^28 / 320 + 1 < 2^20
//   9   p_k = v_k g + 2^10: x and y a DSP 25 x 18 each, z as (g << 8) + (g << 6) + 2^10; |p_k| < 2^29
//   10  d_k = p_k >> 11, saturated
// The product n y0^2 (19 x 34 bits) is split on y0^2's 17-bit halves, as a DSP48E1 cascade takes it; every other
// product has its wider operand (at most 23 bits signed) on A and the narrower (at most 18) on B. The widths rest
// on n in [102400, 262400]: there y0 is within 2^-9 of 2^25 / sqrt(n), relatively (the seed is taken in the middle
// of its 512 values of n), so e is within 2^-8 of 2^20. The Newton step never overshoots and the shifts floor, so
// without the 1 in h, g would be low on average; with it the directions' mean length is 1 - 2.9e-7 over the screen
// (1 - 7.7e-7 without).
//
// The package's facts are named ts_artix_pkg::X, not imported: Yosys 0.23 cannot parse `import`.
module ts_artix_camera #(
    parameter int TAG_W = 1
) (
    input  logic                              clk,
    input  logic                              rst,
    input  logic                              in_valid,
    input  logic [9:0]                        in_col,    // 0..639
    input  logic [8:0]                        in_row,    // 0..479
    input  logic [TAG_W-1:0]                  in_tag,
    output logic                              out_valid,
    output logic [3*ts_artix_pkg::DirW-1:0]   out_d,     // component k at [k*DirW +: DirW], signed, times 2^17
    output logic [TAG_W-1:0]                  out_tag
);
  localparam int DirW = ts_artix_pkg::DirW;
  localparam int DirFrac = ts_artix_pkg::DirFrac;
  localparam int SeedFirst = ts_artix_pkg::SeedFirst;
  localparam int SeedEntries = ts_artix_pkg::SeedEntries;
  localparam int Latency = 11;
  localparam int PlaneZ = 320;                    // the image plane's z, and half the line's width
  localparam int HalfHeight = 240;
  localparam int XW = 10;                         // x = col - 320: -320..319, signed
  localparam int YW = 9;                          // y = row - 240: -240..239, signed
  localparam int AbsW = 9;                        // |x| <= 320, |y| <= 240
  localparam int Squares = PlaneZ + 1;            // the table of squares: 0^2 .. 320^2
  localparam int SquareW = 17;                    // 320^2 = 102400 < 2^17
  localparam int NW = 19;                         // n <= 2 320^2 + 240^2 = 262400 < 2^19
  localparam int SeedAW = 9;                      // (n >> 9) - SeedFirst: 0..312
  localparam int SeedW = 17;                      // y0: 65504..104726
  localparam int SqW = 2 * SeedW;                 // y0^2 < 2^34
  localparam int HalfW = SqW / 2;                 // y0^2's halves, each a B operand
  localparam int LoW = NW + HalfW;                // n sq[16:0] < 2^36
  localparam int HiW = NW + HalfW;                // (n sq) >> 17 < 2^35.01, and n sq[33:17] < 2^36
  localparam int EW = 22;                         // e = hi >> 13: hi's bits 13..34 (bit 35 is zero)
  localparam int HW = 22;                         // h = 2^21 +- 2^12
  localparam int GProdW = HW + SeedW;             // y0 h < 2^39
  localparam int GW = 20;                         // g < 838862
  localparam int PW = 30;                         // p_k: |v_k g| <= 320 g < 2^28 + 2^9, plus 2^10, signed
  localparam int RoundShift = 28 - DirFrac;       // g is times 2^28, d times 2^17
  localparam int NewtonShift = 30;                // e = (n y0^2) >> 30
  localparam int StepShift = 18;                  // g = (y0 h) >> 18
  localparam int SeedShift = 9;                   // a seed serves 512 values of n
  localparam logic [HW-1:0] ThreeHalves = HW'((3 << 20) + 1);  // 3 2^20 + 1: 1.5 in e's scale, and the centring 1
  localparam logic signed [DirW-1:0] DirMax = DirW'((1 << DirFrac) - 1);

  if (SeedEntries != 313 || SeedFirst != 200 || DirFrac != 17 || DirW != 18) begin : g_bad_package
    $error("ts_artix_camera: its widths are derived for 313 seeds from 200 and directions of 18 bits, 2^17");
  end

  // ---- the tables, computed at elaboration ---------------------------------------------------------------------
  // isqrt(2^50 / (512 i + 256)): the model's seed for n >> 9 = i (artix::rsqrt_seeds), the root bit by bit.
  function automatic logic [SeedW-1:0] seed_of(input int i);
    logic [50:0] middle, quotient;  // unsigned: 2^50 / 102656 < 2^34
    logic [SeedW-1:0] root, trial;
    middle = 51'(512 * i + 256);
    quotient = {1'b1, 50'b0} / middle;
    root = '0;
    for (int b = SeedW - 1; b >= 0; b--) begin
      trial = root | (SeedW'(1) << b);
      if (51'(trial) * 51'(trial) <= quotient) root = trial;
    end
    seed_of = root;
  endfunction

  logic [SquareW-1:0] square_rom [Squares];
  logic [SeedW-1:0]   seed_rom [SeedEntries];
  initial begin
    for (int i = 0; i < Squares; i++) square_rom[i] = SquareW'(i * i);
    for (int i = 0; i < SeedEntries; i++) seed_rom[i] = seed_of(SeedFirst + i);
  end

  // ---- valid bits: the only state with a reset; the clock -------------------------------------------------------
  logic [Latency-1:0] valid_q;
  logic               gclk;
  ts_clock_gate gate (.clk, .en(rst || in_valid || |valid_q), .gclk);
  always_ff @(posedge gclk) begin
    if (rst) valid_q <= '0;
    else valid_q <= {valid_q[Latency-2:0], in_valid};
  end

  // ---- 0: x, y, |x|, |y| ---------------------------------------------------------------------------------------
  logic signed [XW-1:0] x0_q;
  logic signed [YW-1:0] y0_q;
  logic [AbsW-1:0]      ax0_q, ay0_q;
  logic [TAG_W-1:0]     tag0_q;
  always_ff @(posedge gclk) begin
    x0_q   <= XW'(in_col) - XW'(PlaneZ);
    y0_q   <= YW'(in_row) - YW'(HalfHeight);
    ax0_q  <= in_col >= 10'(PlaneZ) ? AbsW'(in_col - 10'(PlaneZ)) : AbsW'(10'(PlaneZ) - in_col);
    ay0_q  <= in_row >= 9'(HalfHeight) ? AbsW'(in_row - 9'(HalfHeight)) : AbsW'(9'(HalfHeight) - in_row);
    tag0_q <= in_tag;
  end

  // x and y wait for g, the tag for the result: chains without reset, which synthesis packs into shift-register
  // LUTs (SRL16E), one a bit. (* mem2reg *) marks an array of registers as such for Yosys, which would otherwise
  // take it for a memory first and warn as it turned it back into registers.
  (* mem2reg *) logic signed [XW-1:0] x_q [1:8];
  (* mem2reg *) logic signed [YW-1:0] y_q [1:8];
  (* mem2reg *) logic [TAG_W-1:0]     tag_q [1:Latency-1];
  always_ff @(posedge gclk) begin
    x_q[1]   <= x0_q;
    y_q[1]   <= y0_q;
    tag_q[1] <= tag0_q;
    for (int s = 2; s <= 8; s++) begin
      x_q[s] <= x_q[s-1];
      y_q[s] <= y_q[s-1];
    end
    for (int s = 2; s < Latency; s++) tag_q[s] <= tag_q[s-1];
  end

  // ---- 1, 2: n = x^2 + y^2 + 320^2 -----------------------------------------------------------------------------
  logic [SquareW-1:0] xx1_q, yy1_q;
  logic [NW-1:0]      n2_q;
  always_ff @(posedge gclk) begin
    xx1_q <= square_rom[ax0_q];
    yy1_q <= square_rom[ay0_q];
    n2_q  <= NW'(xx1_q) + NW'(yy1_q) + NW'(PlaneZ * PlaneZ);
  end

  // ---- 3: the seed ---------------------------------------------------------------------------------------------
  logic [SeedAW-1:0] seed_index;
  logic [SeedW-1:0]  seed3_q;
  logic [NW-1:0]     n3_q;
  assign seed_index = SeedAW'(n2_q[NW-1:SeedShift] - (NW - SeedShift)'(SeedFirst));
  always_ff @(posedge gclk) begin
    seed3_q <= seed_rom[seed_index];
    n3_q    <= n2_q;
  end

  // y0 waits for the Newton step.
  (* mem2reg *) logic [SeedW-1:0] seed_q [4:7];
  always_ff @(posedge gclk) begin
    seed_q[4] <= seed3_q;
    for (int s = 5; s <= 7; s++) seed_q[s] <= seed_q[s-1];
  end

  // ---- 4..6: (n y0^2) >> 17 ------------------------------------------------------------------------------------
  logic [SqW-1:0]   sq4_q;
  logic [NW-1:0]    n4_q, n5_q;
  logic [HalfW-1:0] sq_high5_q;
  logic [LoW-1:0]   lo5_q;
  logic [HiW-1:0]   hi6_q;
  always_ff @(posedge gclk) begin
    sq4_q      <= SqW'($signed({1'b0, seed3_q}) * $signed({1'b0, seed3_q}));
    n4_q       <= n3_q;
    lo5_q      <= LoW'($signed({1'b0, n4_q}) * $signed({1'b0, sq4_q[HalfW-1:0]}));
    sq_high5_q <= sq4_q[SqW-1:HalfW];
    n5_q       <= n4_q;
    hi6_q      <= HiW'($signed({1'b0, n5_q}) * $signed({1'b0, sq_high5_q})) + HiW'(lo5_q >> HalfW);
  end

  // ---- 7: h = 3 2^20 - e ---------------------------------------------------------------------------------------
  logic [HW-1:0] h7_q;
  always_ff @(posedge gclk) h7_q <= ThreeHalves - hi6_q[NewtonShift-HalfW+:EW];

  // ---- 8: g = (y0 h) >> 18 -------------------------------------------------------------------------------------
  logic [GProdW-1:0] g_product;
  logic [GW-1:0]     g8_q;
  assign g_product = GProdW'($signed({1'b0, h7_q}) * $signed({1'b0, seed_q[7]}));
  always_ff @(posedge gclk) g8_q <= g_product[StepShift+:GW];

  // ---- 9: p_k = v_k g + 2^10 -----------------------------------------------------------------------------------
  (* mem2reg *) logic signed [PW-1:0] p9_q [3];
  always_ff @(posedge gclk) begin
    p9_q[0] <= PW'(x_q[8] * $signed({1'b0, g8_q})) + PW'(1 << (RoundShift - 1));
    p9_q[1] <= PW'(y_q[8] * $signed({1'b0, g8_q})) + PW'(1 << (RoundShift - 1));
    p9_q[2] <= (PW'(g8_q) << 8) + (PW'(g8_q) << 6) + PW'(1 << (RoundShift - 1));  // 320 g
  end

  // ---- 10: d_k = p_k >> 11, saturated --------------------------------------------------------------------------
  (* mem2reg *) logic signed [PW-RoundShift-1:0] q9 [3];  // 19 bits
  (* mem2reg *) logic signed [DirW-1:0]          d10_q [3];
  always_comb begin
    for (int k = 0; k < 3; k++) q9[k] = p9_q[k][PW-1:RoundShift];
  end
  always_ff @(posedge gclk) begin
    for (int k = 0; k < 3; k++) begin
      if (q9[k] > (PW - RoundShift)'(DirMax)) d10_q[k] <= DirMax;
      else if (q9[k] < -(PW - RoundShift)'(DirMax)) d10_q[k] <= -DirMax;
      else d10_q[k] <= DirW'(q9[k]);
    end
  end

  assign out_valid = valid_q[Latency-1];
  assign out_tag   = tag_q[Latency-1];
  for (genvar k = 0; k < 3; k++) begin : g_out
    assign out_d[k*DirW+:DirW] = d10_q[k];
  end

  /* verilator lint_off UNUSEDSIGNAL */  // bits the arithmetic drops: lo's low 17 (below hi), hi's below e and its
  logic unused;                          // top bit (zero), g's fraction and the product's top bit (zero), p's low 11
  assign unused = ^{lo5_q[HalfW-1:0], hi6_q[HiW-1], hi6_q[NewtonShift-HalfW-1:0], g_product[StepShift-1:0],
                    g_product[GProdW-1], p9_q[0][RoundShift-1:0], p9_q[1][RoundShift-1:0], p9_q[2][RoundShift-1:0]};
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
