// ts_spi_rx: the device's end of the SPI link, a mode 0 slave (CPOL = 0, CPHA = 0), most significant bit first.
//
// C++ model: src/tripsitter/link/spi.h (SpiLink / Endpoint::transfer): the host moves the link's bytes in
// transfers, chip select low for each; transfer boundaries carry no meaning, the receiver reassembles the
// stream byte by byte (docs/link_format.md, "Transfers, the ready line and link time").
//
// Hardware: SCLK, MOSI and CS_n come from the host, asynchronous to the device clock, so each passes two
// flip-flops before it is used (a metastable first stage settles in the second). SCLK and MOSI go through
// synchronisers of the same depth, so a MOSI bit reaches the logic in the same clock as the SCLK edge that it
// was stable around (mode 0: the host changes MOSI on the falling edge, the slave samples it on the rising
// one). A third SCLK flop finds the rising edge. Each SCLK half period must last at least 3 device clocks for
// every edge to be seen once and MOSI to be steady around it; the link's default, 10 MHz against 100 MHz
// (5 clocks per half period), and the fastest allowed, clk/8 (4), both leave margin.
//
// Chip select rising ends the transfer. A byte is delivered when its eighth bit arrives, so the bytes of a
// transfer are the stream; whole transfers just continue it, as in the model (the C++ receiver sees a transfer
// as a span of whole bytes). Chip select rising after 1 to 7 bits of a byte is something the model never sees:
// those bits are dropped (`byte_cut` pulses once) and the next transfer starts on a byte boundary.
module ts_spi_rx (
    input  logic       clk,
    input  logic       rst,
    input  logic       sclk,       // asynchronous
    input  logic       mosi,       // asynchronous
    input  logic       cs_n,       // asynchronous, active low
    output logic       byte_valid, // one clock: byte_data holds the next byte of the stream
    output logic [7:0] byte_data,
    output logic       byte_cut    // one clock: chip select rose inside a byte, whose bits were dropped
);
  logic [2:0] sclk_q;  // two synchroniser stages and one for the edge
  logic [1:0] mosi_q;
  logic [1:0] csn_q;
  logic [6:0] shift;   // the bits of the byte so far
  logic [2:0] bits;    // how many

  wire sclk_rise = sclk_q[1] & ~sclk_q[2];
  wire selected = ~csn_q[1];

  always_ff @(posedge clk) begin
    if (rst) begin
      sclk_q <= '0;
      mosi_q <= '0;
      csn_q <= '1;  // deselected
      shift <= '0;
      bits <= '0;
      byte_valid <= 1'b0;
      byte_data <= '0;
      byte_cut <= 1'b0;
    end else begin
      sclk_q <= {sclk_q[1:0], sclk};
      mosi_q <= {mosi_q[0], mosi};
      csn_q <= {csn_q[0], cs_n};
      byte_valid <= 1'b0;
      byte_cut <= 1'b0;
      if (!selected) begin
        // Between transfers: a partial byte is dropped.
        byte_cut <= bits != 3'd0;
        bits <= '0;
      end else if (sclk_rise) begin
        shift <= {shift[5:0], mosi_q[1]};
        bits <= bits + 3'd1;  // wraps to 0 after the eighth bit
        if (bits == 3'd7) begin
          byte_valid <= 1'b1;
          byte_data <= {shift, mosi_q[1]};
        end
      end
    end
  end
endmodule
