// ts_path_normalise: a scattered direction made a unit vector again, for the bounced ray: the scatter unit's v (the
// path preset's 2^14 unit vectors, of any length from 2^-11 up) normalised to 2^17 and saturated to 18 bits. C++
// model: artix::unit_direction (src/tripsitter/device/artix_path.h), that is approx::unit at 17 bits
// (src/tripsitter/device/approx.h), bit for bit; docs/rtl.md, "Path tracing blocks".
//
// One direction a cycle, out Latency = 15 cycles later with its tag. The caller has dropped a v with v.v < 64 (the
// model absorbs it); every component is within the model's check of a scattered direction, |v_k| < 2^19.
//
// The arithmetic (approx::unit): s = v.v; p the index of s's highest non-zero pair of bits, k = p - 15, so that
// m = s 2^(-2k) lies in [2^30, 2^32) (exact: s 2^30 shifted right by 2p); y0 = the 192-entry table of
// round(2^16 / sqrt((i + 64.5) / 64)) at m's top byte i + 64; one Newton step t = floor(y0^2 m / 2^32),
// y = floor((y0 (3 2^30 - t) + 2^30) / 2^31); then each component round(v_k y / 2^(14 + k)), to nearest with ties away
// from zero, saturated to +-(2^17 - 1). The table is computed at elaboration in integers: round(sqrt(q)) =
// floor((floor(sqrt(4 q)) + 1) / 2) with q = 2^39 / (2 i + 129), 2 sqrt(q) never an odd integer, and
// floor(sqrt(4 q)) the largest w with w^2 (2 i + 129) <= 2^41, by bisection.
//
// Pipeline (stage j's registers hold a direction j + 1 cycles after it reached the ports):
//   0  v                                   1  v_k^2 (20 x 20 bits: two DSP48E1 each)
//   2  s                                   3  p (a priority encoder over s's 20 pairs)
//   4  m = s 2^30 >> 2p, k                 5  y0 (the table, a ROM of LUTs)
//   6  y0^2                                7  y0^2 m (32 x 32 bits)
//   8  t, 3 2^30 - t                       9  y0 (3 2^30 - t)
//   10 y                                   11 v_k y (20 x 17 bits)
//   12 v_k y + 2^(13 + k) - (v_k y < 0)       13 that >> (14 + k), arithmetic: the rounding, ties away from 0
//   14 saturated
module ts_path_normalise #(
    parameter int TAG_W = 1
) (
    input  logic              clk,
    input  logic              rst,
    input  logic              in_valid,
    /* verilator lint_off UNUSEDSIGNAL */  // a scattered component fits 20 bits (the model's check): the rest is sign
    input  logic [3*24-1:0]   in_v,      // x, y, z from the low bits, 24 bits signed each, times 2^14
    /* verilator lint_on UNUSEDSIGNAL */
    input  logic [TAG_W-1:0]  in_tag,
    output logic              out_valid,
    output logic [3*18-1:0]   out_d,     // times 2^17, signed
    output logic [TAG_W-1:0]  out_tag
);
  localparam int Latency = 15;
  localparam int VW = 20;               // |v_k| < 2^19
  localparam int SW = 40;               // s < 3 2^38
  localparam int Pairs = SW / 2;
  localparam int PW = 5;                // p: 3 .. 19 (s >= 64)
  localparam int MW = 32;               // m in [2^30, 2^32)
  localparam int YW = 17;               // y0, y in (2^15, 2^16]
  localparam int TW = 32;               // y0^2 < 2^32 (y0 < 2^16)
  localparam int DW = 18;
  localparam logic signed [DW-1:0] DirMax = DW'((1 << 17) - 1);

  // ---- The table ------------------------------------------------------------------------------------------------
  localparam int Entries = 192, First = 64;
  function automatic logic [Entries*YW-1:0] rsqrt_table();
    logic [63:0] lo, hi, mid, d;
    rsqrt_table = '0;
    for (int i = 0; i < Entries; i++) begin
      d = 64'(2 * i + 129);
      // The largest w with w^2 d <= 2^41: below 2^21.
      lo = 0;
      hi = 64'd1 << 21;
      while (hi - lo > 1) begin
        mid = (lo + hi) >> 1;
        if (mid * mid * d <= (64'd1 << 41)) lo = mid;
        else hi = mid;
      end
      rsqrt_table[i*YW+:YW] = YW'((lo + 1) >> 1);
    end
  endfunction
  localparam logic [Entries*YW-1:0] Table = rsqrt_table();

  // ---- Valid, tag, and what rides beside the arithmetic --------------------------------------------------------
  logic [Latency-1:0] v_q;
  (* mem2reg *) logic [TAG_W-1:0] tag_q [Latency];
  always_ff @(posedge clk) begin
    if (rst) v_q <= '0;
    else v_q <= Latency'({v_q, in_valid});
    tag_q[0] <= in_tag;
    for (int j = 1; j < Latency; j++) tag_q[j] <= tag_q[j-1];
  end
  assign out_valid = v_q[Latency-1];
  assign out_tag = tag_q[Latency-1];

  // 0: v; it waits for stage 11's products.
  (* mem2reg *) logic signed [VW-1:0] v_q0 [3];
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) v_q0[k] <= $signed(in_v[k*24+:VW]);
  end
  (* mem2reg *) logic signed [VW-1:0] v10 [3];
  for (genvar k = 0; k < 3; k++) begin : g_vdelay
    ts_artix_delay #(.W(VW), .N(10)) delay (.clk, .in(v_q0[k]), .out(v10[k]));
  end

  // 1, 2: s.
  (* mem2reg *) logic signed [2*VW-1:0] sq1_q [3];
  logic [SW-1:0] s2_q;
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) sq1_q[k] <= (2 * VW)'(v_q0[k]) * (2 * VW)'(v_q0[k]);
    s2_q <= SW'($unsigned(sq1_q[0])) + SW'($unsigned(sq1_q[1])) + SW'($unsigned(sq1_q[2]));
  end

  // 3: p, the highest non-zero pair.
  logic [PW-1:0] p_top;
  always_comb begin
    p_top = '0;
    for (int i = 0; i < Pairs; i++) if (s2_q[2*i+:2] != 2'b00) p_top = PW'(i);
  end
  logic [SW-1:0] s3_q;
  logic [PW-1:0] p3_q;
  always_ff @(posedge clk) begin
    s3_q <= s2_q;
    p3_q <= p_top;
  end

  // 4: m and k (k = p - 15, -12 .. 4, kept as the final shift 14 + k = p - 1).
  /* verilator lint_off UNUSEDSIGNAL */  // m is the low 32 bits: s 2^30 >> 2p is below 2^32
  logic [SW+29:0] m_wide;
  /* verilator lint_on UNUSEDSIGNAL */
  assign m_wide = {s3_q, 30'd0} >> {p3_q, 1'b0};
  logic [MW-1:0] m4_q;
  logic [PW-1:0] p4_q;
  always_ff @(posedge clk) begin
    m4_q <= m_wide[MW-1:0];
    p4_q <= p3_q;
  end

  // 5: y0.
  logic [YW-1:0] y0_5_q;
  logic [MW-1:0] m5_q;
  logic [7:0] bin;
  assign bin = m4_q[31:24] - 8'(First);  // 0 .. 191
  always_ff @(posedge clk) begin
    y0_5_q <= Table[bin*YW+:YW];
    m5_q <= m4_q;
  end

  // 6 .. 10: the Newton step.
  logic [TW-1:0] y0sq6_q;
  logic [YW-1:0] y0_6_q, y0_7_q, y0_8_q;
  logic [MW-1:0] m6_q;
  /* verilator lint_off UNUSEDSIGNAL */  // t is the product's bits 32 and up
  logic [TW+MW-1:0] xm7_q;
  /* verilator lint_on UNUSEDSIGNAL */
  logic [31:0] r8_q;     // 3 2^30 - t, in (2^30, 2^32): t is within 1% of 2^30 (y0 is 1 / sqrt(x) to 1%)
  /* verilator lint_off UNUSEDSIGNAL */  // y is the product's bits 31 .. 47
  logic [YW+32:0] yr9_q;
  /* verilator lint_on UNUSEDSIGNAL */
  logic [YW-1:0] y10_q;
  always_ff @(posedge clk) begin
    y0sq6_q <= TW'(y0_5_q) * TW'(y0_5_q);
    y0_6_q  <= y0_5_q;
    m6_q    <= m5_q;
    xm7_q   <= (TW + MW)'(y0sq6_q) * (TW + MW)'(m6_q);
    y0_7_q  <= y0_6_q;
    r8_q    <= 32'(3 * (64'd1 << 30)) - 32'(xm7_q[TW+MW-1:32]);
    y0_8_q  <= y0_7_q;
    yr9_q   <= (YW + 33)'(y0_8_q) * (YW + 33)'(r8_q) + (YW + 33)'(64'd1 << 30);
    y10_q   <= YW'(yr9_q[YW+32:31]);
  end

  // The final shift, 14 + k = p - 1 (2 .. 18), waits for stage 11.
  logic [PW-1:0] shift11, shift12_q;
  ts_artix_delay #(.W(PW), .N(7)) shift_delay (.clk, .in(p4_q - PW'(1)), .out(shift11));
  always_ff @(posedge clk) shift12_q <= shift11;

  // 11 .. 14: each component. round(x / 2^shift) with ties away from zero is (x + 2^(shift - 1) - (x < 0)) >> shift,
  // the shift arithmetic: one adder, no magnitude.
  localparam int XW = VW + YW + 1;  // |v_k y| < 2^19 2^16
  for (genvar k = 0; k < 3; k++) begin : g_out
    logic signed [XW-1:0] prod11_q, sum12_q, shifted13_q;
    logic signed [DW-1:0] d14_q;
    always_ff @(posedge clk) begin
      prod11_q    <= v10[k] * $signed({1'b0, y10_q});
      sum12_q     <= prod11_q + (XW'(1) << (shift11 - PW'(1))) - XW'(prod11_q < 0);
      shifted13_q <= sum12_q >>> shift12_q;
      d14_q       <= shifted13_q > XW'(DirMax) ? DirMax : shifted13_q < -XW'(DirMax) ? -DirMax : DW'(shifted13_q);
    end
    assign out_d[k*DW+:DW] = d14_q;
  end
endmodule
