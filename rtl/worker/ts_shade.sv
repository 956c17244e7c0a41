// The worker's shading: a pixel's colour from its last pass's closest hit, as core::normal_colour and the
// mirror model's mixing in core::trace_pixel_with compute it (src/tripsitter/core/sphere_kernel.h), in the
// device's fixed point (device::FixedArith::floor_div, src/tripsitter/device/worker.h), bit for bit.
//
// Normal-map channel k of a hit (ray o + t d, sphere centre c, radius r, num = t 2a, oc = c - o):
//     clamp(floor((7 n_num + 7 den) / den), 0, 14),   n_num = num d_k - 2a oc_k,  den = 2a r
// which is clamp(floor(Y / den) - 1, 0, 14) with Y = 7 n_num + 8 den = (7 num) d_k - 2a (7 oc_k - 8 r): two
// products and a subtraction. Y < 0 gives 0; otherwise q = floor(Y / den) needs only its 4 low bits, since any
// q >= 15 gives 14: a 4-step restoring divider (compare with den 2^i, subtract) that saturates at 15 by itself.
// A miss is the background (0, 3, 6). After k reflections the channel B is tinted (docs/device.md, "The mirror
// model"): floor(B * prod(albedo) / 255^k), at most B, so again 4 quotient bits from 4 restoring steps.
//
// Stages (each a register):
//   E1  7 num, 7 oc_k - 8 r, den = 2a r (one product)
//   E2  (7 num) d_k and 2a (7 oc_k - 8 r) (six products)
//   E3  Y_k
//   E4  quotient bits 3 and 2 (two compare-and-subtract steps per channel)
//   E5  bits 1 and 0, the clamp, the background      -> the colour without reflections (MAX_BOUNCES = 0)
//   E6  B_k * prod(albedo_k)
//   E7  quotient bits 3 and 2 of the division by 255^k
//   E8  bits 1 and 0                                  -> the colour
// Latency 5 (MAX_BOUNCES = 0) or 8 cycles, a new pixel every cycle.
//
// SHARED = 1 (the one-pixel-at-a-time worker, ts_worker.sv): no multiplier of its own. The products of the
// input's operands come in with it, made in that cycle by the sphere test's multipliers (ts_sphere_test.sv,
// mul_*), and the first two stages become
//   E1  num d_x, num d_y, a oc_k, a r (in); num d_z = 320 num (shifts and adds); den = 2 (a r)
//   E2  7 (num d_k) and 2 (7 a oc_k - 8 a r)
// giving the same Y_k and den, bit for bit. Every ray is then the camera's (no reflections), so d_z is 320.
module ts_shade #(
    parameter int NUMW = 50,
    parameter int OCW = 27,
    parameter int RW = 24,
    parameter int DW = 22,
    parameter int AAW = 42,
    parameter int YW = 75,         // Y, signed
    parameter int MAX_BOUNCES = 3, // 0..3
    parameter int PW = 24,         // the albedo products: 8 MAX_BOUNCES bits (1 when MAX_BOUNCES = 0)
    parameter int SHARED = 0,      // 1: the products come in (in_a_oc*, in_a_r, in_num_d*); camera rays only
    parameter int BW = 49          // SHARED = 1: num's width in num d_x, num d_y (b's: num of a hit is at most b)
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic                   flush,
    input  logic                   in_valid,
    input  logic                   in_hit,
    input  logic signed [NUMW-1:0] in_num,
    input  logic signed [OCW-1:0]  in_ocx,
    input  logic signed [OCW-1:0]  in_ocy,
    input  logic signed [OCW-1:0]  in_ocz,
    input  logic [RW-1:0]          in_r,
    input  logic signed [DW-1:0]   in_dx,
    input  logic signed [DW-1:0]   in_dy,
    input  logic signed [DW-1:0]   in_dz,
    input  logic [AAW-1:0]         in_a,
    // SHARED = 1: products of the inputs above, in the same cycle (unused when SHARED = 0).
    input  logic signed [AAW+OCW:0] in_a_ocx,   // a oc_k
    input  logic signed [AAW+OCW:0] in_a_ocy,
    input  logic signed [AAW+OCW:0] in_a_ocz,
    input  logic [AAW+RW-1:0]      in_a_r,      // a r
    input  logic signed [BW+DW-1:0] in_num_dx,  // num d_x, num d_y
    input  logic signed [BW+DW-1:0] in_num_dy,
    input  logic [PW-1:0]          in_tint_r,  // products of the albedos reflected off (1 without reflections)
    input  logic [PW-1:0]          in_tint_g,
    input  logic [PW-1:0]          in_tint_b,
    input  logic [1:0]             in_bounces,
    input  logic [9:0]             in_col,
    output logic                   out_valid,
    output logic [11:0]            out_colour,
    output logic [1:0]             out_bounces,
    output logic [9:0]             out_col
);
  localparam int N7W = NUMW + 3;                            // 7 num
  localparam int WW = (OCW > RW ? OCW : RW) + 5;            // 7 oc_k - 8 r
  localparam int DENW = AAW + 1 + RW;                       // den = 2a r, exact
  localparam int REMW = YW > DENW + 4 ? YW : DENW + 4;      // the divider's remainder
  localparam int XW = PW + 4;                               // B * prod(albedo)
  localparam logic [11:0] Background = 12'h036;

  // One restoring step: the quotient bit of rem / div, and what remains.
  function automatic logic [REMW:0] den_step(input logic [REMW-1:0] rem, input logic [REMW-1:0] div);
    den_step = rem >= div ? {1'b1, rem - div} : {1'b0, rem};
  endfunction
  // 255^k, the tint's divisor after k reflections.
  function automatic logic [XW-1:0] scale_of(input logic [1:0] k);
    scale_of = XW'(1);
    for (int i = 0; i < 3; i++) if (2'(i) < k) scale_of = XW'(scale_of * XW'(255));
  endfunction
  function automatic logic [XW:0] tint_step(input logic [XW-1:0] rem, input logic [XW-1:0] div);
    tint_step = rem >= div ? {1'b1, rem - div} : {1'b0, rem};
  endfunction

  // ---- E1 and E2: the products (ts_shade's own, or the sphere test's) -------------------------------
  logic                 e1_valid, e1_hit;
  logic [DENW-1:0]      e1_den;
  (* mem2reg *) logic [PW-1:0]        e1_tint[3];
  logic [1:0]           e1_bounces;
  logic [9:0]           e1_col;
  logic [DENW-1:0]      den;        // den of the inputs
  (* mem2reg *) logic signed [YW-1:0] p1[3], p2[3];  // E2's (7 num) d_k and 2a (7 oc_k - 8 r), from the E1 registers

  (* mem2reg *) logic [PW-1:0]         in_tint[3];
  assign in_tint[0] = in_tint_r;
  assign in_tint[1] = in_tint_g;
  assign in_tint[2] = in_tint_b;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      e1_valid <= 1'b0;
      e1_hit <= 1'b0;
      for (int k = 0; k < 3; k++) e1_tint[k] <= '0;
      e1_den <= '0;
      e1_bounces <= '0;
      e1_col <= '0;
    end else begin
      e1_valid <= in_valid;
      e1_hit <= in_hit;
      for (int k = 0; k < 3; k++) e1_tint[k] <= in_tint[k];
      e1_den <= den;
      e1_bounces <= in_bounces;
      e1_col <= in_col;
    end
  end

  if (SHARED == 0) begin : g_own
    logic signed [N7W-1:0] e1_n7;
    (* mem2reg *) logic signed [WW-1:0]  e1_w[3];
    logic [AAW:0]          e1_two_a;
    (* mem2reg *) logic signed [DW-1:0]  e1_d[3];
    (* mem2reg *) logic signed [OCW-1:0] in_oc[3];
    (* mem2reg *) logic signed [DW-1:0]  in_d[3];
    assign in_oc[0] = in_ocx;
    assign in_oc[1] = in_ocy;
    assign in_oc[2] = in_ocz;
    assign in_d[0] = in_dx;
    assign in_d[1] = in_dy;
    assign in_d[2] = in_dz;

    assign den = (DENW'(in_a) * DENW'(in_r)) << 1;
    always_ff @(posedge clk) begin
      if (rst || flush) begin
        e1_n7 <= '0;
        for (int k = 0; k < 3; k++) begin
          e1_w[k] <= '0;
          e1_d[k] <= '0;
        end
        e1_two_a <= '0;
      end else begin
        e1_n7 <= (N7W'(in_num) <<< 3) - N7W'(in_num);
        for (int k = 0; k < 3; k++) begin
          e1_w[k] <= (WW'(in_oc[k]) <<< 3) - WW'(in_oc[k]) - (WW'($signed({1'b0, in_r})) <<< 3);
          e1_d[k] <= in_d[k];
        end
        e1_two_a <= {in_a, 1'b0};
      end
    end
    // The six products (modulo 2^YW: Y fits YW bits).
    for (genvar k = 0; k < 3; k++) begin : g_products
      assign p1[k] = YW'(e1_n7) * YW'(e1_d[k]);
      assign p2[k] = YW'($signed({1'b0, e1_two_a})) * YW'(e1_w[k]);
    end

    /* verilator lint_off UNUSEDSIGNAL */  // own multipliers: the sphere test's shared products are not needed
    logic unused_products;
    /* verilator lint_on UNUSEDSIGNAL */
    assign unused_products = ^{in_a_ocx, in_a_ocy, in_a_ocz, in_a_r, in_num_dx, in_num_dy};
  end else begin : g_shared
    // num d_z: without reflections every ray is the camera's (checked below), whose d_z is 320 (core::device_ray).
    logic signed [YW-1:0] e1_nd[3];   // num d_k
    logic signed [YW-1:0] e1_aoc[3];  // a oc_k
    logic signed [YW-1:0] e1_ar;      // a r
    logic signed [YW-1:0] nd_z;
    assign nd_z = (YW'(in_num) <<< 8) + (YW'(in_num) <<< 6);
    assign den = DENW'({in_a_r, 1'b0});
    always_ff @(posedge clk) begin
      if (rst || flush) begin
        for (int k = 0; k < 3; k++) begin
          e1_nd[k] <= '0;
          e1_aoc[k] <= '0;
        end
        e1_ar <= '0;
      end else begin
        e1_nd[0] <= YW'(in_num_dx);
        e1_nd[1] <= YW'(in_num_dy);
        e1_nd[2] <= nd_z;
        e1_aoc[0] <= YW'(in_a_ocx);
        e1_aoc[1] <= YW'(in_a_ocy);
        e1_aoc[2] <= YW'(in_a_ocz);
        e1_ar <= YW'($signed({1'b0, in_a_r}));
      end
    end
    // (7 num) d_k = 8 (num d_k) - num d_k;  2a (7 oc_k - 8 r) = 16 (a oc_k) - 2 (a oc_k) - 16 (a r).
    for (genvar k = 0; k < 3; k++) begin : g_sums
      assign p1[k] = (e1_nd[k] <<< 3) - e1_nd[k];
      assign p2[k] = (e1_aoc[k] <<< 4) - (e1_aoc[k] <<< 1) - (e1_ar <<< 4);
    end

    /* verilator lint_off UNUSEDSIGNAL */  // shared products: the sphere test multiplied these operands already
    logic unused_operands;
    /* verilator lint_on UNUSEDSIGNAL */
    assign unused_operands = ^{in_ocx, in_ocy, in_ocz, in_r, in_dx, in_dy, in_dz, in_a};
    if (MAX_BOUNCES != 0) begin : g_bad_shared
      $error("ts_shade: SHARED takes num d_z as the camera ray's 320 num: no reflections (MAX_BOUNCES = 0)");
    end
    if (YW < BW + DW || YW < AAW + OCW + 1 || YW < AAW + RW + 1) begin : g_bad_shared_widths
      $error("ts_shade: Y's width must hold the products that come in");
    end
  end

  // ---- E2: (7 num) d_k and 2a (7 oc_k - 8 r) -------------------------------------------------------------
  logic                 e2_valid, e2_hit;
  (* mem2reg *) logic signed [YW-1:0] e2_p1[3], e2_p2[3];
  logic [DENW-1:0]      e2_den;
  (* mem2reg *) logic [PW-1:0]        e2_tint[3];
  logic [1:0]           e2_bounces;
  logic [9:0]           e2_col;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      e2_valid <= 1'b0;
      e2_hit <= 1'b0;
      for (int k = 0; k < 3; k++) begin
        e2_p1[k] <= '0;
        e2_p2[k] <= '0;
        e2_tint[k] <= '0;
      end
      e2_den <= '0;
      e2_bounces <= '0;
      e2_col <= '0;
    end else begin
      e2_valid <= e1_valid;
      e2_hit <= e1_hit;
      for (int k = 0; k < 3; k++) begin
        e2_p1[k] <= p1[k];
        e2_p2[k] <= p2[k];
        e2_tint[k] <= e1_tint[k];
      end
      e2_den <= e1_den;
      e2_bounces <= e1_bounces;
      e2_col <= e1_col;
    end
  end

  // ---- E3: Y -------------------------------------------------------------------------------------------
  logic                 e3_valid, e3_hit;
  (* mem2reg *) logic signed [YW-1:0] e3_y[3];
  logic [DENW-1:0]      e3_den;
  (* mem2reg *) logic [PW-1:0]        e3_tint[3];
  logic [1:0]           e3_bounces;
  logic [9:0]           e3_col;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      e3_valid <= 1'b0;
      e3_hit <= 1'b0;
      for (int k = 0; k < 3; k++) begin
        e3_y[k] <= '0;
        e3_tint[k] <= '0;
      end
      e3_den <= '0;
      e3_bounces <= '0;
      e3_col <= '0;
    end else begin
      e3_valid <= e2_valid;
      e3_hit <= e2_hit;
      for (int k = 0; k < 3; k++) begin
        e3_y[k] <= e2_p1[k] - e2_p2[k];
        e3_tint[k] <= e2_tint[k];
      end
      e3_den <= e2_den;
      e3_bounces <= e2_bounces;
      e3_col <= e2_col;
    end
  end

  // ---- E4: quotient bits 3 and 2 -------------------------------------------------------------------------
  logic                 e4_valid, e4_hit;
  (* mem2reg *) logic                 e4_neg[3];
  (* mem2reg *) logic [1:0]           e4_q[3];
  (* mem2reg *) logic [REMW-1:0]      e4_rem[3];
  logic [DENW-1:0]      e4_den;
  (* mem2reg *) logic [PW-1:0]        e4_tint[3];
  logic [1:0]           e4_bounces;
  logic [9:0]           e4_col;

  (* mem2reg *) logic [REMW:0] e3_s3[3], e3_s2[3];
  for (genvar k = 0; k < 3; k++) begin : g_e4
    assign e3_s3[k] = den_step(REMW'(e3_y[k]), REMW'(e3_den) << 3);
    assign e3_s2[k] = den_step(e3_s3[k][REMW-1:0], REMW'(e3_den) << 2);
  end

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      e4_valid <= 1'b0;
      e4_hit <= 1'b0;
      for (int k = 0; k < 3; k++) begin
        e4_neg[k] <= 1'b0;
        e4_q[k] <= '0;
        e4_rem[k] <= '0;
        e4_tint[k] <= '0;
      end
      e4_den <= '0;
      e4_bounces <= '0;
      e4_col <= '0;
    end else begin
      e4_valid <= e3_valid;
      e4_hit <= e3_hit;
      for (int k = 0; k < 3; k++) begin
        e4_neg[k] <= e3_y[k] < 0;
        e4_q[k] <= {e3_s3[k][REMW], e3_s2[k][REMW]};
        e4_rem[k] <= e3_s2[k][REMW-1:0];
        e4_tint[k] <= e3_tint[k];
      end
      e4_den <= e3_den;
      e4_bounces <= e3_bounces;
      e4_col <= e3_col;
    end
  end

  // ---- E5: quotient bits 1 and 0; the channel ------------------------------------------------------------
  logic       e5_valid;
  (* mem2reg *) logic [3:0] e5_base[3];
  (* mem2reg *) logic [PW-1:0] e5_tint[3];
  logic [1:0] e5_bounces;
  logic [9:0] e5_col;

  (* mem2reg *) logic [REMW:0] e4_s1[3], e4_s0[3];
  (* mem2reg *) logic [3:0]    e4_quot[3], e4_ch[3], e4_base[3];
  for (genvar k = 0; k < 3; k++) begin : g_e5
    assign e4_s1[k] = den_step(e4_rem[k], REMW'(e4_den) << 1);
    assign e4_s0[k] = den_step(e4_s1[k][REMW-1:0], REMW'(e4_den));
    assign e4_quot[k] = {e4_q[k], e4_s1[k][REMW], e4_s0[k][REMW]};
    // floor(Y / den) - 1 clamped to 0..14: 0 for Y < 0 or q = 0, 14 for q = 15 (which stands for any q >= 15).
    assign e4_ch[k] = e4_neg[k] || e4_quot[k] == 4'd0 ? 4'd0 : e4_quot[k] == 4'd15 ? 4'd14 : e4_quot[k] - 4'd1;
    assign e4_base[k] = e4_hit ? e4_ch[k] : Background[4*(2-k)+:4];
  end

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      e5_valid <= 1'b0;
      for (int k = 0; k < 3; k++) begin
        e5_base[k] <= '0;
        e5_tint[k] <= '0;
      end
      e5_bounces <= '0;
      e5_col <= '0;
    end else begin
      e5_valid <= e4_valid;
      for (int k = 0; k < 3; k++) begin
        e5_base[k] <= e4_base[k];
        e5_tint[k] <= e4_tint[k];
      end
      e5_bounces <= e4_bounces;
      e5_col <= e4_col;
    end
  end

  if (MAX_BOUNCES == 0) begin : g_plain
    /* verilator lint_off UNUSEDSIGNAL */  // no bounces: no mirror's tint is ever applied
    logic [PW-1:0] unused_tint[3];
    /* verilator lint_on UNUSEDSIGNAL */
    for (genvar k = 0; k < 3; k++) begin : g_unused
      assign unused_tint[k] = e5_tint[k];
    end
    assign out_valid = e5_valid;
    assign out_colour = {e5_base[0], e5_base[1], e5_base[2]};
    assign out_bounces = e5_bounces;
    assign out_col = e5_col;
  end else begin : g_tint
    // ---- E6: B * prod(albedo) ----------------------------------------------------------------------------
    logic            e6_valid;
    (* mem2reg *) logic [XW-1:0]   e6_x[3];
    logic [XW-1:0]   e6_scale;
    logic [1:0]      e6_bounces;
    logic [9:0]      e6_col;
    always_ff @(posedge clk) begin
      if (rst || flush) begin
        e6_valid <= 1'b0;
        for (int k = 0; k < 3; k++) e6_x[k] <= '0;
        e6_scale <= '0;
        e6_bounces <= '0;
        e6_col <= '0;
      end else begin
        e6_valid <= e5_valid;
        for (int k = 0; k < 3; k++) e6_x[k] <= XW'(e5_base[k]) * XW'(e5_tint[k]);
        e6_scale <= scale_of(e5_bounces);
        e6_bounces <= e5_bounces;
        e6_col <= e5_col;
      end
    end

    // ---- E7: quotient bits 3 and 2 of the division by 255^k ------------------------------------------------
    logic            e7_valid;
    (* mem2reg *) logic [1:0]      e7_q[3];
    (* mem2reg *) logic [XW-1:0]   e7_rem[3];
    logic [XW-1:0]   e7_scale;
    logic [1:0]      e7_bounces;
    logic [9:0]      e7_col;
    (* mem2reg *) logic [XW:0]     e6_s3[3], e6_s2[3];
    for (genvar k = 0; k < 3; k++) begin : g_e7
      assign e6_s3[k] = tint_step(e6_x[k], e6_scale << 3);
      assign e6_s2[k] = tint_step(e6_s3[k][XW-1:0], e6_scale << 2);
    end
    always_ff @(posedge clk) begin
      if (rst || flush) begin
        e7_valid <= 1'b0;
        for (int k = 0; k < 3; k++) begin
          e7_q[k] <= '0;
          e7_rem[k] <= '0;
        end
        e7_scale <= '0;
        e7_bounces <= '0;
        e7_col <= '0;
      end else begin
        e7_valid <= e6_valid;
        for (int k = 0; k < 3; k++) begin
          e7_q[k] <= {e6_s3[k][XW], e6_s2[k][XW]};
          e7_rem[k] <= e6_s2[k][XW-1:0];
        end
        e7_scale <= e6_scale;
        e7_bounces <= e6_bounces;
        e7_col <= e6_col;
      end
    end

    // ---- E8: bits 1 and 0: the channel (at most B, so no clamp is needed) ------------------------------------
    (* mem2reg *) logic [XW:0] e7_s1[3], e7_s0[3];
    (* mem2reg *) logic [3:0]  e7_ch[3];
    for (genvar k = 0; k < 3; k++) begin : g_e8
      assign e7_s1[k] = tint_step(e7_rem[k], e7_scale << 1);
      assign e7_s0[k] = tint_step(e7_s1[k][XW-1:0], e7_scale);
      assign e7_ch[k] = {e7_q[k], e7_s1[k][XW], e7_s0[k][XW]};
    end
    always_ff @(posedge clk) begin
      if (rst || flush) begin
        out_valid <= 1'b0;
        out_colour <= '0;
        out_bounces <= '0;
        out_col <= '0;
      end else begin
        out_valid <= e7_valid;
        out_colour <= {e7_ch[0], e7_ch[1], e7_ch[2]};
        out_bounces <= e7_bounces;
        out_col <= e7_col;
      end
    end
  end
endmodule
