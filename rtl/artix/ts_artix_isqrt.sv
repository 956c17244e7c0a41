// ts_artix_isqrt: the exact integer square root of the artix sphere unit, floor(sqrt(x)) for an unsigned x of
// WIDTH bits (core::isqrt, as artix::quadratic takes it of D), fully pipelined: one input a cycle, its root
// (WIDTH / 2 bits) Steps = WIDTH / 2 cycles later, with a tag of TAG_W bits riding along.
//
// Digit by digit, two bits of x a step from the top: with root r and remainder m = (x's bits so far) - r^2,
//     m' = 4 m + (the next two bits),  trial = 4 r + 1;   m' >= trial ? (m' - trial, 2 r + 1) : (m', 2 r)
// which keeps m' <= 2 r' (so m takes Steps + 1 bits and the trial Steps + 2). One subtraction and one mux a stage:
// a carry chain of at most 19 bits for the unit's 34-bit D, well inside a 100 MHz cycle.
module ts_artix_isqrt #(
    parameter int WIDTH = 34,  // even
    parameter int TAG_W = 1
) (
    input  logic                 clk,
    input  logic                 rst,
    input  logic                 in_valid,
    input  logic [WIDTH-1:0]     in_value,
    input  logic [TAG_W-1:0]     in_tag,
    output logic                 out_valid,
    output logic [WIDTH/2-1:0]   out_root,
    output logic [TAG_W-1:0]     out_tag
);
  localparam int Steps = WIDTH / 2;
  localparam int RemW = Steps + 2;  // m < 2 r + 1 <= 2^(Steps + 1), and 4 m + 3 before the subtraction

  if (WIDTH % 2 != 0 || WIDTH < 4) begin : g_bad_width
    $error("ts_artix_isqrt: WIDTH must be even and at least 4");
  end

  // Stage k (1..Steps) holds the root after k steps, and (before the last) the remainder (m <= 2 r < 2^k, Steps
  // bits) and the bits of x still to come, at the top; stage k's fields at [(k - 1) W +: W] of each vector.
  logic [Steps-1:0]           valid_q;
  logic [Steps*Steps-1:0]     root_q;
  logic [(Steps-1)*Steps-1:0] rem_q;   // the last step keeps neither
  logic [(Steps-1)*WIDTH-1:0] rest_q;
  logic [Steps*TAG_W-1:0]     tag_q;

  for (genvar k = 0; k < Steps; k++) begin : g_step
    logic             valid, up;
    logic [Steps-1:0] root, rem;
    logic [RemW-1:0]  shifted, trial, next_rem;
    logic [WIDTH-1:0] rest;
    logic [TAG_W-1:0] tag;
    if (k == 0) begin : g_first
      assign valid = in_valid;
      assign root  = '0;
      assign rem   = '0;
      assign rest  = in_value;
      assign tag   = in_tag;
    end else begin : g_next
      assign valid = valid_q[k-1];
      assign root  = root_q[(k-1)*Steps+:Steps];
      assign rem   = rem_q[(k-1)*Steps+:Steps];
      assign rest  = rest_q[(k-1)*WIDTH+:WIDTH];
      assign tag   = tag_q[(k-1)*TAG_W+:TAG_W];
    end
    // The next two bits of x enter at the bottom of the remainder; the trial is 4 r + 1.
    assign shifted  = {rem, rest[WIDTH-1-:2]};
    assign trial    = {root, 2'b01};
    assign up       = shifted >= trial;
    assign next_rem = up ? shifted - trial : shifted;

    always_ff @(posedge clk) begin
      if (rst) valid_q[k] <= 1'b0;
      else valid_q[k] <= valid;
      root_q[k*Steps+:Steps] <= {root[Steps-2:0], up};
      tag_q[k*TAG_W+:TAG_W]  <= tag;
    end
    if (k + 1 < Steps) begin : g_carry
      always_ff @(posedge clk) begin
        rem_q[k*Steps+:Steps]  <= next_rem[Steps-1:0];
        rest_q[k*WIDTH+:WIDTH] <= rest << 2;
      end
    end
    /* verilator lint_off UNUSEDSIGNAL */  // m' <= 2 r' < 2^(k+2): the top two bits are zero; the last step's m' and
    logic [RemW-1:0] unused_rem;          // x's low bits, used up, go nowhere
    assign unused_rem = next_rem ^ RemW'(rest[WIDTH-3:0]);
    /* verilator lint_on UNUSEDSIGNAL */
  end

  assign out_valid = valid_q[Steps-1];
  assign out_root  = root_q[(Steps-1)*Steps+:Steps];
  assign out_tag   = tag_q[(Steps-1)*TAG_W+:TAG_W];
endmodule
