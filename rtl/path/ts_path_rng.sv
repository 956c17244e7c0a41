// The path preset's random streams (src/tripsitter/device/path_rng.h) in hardware, for the artix path preset's RTL:
// a sample's stream is seeded from (pixel, sample index) through the seed hash, a pipeline that takes a key every
// cycle, and then draws one xorshift32 value a cycle. A colour must not depend on which unit traced it, so the stream
// carries nothing from one sample to the next: the seed is all there is.
//
// Seeding (Latency = 4 cycles, a key a cycle, each with its tag):
//   1. key = pixel + 307200 x sample index (mod 2^32; 307200 = 2^18 + 2^15 + 2^13 + 2^12, four shifted adds);
//   2. x = (key ^ key >> 16) x 0x7feb352d (the low 32 bits: a 32 x 32 multiply, three DSP48E1 on the chip);
//   3. x = (x ^ x >> 15) x 0x846ca68b;
//   4. state = x ^ x >> 16, or 0x9e3779b9 for the one key whose hash is 0 (xorshift never leaves 0).
// The stream: the state the seed pipeline last put out (seed_out_valid loads it), advanced by one xorshift32 step
// (shifts 13, 17, 5) in each cycle `draw` is high; `value` is the stream's current state, so after the k-th draw
// it is PathRng's k-th next().
module ts_path_rng #(
    parameter int TAG_W = 1
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             seed_valid,
    input  logic [18:0]      seed_pixel,   // row x 640 + col
    input  logic [31:0]      seed_sample,  // frame x spp + s, counted from the world's swap
    input  logic [TAG_W-1:0] seed_tag,
    output logic             seed_out_valid,
    output logic [31:0]      seed_out_state,
    output logic [TAG_W-1:0] seed_out_tag,
    input  logic             draw,
    output logic [31:0]      value
);
  localparam logic [31:0] Mix1 = 32'h7feb352d;
  localparam logic [31:0] Mix2 = 32'h846ca68b;
  localparam logic [31:0] ZeroStandIn = 32'h9e3779b9;

  logic [3:0] valid_q;
  logic [4*TAG_W-1:0] tags_q;  // stage i's tag in bits [i x TAG_W +: TAG_W]
  logic [31:0] key_q, mix1_q, mix2_q, state_q;

  logic [31:0] key_x, mix1_x;
  always_comb begin
    key_x = key_q ^ (key_q >> 16);
    mix1_x = mix1_q ^ (mix1_q >> 15);
  end

  always_ff @(posedge clk) begin
    if (rst) begin
      valid_q <= '0;
    end else begin
      valid_q <= {valid_q[2:0], seed_valid};
    end
    tags_q <= {tags_q[3*TAG_W-1:0], seed_tag};
    key_q <= {13'd0, seed_pixel} + (seed_sample << 18) + (seed_sample << 15) + (seed_sample << 13) +
             (seed_sample << 12);
    mix1_q <= key_x * Mix1;
    mix2_q <= mix1_x * Mix2;
    state_q <= (mix2_q ^ (mix2_q >> 16)) == '0 ? ZeroStandIn : mix2_q ^ (mix2_q >> 16);
  end

  assign seed_out_valid = valid_q[3];
  assign seed_out_state = state_q;
  assign seed_out_tag = tags_q[3*TAG_W +: TAG_W];

  // The stream.
  always_ff @(posedge clk) begin
    if (rst) value <= ZeroStandIn;
    else if (seed_out_valid) value <= state_q;
    else if (draw) value <= ts_path_pkg::xorshift32(value);
  end
endmodule
