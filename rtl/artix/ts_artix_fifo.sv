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
endmodule
