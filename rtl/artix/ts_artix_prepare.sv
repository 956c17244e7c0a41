// ts_artix_prepare: a sphere's per-world constants, computed as the sphere is written to scene memory. C++ model:
// artix::prepare_sphere (src/tripsitter/device/artix_kernel.h/.cpp), bit for bit; docs/device.md, "The artix
// preset", gives their use. From the radius r (1 .. 2^21 - 1, raw):
//   e    = bitlen(r) - 17, in -16..4 (the sphere's scale: r / 2^e in [2^16, 2^17))
//   r2s  = r^2 / 4^e, exact when e <= 0 and rounded half up when e > 0; below 2^34
//   rinv = (2^(34 + e) + floor(r / 2)) / r rounded down, which is round(2^(34 + e) / r); in (2^17, 2^18]
// Both come from r normalised, R = r 2^s with s = 21 - bitlen(r) (0..20), so R is in [2^20, 2^21):
//   r2s  = (R^2 + 2^7) >> 8: R^2 = r^2 4^(4 - e), so for e <= 0 this is r^2 4^-e (R^2's low 8 bits are zero and
//          the 2^7 does nothing) and for e > 0 it is (r^2 + 2^(2e - 1)) >> 2e, the model's rounding;
//   rinv = (2^38 + H) / R with H = floor(r / 2) 2^s: the model's numerator and divisor, both times 2^s.
// No multiplier: spheres arrive over SPI (a 24-byte record, at least 64 clocks a byte), so one addition a cycle
// is plenty. R^2 takes 21 shift-and-add steps (LSB first: a 22-bit adder, the product shifting down into the
// register the multiplier leaves); the quotient 19 restoring steps (a 22-bit subtraction), run in the first 19 of
// the 21. The quotient has no bit above 18: its partial remainder starts at (2^38 + H) >> 19 = 2^19 + H[19] < R.
//
// Timing: ready is high when the block is idle (after reset, and from the done cycle on). A start in a cycle t
// with ready takes in_r; done is high in cycle t + Cycles (24) alone, with out_e, out_r2s and out_rinv valid in
// that cycle (they hold until the cycle after the next start). ready is low in cycles t + 1 .. t + 23, and a start
// in the done cycle is taken: one sphere every 24 cycles. A start without ready is ignored. r = 0, outside the
// model's domain, gives meaningless values.
//   t + 1       bitlen(r): the shift s and e
//   t + 2       R = r << s and H = (r >> 1) << s, loaded into the multiplier and the divider
//   t + 3 .. 23 the 21 steps (the divider's 19 in t + 3 .. 21)
//   t + 24      done
//
// The package's facts are named ts_artix_pkg::X, not imported: Yosys 0.23 cannot parse `import`.
module ts_artix_prepare (
    input  logic                             clk,
    input  logic                             rst,
    input  logic                             start,
    input  logic [ts_artix_pkg::RadiusW-1:0] in_r,      // 1 .. 2^21 - 1
    output logic                             ready,
    output logic                             done,      // one cycle per start
    output logic [ts_artix_pkg::ExpW-1:0]    out_e,     // signed, -16..4
    output logic [ts_artix_pkg::R2sW-1:0]    out_r2s,
    output logic [ts_artix_pkg::RinvW-1:0]   out_rinv
);
  localparam int RadiusW = ts_artix_pkg::RadiusW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int R2sW = ts_artix_pkg::R2sW;
  localparam int RinvW = ts_artix_pkg::RinvW;
  localparam int ScaledRadiusBits = ts_artix_pkg::ScaledRadiusBits;
  localparam int Cycles = 24;                     // from a start to its done, and to ready again
  localparam int LenW = $clog2(RadiusW + 1);      // bitlen(r): 0..21, and s
  localparam int MulSteps = RadiusW;              // R's bits
  localparam int DivSteps = RinvW;                // the quotient's bits: rinv <= 2^18
  localparam int ProdW = 2 * RadiusW;             // R^2 + 2^7 < 2^42
  localparam int RoundBits = ProdW - R2sW;        // 8: R^2 = r2s 2^8 before the rounding
  localparam int HalfW = RadiusW - 1;             // H = floor(r / 2) 2^s < 2^20
  localparam int CountW = $clog2(Cycles);
  localparam int FirstStep = 2;                   // the counter's value in the first step's cycle (t + 3)
  localparam int LastStep = FirstStep + MulSteps - 1;

  if (MulSteps < DivSteps || FirstStep + MulSteps + 1 != Cycles || RoundBits != 8 || ScaledRadiusBits != 17)
  begin : g_bad_widths
    $error("ts_artix_prepare: the steps, the rounding or the scale do not fit the package's widths");
  end

  function automatic logic [LenW-1:0] bit_length(input logic [RadiusW-1:0] v);
    bit_length = '0;
    for (int i = 0; i < RadiusW; i++)
      if (v[i]) bit_length = LenW'(i + 1);
  endfunction

  // ---- control: the only state with a reset -------------------------------------------------------------------
  logic              busy_q, done_q;
  logic [CountW-1:0] count_q;  // cycles since the start, less one
  logic              accept, steps_end;
  assign accept = start && ready;
  assign steps_end = busy_q && count_q == CountW'(LastStep);
  always_ff @(posedge clk) begin
    if (rst) begin
      busy_q <= 1'b0;
      done_q <= 1'b0;
    end else begin
      if (accept) busy_q <= 1'b1;
      else if (steps_end) busy_q <= 1'b0;
      done_q <= steps_end;
    end
    count_q <= accept ? '0 : count_q + CountW'(1);
  end
  assign ready = !busy_q;
  assign done = done_q;

  // ---- t + 1: the scale --------------------------------------------------------------------------------------
  logic [RadiusW-1:0]     r_q;
  logic [LenW-1:0]        shift_q;
  logic signed [ExpW-1:0] e_q;
  logic [LenW-1:0]        length;
  assign length = bit_length(r_q);
  always_ff @(posedge clk) begin
    if (accept) r_q <= in_r;
    if (busy_q && count_q == CountW'(0)) begin
      shift_q <= LenW'(RadiusW) - length;
      e_q     <= ExpW'(length) - ExpW'(ScaledRadiusBits);
    end
  end

  // ---- t + 2: the load; t + 3 .. t + 23: the steps -----------------------------------------------------------
  // The multiplier: prod_q = {accumulator (21 bits), R's bits still to come}, the accumulator starting at 2^7 (the
  // rounding) and staying below 2^21; at the end prod_q = R^2 + 2^7. The divider: rem_q < R, and num_q holds the
  // numerator's bits still to come, the quotient's bits coming in at the bottom as they go out at the top.
  logic [RadiusW-1:0] norm, m_q, rem_q;
  logic [HalfW-1:0]   half;
  logic [ProdW-1:0]   prod_q;
  logic [DivSteps-1:0] num_q;
  logic [RadiusW:0]   sum, shifted;
  logic [RadiusW+1:0] diff;
  logic               load, step, div_step, up;
  assign norm     = r_q << shift_q;
  assign half     = HalfW'(r_q >> 1) << shift_q;
  assign load     = busy_q && count_q == CountW'(FirstStep - 1);
  assign step     = busy_q && count_q >= CountW'(FirstStep) && count_q <= CountW'(LastStep);
  assign div_step = step && count_q < CountW'(FirstStep + DivSteps);
  assign sum      = (RadiusW + 1)'(prod_q[ProdW-1:RadiusW]) + (prod_q[0] ? (RadiusW + 1)'(m_q) : '0);
  assign shifted  = {rem_q, num_q[DivSteps-1]};
  assign diff     = (RadiusW + 2)'(shifted) - (RadiusW + 2)'(m_q);
  assign up       = !diff[RadiusW+1];
  always_ff @(posedge clk) begin
    if (load) begin
      m_q    <= norm;
      prod_q <= {RadiusW'(1 << (RoundBits - 1)), norm};
      rem_q  <= RadiusW'(1 << (DivSteps)) | RadiusW'(half[HalfW-1]);
      num_q  <= half[DivSteps-1:0];
    end else if (step) begin
      prod_q <= {sum, prod_q[RadiusW-1:1]};
      if (div_step) begin
        rem_q <= up ? diff[RadiusW-1:0] : shifted[RadiusW-1:0];
        num_q <= {num_q[DivSteps-2:0], up};
      end
    end
  end

  assign out_e    = e_q;
  assign out_r2s  = prod_q[ProdW-1:RoundBits];
  assign out_rinv = num_q;

  /* verilator lint_off UNUSEDSIGNAL */  // the product's rounded-off bits; the remainder's top bits, zero after a
  logic unused;                          // subtraction that leaves it below R
  assign unused = ^{prod_q[RoundBits-1:0], diff[RadiusW]};
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
