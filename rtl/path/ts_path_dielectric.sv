// The path preset's dielectric bounce (src/tripsitter/device/path_kernel.h, scatter(), the dielectric case) as a
// pipeline that takes a bounce a cycle: Snell's law with total internal reflection, Schlick's reflectance against
// the sample's draw, the mirror direction or the refracted one, every product rounded as the model rounds it
// (approx::round_shift: to nearest, ties away from zero) and the refraction's square root rounded to nearest
// (round(sqrt(q)) = (floor(sqrt(4 q)) + 1) / 2, on ts_artix_isqrt), so that the artix path preset's bounce is the
// model's bit for bit.
//
// In: the incoming direction `in` and the outward normal `n` (unit vectors times 2^14), whether the ray is inside
// the sphere, the surface's eta entering and leaving and r0 (times 2^14), whether its index is exactly 1 (it passes
// straight), and the sample's next draw, which the bounce takes only when it compares it with the reflectance
// (`drew`: the stream then moves on). Out, Latency = 6 + 16 + 1 cycles later with the tag: `straight` (the ray
// goes on unchanged; `into` = not inside), or the new direction `next` with `into` (reflected: the ray stays on the
// side it came from; refracted: it crosses) and `refracted`.
//
// Stages: 1. n_f = n or -n (facing the ray), in.n_f; 2. d = round(in.n_f), cos = min(-d, 2^14); 3. sin^2 = 2^28 -
// cos^2, m = 2^14 - max(cos, 0) and m^2, eta^2, cos n_f and 2 d n_f; 4. total internal reflection (eta^2 sin^2 >
// 2^56), m^4, in + cos n_f, the mirror direction in - 2 d n_f; 5. m^5, the refraction's perpendicular part eta (in +
// cos n_f); 6. Schlick's r0 + (2^14 - r0) m^5, q = 2^28 - perp.perp; then reflect when totally reflected or when
// draw >> 18 is below the reflectance, and the square root of 4 |q| (16 cycles); last, along = round(sqrt(|q|)) and
// next = perp - along n_f for a refraction.
//
// TS_PLANT_FLIPPED_TIR (a define, for the tests only) flips the total-internal-reflection comparison: the bug the
// tests must catch.
module ts_path_dielectric #(
    parameter int TAG_W = 1
) (
    input  logic                    clk,
    input  logic                    rst,
    input  logic                    in_valid,
    input  logic [3*17-1:0]         in_dir,        // x, y, z from the low bits: 17 bits signed each, times 2^14
    input  logic [3*17-1:0]         in_normal,     // outward, as in_dir
    input  logic                    in_inside,
    input  logic [17:0]             in_eta_enter,  // times 2^14: 1 / ior, up to 4 (ior 0.25)
    input  logic [17:0]             in_eta_leave,  // ior, up to 8
    input  logic [14:0]             in_r0,         // times 2^14
    input  logic                    in_straight,   // ior exactly 1
    input  logic [31:0]             in_draw,
    input  logic [TAG_W-1:0]        in_tag,
    output logic                    out_valid,
    output logic                    out_straight,
    output logic                    out_into,
    output logic                    out_refracted,
    output logic                    out_drew,      // the draw was taken (not straight, not totally reflected)
    output logic [3*24-1:0]         out_next,      // x, y, z from the low bits: 24 bits signed each, times 2^14
    output logic [TAG_W-1:0]        out_tag
);
  localparam int SqrtW = 32;

  // Each product below is taken at its own width (so that it maps to as few DSP48E1 as its operands need) and
  // widened only to be rounded (ts_path_pkg::round_shift).

  // Stage 1: the normal facing the ray, in.n_f.
  (* mem2reg *) logic signed [16:0] dir_in[3], nf_in[3];
  (* mem2reg *) logic signed [33:0] dot_in[3];
  for (genvar k = 0; k < 3; k++) begin : g_facing
    assign dir_in[k] = in_dir[k*17+:17];
    assign nf_in[k] = in_inside ? -in_normal[k*17+:17] : in_normal[k*17+:17];
    assign dot_in[k] = dir_in[k] * nf_in[k];
  end
  logic                      v1, inside1, straight1;
  (* mem2reg *) logic signed [16:0] in1[3], nf1[3];
  logic signed [35:0]        dot1;
  logic [17:0]               eta1;
  logic [14:0]               r01;
  logic [31:0]               draw1;
  logic [TAG_W-1:0]          tag1;
  always_ff @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    for (int k = 0; k < 3; k++) begin
      in1[k] <= dir_in[k];
      nf1[k] <= nf_in[k];
    end
    dot1 <= 36'(dot_in[0]) + 36'(dot_in[1]) + 36'(dot_in[2]);
    inside1 <= in_inside;
    straight1 <= in_straight;
    eta1 <= in_inside ? in_eta_leave : in_eta_enter;
    r01 <= in_r0;
    draw1 <= in_draw;
    tag1 <= in_tag;
  end

  // Stage 2: d = round(in.n_f) (|d| <= 2^14 + 2), cos = min(-d, 2^14).
  logic                      v2, inside2, straight2;
  (* mem2reg *) logic signed [16:0] in2[3], nf2[3];
  logic signed [17:0]        d2, cos2;
  logic [17:0]               eta2;
  logic [14:0]               r02;
  logic [31:0]               draw2;
  logic [TAG_W-1:0]          tag2;
  logic signed [63:0]        d_x;
  assign d_x = ts_path_pkg::round_shift(64'(dot1), 14);
  always_ff @(posedge clk) begin
    if (rst) v2 <= 1'b0;
    else v2 <= v1;
    for (int k = 0; k < 3; k++) begin
      in2[k] <= in1[k];
      nf2[k] <= nf1[k];
    end
    d2 <= 18'(d_x);
    cos2 <= -d_x < 64'sd16384 ? 18'(-d_x) : 18'sd16384;
    inside2 <= inside1;
    straight2 <= straight1;
    eta2 <= eta1;
    r02 <= r01;
    draw2 <= draw1;
    tag2 <= tag1;
  end

  // Stage 3: sin^2 = 2^28 - cos^2, m = 2^14 - max(cos, 0) and round(m^2), eta^2, round(cos n_f), round(2 d n_f).
  logic [14:0]        m_x;
  logic signed [35:0] cos_sq;
  logic [29:0]        m_sq;
  logic [35:0]        eta_sq;
  (* mem2reg *) logic signed [34:0] cos_nf[3], d_nf[3];
  assign m_x = cos2 > 0 ? 15'(18'sd16384 - cos2) : 15'd16384;
  assign cos_sq = cos2 * cos2;
  assign m_sq = m_x * m_x;
  assign eta_sq = eta2 * eta2;
  for (genvar k = 0; k < 3; k++) begin : g_cos_nf
    assign cos_nf[k] = cos2 * nf2[k];
    assign d_nf[k] = d2 * nf2[k];
  end
  logic                      v3, inside3, straight3;
  (* mem2reg *) logic signed [16:0] in3[3], nf3[3];
  logic signed [31:0]        sin3;
  logic [14:0]               m3;
  logic [15:0]               mm3;
  logic [35:0]               ee3;
  (* mem2reg *) logic signed [17:0] t3[3], rr3[3];
  logic [17:0]               eta3;
  logic [14:0]               r03;
  logic [31:0]               draw3;
  logic [TAG_W-1:0]          tag3;
  always_ff @(posedge clk) begin
    if (rst) v3 <= 1'b0;
    else v3 <= v2;
    for (int k = 0; k < 3; k++) begin
      in3[k] <= in2[k];
      nf3[k] <= nf2[k];
      t3[k] <= 18'(ts_path_pkg::round_shift(64'(cos_nf[k]), 14));
      rr3[k] <= 18'(ts_path_pkg::round_shift(64'(d_nf[k]) <<< 1, 14));
    end
    sin3 <= 32'(36'sd268435456 - cos_sq);
    m3 <= m_x;
    mm3 <= 16'(ts_path_pkg::round_shift(64'(m_sq), 14));
    ee3 <= eta_sq;
    inside3 <= inside2;
    straight3 <= straight2;
    eta3 <= eta2;
    r03 <= r02;
    draw3 <= draw2;
    tag3 <= tag2;
  end

  // Stage 4: total internal reflection, round(m^4), in + cos n_f, the mirror direction in - 2 d n_f.
  logic signed [68:0] eesin;
  logic [31:0]        m4_sq;
  assign eesin = $signed({1'b0, ee3}) * sin3;
  assign m4_sq = mm3 * mm3;
  logic                      v4, inside4, straight4, tir4;
  (* mem2reg *) logic signed [16:0] nf4[3];
  logic [14:0]               m4;
  logic [15:0]               m4th4;
  (* mem2reg *) logic signed [18:0] s4[3], mirror4[3];
  logic [17:0]               eta4;
  logic [14:0]               r04;
  logic [31:0]               draw4;
  logic [TAG_W-1:0]          tag4;
  always_ff @(posedge clk) begin
    if (rst) v4 <= 1'b0;
    else v4 <= v3;
`ifdef TS_PLANT_FLIPPED_TIR
    tir4 <= eesin < (69'sd1 <<< 56);
`else
    tir4 <= eesin > (69'sd1 <<< 56);
`endif
    m4 <= m3;
    m4th4 <= 16'(ts_path_pkg::round_shift(64'(m4_sq), 14));
    for (int k = 0; k < 3; k++) begin
      nf4[k] <= nf3[k];
      s4[k] <= 19'(in3[k]) + 19'(t3[k]);
      mirror4[k] <= 19'(in3[k]) - 19'(rr3[k]);
    end
    inside4 <= inside3;
    straight4 <= straight3;
    eta4 <= eta3;
    r04 <= r03;
    draw4 <= draw3;
    tag4 <= tag3;
  end

  // Stage 5: round(m^5), perp = round(eta (in + cos n_f)) (|perp| < 2^19: eta <= 2^17, |s| < 2^15 + 4).
  logic [30:0]        m5;
  (* mem2reg *) logic signed [37:0] eta_s[3];
  assign m5 = m4th4 * m4;
  for (genvar k = 0; k < 3; k++) begin : g_perp
    assign eta_s[k] = $signed({1'b0, eta4}) * s4[k];
  end
  logic                      v5, inside5, straight5, tir5;
  (* mem2reg *) logic signed [16:0] nf5[3];
  logic [15:0]               p5;
  (* mem2reg *) logic signed [20:0] perp5[3];
  (* mem2reg *) logic signed [18:0] mirror5[3];
  logic [14:0]               r05;
  logic [31:0]               draw5;
  logic [TAG_W-1:0]          tag5;
  always_ff @(posedge clk) begin
    if (rst) v5 <= 1'b0;
    else v5 <= v4;
    tir5 <= tir4;
    p5 <= 16'(ts_path_pkg::round_shift(64'(m5), 14));
    for (int k = 0; k < 3; k++) begin
      nf5[k] <= nf4[k];
      perp5[k] <= 21'(ts_path_pkg::round_shift(64'(eta_s[k]), 14));
      mirror5[k] <= mirror4[k];
    end
    inside5 <= inside4;
    straight5 <= straight4;
    r05 <= r04;
    draw5 <= draw4;
    tag5 <= tag4;
  end

  // Stage 6: Schlick's r0 + round((2^14 - r0) m^5), q = 2^28 - perp.perp.
  logic [30:0]        schlick;
  (* mem2reg *) logic signed [41:0] perp_sq[3];
  logic [14:0] one_less_r0;
  assign one_less_r0 = 15'd16384 - r05;
  assign schlick = one_less_r0 * p5;
  for (genvar k = 0; k < 3; k++) begin : g_perp_sq
    assign perp_sq[k] = perp5[k] * perp5[k];
  end
  logic                      v6, inside6, straight6, tir6;
  (* mem2reg *) logic signed [16:0] nf6[3];
  logic [16:0]               refl6;
  logic signed [44:0]        q6;
  (* mem2reg *) logic signed [20:0] perp6[3];
  (* mem2reg *) logic signed [18:0] mirror6[3];
  logic [31:0]               draw6;
  logic [TAG_W-1:0]          tag6;
  always_ff @(posedge clk) begin
    if (rst) v6 <= 1'b0;
    else v6 <= v5;
    tir6 <= tir5;
    refl6 <= 17'(r05) + 17'(ts_path_pkg::round_shift(64'(schlick), 14));
    q6 <= 45'sd268435456 - 45'(perp_sq[0]) - 45'(perp_sq[1]) - 45'(perp_sq[2]);
    for (int k = 0; k < 3; k++) begin
      nf6[k] <= nf5[k];
      perp6[k] <= perp5[k];
      mirror6[k] <= mirror5[k];
    end
    inside6 <= inside5;
    straight6 <= straight5;
    draw6 <= draw5;
    tag6 <= tag5;
  end

  // The choice, and the square root with everything the last stage needs riding in its tag.
  localparam int RideW = 4 + 3 * 17 + 3 * 21 + 3 * 19 + TAG_W;
  logic               reflects6;
  logic [44:0]        q_abs;
  logic [RideW-1:0]   ride_in, ride_out;
  logic               sqrt_valid;
  logic [SqrtW/2-1:0] root;
  assign reflects6 = tir6 || 32'(draw6 >> 18) < 32'(refl6);
  assign q_abs = q6 < 0 ? 45'(-q6) : 45'(q6);
  assign ride_in = {straight6, inside6, reflects6, tir6, nf6[0], nf6[1], nf6[2], perp6[0], perp6[1], perp6[2],
                    mirror6[0], mirror6[1], mirror6[2], tag6};
  ts_artix_isqrt #(
      .WIDTH(SqrtW),
      .TAG_W(RideW)
  ) u_sqrt (
      .clk,
      .rst,
      .in_valid (v6),
      .in_value (SqrtW'(q_abs << 2)),  // |q| < 2^29 whenever the ray refracts
      .in_tag   (ride_in),
      .out_valid(sqrt_valid),
      .out_root (root),
      .out_tag  (ride_out)
  );

  // Last stage: along = round(sqrt(|q|)), next = perp - round(along n_f) for a refraction, else the mirror.
  logic               straight_r, inside_r, reflects_r, tir_r;
  (* mem2reg *) logic signed [16:0] nf_r[3];
  (* mem2reg *) logic signed [20:0] perp_r[3];
  (* mem2reg *) logic signed [18:0] mirror_r[3];
  (* mem2reg *) logic signed [34:0] along_nf[3];
  logic [TAG_W-1:0]   tag_r;
  logic [16:0]        along;
  assign {straight_r, inside_r, reflects_r, tir_r} = ride_out[RideW-1-:4];
  assign along = 17'((32'(root) + 32'd1) >> 1);
  for (genvar k = 0; k < 3; k++) begin : g_ride
    assign nf_r[k] = ride_out[TAG_W+3*19+3*21+(2-k)*17+:17];
    assign perp_r[k] = ride_out[TAG_W+3*19+(2-k)*21+:21];
    assign mirror_r[k] = ride_out[TAG_W+(2-k)*19+:19];
    assign along_nf[k] = $signed({1'b0, along}) * nf_r[k];
  end
  assign tag_r = ride_out[TAG_W-1:0];
  always_ff @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= sqrt_valid;
    out_straight <= straight_r;
    out_into <= straight_r ? !inside_r : reflects_r ? inside_r : !inside_r;
    out_refracted <= !straight_r && !reflects_r;
    out_drew <= !straight_r && !tir_r;
    for (int k = 0; k < 3; k++)
      out_next[k*24+:24] <= reflects_r ? 24'(mirror_r[k]) : 24'(64'(perp_r[k]) - ts_path_pkg::round_shift(64'(along_nf[k]), 14));
    out_tag <= tag_r;
  end
endmodule
