// ts_debounce: a push button (active high, asynchronous to the clock, bouncing for a few milliseconds when pressed
// or released) as one clock's pulse per press.
//
// The button passes two flip-flops before it is used. Its level is taken as the button's state only when it has
// stayed the same for STABLE_CYCLES clocks in a row (a counter restarts at every change), so contacts that bounce for
// less than that make one press. `pressed` pulses in the clock the state becomes "down".
module ts_debounce #(
    parameter int STABLE_CYCLES = 1_000_000  // 10 ms at 100 MHz; at least 1
) (
    input  logic clk,
    input  logic rst,
    input  logic btn,      // asynchronous, active high
    output logic pressed   // one clock per press
);
  localparam int CountW = $clog2(STABLE_CYCLES + 1);
  if (STABLE_CYCLES < 1) begin : g_bad_stable
    $error("ts_debounce: STABLE_CYCLES must be at least 1");
  end

  // The planted bug that board_rtl_test must catch (TS_PLANT_NO_DEBOUNCE): every contact is a press.
`ifdef TS_PLANT_NO_DEBOUNCE
  localparam bit Planted = 1'b1;
`else
  localparam bit Planted = 1'b0;
`endif

  logic [1:0]        btn_q;
  logic              state_q;  // the debounced level
  logic [CountW-1:0] count_q;  // clocks the synchronised level has differed from state_q

  always_ff @(posedge clk) begin
    if (rst) begin
      btn_q <= 2'b00;
      state_q <= 1'b0;
      count_q <= '0;
      pressed <= 1'b0;
    end else begin
      btn_q <= {btn_q[0], btn};
      pressed <= 1'b0;
      if (btn_q[1] == state_q) begin
        count_q <= '0;
      end else if (Planted || count_q == CountW'(STABLE_CYCLES - 1)) begin
        count_q <= '0;
        state_q <= btn_q[1];
        pressed <= btn_q[1];
      end else begin
        count_q <= count_q + 1'b1;
      end
    end
  end
endmodule
