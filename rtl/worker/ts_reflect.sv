// The worker's mirror reflection: the ray reflected off the metal a pass ended on, as core::reflect computes it
// (src/tripsitter/core/sphere_kernel.h) with device::FixedArith::round_div and scale_direction
// (src/tripsitter/device/worker.h), bit for bit (docs/device.md, "Reflection in fixed point"):
//     p_k = o_k + round(num d_k / 2a)            to nearest, ties away from zero
//     m = p - c,  r_k = d_k (m.m) - 2 (d.m) m_k,  d' = r / 2^s rounded, s >= 0 the least with bit length <= 20
// and the new ray's a' = d'.d'.
//
// The division. num > 0 (a hit), so num d_k has the sign of d_k and round(num d_k / 2a) = sign(d_k) Q_k with
//     Q_k = floor((num |d_k| + a) / 2a)          (|n| / 2a rounded half up is floor((|n| + a) / 2a))
// Q_k = |p_k - o_k| < 2^26 (docs/device.md, Widths), so a radix-8 divider finds it in 9 digits, one per cycle:
// each digit compares the partial remainder with the seven multiples 1..7 of 2a (precomputed: 3, 5 and 7 times
// by one addition each) and keeps the largest that fits. Three such dividers work in parallel, one per axis.
//
// One reflection at a time (the worker reflects one pixel's pass at a time), with fixed timing. From the cycle
// the pass's closest hit is given (in_valid), counting that cycle's clock edge as 0:
//     edge 0      V_k = num |d_k| + a (one product and an addition), the multiples of 2a
//     edges 1-9   the nine digits
//     edge 10     p = o +- Q, m = +-Q - oc                         -> ray_o (the new origin)
//     edge 11     m_k^2, d_k m_k (six products)
//     edge 12     m.m, d.m
//     edge 13     d_k (m.m), (d.m) m_k (six products)
//     edge 14     r_k and |r_k|
//     edge 15     s from the bit length of |r_0| | |r_1| | |r_2|
//     edge 16     d'_k = (r_k + 2^(s-1), less 1 when r_k < 0) >> s    -> ray_d
//     edge 17     d'_k^2 (three products)
//     edge 18     a' = d'.d'                                        -> ray_a
// The products of edges 0, 11, 13 and 17 share two multipliers per axis. So ray_o is the new origin from 11
// cycles after in_valid, ray_d from 17 and ray_a from 19: just when the reflected pass's first pair needs each
// (ts_worker.sv, ts_sphere_test.sv). The ray registers hold until the next reflection.
//
// Widths: the Widths table's (docs/device.md) for formats of at most 24 bits.
module ts_reflect #(
    parameter int NUMW = 50,  // num, signed (> 0 here)
    parameter int OCW = 27,   // oc, signed
    parameter int OW = 26,    // p (a ray origin), signed
    parameter int DW = 22,    // directions, signed
    parameter int AAW = 42    // a, unsigned
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic                   flush,
    input  logic                   in_valid,
    input  logic signed [NUMW-1:0] in_num,
    input  logic signed [OCW-1:0]  in_ocx,
    input  logic signed [OCW-1:0]  in_ocy,
    input  logic signed [OCW-1:0]  in_ocz,
    input  logic signed [OW-1:0]   in_ox,
    input  logic signed [OW-1:0]   in_oy,
    input  logic signed [OW-1:0]   in_oz,
    input  logic signed [DW-1:0]   in_dx,
    input  logic signed [DW-1:0]   in_dy,
    input  logic signed [DW-1:0]   in_dz,
    input  logic [AAW-1:0]         in_a,
    output logic signed [OW-1:0]   ray_ox,
    output logic signed [OW-1:0]   ray_oy,
    output logic signed [OW-1:0]   ray_oz,
    output logic signed [DW-1:0]   ray_dx,
    output logic signed [DW-1:0]   ray_dy,
    output logic signed [DW-1:0]   ray_dz,
    output logic [AAW-1:0]         ray_a
);
  localparam int DIGITS = 9;                 // radix-8 digits of Q
  localparam int QW = 3 * DIGITS;            // Q < 2^27
  localparam int EW = AAW + 1;               // 2a
  localparam int VW = NUMW + DW + 1;         // V = num |d| + a
  localparam int PRW = EW + 3;               // a partial remainder (below 8 2a) and the multiples of 2a
  localparam int MW = OW;                    // m = p - c: |m| < 2^25, as p
  localparam int MMW = 2 * MW - 2;           // m.m < 2^50
  localparam int DMW = DW + MW - 1;          // d.m < 2^46
  localparam int RRW = DW + MMW + 1;         // r_k < 2^72
  localparam int SW = $clog2(RRW + 1);       // shift amounts and bit lengths
  localparam int DIR_BITS = 20;              // core::kDirectionBits

  // Bit length of v (0 for 0).
  function automatic logic [SW-1:0] bit_length(input logic [RRW-1:0] v);
    bit_length = '0;
    for (int i = 0; i < RRW; i++) if (v[i]) bit_length = SW'(i + 1);
  endfunction

  logic [4:0] step;  // 0: idle; 1..18: the edge about to happen (see above)

  // ---- edge 0: V, the multiples ------------------------------------------------------------------------
  (* mem2reg *) logic signed [DW-1:0]   in_d[3];
  (* mem2reg *) logic signed [OCW-1:0]  in_oc[3];
  (* mem2reg *) logic signed [OW-1:0]   in_o[3];
  assign in_d[0] = in_dx;
  assign in_d[1] = in_dy;
  assign in_d[2] = in_dz;
  assign in_oc[0] = in_ocx;
  assign in_oc[1] = in_ocy;
  assign in_oc[2] = in_ocz;
  assign in_o[0] = in_ox;
  assign in_o[1] = in_oy;
  assign in_o[2] = in_oz;

  (* mem2reg *) logic [PRW-1:0]        mult[8];      // j 2a for j = 0..7
  (* mem2reg *) logic [QW-1:0]         v_low[3];     // the dividend's digits still to bring down
  (* mem2reg *) logic [PRW-1:0]        rem[3];       // the partial remainder, below 2a
  (* mem2reg *) logic [QW-1:0]         quot[3];
  (* mem2reg *) logic                  neg[3];       // d_k < 0
  (* mem2reg *) logic signed [DW-1:0]  d[3];
  (* mem2reg *) logic signed [OCW-1:0] oc[3];
  (* mem2reg *) logic signed [OW-1:0]  o[3];

  (* mem2reg *) logic [VW-1:0] v_of[3];
  (* mem2reg *) logic [DW-1:0] abs_d[3];
  logic [EW-1:0] two_a;
  assign two_a = {in_a, 1'b0};
  for (genvar k = 0; k < 3; k++) begin : g_v
    assign abs_d[k] = in_d[k] < 0 ? DW'(-in_d[k]) : DW'(in_d[k]);
  end

  // ---- edges 1-9: a radix-8 digit ------------------------------------------------------------------------
  (* mem2reg *) logic [PRW-1:0] pr[3];       // the remainder with the next digit brought down
  (* mem2reg *) logic [2:0]     digit[3];
  for (genvar k = 0; k < 3; k++) begin : g_digit
    assign pr[k] = {rem[k][PRW-4:0], v_low[k][QW-1-:3]};
    always_comb begin
      digit[k] = 3'd0;
      for (int j = 1; j < 8; j++) if (pr[k] >= mult[j]) digit[k] = 3'(j);
    end
  end

  // ---- edge 10: p and m ------------------------------------------------------------------------------------
  (* mem2reg *) logic signed [MW-1:0] m[3];
  (* mem2reg *) logic signed [OW:0]   q_signed[3];
  for (genvar k = 0; k < 3; k++) begin : g_q
    assign q_signed[k] = neg[k] ? -$signed({1'b0, OW'(quot[k])}) : $signed({1'b0, OW'(quot[k])});
  end

  // ---- edges 11-18 -------------------------------------------------------------------------------------------
  (* mem2reg *) logic [2*MW-1:0]         m2[3];
  (* mem2reg *) logic signed [DW+MW-1:0] dmk[3];
  logic [MMW-1:0]          mm;
  logic signed [DMW-1:0]   dm;
  (* mem2reg *) logic signed [RRW-1:0]   p_dmm[3], p_dmm2[3];
  (* mem2reg *) logic signed [RRW-1:0]   r[3];
  (* mem2reg *) logic [RRW-1:0]          r_abs[3];
  logic [SW-1:0]           shift;
  (* mem2reg *) logic [2*DW-1:0]         d2[3];

  logic [SW-1:0] length;
  assign length = bit_length(r_abs[0] | r_abs[1] | r_abs[2]);

  // ---- the multipliers: two per axis, shared by the edges that multiply (0, 11, 13 and 17) ------------------
  //   A: num |d_k| (edge 0), m_k^2 (11), (m.m) d_k (13), d'_k^2 (17)      at most 51 x 26 bits
  //   B: d_k m_k (11), (d.m) m_k (13)                                     at most 47 x 26 bits
  localparam int XAW = NUMW > MMW + 1 ? NUMW : MMW + 1;
  localparam int YAW = MW > DW + 1 ? MW : DW + 1;
  localparam int XBW = DMW > DW ? DMW : DW;
  (* mem2reg *) logic signed [XAW-1:0]     mul_xa[3];
  (* mem2reg *) logic signed [YAW-1:0]     mul_ya[3];
  (* mem2reg *) logic signed [XAW+YAW-1:0] mul_a[3];
  (* mem2reg *) logic signed [XBW-1:0]     mul_xb[3];
  (* mem2reg *) logic signed [MW-1:0]      mul_yb[3];
  (* mem2reg *) logic signed [XBW+MW-1:0]  mul_b[3];
  (* mem2reg *) logic signed [DW-1:0]      ray_d[3];
  assign ray_d[0] = ray_dx;
  assign ray_d[1] = ray_dy;
  assign ray_d[2] = ray_dz;
  for (genvar k = 0; k < 3; k++) begin : g_mul
    always_comb begin
      if (in_valid) begin
        mul_xa[k] = XAW'(in_num);
        mul_ya[k] = YAW'($signed({1'b0, abs_d[k]}));
      end else if (step == 5'd11) begin
        mul_xa[k] = XAW'(m[k]);
        mul_ya[k] = YAW'(m[k]);
      end else if (step == 5'd13) begin
        mul_xa[k] = XAW'($signed({1'b0, mm}));
        mul_ya[k] = YAW'(d[k]);
      end else begin
        mul_xa[k] = XAW'(ray_d[k]);
        mul_ya[k] = YAW'(ray_d[k]);
      end
      if (step == 5'd11) begin
        mul_xb[k] = XBW'(d[k]);
      end else begin
        mul_xb[k] = XBW'(dm);
      end
      mul_yb[k] = m[k];
    end
    assign mul_a[k] = (XAW + YAW)'(mul_xa[k]) * (XAW + YAW)'(mul_ya[k]);
    assign mul_b[k] = (XBW + MW)'(mul_xb[k]) * (XBW + MW)'(mul_yb[k]);
    assign v_of[k] = VW'(mul_a[k]) + VW'(in_a);
  end

  // d'_k: r_k shifted right by s, rounded to nearest with ties away from zero (floor((r + 2^(s-1) - [r < 0]) / 2^s)).
  function automatic logic signed [DW-1:0] scaled(input logic signed [RRW-1:0] rv, input logic [SW-1:0] s);
    logic signed [RRW:0] biased;
    logic signed [RRW:0] half;
    /* verilator lint_off UNUSEDSIGNAL */  // |r / 2^s| <= 2^20: the bits above DW are sign
    logic signed [RRW:0] shifted;
    /* verilator lint_on UNUSEDSIGNAL */
    half = s == 0 ? '0 : (RRW + 1)'(1) <<< (s - 1);
    biased = (RRW + 1)'(rv) + half - ((rv < 0 && s != 0) ? (RRW + 1)'(1) : '0);
    shifted = biased >>> s;
    scaled = DW'(shifted);
  endfunction

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      step <= '0;
      for (int j = 0; j < 8; j++) mult[j] <= '0;
      for (int k = 0; k < 3; k++) begin
        v_low[k] <= '0;
        rem[k] <= '0;
        quot[k] <= '0;
        neg[k] <= 1'b0;
        d[k] <= '0;
        oc[k] <= '0;
        o[k] <= '0;
        m[k] <= '0;
        m2[k] <= '0;
        dmk[k] <= '0;
        p_dmm[k] <= '0;
        p_dmm2[k] <= '0;
        r[k] <= '0;
        r_abs[k] <= '0;
        d2[k] <= '0;
      end
      mm <= '0;
      dm <= '0;
      shift <= '0;
      ray_ox <= '0;
      ray_oy <= '0;
      ray_oz <= '0;
      ray_dx <= '0;
      ray_dy <= '0;
      ray_dz <= '0;
      ray_a <= '0;
    end else begin
      if (in_valid) begin  // edge 0
        step <= 5'd1;
        mult[0] <= '0;
        mult[1] <= PRW'(two_a);
        mult[2] <= PRW'(two_a) << 1;
        mult[3] <= (PRW'(two_a) << 1) + PRW'(two_a);
        mult[4] <= PRW'(two_a) << 2;
        mult[5] <= (PRW'(two_a) << 2) + PRW'(two_a);
        mult[6] <= ((PRW'(two_a) << 1) + PRW'(two_a)) << 1;
        mult[7] <= (PRW'(two_a) << 3) - PRW'(two_a);
        for (int k = 0; k < 3; k++) begin
          v_low[k] <= v_of[k][QW-1:0];
          rem[k] <= PRW'(v_of[k] >> QW);  // below 2a, since Q < 2^27
          quot[k] <= '0;
          neg[k] <= in_d[k] < 0;
          d[k] <= in_d[k];
          oc[k] <= in_oc[k];
          o[k] <= in_o[k];
        end
      end else if (step != 0) begin
        step <= step == 5'd18 ? 5'd0 : step + 5'd1;
        if (step <= 5'(DIGITS)) begin  // edges 1-9: one digit per axis
          for (int k = 0; k < 3; k++) begin
            rem[k] <= pr[k] - mult[digit[k]];
            quot[k] <= {quot[k][QW-4:0], digit[k]};
            v_low[k] <= v_low[k] << 3;
          end
        end
        if (step == 5'd10) begin  // the hit point and its normal
          for (int k = 0; k < 3; k++) m[k] <= MW'(q_signed[k] - (OW + 1)'(oc[k]));
          ray_ox <= OW'(o[0] + OW'(q_signed[0]));
          ray_oy <= OW'(o[1] + OW'(q_signed[1]));
          ray_oz <= OW'(o[2] + OW'(q_signed[2]));
        end
        if (step == 5'd11) begin
          for (int k = 0; k < 3; k++) begin
            m2[k] <= (2 * MW)'(mul_a[k]);
            dmk[k] <= (DW + MW)'(mul_b[k]);
          end
        end
        if (step == 5'd12) begin
          mm <= MMW'(m2[0]) + MMW'(m2[1]) + MMW'(m2[2]);
          dm <= DMW'(dmk[0]) + DMW'(dmk[1]) + DMW'(dmk[2]);
        end
        if (step == 5'd13) begin
          for (int k = 0; k < 3; k++) begin
            p_dmm[k] <= RRW'(mul_a[k]);
            p_dmm2[k] <= RRW'(mul_b[k]) <<< 1;
          end
        end
        if (step == 5'd14) begin
          for (int k = 0; k < 3; k++) begin
            r[k] <= p_dmm[k] - p_dmm2[k];
            r_abs[k] <= p_dmm[k] >= p_dmm2[k] ? RRW'(p_dmm[k] - p_dmm2[k]) : RRW'(p_dmm2[k] - p_dmm[k]);
          end
        end
        if (step == 5'd15) shift <= length > SW'(DIR_BITS) ? length - SW'(DIR_BITS) : '0;
        if (step == 5'd16) begin
          ray_dx <= scaled(r[0], shift);
          ray_dy <= scaled(r[1], shift);
          ray_dz <= scaled(r[2], shift);
        end
        if (step == 5'd17) begin
          for (int k = 0; k < 3; k++) d2[k] <= (2 * DW)'(mul_a[k]);
        end
        if (step == 5'd18) ray_a <= AAW'(d2[0]) + AAW'(d2[1]) + AAW'(d2[2]);
      end
    end
  end
endmodule
