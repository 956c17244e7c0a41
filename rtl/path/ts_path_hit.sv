// ts_path_hit: where a path's ray hit and which way the surface faces there, from the sphere unit's closest hit,
// as the scatter unit takes it: the hit point (the bounced ray's origin), the outward unit normal times 2^17, and
// the normal and the incoming direction rounded to the path preset's 2^14 unit vectors. C++ model: artix::hit_point
// and artix::normal (with `far` for the far side of the sphere the ray is in) of src/tripsitter/device/artix_kernel.h,
// then the rounding trace_path_sample takes (approx::round_shift by 3, artix_path.h); docs/device.md, "Path tracing
// on the artix datapath", and docs/rtl.md, "Path tracing blocks".
//
// One hit a cycle, its three components side by side (the units' hits meet here on their way to the one scatter
// unit, which takes a bounce a cycle), out Latency = 8 cycles later with its tag. The arithmetic is the artix
// shading's (ts_artix_shade_reflect, "The arithmetic"): with z = max(0, -e), e+ = max(e, 0) and beta b d's low 17
// bits read as a signed number,
//     Q_k = floor(beta d_k / 2^17) 2^z - (f_k 2^z + s 2^e+ d_k)      (the far side: + s 2^e+ d_k)
//     n_k = (floor(Q_k / 2^(18 + e+)) rinv) >> 16, saturated to +-(2^17 - 1)
//     p_k = o_k + floor((t d_k + 2^16) / 2^17),  t = floor((t d + 2^16) / 2^17)
// the far side's sign taken on s 2^e+ as it enters its multiplier. Each product is one DSP48E1: beta d_k 17 x 18,
// s 2^e+ d_k 22 x 18, t d_k 25 x 18 with o_k 2^17 + 2^16 on the post-adder, the normal's 20 x 18: 12 in all.
//
// Pipeline (stage j's registers hold a hit j + 1 cycles after it reached the ports):
//   0  the ports: per hit beta, s 2^e+ (negated for the far side), t, z, e+, rinv; per component o_k 2^17 + 2^16,
//      d_k, f_k
//   1  beta d_k, s 2^e+ d_k, o_k 2^17 + 2^16 + t d_k; f_k 2^z
//   2  u = floor(beta d_k / 2^17) 2^z; nh = f_k 2^z + s 2^e+ d_k; p_k
//   3  Q_k = u - nh
//   4  Q_k / 2^(18 + e+) (the model checks 18 bits)
//   5  its product with rinv
//   6  n_k saturated
//   7  its rounding to 2^14 (and d_k's, which waits beside)
// Widths (a hit's, the model's checks): |f_k 2^z| < 2^38, |s 2^e+ d_k| < 2^38, |Q_k| < 2^40; t 25 bits, p_k 24.
module ts_path_hit #(
    parameter int TAG_W = 1
) (
    input  logic                               clk,
    input  logic                               rst,
    input  logic                               in_valid,
    input  logic [3*ts_artix_pkg::OriginW-1:0] in_o,     // raw, signed
    input  logic [3*ts_artix_pkg::DirW-1:0]    in_d,     // times 2^17, signed
    input  logic [ts_artix_pkg::TdW-1:0]       in_td,    // signed, > 0
    /* verilator lint_off UNUSEDSIGNAL */  // b d's fraction only, beta
    input  logic [ts_artix_pkg::BdW-1:0]       in_bd,    // signed
    /* verilator lint_on UNUSEDSIGNAL */
    /* verilator lint_off UNUSEDSIGNAL */  // a hit's f_k fits 39 bits (Widths): the rest is its sign
    input  logic [3*ts_artix_pkg::FW-1:0]      in_f,     // signed
    /* verilator lint_on UNUSEDSIGNAL */
    input  logic [ts_artix_pkg::SqrtW-1:0]     in_s,
    input  logic [ts_artix_pkg::ExpW-1:0]      in_e,     // signed, -16..4
    input  logic [ts_artix_pkg::RinvW-1:0]     in_rinv,
    input  logic                               in_far,   // the far side of the sphere the ray is in
    input  logic [TAG_W-1:0]                   in_tag,
    output logic                               out_valid,
    output logic [3*ts_artix_pkg::OriginW-1:0] out_point,   // raw, signed
    output logic [3*ts_artix_pkg::DirW-1:0]    out_normal,  // times 2^17, signed
    output logic [3*17-1:0]                    out_normal14,  // times 2^14, 17 bits signed each
    output logic [3*17-1:0]                    out_dir14,
    output logic [TAG_W-1:0]                   out_tag
);
  localparam int OriginW = ts_artix_pkg::OriginW;
  localparam int DirW = ts_artix_pkg::DirW;
  localparam int DirFrac = ts_artix_pkg::DirFrac;
  localparam int FW = ts_artix_pkg::FW;
  localparam int TdW = ts_artix_pkg::TdW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int RinvW = ts_artix_pkg::RinvW;
  localparam int SqrtW = ts_artix_pkg::SqrtW;

  localparam int Latency = 8;
  localparam int BetaW = DirFrac;              // beta in [-2^16, 2^16)
  localparam int ZW = 5;                       // z: 0..16
  localparam int EpW = 3;                      // e+: 0..4
  localparam int FzW = 39;                     // f_k and f_k 2^z of a hit
  localparam int SsW = SqrtW + 5;              // +-s 2^e+, |.| < 2^21
  localparam int TW = 25;                      // t
  localparam int P1W = BetaW + DirW;           // beta d_k
  localparam int P2W = SsW + DirW;             // s 2^e+ d_k
  localparam int P6W = TW + DirW;              // o_k 2^17 + 2^16 + t d_k < 2^42
  localparam int UW = 34;                      // u: |.| <= 2^32
  localparam int NhW = 40;                     // nh: |.| < 2^39
  localparam int QW = 41;                      // |Q_k| < 2^40
  localparam int TopW = DirW;                  // Q_k / 2^(18 + e+)
  localparam int RinvSW = RinvW + 1;           // rinv <= 2^18 as a signed operand
  localparam int P3W = RinvSW + TopW;          // |.| <= 2^35
  localparam int UnitW = 17;                   // a 2^14 unit vector's component
  localparam logic signed [DirW-1:0] DirMax = DirW'((1 << DirFrac) - 1);

  if (DirFrac != 17 || DirW != 18 || SqrtW != 17 || RinvW != 19 || OriginW != 24) begin : g_bad_package
    $error("ts_path_hit: its widths are derived for the package's formats of this version");
  end

  // x >> 3 rounded to nearest, ties away from zero (approx::round_shift), of a direction or normal component.
  function automatic logic signed [UnitW-1:0] to_unit14(input logic signed [DirW-1:0] v);
    to_unit14 = UnitW'(ts_path_pkg::round_shift(64'(v), 3));
  endfunction

  logic [Latency-1:0] v_q;
  always_ff @(posedge clk) begin
    if (rst) v_q <= '0;
    else v_q <= Latency'({v_q, in_valid});
  end

  // ---- 0: per hit ----------------------------------------------------------------------------------------------
  logic signed [ExpW-1:0] in_se;
  logic [EpW-1:0]         in_ep;
  logic [SsW-1:0]         in_ss;
  /* verilator lint_off UNUSEDSIGNAL */  // t d's top: a hit's t fits 25 bits (the model's check)
  logic signed [TdW-1:0]  td_rounded;
  /* verilator lint_on UNUSEDSIGNAL */
  assign in_se = $signed(in_e);
  assign in_ep = in_se < 0 ? '0 : EpW'(in_se);
  assign in_ss = SsW'(in_s) << in_ep;  // below 2^21
  assign td_rounded = $signed(in_td) + TdW'(1 << (DirFrac - 1));
  logic signed [BetaW-1:0]  beta0_q;
  logic signed [SsW-1:0]    ss0_q;
  logic signed [TW-1:0]     t0_q;
  logic [ZW-1:0]            z0_q, z1_q;
  logic [EpW-1:0]           ep0_q, ep1_q, ep2_q, ep3_q;
  logic [RinvW-1:0]         rinv0_q, rinv1_q, rinv2_q, rinv3_q, rinv4_q;
  always_ff @(posedge clk) begin
    beta0_q <= $signed(in_bd[BetaW-1:0]);
    ss0_q   <= in_far ? -$signed(in_ss) : $signed(in_ss);
    t0_q    <= TW'(td_rounded >>> DirFrac);
    z0_q    <= in_se < 0 ? ZW'(-in_se) : '0;
    ep0_q   <= in_ep;
    rinv0_q <= in_rinv;
    {z1_q, ep1_q, rinv1_q} <= {z0_q, ep0_q, rinv0_q};
    {ep2_q, rinv2_q} <= {ep1_q, rinv1_q};
    {ep3_q, rinv3_q} <= {ep2_q, rinv2_q};
    rinv4_q <= rinv3_q;
  end

  // The tag and the incoming direction's rounding wait beside the arithmetic.
  (* mem2reg *) logic [TAG_W-1:0] tag_q [Latency];
  (* mem2reg *) logic [3*UnitW-1:0] dir14_q [Latency];
  always_ff @(posedge clk) begin
    tag_q[0] <= in_tag;
    for (int k = 0; k < 3; k++) dir14_q[0][k*UnitW+:UnitW] <= to_unit14($signed(in_d[k*DirW+:DirW]));
    for (int j = 1; j < Latency; j++) begin
      tag_q[j]   <= tag_q[j-1];
      dir14_q[j] <= dir14_q[j-1];
    end
  end
  assign out_tag = tag_q[Latency-1];
  assign out_dir14 = dir14_q[Latency-1];
  assign out_valid = v_q[Latency-1];

  // ---- per component -------------------------------------------------------------------------------------------
  for (genvar k = 0; k < 3; k++) begin : g_k
    // 0: the operands.
    logic signed [P6W-1:0] oc0_q;
    logic signed [DirW-1:0] d0_q;
    logic signed [FzW-1:0] f0_q;
    always_ff @(posedge clk) begin
      oc0_q <= (P6W'($signed(in_o[k*OriginW+:OriginW])) <<< DirFrac) | P6W'(1 << (DirFrac - 1));
      d0_q  <= $signed(in_d[k*DirW+:DirW]);
      f0_q  <= $signed(in_f[k*FW+:FzW]);
    end
    // 1: the products; f_k 2^z.
    logic signed [P1W-1:0] p1_q;
    logic signed [P2W-1:0] p2_q;
    logic signed [P6W-1:0] p6_q;
    logic signed [FzW-1:0] fz1_q;
    always_ff @(posedge clk) begin
      p1_q  <= beta0_q * d0_q;
      p2_q  <= ss0_q * d0_q;
      p6_q  <= oc0_q + t0_q * d0_q;
      fz1_q <= f0_q <<< z0_q;
    end
    // 2: u, nh, the hit point.
    /* verilator lint_off UNUSEDSIGNAL */  // the hit point's low bits: below the position grid
    logic signed [P6W-1:0] p6_shifted;
    /* verilator lint_on UNUSEDSIGNAL */
    logic signed [UW-1:0]  u2_q;
    logic signed [NhW-1:0] nh2_q;
    (* mem2reg *) logic signed [OriginW-1:0] point_q [Latency - 2];
    assign p6_shifted = p6_q >>> DirFrac;
    always_ff @(posedge clk) begin
      u2_q  <= UW'(p1_q >>> DirFrac) <<< z1_q;
      nh2_q <= NhW'(fz1_q) + NhW'(p2_q);
      point_q[0] <= OriginW'(p6_shifted);
      for (int j = 1; j < Latency - 2; j++) point_q[j] <= point_q[j-1];
    end
    assign out_point[k*OriginW+:OriginW] = point_q[Latency-3];
    // 3: Q_k.
    logic signed [QW-1:0] q3_q;
    always_ff @(posedge clk) q3_q <= QW'(u2_q) - QW'(nh2_q);
    // 4: the normal's operand.
    /* verilator lint_off UNUSEDSIGNAL */  // Q_k's top: the operand fits 18 bits (the model's check)
    logic signed [QW-1:0] q_shifted;
    /* verilator lint_on UNUSEDSIGNAL */
    logic signed [TopW-1:0] top4_q;
    assign q_shifted = q3_q >>> (DirFrac + 1 + 32'(ep3_q));
    always_ff @(posedge clk) top4_q <= TopW'(q_shifted);
    // 5: its product with rinv.
    logic signed [P3W-1:0] p5_q;
    always_ff @(posedge clk) p5_q <= $signed({1'b0, rinv4_q}) * top4_q;
    // 6: saturated; 7: rounded to 2^14.
    logic signed [DirW-1:0] n;
    logic signed [DirW-1:0] n6_q, n7_q;
    logic signed [UnitW-1:0] n14_q;
    /* verilator lint_off UNUSEDSIGNAL */  // the product's low bits: below the normal's 2^-17
    logic signed [P3W-1:0] p5_shifted;
    /* verilator lint_on UNUSEDSIGNAL */
    assign p5_shifted = p5_q >>> (DirFrac - 1);
    assign n = p5_shifted > P3W'(DirMax) ? DirMax : p5_shifted < -P3W'(DirMax) ? -DirMax : DirW'(p5_shifted);
    always_ff @(posedge clk) begin
      n6_q  <= n;
      n7_q  <= n6_q;
      n14_q <= to_unit14(n6_q);
    end
    assign out_normal[k*DirW+:DirW] = n7_q;
    assign out_normal14[k*UnitW+:UnitW] = n14_q;
  end
endmodule
