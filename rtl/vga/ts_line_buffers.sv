// ts_line_buffers: the device's two line buffers of 640 RGB444 pixels, ping-pong. The controller writes the
// colours of the next line into the back buffer while the VGA block reads the current line from the front one;
// the two swap roles at the end of every line.
//
// C++ model: Device's line_buffers_ and front_ (src/tripsitter/device/device.h/.cpp): the back buffer is filled
// at the start of each line's work, the VGA block reads front[col] for each visible column, and front_ flips
// after the line's last pixel clock (column 799). In the model every slot of a new line is written: the colour
// of a pixel finished in time, black otherwise (schedule_pixels: a worker clears a pixel's slot when it starts
// it, and a pixel never started stays black).
//
// Banks. Workers finish pixels independently and, in the pipelined preset with few spheres, every worker can
// deliver a colour in the same cycle (one sphere: all N workers, every cycle). One write port per buffer cannot
// take that, so each buffer is split by worker: bank i holds the columns of worker i (i, i + N, i + 2N, ...), slot
// s of bank i being column i + s N. Each bank of each buffer is a memory of SLOTS = ceil(640 / N) words (a written
// flag and the 12-bit colour) with one write port and one registered read port (a simple dual-port RAM): worker i
// writes only its own bank, so N colours can land in one cycle. Yosys maps each to block RAM when it is deep
// (N = 1: two RAMB18 of 640 words) and to distributed RAM when it is shallow (N = 10: 64 words, LUT RAM),
// whichever is cheaper; BLOCK_RAM = 1 asks for block RAM in every case (N = 10: 20 RAMB18, and no LUT RAM). The
// total is always the two buffers of 640 pixels.
//
// Black slots. A bank's write port belongs to the controller while the bank is in the back buffer, and to the
// VGA side while it is in the front buffer: the VGA block reads each front slot once per line (rd_en, columns in
// order from 0) and the cycle after the read its slot is made black (its flag cleared). Every line sweeps all 640
// slots of the front buffer, blanking lines included, so a buffer is all black when it becomes the back buffer,
// and a slot the controller does not write in the line's window (a late or unstarted pixel) shows black, as in
// the model. After reset the buffers hold anything, but 44 blanking lines sweep both before the first line is
// written.
module ts_line_buffers #(
    parameter int N = 10,                                 // workers, one bank each
    parameter int BLOCK_RAM = 0,                          // 1: ask Yosys for block RAM whatever the depth
    localparam int Slots = (640 + N - 1) / N,             // pixels of the busiest worker
    localparam int SlotW = Slots > 1 ? $clog2(Slots) : 1,
    localparam int BankW = N > 1 ? $clog2(N) : 1
) (
    input  logic              clk,
    input  logic              rst,
    input  logic              swap,       // the line's last cycle: the buffers swap after it (ts_vga_timing line_end)
    // The controller: worker i's colour for slot wr_slot[i] of bank i in the back buffer.
    input  logic [N-1:0]      wr_en,
    input  logic [N*SlotW-1:0] wr_slot,
    input  logic [N*12-1:0]   wr_colour,
    // The VGA block: the front buffer's next pixel (column 0 first after each swap); its slot then turns black.
    input  logic              rd_en,
    output logic [11:0]       rd_data     // the cycle after rd_en
);
  logic             front_q;    // which buffer (0 or 1) the VGA block reads
  logic [BankW-1:0] rd_bank_q;  // the next column to read, as bank (column mod N) and slot (column div N)
  logic [SlotW-1:0] rd_slot_q;
  logic             clr_q;      // the slot read in the previous cycle is cleared in this one
  logic [BankW-1:0] clr_bank_q;
  logic [SlotW-1:0] clr_slot_q;
  logic             sel_front_q;  // which memory's read register holds rd_data
  logic [BankW-1:0] sel_bank_q;

  always_ff @(posedge clk) begin
    if (rst) begin
      front_q     <= 1'b0;
      rd_bank_q   <= '0;
      rd_slot_q   <= '0;
      clr_q       <= 1'b0;
      clr_bank_q  <= '0;
      clr_slot_q  <= '0;
      sel_front_q <= 1'b0;
      sel_bank_q  <= '0;
    end else begin
      clr_q      <= rd_en;
      clr_bank_q <= rd_bank_q;
      clr_slot_q <= rd_slot_q;
      if (rd_en) begin
        sel_front_q <= front_q;
        sel_bank_q  <= rd_bank_q;
        // Columns in order: the next bank, and the next slot after the last bank.
        if (rd_bank_q == BankW'(N - 1)) begin
          rd_bank_q <= '0;
          rd_slot_q <= rd_slot_q + SlotW'(1);
        end else begin
          rd_bank_q <= rd_bank_q + BankW'(1);
        end
      end
      if (swap) begin
        front_q   <= !front_q;
        rd_bank_q <= '0;
        rd_slot_q <= '0;
      end
    end
  end

  // The 2N memories: buffer b, bank i. A word is a written flag and the colour: a clear writes only the flag
  // (0) and leaves the colour bits as they come, which saves a 12-bit multiplexer on every memory's write data;
  // the flag zeroes the colour once, after the read multiplexer. Their read registers, flattened per buffer:
  // bank i at bits i 13.
  logic [N*13-1:0] q_buf0, q_buf1;

  for (genvar b = 0; b < 2; b++) begin : g_buffer
    for (genvar i = 0; i < N; i++) begin : g_bank
      logic [12:0] q;
      logic is_front;
      logic we, re;
      logic [SlotW-1:0] waddr;
      logic [12:0] wdata;

      assign is_front = front_q == 1'(b);
      // Back: the controller's colours. Front: black (the flag 0) into the slot read the cycle before.
      assign we    = is_front ? clr_q && clr_bank_q == BankW'(i) : wr_en[i];
      assign waddr = is_front ? clr_slot_q : wr_slot[i*SlotW+:SlotW];
      assign wdata = {!is_front, wr_colour[i*12+:12]};
      // Only the front buffer is read, so a memory is never read and written in the same cycle at one address
      // (the clear follows its read by one cycle; the next read is four cycles later).
      assign re    = rd_en && is_front;

      if (BLOCK_RAM != 0) begin : g_block
        (* ram_style = "block" *) logic [12:0] mem[Slots];
        always_ff @(posedge clk) begin
          if (we) mem[waddr] <= wdata;
        end
        always_ff @(posedge clk) begin
          if (rst) q <= 13'h0000;
          else if (re) q <= mem[rd_slot_q];
        end
      end else begin : g_auto
        logic [12:0] mem[Slots];
        always_ff @(posedge clk) begin
          if (we) mem[waddr] <= wdata;
        end
        always_ff @(posedge clk) begin
          if (rst) q <= 13'h0000;
          else if (re) q <= mem[rd_slot_q];
        end
      end
      if (b == 0) begin : g_q0
        assign q_buf0[i*13+:13] = q;
      end else begin : g_q1
        assign q_buf1[i*13+:13] = q;
      end
    end
  end

  // The colour of the memory read: a 2N-to-1 multiplexer on the read registers.
  logic [12:0] word;
  assign word    = sel_front_q ? q_buf1[sel_bank_q*13+:13] : q_buf0[sel_bank_q*13+:13];
  assign rd_data = word[12] ? word[11:0] : 12'h000;
endmodule
