// The path preset's lambertian and metal bounces (src/tripsitter/device/path_kernel.h, scatter(); approx.h,
// random_unit and reflect) as a pipeline that takes a bounce a cycle, with the artix path preset's arithmetic, so that
// its directions are the model's bit for bit.
//
// The random unit vector of a draw: z = (2 (draw >> 17) + 1 - 2^15) / 2^15 (odd multiples of 2^-15), rho =
// round(sqrt(1 - z^2)) times 2^14 (round(sqrt(x)) = (floor(sqrt(4 x)) + 1) / 2, on ts_artix_isqrt), the azimuth
// phi = (draw >> 5) & 4095 in 4096ths of a turn, u = (round(rho cos phi), round(rho sin phi), round(z 2^14)), the
// sine and cosine from a quarter-wave table of 1025 entries, round(2^14 sin(2 pi i / 4096)), computed here at
// elaboration in integers (a Taylor series in 62 fractional bits: every entry as the model's double gives it, the
// nearest to a tie 2.3e-4 of a unit away).
// Lambertian: next = n + u, or n where |n + u| < 2^-6. Metal: next = in - 2 round(in.n) n (each product rounded), plus
// round(u fuzz) when the fuzz is not 0; absorbed when next.n <= 0 (the fuzz pushed it below the surface).
// In: `metal` (else lambertian), the incoming direction `in` and the outward normal `n` (unit vectors times 2^14),
// the fuzz (times 2^-16) and the sample's next draw. Out, Latency = 20 cycles later with the tag: `next`, `absorbed`,
// and `drew` (the draw was taken: a lambertian bounce, or a metal with fuzz; the stream moves on only then).
module ts_path_diffuse #(
    parameter int TAG_W = 1
) (
    input  logic                    clk,
    input  logic                    rst,
    input  logic                    in_valid,
    input  logic                    in_metal,
    input  logic [3*17-1:0]         in_dir,        // x, y, z from the low bits: 17 bits signed each, times 2^14
    input  logic [3*17-1:0]         in_normal,     // outward, as in_dir
    input  logic [15:0]             in_fuzz,       // times 2^-16
    input  logic [31:0]             in_draw,
    input  logic [TAG_W-1:0]        in_tag,
    output logic                    out_valid,
    output logic                    out_absorbed,
    output logic                    out_drew,
    output logic [3*24-1:0]         out_next,      // x, y, z from the low bits: 24 bits signed each, times 2^14
    output logic [TAG_W-1:0]        out_tag
);
  localparam int SqrtW = 30;       // 4 x < 2^30
  localparam int Quarter = 1024;
  localparam logic [63:0] PiQ62 = 64'hC90FDAA22168C234;  // pi times 2^62


  // round(2^14 sin(pi i / 2048)) for 0 <= i <= 1024: sin x = x - x^3/3! + x^5/5! - ..., magnitudes in 62 fractional
  // bits, to x^21/21!.
  function automatic logic [14:0] quarter_sine(input int i);
    logic [127:0] x, x2, term, sum;
    x = 128'(PiQ62) * 128'(i) / 128'd2048;
    x2 = (x * x) >> 62;
    term = x;
    sum = x;
    for (int k = 1; k <= 10; k++) begin
      term = ((term * x2) >> 62) / 128'(2 * k * (2 * k + 1));
      if (k % 2 == 1) sum = sum - term;
      else sum = sum + term;
    end
    quarter_sine = 15'((sum * 128'd16384 + (128'd1 << 61)) >> 62);
  endfunction

  logic [14:0] sine_rom [Quarter + 1];
  initial begin
    for (int i = 0; i <= Quarter; i++) sine_rom[i] = quarter_sine(i);
  end

  // sin(2 pi i / 4096) times 2^14 from the quarter wave.
  function automatic logic signed [15:0] sine(input logic [11:0] i);
    logic [9:0] j;
    j = i[9:0];
    case (i[11:10])
      2'd0: sine = 16'(sine_rom[{1'b0, j}]);
      2'd1: sine = 16'(sine_rom[11'(Quarter) - {1'b0, j}]);
      2'd2: sine = -(16'(sine_rom[{1'b0, j}]));
      default: sine = -(16'(sine_rom[11'(Quarter) - {1'b0, j}]));
    endcase
  endfunction

  /* verilator lint_off UNUSEDSIGNAL */  // the draw's low 5 bits: the model's unit vector takes bits 5..31 only
  logic [4:0] unused_draw;
  assign unused_draw = in_draw[4:0];
  /* verilator lint_on UNUSEDSIGNAL */

  // Stage 1: z, (1 - z^2) / 4, the azimuth; in.n for the mirror.
  (* mem2reg *) logic signed [16:0] dir_in[3], n_in[3];
  (* mem2reg *) logic signed [33:0] dn_in[3];
  for (genvar k = 0; k < 3; k++) begin : g_in
    assign dir_in[k] = in_dir[k*17+:17];
    assign n_in[k] = in_normal[k*17+:17];
    assign dn_in[k] = dir_in[k] * n_in[k];
  end
  logic signed [16:0] zq_in;  // z times 2^15, odd
  logic signed [33:0] zsq_in;
  assign zq_in = 17'($signed({1'b0, in_draw[31:17], 1'b1})) - 17'sd32768;
  assign zsq_in = zq_in * zq_in;
  logic               v1;
  logic [27:0]        x1;     // (2^30 - z^2 2^30) >> 2
  localparam int RideW = 1 + 3 * 17 + 3 * 17 + 36 + 17 + 12 + 16 + 1 + TAG_W;
  logic [RideW-1:0]   ride1, ride_out;
  always_ff @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    x1 <= 28'((35'sd1073741824 - 35'(zsq_in)) >>> 2);
    ride1 <= {in_metal, in_dir, in_normal, 36'(dn_in[0]) + 36'(dn_in[1]) + 36'(dn_in[2]), zq_in, in_draw[16:5],
              in_fuzz, in_metal ? in_fuzz != 16'd0 : 1'b1, in_tag};
  end

  // rho: the square root, everything else riding in its tag.
  logic               sqrt_valid;
  logic [SqrtW/2-1:0] root;
  ts_artix_isqrt #(
      .WIDTH(SqrtW),
      .TAG_W(RideW)
  ) u_sqrt (
      .clk,
      .rst,
      .in_valid (v1),
      .in_value (SqrtW'(x1) << 2),
      .in_tag   (ride1),
      .out_valid(sqrt_valid),
      .out_root (root),
      .out_tag  (ride_out)
  );

  logic               metal_r, drew_r;
  (* mem2reg *) logic signed [16:0] dir_r[3], n_r[3];
  logic signed [35:0] dot_r;
  logic signed [16:0] zq_r;
  logic [11:0]        phi_r;
  logic [15:0]        fuzz_r;
  logic [TAG_W-1:0]   tag_r;
  assign metal_r = ride_out[RideW-1];
  for (genvar k = 0; k < 3; k++) begin : g_ride
    assign dir_r[k] = ride_out[RideW-1-3*17+k*17+:17];
    assign n_r[k] = ride_out[RideW-1-6*17+k*17+:17];
  end
  assign {dot_r, zq_r, phi_r, fuzz_r, drew_r, tag_r} = ride_out[RideW-1-6*17-1:0];

  // Stage 2: rho, the table's sine and cosine, round(in.n).
  logic               v2, metal2, drew2;
  (* mem2reg *) logic signed [16:0] dir2[3], n2[3];
  logic [15:0]        rho2;
  logic signed [15:0] cos2, sin2;
  logic signed [17:0] d2;
  logic signed [16:0] zq2;
  logic [15:0]        fuzz2;
  logic [TAG_W-1:0]   tag2;
  always_ff @(posedge clk) begin
    if (rst) v2 <= 1'b0;
    else v2 <= sqrt_valid;
    metal2 <= metal_r;
    drew2 <= drew_r;
    for (int k = 0; k < 3; k++) begin
      dir2[k] <= dir_r[k];
      n2[k] <= n_r[k];
    end
    rho2 <= 16'((32'(root) + 32'd1) >> 1);
    cos2 <= sine(phi_r + 12'(Quarter));
    sin2 <= sine(phi_r);
    d2 <= 18'(ts_path_pkg::round_shift(64'(dot_r), 14));
    zq2 <= zq_r;
    fuzz2 <= fuzz_r;
    tag2 <= tag_r;
  end

  // Stage 3: u, and the mirror direction in - round(2 d n).
  logic signed [32:0] rho_cos, rho_sin;
  (* mem2reg *) logic signed [35:0] d_n[3];
  assign rho_cos = $signed({1'b0, rho2}) * cos2;
  assign rho_sin = $signed({1'b0, rho2}) * sin2;
  for (genvar k = 0; k < 3; k++) begin : g_mirror
    assign d_n[k] = d2 * n2[k];
  end
  logic               v3, metal3, drew3;
  (* mem2reg *) logic signed [16:0] n3[3];
  (* mem2reg *) logic signed [16:0] u3[3];
  (* mem2reg *) logic signed [18:0] mirror3[3];
  logic [15:0]        fuzz3;
  logic [TAG_W-1:0]   tag3;
  always_ff @(posedge clk) begin
    if (rst) v3 <= 1'b0;
    else v3 <= v2;
    metal3 <= metal2;
    drew3 <= drew2;
    u3[0] <= 17'(ts_path_pkg::round_shift(64'(rho_cos), 14));
    u3[1] <= 17'(ts_path_pkg::round_shift(64'(rho_sin), 14));
    u3[2] <= 17'(ts_path_pkg::round_shift(64'(zq2), 1));
    for (int k = 0; k < 3; k++) begin
      n3[k] <= n2[k];
      mirror3[k] <= 19'(dir2[k]) - 19'(ts_path_pkg::round_shift(64'(d_n[k]) <<< 1, 14));
    end
    fuzz3 <= fuzz2;
    tag3 <= tag2;
  end

  // Stage 4: next = the mirror plus round(u fuzz) (metal), or n + u (lambertian).
  (* mem2reg *) logic signed [33:0] u_fuzz[3];
  for (genvar k = 0; k < 3; k++) begin : g_fuzz
    assign u_fuzz[k] = u3[k] * $signed({1'b0, fuzz3});
  end
  logic               v4, metal4, drew4;
  (* mem2reg *) logic signed [16:0] n4[3];
  (* mem2reg *) logic signed [19:0] next4[3];
  logic [TAG_W-1:0]   tag4;
  always_ff @(posedge clk) begin
    if (rst) v4 <= 1'b0;
    else v4 <= v3;
    metal4 <= metal3;
    drew4 <= drew3;
    for (int k = 0; k < 3; k++) begin
      n4[k] <= n3[k];
      if (metal3) next4[k] <= 20'(mirror3[k]) + (fuzz3 != 16'd0 ? 20'(ts_path_pkg::round_shift(64'(u_fuzz[k]), 16)) : 20'sd0);
      else next4[k] <= 20'(n3[k]) + 20'(u3[k]);
    end
    tag4 <= tag3;
  end

  // Last stage: a metal below its surface is absorbed; a lambertian direction shorter than 2^-6 is the normal.
  (* mem2reg *) logic signed [36:0] next_n[3], next_sq[3];
  for (genvar k = 0; k < 3; k++) begin : g_check
    assign next_n[k] = next4[k] * n4[k];
    assign next_sq[k] = next4[k] * next4[k];
  end
  logic signed [38:0] along_n, length_sq;
  assign along_n = 39'(next_n[0]) + 39'(next_n[1]) + 39'(next_n[2]);
  assign length_sq = 39'(next_sq[0]) + 39'(next_sq[1]) + 39'(next_sq[2]);
  always_ff @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v4;
    out_absorbed <= metal4 && along_n <= 0;
    out_drew <= drew4;
    for (int k = 0; k < 3; k++)
      out_next[k*24+:24] <= !metal4 && length_sq < 39'sd65536 ? 24'(n4[k]) : 24'(next4[k]);
    out_tag <= tag4;
  end
endmodule
