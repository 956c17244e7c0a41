// The worker's sphere test: one (ray, sphere) pair from scene memory's data to num = b - sqrt(D), as
// core::sphere_num and core::hit_num compute it (src/tripsitter/core/sphere_kernel.h) in the device's fixed
// point (device::FixedArith, src/tripsitter/device/worker.h), bit for bit:
//     oc = c - o,  a = d.d,  b = 2 d.oc,  c' = oc.oc - r^2,  D = b^2 - 4ac',  num = b - sqrt(D)
// and the pair hits when D >= 0 and num > 0 (the near intersection in front of the ray's origin).
//
// A pair's ray is the camera's ray of pixel (col, row), d = (col - 320, row - 240, 320) from the origin
// (core::device_ray), or, with in_refl, the worker's reflected ray refl_o, refl_d, refl_a. The reflected ray is
// read at the stage that needs it (o at S1, d at S2, a at S4), not carried from the input: the worker changes it
// only between passes, and a reflected pass's first pair reaches each stage no sooner than the reflection has
// produced that part (ts_reflect.sv).
//
// Stages, each a register (the input is the cycle the sphere's fields arrive from scene memory):
//   S1  oc_k = c_k - o_k; the camera ray's dx^2, dy^2
//   S2  d_k oc_k, oc_k^2, r^2 (seven products); the camera ray's a = dx^2 + dy^2 + 320^2
//   S3  b = 2 (sum of d_k oc_k), c' = sum of oc_k^2 - r^2
//   S4  b^2, 4 a c' (the two wide products)
//   S5  D = b^2 - 4ac', and whether it is negative
//   ts_sqrt_unit: N + 3 cycles pipelined, N CPI + 3 iterative
//   S6  num = b - S, hit
// Latency: 6 + the square-root unit's (25 cycles for `wide`, 41 for `board-2023`). Pipelined, a new pair every
// cycle; with the iterative square root, a pair at most every N CPI + 3 cycles.
//
// Multipliers. Pipelined, every product has its own. With the iterative square root (PIPELINED = 0, the
// one-pixel-at-a-time worker) pairs come N CPI + 3 or more cycles apart, and a pair uses S2's seven multipliers
// in one cycle and S4's two in another, so the nine serve more than one use each:
//   - the camera ray's squares (S1) are made on the multipliers of d_x oc_x and d_y oc_y, in the cycle before S2;
//   - the worker's shading (ts_shade.sv, SHARED = 1) borrows them in a cycle of its own, mul_shade, when no pair
//     is at S2 or S4 (ts_worker.sv keeps that: the shading's cycle falls between a pixel's last pair and the
//     next pixel's first). Its six products, of the pass's closest hit and the camera ray:
//       a oc_k (k = x, y, z) on the multipliers of oc_k^2,  a r on that of r^2,
//       num d_x on that of b^2,                             num d_y on that of a c'
//     num is that of a hit, 0 < num <= b, so b's width holds it. Each operand is no wider than the one it
//     replaces, or still within a DSP48E1's 25 x 18 (a, 20 bits signed, beside oc_k's 16), so the shading adds no
//     slice; multiplexers choose each cycle's operands.
//
// Widths (docs/device.md, "Widths"; ts_worker.sv chooses them from the formats): every named quantity is held
// in a vector wide enough for its bound, and computed modulo that width (two's complement sums and products are
// exact modulo 2^W, so a quantity that fits its width is right even when a partial sum would not).
module ts_sphere_test #(
    parameter int CW = 24,    // centre coordinates, signed
    parameter int RW = 24,    // radius, unsigned
    parameter int DW = 22,    // direction components, signed
    parameter int OW = 26,    // ray origin components, signed
    parameter int OCW = 27,   // oc = c - o, signed
    parameter int AAW = 42,   // a = d.d, unsigned
    parameter int BW = 49,    // b, signed
    parameter int CPW = 52,   // c', signed
    parameter int DSW = 96,   // b^2, 4ac' and D, signed
    parameter int SQW = 95,   // the square-root unit's input: D when D >= 0
    parameter int NUMW = 50,  // num, signed
    parameter int ITERATIONS = 16,
    parameter int PIPELINED = 1,
    parameter int CYCLES_PER_ITERATION = 1,
    parameter int TAG_W = 1   // the worker's bits, carried along
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic                   flush,     // drop every pair in flight
    // The pair, in the cycle its sphere's fields arrive.
    input  logic                   in_valid,
    input  logic [TAG_W-1:0]       in_tag,
    input  logic                   in_refl,   // the reflected ray, not the camera's
    input  logic                   in_kill,   // never a hit (the sphere a reflected ray leaves)
    input  logic [9:0]             in_col,
    input  logic [8:0]             in_row,
    input  logic signed [CW-1:0]   in_cx,
    input  logic signed [CW-1:0]   in_cy,
    input  logic signed [CW-1:0]   in_cz,
    input  logic [RW-1:0]          in_r,
    // The worker's reflected ray.
    input  logic signed [OW-1:0]   refl_ox,
    input  logic signed [OW-1:0]   refl_oy,
    input  logic signed [OW-1:0]   refl_oz,
    input  logic signed [DW-1:0]   refl_dx,
    input  logic signed [DW-1:0]   refl_dy,
    input  logic signed [DW-1:0]   refl_dz,
    input  logic [AAW-1:0]         refl_a,
    // The shading's products (PIPELINED = 0; ignored, and the products 0, when pipelined): with mul_shade, this
    // cycle's multipliers take these operands, and the products come out in the same cycle.
    input  logic                   mul_shade,
    input  logic [AAW-1:0]         mul_a,
    input  logic signed [OCW-1:0]  mul_ocx,
    input  logic signed [OCW-1:0]  mul_ocy,
    input  logic signed [OCW-1:0]  mul_ocz,
    input  logic [RW-1:0]          mul_r,
    input  logic signed [BW-1:0]   mul_num,
    input  logic signed [DW-1:0]   mul_dx,
    input  logic signed [DW-1:0]   mul_dy,
    output logic signed [AAW+OCW:0] mul_a_ocx,   // a oc_k, exact
    output logic signed [AAW+OCW:0] mul_a_ocy,
    output logic signed [AAW+OCW:0] mul_a_ocz,
    output logic [AAW+RW-1:0]      mul_a_r,      // a r, exact
    output logic signed [BW+DW-1:0] mul_num_dx,  // num d_x, num d_y: exact when 0 < num <= b
    output logic signed [BW+DW-1:0] mul_num_dy,
    // The result.
    output logic                   out_valid,
    output logic [TAG_W-1:0]       out_tag,
    output logic                   out_refl,
    output logic [9:0]             out_col,
    output logic [8:0]             out_row,
    output logic [18:0]            out_a_cam,  // a of the camera's ray (below 2^19)
    output logic                   out_hit,
    output logic signed [NUMW-1:0] out_num,    // > 0 when out_hit
    output logic signed [OCW-1:0]  out_ocx,
    output logic signed [OCW-1:0]  out_ocy,
    output logic signed [OCW-1:0]  out_ocz,
    output logic [RW-1:0]          out_r
);
  localparam int RTW = (SQW + 1) / 2 + 1;  // the square root's bits

  localparam logic signed [DW-1:0] CamDz = DW'(320);

  // ---- S1: oc = c - o; the camera ray's squares -----------------------------------------------------
  logic                   s1_valid, s1_refl, s1_kill;
  logic [TAG_W-1:0]       s1_tag;
  logic [9:0]             s1_col;
  logic [8:0]             s1_row;
  (* mem2reg *) logic signed [OCW-1:0]  s1_oc[3];
  logic [RW-1:0]          s1_r;
  logic [17:0]            s1_dx2, s1_dy2;  // (col - 320)^2 <= 102400, (row - 240)^2 <= 57600

  (* mem2reg *) logic signed [OCW-1:0]  in_c[3], in_o[3];
  assign in_c[0] = OCW'(in_cx);
  assign in_c[1] = OCW'(in_cy);
  assign in_c[2] = OCW'(in_cz);
  assign in_o[0] = in_refl ? OCW'(refl_ox) : '0;
  assign in_o[1] = in_refl ? OCW'(refl_oy) : '0;
  assign in_o[2] = in_refl ? OCW'(refl_oz) : '0;

  logic signed [10:0] in_dx;
  logic signed [9:0]  in_dy;
  assign in_dx = $signed({1'b0, in_col}) - 11'sd320;
  assign in_dy = $signed({1'b0, in_row}) - 10'sd240;

  // The products, each registered by its stage (g_own_multipliers, g_shared_multipliers below).
  logic [17:0]              m_dx2, m_dy2;  // S1
  (* mem2reg *) logic signed [DW+OCW-1:0] m_doc[3];      // S2
  (* mem2reg *) logic [2*OCW-1:0]         m_oc2[3];
  logic [2*RW-1:0]          m_r2;
  logic signed [DSW-1:0]    m_b2, m_ac;    // S4: b^2, a c'

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      s1_valid <= 1'b0;
      s1_refl <= 1'b0;
      s1_kill <= 1'b0;
      s1_tag <= '0;
      s1_col <= '0;
      s1_row <= '0;
      for (int k = 0; k < 3; k++) s1_oc[k] <= '0;
      s1_r <= '0;
      s1_dx2 <= '0;
      s1_dy2 <= '0;
    end else begin
      s1_valid <= in_valid;
      s1_refl <= in_refl;
      s1_kill <= in_kill;
      s1_tag <= in_tag;
      s1_col <= in_col;
      s1_row <= in_row;
      for (int k = 0; k < 3; k++) s1_oc[k] <= in_c[k] - in_o[k];
      s1_r <= in_r;
      s1_dx2 <= m_dx2;
      s1_dy2 <= m_dy2;
    end
  end

  // ---- S2: the seven products; the camera ray's a ---------------------------------------------------
  logic                     s2_valid, s2_refl, s2_kill;
  logic [TAG_W-1:0]         s2_tag;
  logic [9:0]               s2_col;
  logic [8:0]               s2_row;
  (* mem2reg *) logic signed [OCW-1:0]    s2_oc[3];
  logic [RW-1:0]            s2_r;
  (* mem2reg *) logic signed [DW+OCW-1:0] s2_doc[3];
  (* mem2reg *) logic [2*OCW-1:0]         s2_oc2[3];
  logic [2*RW-1:0]          s2_r2;
  logic [18:0]              s2_a_cam;

  (* mem2reg *) logic signed [DW-1:0] s1_d[3];
  logic signed [DW-1:0] s1_cam_dx, s1_cam_dy;
  ts_pixel_ray #(.DW(DW)) s1_camera (.col(s1_col), .row(s1_row), .dx(s1_cam_dx), .dy(s1_cam_dy));
  assign s1_d[0] = s1_refl ? refl_dx : s1_cam_dx;
  assign s1_d[1] = s1_refl ? refl_dy : s1_cam_dy;
  assign s1_d[2] = s1_refl ? refl_dz : CamDz;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      s2_valid <= 1'b0;
      s2_refl <= 1'b0;
      s2_kill <= 1'b0;
      s2_tag <= '0;
      s2_col <= '0;
      s2_row <= '0;
      for (int k = 0; k < 3; k++) begin
        s2_oc[k] <= '0;
        s2_doc[k] <= '0;
        s2_oc2[k] <= '0;
      end
      s2_r <= '0;
      s2_r2 <= '0;
      s2_a_cam <= '0;
    end else begin
      s2_valid <= s1_valid;
      s2_refl <= s1_refl;
      s2_kill <= s1_kill;
      s2_tag <= s1_tag;
      s2_col <= s1_col;
      s2_row <= s1_row;
      for (int k = 0; k < 3; k++) begin
        s2_oc[k] <= s1_oc[k];
        s2_doc[k] <= m_doc[k];
        s2_oc2[k] <= m_oc2[k];
      end
      s2_r <= s1_r;
      s2_r2 <= m_r2;
      s2_a_cam <= 19'(s1_dx2) + 19'(s1_dy2) + 19'(102400);
    end
  end

  // ---- S3: b and c' --------------------------------------------------------------------------------
  logic                   s3_valid, s3_refl, s3_kill;
  logic [TAG_W-1:0]       s3_tag;
  logic [9:0]             s3_col;
  logic [8:0]             s3_row;
  (* mem2reg *) logic signed [OCW-1:0]  s3_oc[3];
  logic [RW-1:0]          s3_r;
  logic [18:0]            s3_a_cam;
  logic signed [BW-1:0]   s3_b;
  logic signed [CPW-1:0]  s3_cp;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      s3_valid <= 1'b0;
      s3_refl <= 1'b0;
      s3_kill <= 1'b0;
      s3_tag <= '0;
      s3_col <= '0;
      s3_row <= '0;
      for (int k = 0; k < 3; k++) s3_oc[k] <= '0;
      s3_r <= '0;
      s3_a_cam <= '0;
      s3_b <= '0;
      s3_cp <= '0;
    end else begin
      s3_valid <= s2_valid;
      s3_refl <= s2_refl;
      s3_kill <= s2_kill;
      s3_tag <= s2_tag;
      s3_col <= s2_col;
      s3_row <= s2_row;
      for (int k = 0; k < 3; k++) s3_oc[k] <= s2_oc[k];
      s3_r <= s2_r;
      s3_a_cam <= s2_a_cam;
      s3_b <= (BW'(s2_doc[0]) + BW'(s2_doc[1]) + BW'(s2_doc[2])) <<< 1;
      s3_cp <= $signed(CPW'(s2_oc2[0]) + CPW'(s2_oc2[1]) + CPW'(s2_oc2[2]) - CPW'(s2_r2));
    end
  end

  // ---- S4: b^2 and 4ac' ----------------------------------------------------------------------------
  logic                   s4_valid, s4_refl, s4_kill;
  logic [TAG_W-1:0]       s4_tag;
  logic [9:0]             s4_col;
  logic [8:0]             s4_row;
  (* mem2reg *) logic signed [OCW-1:0]  s4_oc[3];
  logic [RW-1:0]          s4_r;
  logic [18:0]            s4_a_cam;
  logic signed [BW-1:0]   s4_b;
  logic signed [DSW-1:0]  s4_b2, s4_ac4;

  logic [AAW-1:0] s3_a;
  assign s3_a = s3_refl ? refl_a : AAW'(s3_a_cam);

  // ---- the multipliers ------------------------------------------------------------------------------
  if (PIPELINED != 0) begin : g_own_multipliers
    assign m_dx2 = 18'(22'(in_dx) * 22'(in_dx));
    assign m_dy2 = 18'(20'(in_dy) * 20'(in_dy));
    for (genvar k = 0; k < 3; k++) begin : g_s2
      assign m_doc[k] = (DW + OCW)'(s1_d[k]) * (DW + OCW)'(s1_oc[k]);
      assign m_oc2[k] = (2 * OCW)'((2 * OCW)'(s1_oc[k]) * (2 * OCW)'(s1_oc[k]));
    end
    assign m_r2 = (2 * RW)'(s1_r) * (2 * RW)'(s1_r);
    assign m_b2 = DSW'(s3_b) * DSW'(s3_b);
    assign m_ac = DSW'($signed({1'b0, s3_a})) * DSW'(s3_cp);

    // Every pair has its own products: the shading has its own multipliers.
    assign mul_a_ocx = '0;
    assign mul_a_ocy = '0;
    assign mul_a_ocz = '0;
    assign mul_a_r = '0;
    assign mul_num_dx = '0;
    assign mul_num_dy = '0;
    /* verilator lint_off UNUSEDSIGNAL */  // the shading's shared products go unused: it has its own multipliers
    logic unused_mul;
    /* verilator lint_on UNUSEDSIGNAL */
    assign unused_mul = ^{mul_shade, mul_a, mul_ocx, mul_ocy, mul_ocz, mul_r, mul_num, mul_dx, mul_dy};
  end else begin : g_shared_multipliers
    // A pair is at S1 (in_valid), at S2 (s1_valid) or at S4 (s3_valid) in different cycles, and the shading's
    // cycle (mul_shade) is none of them (the module's header): each multiplier takes the operands of whichever
    // uses it in this cycle. The camera ray's components (-320..319, -240..239) fit DW and OCW (checked below).
    localparam int AW1 = AAW + 1;                   // a as a signed operand
    localparam int QW = AW1 > OCW ? AW1 : OCW;      // oc_k's multiplier's second operand: oc_k or a
    localparam int RQW = AAW > RW ? AAW : RW;       // r's: r or a
    logic signed [DW-1:0]     doc_d[3];
    logic signed [OCW-1:0]    doc_oc[3];
    logic signed [OCW-1:0]    oc_first[3];
    logic signed [QW-1:0]     oc_second[3];
    /* verilator lint_off UNUSEDSIGNAL */           // the top bits of the wider operand's products
    logic signed [OCW+QW-1:0] oc_prod[3];
    logic [RW+RQW-1:0]        r_prod;
    /* verilator lint_on UNUSEDSIGNAL */
    logic signed [OCW-1:0]    mul_oc[3];
    assign mul_oc[0] = mul_ocx;
    assign mul_oc[1] = mul_ocy;
    assign mul_oc[2] = mul_ocz;

    // d_x oc_x and d_y oc_y; in the cycle before, the camera ray's dx^2 and dy^2. d_z oc_z alone.
    assign doc_d[0] = in_valid ? DW'(in_dx) : s1_d[0];
    assign doc_oc[0] = in_valid ? OCW'(in_dx) : s1_oc[0];
    assign doc_d[1] = in_valid ? DW'(in_dy) : s1_d[1];
    assign doc_oc[1] = in_valid ? OCW'(in_dy) : s1_oc[1];
    assign doc_d[2] = s1_d[2];
    assign doc_oc[2] = s1_oc[2];
    for (genvar k = 0; k < 3; k++) begin : g_s2
      assign m_doc[k] = (DW + OCW)'(doc_d[k]) * (DW + OCW)'(doc_oc[k]);
      // oc_k^2, or the shading's a oc_k.
      assign oc_first[k] = mul_shade ? mul_oc[k] : s1_oc[k];
      assign oc_second[k] = mul_shade ? QW'($signed({1'b0, mul_a})) : QW'(s1_oc[k]);
      assign oc_prod[k] = (OCW + QW)'(oc_first[k]) * (OCW + QW)'(oc_second[k]);
      assign m_oc2[k] = (2 * OCW)'(oc_prod[k]);
    end
    assign m_dx2 = 18'(m_doc[0]);
    assign m_dy2 = 18'(m_doc[1]);
    assign mul_a_ocx = (AAW + OCW + 1)'(oc_prod[0]);
    assign mul_a_ocy = (AAW + OCW + 1)'(oc_prod[1]);
    assign mul_a_ocz = (AAW + OCW + 1)'(oc_prod[2]);

    // r^2, or the shading's a r.
    logic [RW-1:0]  r_first;
    logic [RQW-1:0] r_second;
    assign r_first = mul_shade ? mul_r : s1_r;
    assign r_second = mul_shade ? RQW'(mul_a) : RQW'(s1_r);
    assign r_prod = (RW + RQW)'(r_first) * (RW + RQW)'(r_second);
    assign m_r2 = (2 * RW)'(r_prod);
    assign mul_a_r = (AAW + RW)'(r_prod);

    // b^2 and a c', or the shading's num d_x and num d_y.
    logic signed [BW-1:0]  b_first, b_second;
    logic signed [AW1-1:0] ac_first;
    logic signed [CPW-1:0] ac_second;
    assign b_first = mul_shade ? mul_num : s3_b;
    assign b_second = mul_shade ? BW'(mul_dx) : s3_b;
    assign ac_first = mul_shade ? AW1'(mul_dy) : $signed({1'b0, s3_a});
    assign ac_second = mul_shade ? CPW'(mul_num) : s3_cp;
    assign m_b2 = DSW'(b_first) * DSW'(b_second);
    assign m_ac = DSW'(ac_first) * DSW'(ac_second);
    assign mul_num_dx = (BW + DW)'(m_b2);
    assign mul_num_dy = (BW + DW)'(m_ac);

    if (DW < 10 || OCW < 10 || AW1 < DW || BW < DW || CPW < BW || DSW < BW + DW) begin : g_bad_widths
      $error("ts_sphere_test: the shared multipliers' operands do not fit the widths");
    end
  end

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      s4_valid <= 1'b0;
      s4_refl <= 1'b0;
      s4_kill <= 1'b0;
      s4_tag <= '0;
      s4_col <= '0;
      s4_row <= '0;
      for (int k = 0; k < 3; k++) s4_oc[k] <= '0;
      s4_r <= '0;
      s4_a_cam <= '0;
      s4_b <= '0;
      s4_b2 <= '0;
      s4_ac4 <= '0;
    end else begin
      s4_valid <= s3_valid;
      s4_refl <= s3_refl;
      s4_kill <= s3_kill;
      s4_tag <= s3_tag;
      s4_col <= s3_col;
      s4_row <= s3_row;
      for (int k = 0; k < 3; k++) s4_oc[k] <= s3_oc[k];
      s4_r <= s3_r;
      s4_a_cam <= s3_a_cam;
      s4_b <= s3_b;
      s4_b2 <= m_b2;
      s4_ac4 <= m_ac <<< 2;
    end
  end

  // ---- S5: D ---------------------------------------------------------------------------------------
  logic                   s5_valid, s5_refl, s5_kill, s5_neg;
  logic [TAG_W-1:0]       s5_tag;
  logic [9:0]             s5_col;
  logic [8:0]             s5_row;
  (* mem2reg *) logic signed [OCW-1:0]  s5_oc[3];
  logic [RW-1:0]          s5_r;
  logic [18:0]            s5_a_cam;
  logic signed [BW-1:0]   s5_b;
  logic [SQW-1:0]         s5_disc;

  logic signed [DSW-1:0] s4_disc;
  assign s4_disc = s4_b2 - s4_ac4;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      s5_valid <= 1'b0;
      s5_refl <= 1'b0;
      s5_kill <= 1'b0;
      s5_neg <= 1'b0;
      s5_tag <= '0;
      s5_col <= '0;
      s5_row <= '0;
      for (int k = 0; k < 3; k++) s5_oc[k] <= '0;
      s5_r <= '0;
      s5_a_cam <= '0;
      s5_b <= '0;
      s5_disc <= '0;
    end else begin
      s5_valid <= s4_valid;
      s5_refl <= s4_refl;
      s5_kill <= s4_kill;
      s5_neg <= s4_disc < 0;
      s5_tag <= s4_tag;
      s5_col <= s4_col;
      s5_row <= s4_row;
      for (int k = 0; k < 3; k++) s5_oc[k] <= s4_oc[k];
      s5_r <= s4_r;
      s5_a_cam <= s4_a_cam;
      s5_b <= s4_b;
      s5_disc <= s4_disc < 0 ? '0 : SQW'(s4_disc);  // a miss needs no root: 0 keeps the unit's work trivial
    end
  end

  // ---- the square root, with everything else riding along as its tag --------------------------------
  localparam int CARRY_W = TAG_W + 3 + 10 + 9 + 19 + 3 * OCW + RW + BW;
  logic [CARRY_W-1:0] sq_in_carry, sq_out_carry;
  logic               sq_out_valid;
  logic [RTW-1:0]     sq_root;
  /* verilator lint_off UNUSEDSIGNAL */  // the worker's schedule never outpaces the root unit (see in_ready below)
  logic               sq_ready_unused;
  /* verilator lint_on UNUSEDSIGNAL */

  assign sq_in_carry = {s5_tag, s5_refl, s5_kill, s5_neg, s5_col, s5_row, s5_a_cam, s5_oc[0], s5_oc[1], s5_oc[2], s5_r,
                        s5_b};

  ts_sqrt_unit #(
      .ITERATIONS(ITERATIONS),
      .WIDTH(SQW),
      .PIPELINED(PIPELINED),
      .CYCLES_PER_ITERATION(CYCLES_PER_ITERATION),
      .TAG_W(CARRY_W)
  ) u_sqrt (
      .clk(clk),
      .rst(rst),
      .flush(flush),
      .in_valid(s5_valid),
      .in_ready(sq_ready_unused),  // pairs come no faster than the unit takes them (the worker's schedule)
      .in_value(s5_disc),
      .in_tag(sq_in_carry),
      .out_valid(sq_out_valid),
      .out_root(sq_root),
      .out_tag(sq_out_carry)
  );

  logic [TAG_W-1:0]      q_tag;
  logic                  q_refl, q_kill, q_neg;
  logic [9:0]            q_col;
  logic [8:0]            q_row;
  logic [18:0]           q_a_cam;
  logic signed [OCW-1:0] q_ocx, q_ocy, q_ocz;
  logic [RW-1:0]         q_r;
  logic signed [BW-1:0]  q_b;
  assign {q_tag, q_refl, q_kill, q_neg, q_col, q_row, q_a_cam, q_ocx, q_ocy, q_ocz, q_r, q_b} = sq_out_carry;

  // ---- S6: num = b - sqrt(D), the hit ----------------------------------------------------------------
  logic signed [NUMW-1:0] q_num;
  assign q_num = NUMW'(q_b) - NUMW'($signed({1'b0, sq_root}));

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      out_valid <= 1'b0;
      out_tag <= '0;
      out_refl <= 1'b0;
      out_col <= '0;
      out_row <= '0;
      out_a_cam <= '0;
      out_hit <= 1'b0;
      out_num <= '0;
      out_ocx <= '0;
      out_ocy <= '0;
      out_ocz <= '0;
      out_r <= '0;
    end else begin
      out_valid <= sq_out_valid;
      out_tag <= q_tag;
      out_refl <= q_refl;
      out_col <= q_col;
      out_row <= q_row;
      out_a_cam <= q_a_cam;
      out_hit <= !q_neg && !q_kill && q_num > 0;
      out_num <= q_num;
      out_ocx <= q_ocx;
      out_ocy <= q_ocy;
      out_ocz <= q_ocz;
      out_r <= q_r;
    end
  end
endmodule
