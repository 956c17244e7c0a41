// ts_clock_gate: a clock that runs only in the cycles that need it. gclk has clk's rising edge in every cycle
// whose `en` is high at that edge, and none in the others, so registers clocked by gclk hold their values while `en`
// is low, as if every one of them had `en` as its clock enable.
//
// On the XC7A100T this is a BUFGCE, the global clock buffer with a glitch-free enable (7 Series Clocking Resources,
// UG472): the gated clock is a global clock of its own, timed against clk by the tools (same source, one buffer
// each), and a block it clocks draws no dynamic power while it waits. A device has 32 global buffers: the artix
// device uses 13 (clk's own, one per sphere unit (9), the camera's, the world engine's and the tile builder's),
// ts_device one per worker beside clk's (11 with ten workers). In simulation (Verilator) it is the latch-and-AND
// gate that a BUFGCE is inside: `en` is taken while clk is low and held while it is high. The gate is also what
// makes the RTL simulate at the speed of its busy blocks: Verilator evaluates a block clocked by gclk, its
// combinational logic included, only at gclk's edges (docs/rtl.md, "The workers' clocks", and "The artix device",
// "The clocks" and "Simulation speed").
//
// `en` must come from registers of clk's or gclk's domain through logic short enough to meet the BUFGCE's CE setup
// time, and it must be high in every cycle in which a register of the gated block would change.
module ts_clock_gate (
    input  logic clk,
    input  logic en,
    output logic gclk
);
`ifdef VERILATOR
  logic en_low;
  always_latch if (!clk) en_low = en;
  assign gclk = clk & en_low;
`else
  BUFGCE gate (.I(clk), .CE(en), .O(gclk));
`endif
endmodule
