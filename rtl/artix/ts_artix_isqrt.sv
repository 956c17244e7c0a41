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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs artix_isqrt, artix_isqrt_34). The
  // contract: out_root = floor(sqrt(x)) for every x, that is r^2 <= x < (r + 1)^2. Proven stage by stage: after
  // step k the stage holds the floor root r of x's top 2k bits and their remainder, top - r^2, which the next step
  // keeps. A property over the stages is one assertion on a vector of them (bit k - 1: after step k); a
  // counterexample's VCD shows which bit fell.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  localparam int FW = WIDTH + 2;  // (r + 1)^2 < 2^(WIDTH + 1)
  logic [Steps*WIDTH-1:0] f_x_q;   // each stage's x, carried beside it: after step k at [(k - 1) WIDTH +: WIDTH]
  logic [Steps-1:0]       f_root_bits, f_floor;
  logic [Steps-2:0]       f_remainder, f_rest;
  for (genvar k = 0; k < Steps; k++) begin : g_f_step
    logic [WIDTH-1:0] x;
    logic [FW-1:0]    top, r, sq;
    always_ff @(posedge clk) f_x_q[k*WIDTH+:WIDTH] <= k == 0 ? in_value : f_x_q[(k-1)*WIDTH+:WIDTH];
    assign x   = f_x_q[k*WIDTH+:WIDTH];
    assign top = FW'(x) >> (WIDTH - 2 * (k + 1));  // the bits of x taken so far
    assign r   = FW'(root_q[k*Steps+:Steps]);
    assign sq  = r * r;
    assign f_root_bits[k] = !valid_q[k] || r >> (k + 1) == '0;
    assign f_floor[k]     = !valid_q[k] || sq <= top && top < sq + (r << 1) + FW'(1);
    if (k + 1 < Steps) begin : g_inner
      assign f_remainder[k] = !valid_q[k] || FW'(rem_q[k*Steps+:Steps]) == top - sq;
      assign f_rest[k]      = !valid_q[k] || rest_q[k*WIDTH+:WIDTH] == x << 2 * (k + 1);
    end
  end

  // Above 24 bits z3 cannot bit-blast the squares for every input within the proofs' budget (WIDTH = 24 takes
  // 30 s, and each 4 more bits about four times that): the inputs are then those within 2^FWin of either end of
  // the range, where the root's and the remainder's widths are tested hardest (the remainder reaches 2 r with r
  // at its largest). Every input of the same logic at WIDTH = 16 is proven by the proof artix_isqrt.
  localparam int FWin = 12;
  if (WIDTH > 24) begin : g_window
    always_comb begin
      assume (in_value < WIDTH'(1) << FWin || in_value > ~(WIDTH'(1) << FWin));
    end
    for (genvar k = 0; k < Steps; k++) begin : g_carried
      always_comb assume (f_x_q[k*WIDTH+:WIDTH] < WIDTH'(1) << FWin || f_x_q[k*WIDTH+:WIDTH] > ~(WIDTH'(1) << FWin));
    end
  end

  always_comb begin
    if (past_valid) begin
      // After step k the root has k bits: rules out a root bit shifted in at the wrong place.
      p_root_bits: assert (&f_root_bits);
      // The remainder is top - r^2 (top: x's first 2k bits), and x's bits still to come are at the top of rest:
      // rules out a wrong trial, a flipped or off-by-one comparison, a bit pair taken from the wrong place, a
      // remainder bit lost to a narrow register.
      p_remainder: assert (&f_remainder);
      p_rest: assert (&f_rest);
      // r^2 <= top < (r + 1)^2 after each step; after the last, top is x: the contract, for every x.
      p_floor_root: assert (&f_floor);
    end
  end
`endif
endmodule
