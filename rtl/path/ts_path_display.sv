// The path preset's display (src/tripsitter/device/frame_memory.h, display_colour): what a pixel shows of its frame
// memory entry, one entry a cycle, 3 cycles later.
//
//   stage 1: the reciprocal of the count, round(2^18 / count), from a 256-entry table (19 bits);
//   stage 2: each channel's mean, (sum * reciprocal + 2^17) >> 18, at most 511 (a 17 x 19-bit product: one DSP48E1
//            a channel), looked up in the 512-entry table of 240 * sRGB(mean / 512), rounded (8 bits);
//   stage 3: the 4-bit channel, (that + t) >> 4, with t the pixel's 4 x 4 Bayer threshold (ordered dithering), or
//            8 (rounding) without dithering. An entry of count 0 shows black.
//
// The entry is ts_path_pixels', {epoch 5, count 8, b, g, r 17 bits each}; its epoch is not looked at (an entry of
// another world's epoch reaches the display only through the pixels' load, which opens it empty). Both tables
// are computed at elaboration in integers: the sRGB curve's power 1 / 2.4 = 5 / 12 by comparing twelfth and fifth
// powers exactly (gamma_of below), so no real arithmetic reaches the tools.
module ts_path_display #(
    parameter int TAG_W = 1
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             in_valid,
    input  logic [63:0]      in_entry,
    input  logic [1:0]       in_col,     // the pixel's column and row, modulo 4: its Bayer threshold
    input  logic [1:0]       in_row,
    input  logic             in_dither,
    input  logic [TAG_W-1:0] in_tag,
    output logic             out_valid,
    output logic [11:0]      out_rgb,    // r in the high 4 bits
    output logic [TAG_W-1:0] out_tag
);
  // round(2^18 / c), c = 1..255 (0 for c = 0: the entry shows black whatever the product).
  function automatic logic [18:0] reciprocal_of(input int c);
    reciprocal_of = c == 0 ? 19'd0 : 19'(((1 << 18) + c / 2) / c);
  endfunction

  // round(240 * sRGB(v / 512)), v = 0..511. On the linear segment (v / 512 <= 0.0031308: v <= 1) 240 * 12.92 v / 512;
  // above it, the count of levels k = 0..239 that 240 (1.055 x^(5/12) - 0.055) reaches k + 1/2 at, which is
  // x^(5/12) >= (10 k + 137) / 2532, that is v^5 2532^12 >= (10 k + 137)^12 2^45 (x = v / 2^9): monotonic in k, so a
  // binary search finds the count.
  function automatic logic [191:0] pow12(input logic [191:0] b);
    logic [191:0] p;
    p = 192'd1;
    for (int i = 0; i < 12; i++) p = p * b;
    pow12 = p;
  endfunction
  function automatic logic [7:0] gamma_of(input int v);
    logic [191:0] lhs;
    int lo, hi, mid, base;
    if (v <= 1) begin
      gamma_of = 8'((2 * 240 * 1292 * v + 51200) / 102400);
    end else begin
      lhs = 192'(v) * 192'(v) * 192'(v) * 192'(v) * 192'(v) * pow12(192'd2532);
      lo = 0;    // levels reached: at least lo, fewer than hi + 1
      hi = 240;
      for (int step = 0; step < 8; step++) begin  // 2^8 > 241 candidates
        mid = (lo + hi + 1) / 2;  // is level mid - 1 reached?
        base = 10 * (mid - 1) + 137;
        if (lo < hi) begin
          if (lhs >= (pow12(192'(base)) << 45)) lo = mid;
          else hi = mid - 1;
        end
      end
      gamma_of = 8'(lo);
    end
  endfunction

  logic [18:0] reciprocal[256];
  logic [7:0]  gamma[512];
  initial begin
    for (int c = 0; c < 256; c++) reciprocal[c] = reciprocal_of(c);
    for (int v = 0; v < 512; v++) gamma[v] = gamma_of(v);
  end

  // The pixel's threshold: the 4 x 4 Bayer matrix, row by row.
  function automatic logic [3:0] bayer(input logic [1:0] row, input logic [1:0] col);
    logic [63:0] m;
    m = {4'd5, 4'd13, 4'd7, 4'd15, 4'd9, 4'd1, 4'd11, 4'd3, 4'd6, 4'd14, 4'd4, 4'd12, 4'd10, 4'd2, 4'd8, 4'd0};
    bayer = m[{row, col, 2'b00}+:4];
  endfunction

  logic unused_epoch;  // the entry's epoch: see above
  assign unused_epoch = ^in_entry[63:59];

  // ---- stage 1 --------------------------------------------------------------------------------------------------
  logic             v1, shown1;
  logic [3*17-1:0]  sum1;
  logic [18:0]      rcp1;
  logic [3:0]       t1;
  logic [TAG_W-1:0] tag1;
  always_ff @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    shown1 <= in_entry[58:51] != 8'd0;
    sum1   <= in_entry[50:0];
    rcp1   <= reciprocal[in_entry[58:51]];
    t1     <= in_dither ? bayer(in_row, in_col) : 4'd8;
    tag1   <= in_tag;
  end

  // ---- stage 2 --------------------------------------------------------------------------------------------------
  logic             v2, shown2;
  logic [3*8-1:0]   g2;
  logic [3:0]       t2;
  logic [TAG_W-1:0] tag2;
  always_ff @(posedge clk) begin
    if (rst) v2 <= 1'b0;
    else v2 <= v1;
    shown2 <= shown1;
    t2 <= t1;
    tag2 <= tag1;
    for (int k = 0; k < 3; k++) begin
      logic [35:0] product;
      logic [17:0] mean;
      product = 36'(sum1[k*17+:17]) * 36'(rcp1);
      mean = 18'((product + 36'(1 << 17)) >> 18);
      g2[k*8+:8] <= gamma[mean > 18'd511 ? 9'd511 : 9'(mean)];
    end
  end

  // ---- stage 3 --------------------------------------------------------------------------------------------------
  always_ff @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v2;
    for (int k = 0; k < 3; k++) out_rgb[(2-k)*4+:4] <= shown2 ? 4'((9'(g2[k*8+:8]) + 9'(t2)) >> 4) : 4'd0;
    out_tag <= tag2;
  end
endmodule
