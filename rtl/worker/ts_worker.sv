// One ray-tracing worker: the pixel (col, row) traced against every sphere of scene memory in the mirror
// model, bit for bit device::Worker::trace (src/tripsitter/device/worker.h; core::trace_pixel in
// src/tripsitter/core/sphere_kernel.h): the closest hit over all spheres (ties to the lower index), a metal
// reflects while fewer than MAX_BOUNCES reflections were traced (the reflected ray against every sphere but
// the metal it leaves) and tints what its ray sees by its albedo, anything else is normal-map shaded, a miss is
// 0x036. It reports the colour and the number of reflections, cycle for cycle with the model's schedule
// (DevicePreset::pixel_occupancy and drain_cycles, src/tripsitter/device/preset.cpp; docs/device.md, "Cycle
// costs").
//
// Ports. A pixel: `start` with col, row in a cycle where `ready` is high. Scene memory: the worker reads sphere
// sphere_addr with sphere_rd, and its fields arrive in the next cycle (a registered read, like block RAM);
// sphere_count spheres are in memory (constant during a frame). The result: `done` for one cycle with done_col,
// colour and bounces. `flush` (from the controller, at the end of a line's window) drops every pixel in flight:
// a done pulse due in the flush cycle is still given, none after it, and the worker is ready in the next cycle.
//
// Timing (the controller's contract). A pixel started in cycle s that reflects k times makes the worker ready
// again in cycle s + pixel_occupancy(spheres, k) and gives its done pulse in cycle
// s + pixel_occupancy(spheres, k) + drain_cycles() - 1, where with n spheres
//   PIPELINED = 0 (board-2023): occupancy 2 + (k + 1) n 45 + 10 k + 4, drain 0    (MAX_BOUNCES must be 0)
//   PIPELINED = 1 (wide):       occupancy (k + 1) max(n, 1) + 41 k,   drain 35
// For the pipelined worker, whether a pixel reflects is known only 26 cycles after its last pair was issued,
// while a pixel that does not reflect frees the worker at once: so the worker issues speculatively. It keeps
// the pixels in flight in a queue (in order), raises `ready` whenever the model would let the next pixel start
// if nothing reflects, and when a pass ends on a metal it squashes every younger pair, reflects, issues the
// reflected pass's first pair 42 cycles after the pass's last one (the model's pass latency of 31 and its
// reflection of 10: the 41 cycles in between are the occupancy's stall), and then re-issues the squashed
// pixels from the queue, ready only once they are issued again. Pixels started back to
// back (as the controller starts them) so get exactly the model's times, counted from the first pixel's start;
// a pixel started speculatively and squashed gets its done pulse where the model's schedule puts it, which is
// later than "its start + its occupancy + drain" by the occupancy of the reflections that overtook it.
//
// The datapath (pair = one ray against one sphere; cycle t = the pair's issue):
//   t            issue: sphere_addr, and the pair's tag into S0
//   t+1..t+26    ts_sphere_test.sv: num = b - sqrt(D) and the hit (25 cycles, one stage per square-root
//                iteration; 41 cycles with the board's iterative square root)
//   t+26         the closest update; on the pass's last pair the pass ends: the closest hit is final
//   t+27..       ts_shade.sv (5 cycles, 8 with the tint) and a delay to the drain, or ts_reflect.sv (19 cycles)
// Widths follow docs/device.md, "Widths" (below).
//
// The clock. The worker runs on a gated clock (ts_clock_gate: a BUFGCE on the chip) with an edge at start, flush and
// reset and while it is busy (a pixel in flight, a reflection stall, and the drain after the last pixel retires):
// in every other cycle no register would change but a data register its valid bit masks. An idle worker costs the
// chip no clock power and the simulation nothing (docs/rtl.md, "The workers' clocks").
//
// Multipliers (DSP48E1 slices on the board's FPGA). The pipelined worker gives every product its own. The
// one-pixel-at-a-time worker issues a pair every PER_SPHERE cycles, and the sphere test multiplies in three of
// them: t+1 (the camera ray's squares, on two of S2's multipliers), t+2 (S2) and t+4 (b^2 and 4ac'). Its shading
// multiplies once, in cycle PASS_END after the last pair's issue, which falls after that pair's t+4 and before the
// next pixel's first pair (g_bad_slot below: the shading ends inside the last sphere's slot, before the worker is
// ready again). So the shading borrows the sphere test's multipliers (ts_sphere_test.sv, mul_*; ts_shade.sv with
// SHARED = 1), and the occupancy's n PER_SPHERE is shifts and adds: the worker has no multiplier of its own.
module ts_worker #(
    parameter int X_W = 24,                      // scene memory's formats: x, y, z signed, radius unsigned
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int SQRT_ITERATIONS = 16,
    parameter int SQRT_CYCLES_PER_ITERATION = 2, // PIPELINED = 0 only: the iterative square root's
    parameter int MAX_BOUNCES = 3,               // 0..3 (PIPELINED = 0: 0)
    parameter int AW = 12,                       // sphere index bits (scene memory of 2^AW spheres)
    parameter int PIPELINED = 1
) (
    input  logic                  clk,
    input  logic                  rst,
    input  logic                  flush,
    input  logic                  start,
    input  logic [9:0]            col,
    input  logic [8:0]            row,
    output logic                  ready,
    output logic [AW-1:0]         sphere_addr,
    output logic                  sphere_rd,
    input  logic signed [X_W-1:0] sphere_x,
    input  logic signed [Y_W-1:0] sphere_y,
    input  logic signed [Z_W-1:0] sphere_z,
    input  logic [R_W-1:0]        sphere_r,
    input  logic                  sphere_metal,
    input  logic [23:0]           sphere_albedo,  // r, g, b bytes from the high byte down
    input  logic [AW:0]           sphere_count,
    output logic                  done,
    output logic [9:0]            done_col,
    output logic [11:0]           colour,
    output logic [1:0]            bounces
);
  // ---- widths (docs/device.md, "Widths") ----------------------------------------------------------------
  // With reflections, the table's bounds for formats of up to 24 bits (each length adds EXTRA bits beyond):
  // directions of 22 bits (|d_k| <= 2^20), a < 2^42, origins and hit normals < 2^25, oc < 2^26, b < 2^48,
  // c' < 2^51, b^2 and 4ac' < 2^95, num < 2^49, Y = 7 n_num + 8 den < 2^74. Without, only the camera's rays
  // (o = 0, |d_k| <= 320, a <= 262400 < 2^19), bounded from the formats: with L = max(coordinate, radius bits),
  // |b| <= 2 (320 + 240 + 320) 2^(CW-1) < 2^(CW+10), |c'| < 2^2L, b^2 < 2^(2CW+20), |4ac'| < 2^(2L+21),
  // |Y| < 2^(L+24). (board-2023: b 27 bits, D 54, the square root's input 53.)
  localparam int CW = X_W > Y_W ? (X_W > Z_W ? X_W : Z_W) : (Y_W > Z_W ? Y_W : Z_W);
  localparam int LW = CW > R_W ? CW : R_W;
  localparam int EXTRA = LW > 24 ? LW - 24 : 0;
  localparam bit REFLECT = MAX_BOUNCES > 0;
  localparam int DW = REFLECT ? 22 : 10;
  localparam int AAW = REFLECT ? 42 : 19;
  localparam int OW = REFLECT ? 26 + EXTRA : 1;
  localparam int OCW = REFLECT ? 27 + EXTRA : CW;
  localparam int BW = REFLECT ? 49 + EXTRA : CW + 11;
  localparam int CPW = REFLECT ? 52 + 2 * EXTRA : 2 * LW + 1;
  localparam int SQM = REFLECT ? 95 + 2 * EXTRA : (2 * CW + 20 > 2 * LW + 21 ? 2 * CW + 20 : 2 * LW + 21);
  localparam int DSW = SQM + 1;
  localparam int RTW = (SQM + 1) / 2 + 1;
  localparam int NUMW = (BW > RTW + 1 ? BW : RTW + 1) + 1;
  localparam int YW = REFLECT ? 75 + EXTRA : LW + 25;
  localparam int PW = REFLECT ? 8 * MAX_BOUNCES : 1;  // products of albedo bytes
  localparam int TAG_W = 2 + AW + 1 + 24;             // first, last, sphere index, metal, albedo

  // ---- cycle costs (DevicePreset::costs of both presets) ------------------------------------------------
  localparam int PIXEL_SETUP = 2;
  localparam int SPHERE_TEST = 12;
  localparam int CLOSEST_UPDATE = 1;
  localparam int SHADE = 4;
  localparam int REFLECT_CYCLES = 10;
  localparam int SQRT_CYCLES = SQRT_ITERATIONS * (PIPELINED != 0 ? 1 : SQRT_CYCLES_PER_ITERATION);
  localparam int PER_SPHERE = SPHERE_TEST + SQRT_CYCLES + CLOSEST_UPDATE;  // 45 (board), 29 (wide)
  localparam int PASS_LATENCY = PIXEL_SETUP + PER_SPHERE;                  // 31 (wide)
  localparam int DRAIN = PIXEL_SETUP + PER_SPHERE + SHADE;                 // 35 (wide)
  // This datapath's own latencies, from a pair's issue: the closest update sees it at CAND, the pass's end is
  // registered at PASS_END, the shade's colour comes SHADE_LAT later.
  localparam int TEST_LAT = 6 + SQRT_ITERATIONS * (PIPELINED != 0 ? 1 : SQRT_CYCLES_PER_ITERATION) + 3;
  localparam int CAND = 1 + TEST_LAT;         // 26 (wide), 42 (board)
  localparam int PASS_END = CAND + 1;
  localparam int SHADE_LAT = REFLECT ? 8 : 5;

  if (MAX_BOUNCES < 0 || MAX_BOUNCES > 3) begin : g_bad_bounces
    $error("ts_worker: MAX_BOUNCES must be 0..3 (the bounces port has 2 bits)");
  end
  if (PIPELINED == 0 && MAX_BOUNCES != 0) begin : g_bad_sequential
    $error("ts_worker: the one-pixel-at-a-time worker has no reflection unit (MAX_BOUNCES must be 0)");
  end
  if (REFLECT && EXTRA != 0) begin : g_bad_formats
    $error("ts_worker: reflections are built for formats of at most 24 bits");
  end
  if (PIPELINED != 0 && PASS_END + SHADE_LAT > DRAIN) begin : g_bad_drain
    $error("ts_worker: the shading does not fit the drain");
  end
  // The pipelined worker's reflection stall: from the squash (in the cycle the pass's last pair is at the closest
  // update) to the reflected pass's first pair, which is issued PASS_LATENCY + REFLECT_CYCLES cycles after the
  // last pair's issue cycle ends.
  localparam int STALL = 1 + PASS_LATENCY + REFLECT_CYCLES - CAND - 1;
  if (PIPELINED != 0 && (STALL < 1 || STALL > 31)) begin : g_bad_stall
    $error("ts_worker: the reflection stall does not fit its counter");
  end
  // One pixel at a time: the last sphere's colour must be held by the done pulse (occupancy - 1 after start).
  if (PIPELINED == 0 && PASS_END + SHADE_LAT + 1 > PER_SPHERE + PIXEL_SETUP + SHADE - 1) begin : g_bad_slot
    $error("ts_worker: the shading does not fit the last sphere's slot");
  end

  localparam logic [11:0] Background = 12'h036;

  // ---- the worker's clock: gated (ts_clock_gate) to the cycles in which any of its registers can change ------
  logic gclk;
  logic busy_any;  // a pixel is in flight, or its colour is on its way to the done pulse
  ts_clock_gate gate (.clk, .en(rst || flush || start || busy_any), .gclk);


  // ---- issue: the pair's tag (S0); the sphere's fields arrive with it in the next cycle -------------------
  logic              issue;        // a pair is issued this cycle
  logic [AW:0]       issue_j;      // its sphere
  logic              issue_first, issue_last, issue_refl, issue_kill;
  logic [9:0]        issue_col;
  logic [8:0]        issue_row;
  logic              squash;       // the closest update reflects: drop every younger pair
  logic              s0_valid, s0_first, s0_last, s0_refl, s0_kill;
  logic [AW-1:0]     s0_idx;
  logic [9:0]        s0_col;
  logic [8:0]        s0_row;

  assign sphere_addr = issue_j[AW-1:0];
  assign sphere_rd = issue;

  always_ff @(posedge gclk) begin
    if (rst || flush || squash) begin
      s0_valid <= 1'b0;
      s0_first <= 1'b0;
      s0_last <= 1'b0;
      s0_refl <= 1'b0;
      s0_kill <= 1'b0;
      s0_idx <= '0;
      s0_col <= '0;
      s0_row <= '0;
    end else begin
      s0_valid <= issue;
      s0_first <= issue_first;
      s0_last <= issue_last;
      s0_refl <= issue_refl;
      s0_kill <= issue_kill;
      s0_idx <= issue_j[AW-1:0];
      s0_col <= issue_col;
      s0_row <= issue_row;
    end
  end

  // ---- the sphere test ---------------------------------------------------------------------------------
  // The pass's end (registered below), the shading's operands, and their products, which the one-pixel worker
  // makes on the sphere test's multipliers (0 when pipelined: the shading has its own).
  logic                    shade_start;
  logic signed [NUMW-1:0]  pe_num;
  (* mem2reg *) logic signed [OCW-1:0]   pe_oc[3];
  logic [R_W-1:0]          pe_r;
  (* mem2reg *) logic signed [DW-1:0]    pe_d[3];
  logic [AAW-1:0]          pe_a;
  (* mem2reg *) logic signed [AAW+OCW:0] pe_a_oc[3];
  logic [AAW+R_W-1:0]      pe_a_r;
  (* mem2reg *) logic signed [BW+DW-1:0] pe_num_d[2];

  (* mem2reg *) logic signed [OW-1:0]   ray_o[3];   // the reflected ray (ts_reflect); 0 without reflections
  (* mem2reg *) logic signed [DW-1:0]   ray_d[3];
  logic [AAW-1:0]         ray_a;

  logic                   ct_valid, ct_refl, ct_hit;
  logic [TAG_W-1:0]       ct_tag;
  logic [9:0]             ct_col;
  logic [8:0]             ct_row;
  logic [18:0]            ct_a_cam;
  logic signed [NUMW-1:0] ct_num;
  (* mem2reg *) logic signed [OCW-1:0]  ct_oc[3];
  logic [R_W-1:0]         ct_r;
  logic                   ct_first, ct_last, ct_metal;
  logic [AW-1:0]          ct_idx;
  logic [23:0]            ct_albedo;
  assign {ct_first, ct_last, ct_idx, ct_metal, ct_albedo} = ct_tag;

  ts_sphere_test #(
      .CW(CW), .RW(R_W), .DW(DW), .OW(OW), .OCW(OCW), .AAW(AAW), .BW(BW), .CPW(CPW), .DSW(DSW), .SQW(SQM),
      .NUMW(NUMW), .ITERATIONS(SQRT_ITERATIONS), .PIPELINED(PIPELINED),
      .CYCLES_PER_ITERATION(PIPELINED != 0 ? 1 : SQRT_CYCLES_PER_ITERATION), .TAG_W(TAG_W)
  ) u_test (
      .clk(gclk),
      .rst(rst),
      .flush(flush || squash),
      .in_valid(s0_valid),
      .in_tag({s0_first, s0_last, s0_idx, sphere_metal, sphere_albedo}),
      .in_refl(s0_refl),
      .in_kill(s0_kill),
      .in_col(s0_col),
      .in_row(s0_row),
      .in_cx(CW'(sphere_x)),
      .in_cy(CW'(sphere_y)),
      .in_cz(CW'(sphere_z)),
      .in_r(sphere_r),
      .refl_ox(ray_o[0]),
      .refl_oy(ray_o[1]),
      .refl_oz(ray_o[2]),
      .refl_dx(ray_d[0]),
      .refl_dy(ray_d[1]),
      .refl_dz(ray_d[2]),
      .refl_a(ray_a),
      .mul_shade(shade_start),
      .mul_a(pe_a),
      .mul_ocx(pe_oc[0]),
      .mul_ocy(pe_oc[1]),
      .mul_ocz(pe_oc[2]),
      .mul_r(pe_r),
      .mul_num(BW'(pe_num)),
      .mul_dx(pe_d[0]),
      .mul_dy(pe_d[1]),
      .mul_a_ocx(pe_a_oc[0]),
      .mul_a_ocy(pe_a_oc[1]),
      .mul_a_ocz(pe_a_oc[2]),
      .mul_a_r(pe_a_r),
      .mul_num_dx(pe_num_d[0]),
      .mul_num_dy(pe_num_d[1]),
      .out_valid(ct_valid),
      .out_tag(ct_tag),
      .out_refl(ct_refl),
      .out_col(ct_col),
      .out_row(ct_row),
      .out_a_cam(ct_a_cam),
      .out_hit(ct_hit),
      .out_num(ct_num),
      .out_ocx(ct_oc[0]),
      .out_ocy(ct_oc[1]),
      .out_ocz(ct_oc[2]),
      .out_r(ct_r)
  );

  // ---- the closest update: the pass's nearest hit so far; ties keep the lower index ----------------------
  logic                   acc_hit, acc_metal;
  logic signed [NUMW-1:0] acc_num;
  (* mem2reg *) logic signed [OCW-1:0]  acc_oc[3];
  logic [R_W-1:0]         acc_r;
  logic [AW-1:0]          acc_idx;
  logic [23:0]            acc_albedo;

  logic                   better, fin_hit, fin_metal;
  logic signed [NUMW-1:0] fin_num;
  (* mem2reg *) logic signed [OCW-1:0]  fin_oc[3];
  logic [R_W-1:0]         fin_r;
  logic [AW-1:0]          fin_idx;
  logic [23:0]            fin_albedo;
  logic                   pass_end;
  logic [1:0]             head_k;     // reflections traced so far for the oldest pixel in flight
  (* mem2reg *) logic [PW-1:0]          head_p[3];  // their albedos' products
  logic                   reflect_now;

  assign better = ct_hit && (ct_first || !acc_hit || ct_num < acc_num);
  assign fin_hit = better || (!ct_first && acc_hit);
  assign fin_metal = better ? ct_metal : acc_metal;
  assign fin_num = better ? ct_num : acc_num;
  assign fin_r = better ? ct_r : acc_r;
  assign fin_idx = better ? ct_idx : acc_idx;
  assign fin_albedo = better ? ct_albedo : acc_albedo;
  for (genvar k = 0; k < 3; k++) begin : g_fin
    assign fin_oc[k] = better ? ct_oc[k] : acc_oc[k];
  end
  assign pass_end = ct_valid && ct_last;
  assign reflect_now = REFLECT && pass_end && fin_hit && fin_metal && 32'(head_k) < MAX_BOUNCES;
  assign squash = reflect_now;

  always_ff @(posedge gclk) begin
    if (rst || flush) begin
      acc_hit <= 1'b0;
      acc_metal <= 1'b0;
      acc_num <= '0;
      for (int k = 0; k < 3; k++) acc_oc[k] <= '0;
      acc_r <= '0;
      acc_idx <= '0;
      acc_albedo <= '0;
    end else if (ct_valid) begin
      acc_hit <= fin_hit;
      acc_metal <= fin_metal;
      acc_num <= fin_num;
      for (int k = 0; k < 3; k++) acc_oc[k] <= fin_oc[k];
      acc_r <= fin_r;
      acc_idx <= fin_idx;
      acc_albedo <= fin_albedo;
    end
  end

  // ---- the pass's end: to the shading, or to the reflection ---------------------------------------------
  logic                   pe_valid, pe_reflect, pe_hit, pe_refl;
  logic [23:0]            pe_albedo;
  logic [9:0]             pe_col;
  logic [8:0]             pe_row;
  logic [18:0]            pe_a_cam;
  logic [1:0]             pe_k;
  (* mem2reg *) logic [PW-1:0]          pe_p[3];

  always_ff @(posedge gclk) begin
    if (rst || flush) begin
      pe_valid <= 1'b0;
      pe_reflect <= 1'b0;
      pe_hit <= 1'b0;
      pe_refl <= 1'b0;
      pe_num <= '0;
      for (int k = 0; k < 3; k++) begin
        pe_oc[k] <= '0;
        pe_p[k] <= '0;
      end
      pe_r <= '0;
      pe_albedo <= '0;
      pe_col <= '0;
      pe_row <= '0;
      pe_a_cam <= '0;
      pe_k <= '0;
    end else begin
      pe_valid <= pass_end;
      pe_reflect <= reflect_now;
      pe_hit <= fin_hit;
      pe_refl <= ct_refl;
      pe_num <= fin_num;
      for (int k = 0; k < 3; k++) begin
        pe_oc[k] <= fin_oc[k];
        pe_p[k] <= head_p[k];
      end
      pe_r <= fin_r;
      pe_albedo <= fin_albedo;
      pe_col <= ct_col;
      pe_row <= ct_row;
      pe_a_cam <= ct_a_cam;
      pe_k <= head_k;
    end
  end

  // The pass's ray: the camera's, or the reflected one it was traced along.
  logic signed [DW-1:0] pe_cam_dx, pe_cam_dy;
  ts_pixel_ray #(.DW(DW)) pe_camera (.col(pe_col), .row(pe_row), .dx(pe_cam_dx), .dy(pe_cam_dy));
  assign pe_d[0] = pe_refl ? ray_d[0] : pe_cam_dx;
  assign pe_d[1] = pe_refl ? ray_d[1] : pe_cam_dy;
  assign pe_d[2] = pe_refl ? ray_d[2] : DW'(320);
  assign pe_a = pe_refl ? ray_a : AAW'(pe_a_cam);

  logic        sh_valid;
  logic [11:0] sh_colour;
  logic [1:0]  sh_bounces;
  logic [9:0]  sh_col;

  assign shade_start = pe_valid && !pe_reflect;

  ts_shade #(
      .NUMW(NUMW), .OCW(OCW), .RW(R_W), .DW(DW), .AAW(AAW), .YW(YW), .MAX_BOUNCES(MAX_BOUNCES), .PW(PW),
      .SHARED(PIPELINED == 0 ? 1 : 0), .BW(BW)
  ) u_shade (
      .clk(gclk),
      .rst(rst),
      .flush(flush),
      .in_valid(shade_start),
      .in_hit(pe_hit),
      .in_num(pe_num),
      .in_ocx(pe_oc[0]),
      .in_ocy(pe_oc[1]),
      .in_ocz(pe_oc[2]),
      .in_r(pe_r),
      .in_dx(pe_d[0]),
      .in_dy(pe_d[1]),
      .in_dz(pe_d[2]),
      .in_a(pe_a),
      .in_a_ocx(pe_a_oc[0]),
      .in_a_ocy(pe_a_oc[1]),
      .in_a_ocz(pe_a_oc[2]),
      .in_a_r(pe_a_r),
      .in_num_dx(pe_num_d[0]),
      .in_num_dy(pe_num_d[1]),
      .in_tint_r(pe_p[0]),
      .in_tint_g(pe_p[1]),
      .in_tint_b(pe_p[2]),
      .in_bounces(pe_k),
      .in_col(pe_col),
      .out_valid(sh_valid),
      .out_colour(sh_colour),
      .out_bounces(sh_bounces),
      .out_col(sh_col)
  );

  // The reflected ray, and the oldest pixel's reflections (the only pixel that can have any).
  if (REFLECT) begin : g_reflect
    (* mem2reg *) logic signed [OW-1:0] pe_o[3];
    for (genvar k = 0; k < 3; k++) begin : g_pe_o
      assign pe_o[k] = pe_refl ? ray_o[k] : '0;
    end
    ts_reflect #(.NUMW(NUMW), .OCW(OCW), .OW(OW), .DW(DW), .AAW(AAW)) u_reflect (
        .clk(gclk),
        .rst(rst),
        .flush(flush),
        .in_valid(pe_valid && pe_reflect),
        .in_num(pe_num),
        .in_ocx(pe_oc[0]),
        .in_ocy(pe_oc[1]),
        .in_ocz(pe_oc[2]),
        .in_ox(pe_o[0]),
        .in_oy(pe_o[1]),
        .in_oz(pe_o[2]),
        .in_dx(pe_d[0]),
        .in_dy(pe_d[1]),
        .in_dz(pe_d[2]),
        .in_a(pe_a),
        .ray_ox(ray_o[0]),
        .ray_oy(ray_o[1]),
        .ray_oz(ray_o[2]),
        .ray_dx(ray_d[0]),
        .ray_dy(ray_d[1]),
        .ray_dz(ray_d[2]),
        .ray_a(ray_a)
    );
  end else begin : g_no_reflect
    for (genvar k = 0; k < 3; k++) begin : g_zero
      assign ray_o[k] = '0;
      assign ray_d[k] = '0;
    end
    assign ray_a = '0;
  end

  // head_k, head_p: reset when the oldest pixel retires; a reflection adds one and multiplies in the metal's
  // albedo (one cycle later, from the pass-end registers).
  always_ff @(posedge gclk) begin
    if (rst || flush) begin
      head_k <= '0;
      for (int k = 0; k < 3; k++) head_p[k] <= PW'(1);
    end else if (reflect_now) begin
      head_k <= head_k + 2'd1;
    end else if (pass_end) begin
      head_k <= '0;
      for (int k = 0; k < 3; k++) head_p[k] <= PW'(1);
    end else if (pe_valid && pe_reflect) begin
      for (int k = 0; k < 3; k++) head_p[k] <= PW'(head_p[k] * PW'(pe_albedo[8*(2-k)+:8]));
    end
  end

  if (PIPELINED != 0) begin : g_pipelined
    // ---- speculative in-order issue ------------------------------------------------------------------------
    localparam int QAW = 5;                 // a queue of 32 pixels: at most CAND + 1 are ever in flight
    localparam int QD = 1 << QAW;

    logic [9:0]   q_col[QD];  // the pixels in flight, oldest first (a small memory: written before read)
    logic [8:0]   q_row[QD];
    logic [QAW:0] head, iss, tail;
    logic         active;     // issuing a pass (of the entry iss)
    logic         pass_refl;  // that pass is the oldest pixel's reflected pass
    logic [AW:0]  j;          // the next sphere of the pass
    logic [4:0]   stall;      // cycles of the reflection stall left
    logic [AW-1:0] excl;      // the metal the reflected ray leaves
    logic [AW:0]  n_eff;
    logic [QAW:0] in_flight;
    logic         take;       // the controller's pixel starts now

    // After the oldest pixel retires its colour takes DRAIN - PASS_END more cycles to its done pulse: the clock
    // runs on for DRAIN cycles after the last cycle with a pixel in flight (a counter on the free-running clock).
    logic [5:0] linger;
    always_ff @(posedge clk) begin
      if (rst) linger <= '0;
      else if (take || in_flight != '0 || stall != '0) linger <= 6'(DRAIN);
      else if (linger != '0) linger <= linger - 6'd1;
    end
    assign busy_any = in_flight != '0 || stall != '0 || linger != '0;

    assign n_eff = sphere_count == '0 ? (AW + 1)'(1) : sphere_count;
    assign in_flight = tail - head;
    assign ready = !active && stall == '0 && in_flight < (QAW + 1)'(QD - 1);
    assign take = start && ready;
    assign issue = active || take;
    assign issue_j = active ? j : '0;
    assign issue_first = issue_j == '0;
    assign issue_last = issue_j == n_eff - (AW + 1)'(1);
    assign issue_refl = active && pass_refl;
    assign issue_kill = sphere_count == '0 || (issue_refl && issue_j[AW-1:0] == excl);
    assign issue_col = active ? q_col[iss[QAW-1:0]] : col;
    assign issue_row = active ? q_row[iss[QAW-1:0]] : row;

    always_ff @(posedge gclk) begin
      if (take) begin
        q_col[tail[QAW-1:0]] <= col;
        q_row[tail[QAW-1:0]] <= row;
      end
    end

    always_ff @(posedge gclk) begin
      if (rst || flush) begin
        head <= '0;
        iss <= '0;
        tail <= '0;
        active <= 1'b0;
        pass_refl <= 1'b0;
        j <= '0;
        stall <= '0;
        excl <= '0;
      end else begin
        if (take) tail <= tail + (QAW + 1)'(1);
        if (pass_end && !reflect_now) head <= head + (QAW + 1)'(1);  // the oldest pixel retires
        if (reflect_now) begin
          excl <= fin_idx;
          active <= 1'b0;
          pass_refl <= 1'b0;
          stall <= 5'(STALL);
          iss <= head;
        end else if (stall != '0) begin
          stall <= stall - 5'd1;
          if (stall == 5'd1) begin  // the reflected pass starts next cycle
            active <= 1'b1;
            pass_refl <= 1'b1;
            j <= '0;
          end
        end else if (active) begin
          if (issue_last) begin  // the pass is issued: on to the next pixel in the queue (a squashed one)
            pass_refl <= 1'b0;
            j <= '0;
            iss <= iss + (QAW + 1)'(1);
            active <= iss + (QAW + 1)'(1) != tail;
          end else begin
            j <= j + (AW + 1)'(1);
          end
        end else if (take) begin
          if (issue_last) iss <= iss + (QAW + 1)'(1);
          else begin
            active <= 1'b1;
            j <= (AW + 1)'(1);
          end
        end
      end
    end

    // ---- the colour: the shade's, delayed to the drain ----------------------------------------------------
    localparam int DELAY = DRAIN - PASS_END - SHADE_LAT;
    (* mem2reg *) logic        dl_valid[DELAY+1];
    (* mem2reg *) logic [9:0]  dl_col[DELAY+1];
    (* mem2reg *) logic [11:0] dl_colour[DELAY+1];
    (* mem2reg *) logic [1:0]  dl_bounces[DELAY+1];
    assign dl_valid[0] = sh_valid;
    assign dl_col[0] = sh_col;
    assign dl_colour[0] = sh_colour;
    assign dl_bounces[0] = sh_bounces;
    for (genvar i = 0; i < DELAY; i++) begin : g_delay
      always_ff @(posedge gclk) begin
        if (rst || flush) begin
          dl_valid[i+1] <= 1'b0;
          dl_col[i+1] <= '0;
          dl_colour[i+1] <= '0;
          dl_bounces[i+1] <= '0;
        end else begin
          dl_valid[i+1] <= dl_valid[i];
          dl_col[i+1] <= dl_col[i];
          dl_colour[i+1] <= dl_colour[i];
          dl_bounces[i+1] <= dl_bounces[i];
        end
      end
    end
    assign done = dl_valid[DELAY];
    assign done_col = dl_col[DELAY];
    assign colour = dl_colour[DELAY];
    assign bounces = dl_bounces[DELAY];
  end else begin : g_sequential
    // ---- one pixel at a time: a sphere every PER_SPHERE cycles, the colour when the occupancy ends -----------
    localparam int CNTW = AW + 8;
    logic [CNTW-1:0] busy;     // cycles until ready
    logic [5:0]      slot;     // cycles until the next sphere's issue
    logic [AW:0]     j;        // the next sphere
    logic [AW:0]     n;        // the pixel's spheres
    logic [9:0]      px_col;
    logic [8:0]      px_row;
    logic [11:0]     result;   // the shade's colour, held until the done pulse
    logic            take;
    logic [AW:0]     n_now;

    // n PER_SPHERE: a constant multiply, so shifts and adds (a multiplier here would cost a DSP48E1 slice).
    function automatic logic [CNTW-1:0] times_per_sphere(input logic [AW:0] count);
      times_per_sphere = '0;
      for (int i = 0; i < 31; i++)
        if (((PER_SPHERE >> i) & 1) != 0) times_per_sphere = times_per_sphere + (CNTW'(count) << i);
    endfunction

    assign ready = busy == '0;
    assign take = start && ready;
    assign busy_any = busy != '0;
    assign n_now = take ? sphere_count : n;
    assign issue = take ? sphere_count != '0 : busy != '0 && slot == '0 && j < n;
    assign issue_j = take ? '0 : j;
    assign issue_first = issue_j == '0;
    assign issue_last = issue_j == n_now - (AW + 1)'(1);
    assign issue_refl = 1'b0;
    assign issue_kill = 1'b0;
    assign issue_col = take ? col : px_col;
    assign issue_row = take ? row : px_row;

    always_ff @(posedge gclk) begin
      if (rst || flush) begin
        busy <= '0;
        slot <= '0;
        j <= '0;
        n <= '0;
        px_col <= '0;
        px_row <= '0;
        result <= '0;
      end else begin
        if (take) begin
          // occupancy - 1 = PIXEL_SETUP + n PER_SPHERE + SHADE - 1
          busy <= CNTW'(PIXEL_SETUP + SHADE - 1) + times_per_sphere(sphere_count);
          slot <= 6'(PER_SPHERE - 1);
          j <= (AW + 1)'(1);
          n <= sphere_count;
          px_col <= col;
          px_row <= row;
        end else if (busy != '0) begin
          busy <= busy - CNTW'(1);
          if (slot == '0) begin
            slot <= 6'(PER_SPHERE - 1);
            if (j < n) j <= j + (AW + 1)'(1);
          end else begin
            slot <= slot - 6'd1;
          end
        end
        if (sh_valid) result <= sh_colour;
      end
    end

    /* verilator lint_off UNUSEDSIGNAL */  // the shading's bounce count and column: this worker tracks its own pixel
    logic [11:0] unused;
    /* verilator lint_on UNUSEDSIGNAL */
    assign unused = {sh_bounces, sh_col};
    assign done = busy == CNTW'(1);
    assign done_col = px_col;
    assign colour = n == '0 ? Background : result;
    assign bounces = 2'd0;
  end
endmodule
