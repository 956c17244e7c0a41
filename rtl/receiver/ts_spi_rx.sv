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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proof spi_rx). The pins are free: any levels in
  // any clock, SCLK faster than the 3-clock half period the host must keep included (what the block then does is
  // still what these properties say: it counts the edges it sees). Only the reset at the start is assumed.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The specification, written from the pins alone: each pin as it was two clocks before (f_*_d2, with SCLK's
  // level a clock older, f_sclk_d3, for its rising edge), reset to the levels the block resets its flops to. A byte
  // is the 8 MOSI levels seen at 8 rising SCLK edges counted from the clock chip select is seen low; the count
  // starts again whenever chip select is seen high.
  logic [1:0] f_since_rst;  // clocks since the last reset, up to 3
  logic f_sclk_d1, f_sclk_d2, f_sclk_d3, f_mosi_d1, f_mosi_d2, f_csn_d1, f_csn_d2;
  logic [3:0] f_edges;      // rising SCLK edges since chip select fell (wraps at 16: a multiple of 8 is bits 2:0 = 0)
  logic [6:0] f_byte;       // the MOSI levels at the last 7 of them, the latest in bit 0
  wire f_sel = !f_csn_d2;
  wire f_rise = f_sclk_d2 && !f_sclk_d3;
  always_ff @(posedge clk) begin
    if (rst) begin
      f_since_rst <= '0;
      {f_sclk_d1, f_sclk_d2, f_sclk_d3, f_mosi_d1, f_mosi_d2} <= '0;
      {f_csn_d1, f_csn_d2} <= '1;
      f_edges <= '0;
      f_byte <= '0;
    end else begin
      if (f_since_rst != 2'd3) f_since_rst <= f_since_rst + 2'd1;
      {f_sclk_d3, f_sclk_d2, f_sclk_d1} <= {f_sclk_d2, f_sclk_d1, sclk};
      {f_mosi_d2, f_mosi_d1} <= {f_mosi_d1, mosi};
      {f_csn_d2, f_csn_d1} <= {f_csn_d1, cs_n};
      if (!f_sel) begin
        f_edges <= '0;
      end else if (f_rise) begin
        f_edges <= f_edges + 4'd1;
        f_byte <= {f_byte[5:0], f_mosi_d2};
      end
    end
  end

  always_comb begin
    // Invariants that make the induction close, each itself a property: the block's bit count and partial byte are
    // the specification's (the synchronisers need none: three clocks determine them).
    if (past_valid) begin
      p_bits_count_edges: assert (bits == f_edges[2:0]);
      p_shift_is_bits: assert (shift == f_byte);
    end
  end
  always_ff @(posedge clk) begin
    // The synchronisers: each level the logic uses is the pin's level of exactly two clocks before, so it changes
    // at most once a clock and only after passing two flops (none of them reads a pin or a first stage directly:
    // a one-flop path fails p_byte_data or p_byte_at_eighth_edge); SCLK's third flop is its second's level a clock
    // later. Rules out a stage missing or a pin read directly, which the simulation's clean edges cannot show.
    if (past_valid && f_since_rst >= 2'd2) begin
      p_sclk_sync: assert (sclk_q[1] == $past(sclk, 2));
      p_mosi_sync: assert (mosi_q[1] == $past(mosi, 2));
      p_csn_sync: assert (csn_q[1] == $past(cs_n, 2));
    end
    if (past_valid && !$past(rst)) begin
      p_sclk_edge_flop: assert (sclk_q[2] == $past(sclk_q[1]));
      // A byte comes exactly in the clock after the eighth (16th, ...) rising SCLK edge seen since chip select was
      // seen low, and at no other time: never from edges of two transfers, never from edges while deselected.
      // Rules out a byte assembled across a chip-select gap or early/late by an edge.
      p_byte_at_eighth_edge: assert (byte_valid == $past(f_sel && f_rise && f_edges[2:0] == 3'd7));
      // Its bits are the MOSI levels at those 8 edges, the first in the top bit. Rules out a bit taken a clock off
      // its edge (another stage of the MOSI synchroniser) or shifted the wrong way.
      if (byte_valid) begin
        p_byte_data: assert (byte_data == $past({f_byte, f_mosi_d2}));
      end
      // A transfer that ends after 1 to 7 edges of a byte drops them and says so once; one ending on a byte boundary
      // does not. Rules out a partial byte carried into the next transfer.
      p_byte_cut: assert (byte_cut == $past(!f_sel && f_edges[2:0] != 3'd0));
    end
  end
`endif
endmodule
