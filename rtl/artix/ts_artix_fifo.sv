// ts_artix_fifo: a first-in first-out queue of DEPTH words of W bits in distributed RAM (LUT RAM: an asynchronous
// read, so the front is readable in the cycle it is needed), for the artix unit's passes in flight and its
// reflected rays waiting for the issue port. A push and a pop may come in the same cycle. `clear` empties it (the
// line window's end drops everything in flight). The unit proves that it never overflows (ts_artix_unit.sv);
// `overflow` is a sticky flag for the tests to read. `empty` is a register of its own (not count == 0), so that the
// logic deciding on it (the unit's issue port, the world's engine) starts from a flip-flop.
module ts_artix_fifo #(
    parameter int W = 8,
    parameter int DEPTH = 32,  // a power of two
    localparam int AW = $clog2(DEPTH)
) (
    input  logic         clk,
    input  logic         rst,
    input  logic         clear,
    input  logic         push,
    input  logic [W-1:0] push_data,
    input  logic         pop,        // only when not empty
    output logic [W-1:0] front,
    output logic         empty,
    output logic         overflow
);
  logic [W-1:0]  mem [DEPTH];
  logic [AW-1:0] rd_q, wr_q;
  logic [AW:0]   count_q;
  logic          empty_q;

  assign front = mem[rd_q];
  assign empty = empty_q;

  always_ff @(posedge clk) begin
    if (push) mem[wr_q] <= push_data;
  end

  always_ff @(posedge clk) begin
    if (rst) begin
      rd_q     <= '0;
      wr_q     <= '0;
      count_q  <= '0;
      empty_q  <= 1'b1;
      overflow <= 1'b0;
    end else if (clear) begin
      rd_q    <= '0;
      wr_q    <= '0;
      count_q <= '0;
      empty_q <= 1'b1;
    end else begin
      if (push) wr_q <= wr_q + AW'(1);
      if (pop) rd_q <= rd_q + AW'(1);
      if (push && !pop) begin
        count_q <= count_q + (AW + 1)'(1);
        empty_q <= 1'b0;
      end else if (pop && !push) begin
        count_q <= count_q - (AW + 1)'(1);
        empty_q <= count_q == (AW + 1)'(1);
      end
      if (push && !pop && count_q == (AW + 1)'(DEPTH)) overflow <= 1'b1;
    end
  end
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proof artix_fifo). The user keeps the rule
  // above, a pop only when not empty; a push into a full queue without a pop is an overflow, which the flag must
  // report, and after which the queue promises nothing more (the unit proves it never happens).
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);
  always_comb if (!rst) assume (!(pop && empty));

  // One element tracked from its push to its pop (the free-element trick: f_pick chooses which, any push may be
  // the one): its data and how many elements are ahead of it.
  /* verilator lint_off UNDRIVEN */  // a free input of the proof: the solver drives it
  (* anyseq *) logic f_pick;
  /* verilator lint_on UNDRIVEN */
  logic          f_tracking_q;
  logic [W-1:0]  f_data_q;
  logic [AW:0]   f_ahead_q;
  always_ff @(posedge clk) begin
    if (rst || clear) begin
      f_tracking_q <= 1'b0;
    end else if (f_tracking_q) begin
      if (pop) begin
        f_tracking_q <= f_ahead_q != '0;
        f_ahead_q    <= f_ahead_q - (AW + 1)'(1);
      end
    end else if (push && f_pick) begin
      f_tracking_q <= 1'b1;
      f_data_q     <= push_data;
      f_ahead_q    <= count_q - (AW + 1)'(pop);
    end
  end

  always_comb begin
    if (past_valid && !overflow) begin
      // The count stays within 0..DEPTH (no underflow past 0, no count beyond the memory), empty says whether it
      // is 0, and the pointers are count apart: rules out an empty flag that disagrees with the count (the
      // register of its own that the unit's issue port decides on), a pointer stepping without the count.
      p_count: assert (count_q <= (AW + 1)'(DEPTH) && empty_q == (count_q == '0)
                       && wr_q - rd_q == count_q[AW-1:0]);
      // The tracked element is where its place says, unchanged, and comes out in its turn: rules out a lost or
      // overwritten element, and one that comes out before or after its turn.
      if (f_tracking_q) begin
        p_tracked: assert (f_ahead_q < count_q && mem[rd_q+f_ahead_q[AW-1:0]] == f_data_q);
        if (pop && f_ahead_q == '0) p_order: assert (front == f_data_q);
      end
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      // overflow is sticky and rises exactly at a push into a full queue without a pop: rules out an overflow
      // that goes unreported (or is reported without one).
      p_overflow: assert (overflow == ($past(overflow)
                                       || !$past(clear) && $past(push && !pop && count_q == (AW + 1)'(DEPTH))));
    end
  end
`endif
endmodule
