// The path preset's light book-keeping (src/tripsitter/device/path_kernel.h): a path's throughput times the albedo of
// the surface it bounces off (take_albedo), and the sky's light a path that escapes brings back (sky_light), every
// product rounded as the model rounds it. Both from one input, 2 cycles later, a path a cycle, with a tag.
//
// throughput' = (throughput x albedo + 2^15) >> 16 (each times 2^16, 1.0 = 65536; albedo = a 257 + a / 128 for a byte
// a, up to 65536). The sky: a = (2^14 + up + 1) >> 1 from the escaping direction's up component (times 2^14), sky =
// bottom + round((top - bottom) a / 2^14) per channel (bottom white, 65536; top (32768, 45875, 65536)), light =
// round(throughput x sky / 2^16).
module ts_path_light #(
    parameter int TAG_W = 1
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             in_valid,
    input  logic [3*17-1:0]  in_throughput,  // r, g, b from the low bits, 17 bits each, times 2^16
    input  logic [3*17-1:0]  in_albedo,      // as the throughput
    input  logic [16:0]      in_up,          // signed, times 2^14
    input  logic [TAG_W-1:0] in_tag,
    output logic             out_valid,
    output logic [3*17-1:0]  out_throughput, // throughput times albedo
    output logic [3*18-1:0]  out_light,      // the sky's light times the throughput, 18 bits each, times 2^16
    output logic [TAG_W-1:0] out_tag
);
  // The sky's top less its bottom, channel k.
  function automatic logic signed [17:0] sky_top_less(input int k);
    case (k)
      0: sky_top_less = -18'sd32768;
      1: sky_top_less = -18'sd19661;
      default: sky_top_less = 18'sd0;
    endcase
  endfunction

  // Stage 1: the throughput's products, and the sky's colour.
  (* mem2reg *) logic [33:0] kept[3];
  (* mem2reg *) logic signed [33:0] blend[3];
  logic [14:0] a;
  assign a = 15'((18'sd16384 + 18'($signed(in_up)) + 18'sd1) >>> 1);
  for (genvar k = 0; k < 3; k++) begin : g_mix
    assign kept[k] = in_throughput[k*17+:17] * in_albedo[k*17+:17];
    assign blend[k] = sky_top_less(k) * $signed({1'b0, a});
  end
  logic               v1;
  logic [3*17-1:0]    throughput1, kept1;
  (* mem2reg *) logic [16:0] sky1[3];
  logic [TAG_W-1:0]   tag1;
  always_ff @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    throughput1 <= in_throughput;
    for (int k = 0; k < 3; k++) begin
      kept1[k*17+:17] <= 17'((kept[k] + 34'd32768) >> 16);
      sky1[k] <= 17'(64'sd65536 + ts_path_pkg::round_shift(64'(blend[k]), 14));
    end
    tag1 <= in_tag;
  end

  // Stage 2: the light.
  (* mem2reg *) logic [33:0] lit[3];
  for (genvar k = 0; k < 3; k++) begin : g_light
    assign lit[k] = throughput1[k*17+:17] * sky1[k];
  end
  always_ff @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v1;
    out_throughput <= kept1;
    for (int k = 0; k < 3; k++) out_light[k*18+:18] <= 18'((lit[k] + 34'd32768) >> 16);
    out_tag <= tag1;
  end
endmodule
