// ts_rx_v1_word: the v1 wire: every 8 bytes from the start of the stream are one 64-bit sphere word, taken apart,
// moved from its 3 fractional bits to the preset's and checked against the preset's formats. Part of ts_receiver
// (docs/rtl.md).
//
// C++ twin: link::V1StreamDecoder and decode_v1_word (src/tripsitter/link/wire_v1.h/.cpp), and the conversion of
// device::Receiver::accept_v1 (src/tripsitter/device/receiver.cpp): x, y, z rescaled (core::rescale_raw: a shift
// left, or round to nearest with ties away from zero), the radius 2^(r + Frac) raw, the RGB444 colour's nibbles
// times 17 as the albedo; the word is out of range when a coordinate or the radius does not fit the preset.
//
// Timing: the byte's word is whole in the clock `byte_valid` brings its eighth byte; `word_valid` follows for one
// clock with `word_ok` and the sphere, which hold until the next word. `end_of_stream` drops a partial word (a byte
// in the same clock comes first): `partial_valid` for one clock with its bytes, when there are any.
module ts_rx_v1_word #(
    parameter int Frac = 4,  // fractional bits of the preset's formats
    parameter int XW = 24,   // total bits: x, y, z signed, radius unsigned
    parameter int YW = 24,
    parameter int ZW = 24,
    parameter int RW = 24
) (
    input  logic          clk,
    input  logic          rst,
    input  logic          byte_valid,
    input  logic [7:0]    byte_data,
    input  logic          end_of_stream,
    output logic          word_valid,
    output logic          word_ok,        // the sphere fits the preset's formats
    output logic [XW-1:0] x,
    output logic [YW-1:0] y,
    output logic [ZW-1:0] z,
    output logic [RW-1:0] r,
    output logic [23:0]   albedo,         // r, g, b from the high byte down
    output logic          partial_valid,
    output logic [2:0]    partial_bytes
);
  localparam int WordBytes = ts_link_pkg::V1WordBytes;
  localparam int Up = (Frac >= ts_link_pkg::V1Frac) ? Frac - ts_link_pkg::V1Frac : 0;    // to Frac: shift left,
  localparam int Down = (Frac < ts_link_pkg::V1Frac) ? ts_link_pkg::V1Frac - Frac : 0;  // or right, rounding
  localparam logic signed [63:0] Half = (Down > 0) ? (64'sd1 <<< (Down - 1)) : 64'sd0;
  // The preset's ranges (core::FixedFormat::contains), as 64-bit signed bounds.
  localparam logic signed [63:0] XMin = -(64'sd1 <<< (XW - 1));
  localparam logic signed [63:0] XMax = (64'sd1 <<< (XW - 1)) - 64'sd1;
  localparam logic signed [63:0] YMin = -(64'sd1 <<< (YW - 1));
  localparam logic signed [63:0] YMax = (64'sd1 <<< (YW - 1)) - 64'sd1;
  localparam logic signed [63:0] ZMin = -(64'sd1 <<< (ZW - 1));
  localparam logic signed [63:0] ZMax = (64'sd1 <<< (ZW - 1)) - 64'sd1;

  // core::rescale_raw from 3 fractional bits to Frac.
  function automatic logic signed [63:0] rescale(input logic signed [63:0] raw);
    logic signed [63:0] mag;
    mag = raw < 0 ? -raw : raw;
    mag = (mag + Half) >>> Down;
    rescale = (Down == 0) ? raw <<< Up : (raw < 0 ? -mag : mag);
  endfunction

  logic [55:0] word_q;        // the word's bytes so far, first byte in the top bits
  logic [2:0] filled_q;       // its bytes so far
  wire [63:0] word = {word_q, byte_data};
  wire whole = byte_valid && filled_q == 3'(WordBytes - 1);

  // The word that byte_data completes, taken apart.
  localparam int XAt = ts_link_pkg::V1XShift, XBits = ts_link_pkg::V1XW;
  localparam int YAt = ts_link_pkg::V1YShift, YBits = ts_link_pkg::V1YW;
  localparam int ZAt = ts_link_pkg::V1ZShift, ZBits = ts_link_pkg::V1ZW;
  wire signed [63:0] wx = rescale({{(64 - XBits){word[XAt+XBits-1]}}, word[XAt+:XBits]});  // sign-extended
  wire signed [63:0] wy = rescale({{(64 - YBits){word[YAt+YBits-1]}}, word[YAt+:YBits]});
  wire signed [63:0] wz = rescale({{(64 - ZBits){word[ZAt+ZBits-1]}}, word[ZAt+:ZBits]});
  wire [ts_link_pkg::V1RW-1:0] wr = word[ts_link_pkg::V1RShift+:ts_link_pkg::V1RW];
  wire [11:0] colour = word[ts_link_pkg::V1ColourShift+:ts_link_pkg::V1ColourW];
  wire [6:0] shift = {1'b0, wr} + 7'(Frac);  // the radius is 2^(r + Frac) raw
  wire ok = shift < 7'(RW) && wx >= XMin && wx <= XMax && wy >= YMin && wy <= YMax && wz >= ZMin && wz <= ZMax;

  wire [2:0] filled_next = byte_valid ? filled_q + 3'd1 : filled_q;  // wraps to 0 after the eighth byte

  always_ff @(posedge clk) begin
    if (rst) begin
      filled_q <= '0;
      word_valid <= 1'b0;
      partial_valid <= 1'b0;
    end else begin
      word_valid <= whole;
      partial_valid <= end_of_stream && filled_next != 3'd0;
      filled_q <= end_of_stream ? 3'd0 : filled_next;
    end
  end

  // Datapath: no reset (word_valid and filled_q say when these hold).
  /* verilator lint_off UNUSEDSIGNAL */  // the rescaled fields' high bits: the range check made them the sign's copies
  always_ff @(posedge clk) begin
    if (byte_valid) word_q <= word[55:0];
    partial_bytes <= filled_next;
    if (whole) begin
      word_ok <= ok;
      x <= wx[XW-1:0];
      y <= wy[YW-1:0];
      z <= wz[ZW-1:0];
      r <= RW'(1) << shift;
      // RGB444 colour to 8-bit albedo: each nibble times 17 (0xF -> 0xFF).
      albedo <= {colour[11:8], colour[11:8], colour[7:4], colour[7:4], colour[3:0], colour[3:0]};
    end
  end
  /* verilator lint_on UNUSEDSIGNAL */
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proof rx_v1_word). The byte stream is free.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The bytes of the current word so far, counted from the stream's start and from each end_of_stream (which
  // drops a partial word; a byte in the same clock comes first), and the clocks since the last word (up to 8).
  logic [3:0] f_bytes, f_since_word;
  always_ff @(posedge clk) begin
    if (rst) begin
      f_bytes <= '0;
      f_since_word <= 4'd8;
    end else begin
      if (end_of_stream) f_bytes <= '0;
      else if (byte_valid) f_bytes <= (f_bytes == 4'd7) ? 4'd0 : f_bytes + 4'd1;
      f_since_word <= word_valid ? 4'd1 : (f_since_word == 4'd8) ? 4'd8 : f_since_word + 4'd1;
    end
  end
  always_comb begin
    if (past_valid) begin
      // Invariant that makes the induction close: the block's count of the word's bytes is the stream's.
      p_filled_counts: assert (4'(filled_q) == f_bytes && f_bytes <= 4'd7
                               && (f_since_word >= 4'(filled_q) || f_since_word == 4'd8));
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      // A word comes the clock after its eighth byte, every 8 bytes of the stream, and never within 8 clocks of
      // the last (ts_rx_commit's contract for v1, f_v1_ok); a partial word only at end_of_stream with its 1 to 7
      // bytes, never with a word. Rules out a word assembled across an end of stream, or from 7 or 9 bytes.
      p_word_at_eighth_byte: assert (word_valid == $past(byte_valid && f_bytes == 4'd7));
      if (word_valid) p_word_spacing: assert ($past(f_since_word) >= 4'd7 && !partial_valid);
      p_partial_at_end: assert (partial_valid
                                == $past(end_of_stream && (byte_valid ? f_bytes != 4'd7 : f_bytes != 4'd0)));
      if (partial_valid) begin
        p_partial_bytes: assert (partial_bytes != 3'd0 && 4'(partial_bytes) == $past(f_bytes + 4'(byte_valid)));
      end
    end
  end
`endif
endmodule
