// ts_reset_sync: the board's reset. A push button (active low, asynchronous to the clock) and the FPGA's power-up
// become one synchronous, active-high reset for the device (ts_artix_device's `rst`).
//
// The button passes two flip-flops before it is used (a metastable first stage settles in the second). The reset is
// held for HOLD_CYCLES clocks after the button is released, and for HOLD_CYCLES clocks after configuration: the
// counter's power-up value (the FPGA loads every flip-flop's initial value when it is configured; Vivado and Yosys
// take it from the declaration) is 0, so the device starts reset without the button being pressed. A bouncing
// button only restarts the count: the reset ends HOLD_CYCLES after the last bounce.
module ts_reset_sync #(
    parameter int HOLD_CYCLES = 16  // clocks the reset outlasts the button and power-up; at least 2
) (
    input  logic clk,
    input  logic btn_n,  // asynchronous, active low
    output logic rst     // synchronous, active high
);
  localparam int CountW = $clog2(HOLD_CYCLES + 1);
  if (HOLD_CYCLES < 2) begin : g_bad_hold
    $error("ts_reset_sync: HOLD_CYCLES must be at least 2");
  end

  logic [1:0]        btn_q = 2'b00;      // the button's synchroniser; power-up: pressed
  logic [CountW-1:0] count_q = '0;       // clocks since the button was last seen pressed
  logic              rst_q = 1'b1;

  always_ff @(posedge clk) begin
    btn_q <= {btn_q[0], btn_n};
    if (!btn_q[1]) begin
      count_q <= '0;
      rst_q <= 1'b1;
    end else if (count_q != CountW'(HOLD_CYCLES)) begin
      count_q <= count_q + 1'b1;
      rst_q <= 1'b1;
    end else begin
      rst_q <= 1'b0;
    end
  end
  assign rst = rst_q;
endmodule
