// ts_crc32: the link's CRC-32, one byte per clock.
//
// C++ model: src/tripsitter/core/crc32.cpp (core::crc32), the CRC of zlib, PNG and Ethernet that both framed
// wires use (docs/link_format.md): reflected polynomial 0xEDB88320, register preset to all ones, result
// inverted. The bytes of a frame are fed in wire order; `crc` is then exactly core::crc32 of them.
//
// Hardware: the 32-bit remainder register and the eight shift-and-conditionally-xor steps of one byte, unrolled
// into one combinational stage (about 32 XOR trees of a few inputs each: the table of the C++ model, computed
// instead of stored). Taking a byte every clock is far above the link's rate (one byte per 64 clocks or more).
module ts_crc32 (
    input  logic        clk,
    input  logic        rst,
    input  logic        clear,  // start a new CRC; with `en`, `data` is its first byte
    input  logic        en,     // take `data`
    input  logic [7:0]  data,
    output logic [31:0] crc     // CRC-32 of the bytes taken since the last clear (final inversion applied)
);
  localparam logic [31:0] kPoly = 32'hEDB8_8320;  // x^32 + x^26 + ... + 1, bit-reversed

  // One byte into the remainder: xor it into the low byte, then eight reflected shift steps.
  function automatic logic [31:0] step_byte(input logic [31:0] state, input logic [7:0] b);
    logic [31:0] c;
    c = state ^ {24'd0, b};
    for (int k = 0; k < 8; k++) c = c[0] ? ((c >> 1) ^ kPoly) : (c >> 1);
    step_byte = c;
  endfunction

  logic [31:0] state;  // the remainder, kept un-inverted (all ones after a clear)

  always_ff @(posedge clk) begin
    if (rst) begin
      state <= '1;
    end else if (en) begin
      state <= step_byte(clear ? '1 : state, data);
    end else if (clear) begin
      state <= '1;
    end
  end

  assign crc = ~state;
endmodule
