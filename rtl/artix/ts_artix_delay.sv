// ts_artix_delay: W bits delayed by N clock cycles (N = 0: a wire). The artix blocks carry a pair's side data this way
// while the arithmetic works on it, so the delays are many and wide, and each is built where it is cheapest:
//   N = 1, 2   flip-flops;
//   N >= 3     a ring of 2^ceil(log2 N) words in distributed RAM (LUT RAM: RAM32M holds 32 words of 6 bits in 4
//              LUTs, so a bit costs 2/3 of a LUT up to 32 cycles, where a shift-register LUT costs one), written every
//              cycle at a free-running pointer and read N - 1 words behind it into an output register.
// The data have no reset (nothing reads them before valid bits that do); the pointer needs none either, as only its
// differences matter. A ring also simulates far faster than a shift register of N wide words, which Verilator
// moves whole every cycle.
module ts_artix_delay #(
    parameter int W = 1,
    parameter int N = 1
) (
    input  logic         clk,
    input  logic [W-1:0] in,
    output logic [W-1:0] out
);
  if (N == 0) begin : g_wire
    assign out = in;
    /* verilator lint_off UNUSEDSIGNAL */
    logic unused_clk;  // no register: the clock goes nowhere
    assign unused_clk = clk;
    /* verilator lint_on UNUSEDSIGNAL */
  end else if (N == 1) begin : g_flop
    logic [W-1:0] out_q;
    always_ff @(posedge clk) out_q <= in;
    assign out = out_q;
  end else if (N == 2) begin : g_flops
    logic [W-1:0] first_q, out_q;
    always_ff @(posedge clk) begin
      first_q <= in;
      out_q   <= first_q;
    end
    assign out = out_q;
  end else begin : g_ring
    localparam int AW = $clog2(N);
    logic [W-1:0]  ring [2**AW];
    logic [AW-1:0] wr_q;
    logic [W-1:0]  out_q;
    // in(t) is written at wr(t); in cycle t the word written N - 1 cycles before, in(t - N + 1), is read into the
    // output register, which holds it in cycle t + 1: a delay of N. The ring has at least N words, so that word has
    // not been overwritten.
    always_ff @(posedge clk) begin
      ring[wr_q] <= in;
      wr_q       <= wr_q + 1'b1;
      out_q      <= ring[wr_q - AW'(N - 1)];
    end
    assign out = out_q;
  end
endmodule
