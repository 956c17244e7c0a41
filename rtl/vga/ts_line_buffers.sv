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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs line_buffers, line_buffers_odd,
  // line_buffers_one). Every
  // input is free. The properties about what the VGA block reads hold while the reader has kept its side
  // (f_reader_ok, below), which ts_vga_timing does (its proven counters: rd_en at phase 0 of columns 0..639 and
  // swap at phase 3 of column 799, from column 0 after the reset); nothing is assumed but the reset.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The reader's side: 640 reads between two swaps (and from the reset to the first), none in a swap's cycle.
  // f_reader_ok falls for good at a breach. f_reads_q: the reads since the last swap (the column read next);
  // f_front_q: the buffer shown, 0 from the reset, the other after each swap (f_swapped_q: a swap a cycle ago);
  // f_rd_q: a read in the previous cycle, of column f_rd_col_q of buffer f_rd_buf_q (its slot turns black in this
  // cycle).
  logic       f_reader_ok, f_front_q, f_rd_q, f_rd_buf_q, f_swapped_q;
  logic [9:0] f_reads_q, f_rd_col_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      f_reader_ok <= 1'b1;
      f_front_q   <= 1'b0;
      f_reads_q   <= 10'd0;
      f_rd_q      <= 1'b0;
      f_swapped_q <= 1'b0;
    end else begin
      if ((rd_en && (swap || f_reads_q == 10'd640)) || (swap && f_reads_q != 10'd640)) f_reader_ok <= 1'b0;
      if (swap) f_front_q <= !f_front_q;
      f_reads_q <= swap ? 10'd0 : f_reads_q + 10'(rd_en);
      f_rd_q    <= rd_en;
      f_swapped_q <= swap;
    end
    f_rd_col_q <= f_reads_q;
    f_rd_buf_q <= f_front_q;
  end

  // Three columns tracked in each buffer: the first (bank 0, slot 0), the last bank's first (N - 1) and the last
  // (639), a ghost of each: what its slot holds for the VGA block, unknown after the reset (0), black (1: read and
  // so cleared since the controller last wrote it) or a colour written by the controller while the buffer was
  // the back one (2, f_colour). (Three fixed columns rather than a free one: the banks are memories, and a
  // solver-chosen address into them is slower.)
  localparam int Tracked = 3;
  logic [2*Tracked-1:0] f_holds_ok, f_black_ok, f_colour_ok, f_swept_ok;
  for (genvar b = 0; b < 2; b++) begin : f_buffer
    for (genvar j = 0; j < Tracked; j++) begin : f_column
      localparam int C = j == 0 ? 0 : j == 1 ? N - 1 : 639;
      localparam int Bank = C % N, Slot = C / N;
      logic [12:0] f_word;  // the slot's memory word
      if (BLOCK_RAM != 0) begin : f_block
        assign f_word = g_buffer[b].g_bank[Bank].g_block.mem[Slot];
      end else begin : f_auto
        assign f_word = g_buffer[b].g_bank[Bank].g_auto.mem[Slot];
      end
      logic [1:0]  f_state_q;
      logic [11:0] f_colour_q;
      logic [12:0] f_word_q;     // the word a cycle ago
      logic        f_was_front;  // the buffer was the front one a cycle ago
      logic        f_check_q;    // the column was read from this buffer a cycle ago, in state f_seen_q
      logic [1:0]  f_seen_q;
      logic [11:0] f_seen_colour_q;
      wire f_written = wr_en[Bank] && wr_slot[Bank*SlotW+:SlotW] == SlotW'(Slot) && f_front_q != 1'(b);
      wire f_cleared = f_rd_q && f_rd_buf_q == 1'(b) && f_rd_col_q == 10'(C);
      always_ff @(posedge clk) begin
        if (rst) begin
          f_state_q <= 2'd0;
          f_check_q <= 1'b0;
        end else begin
          if (f_written) begin
            f_state_q  <= 2'd2;
            f_colour_q <= wr_colour[Bank*12+:12];
          end else if (f_cleared) begin
            f_state_q <= 2'd1;
          end
          f_check_q <= rd_en && f_front_q == 1'(b) && f_reads_q == 10'(C);
        end
        f_seen_q        <= f_state_q;
        f_seen_colour_q <= f_colour_q;
        f_word_q        <= f_word;
        f_was_front     <= !rst && f_front_q == 1'(b);
      end
      localparam int K = b * Tracked + j;
      // The front buffer's word changes only to black (a clear): the controller never writes it.
      assign f_holds_ok[K] = !f_was_front || f_word == f_word_q || !f_word[12];
      // A slot cleared since the controller last wrote it holds black, and a read of it returns black; ...
      assign f_black_ok[K] = (f_state_q != 2'd1 || !f_word[12])
                             && (!f_check_q || f_seen_q != 2'd1 || rd_data == 12'h000);
      // ... a slot written holds the colour, and a read of it returns the colour.
      assign f_colour_ok[K] = (f_state_q != 2'd2 || f_word == {1'b1, f_colour_q})
                              && (!f_check_q || f_seen_q != 2'd2 || rd_data == f_seen_colour_q);
      // A front buffer's column read this line is black (cleared the cycle after its read), so a buffer becomes
      // the back one black.
      assign f_swept_ok[K] = (f_front_q != 1'(b) || f_reads_q <= 10'(C) || f_state_q == 2'd1
                              || (f_rd_q && f_rd_col_q == 10'(C) && f_rd_buf_q == 1'(b)))
                             && (!f_swapped_q || f_front_q == 1'(b) || f_state_q == 2'd1);
    end
  end

  always_comb begin
    if (past_valid) begin
      // The front buffer is never written: the words of the buffer shown change only to black, whatever comes
      // on the ports. Rules out a colour written into the line on screen (a write port routed to the front).
      p_front_holds: assert (&f_holds_ok);
      // The buffer shown (invariant).
      p_front_tracks: assert (front_q == f_front_q);
      if (f_reader_ok) begin
        // A late pixel shows black: the slot read in the previous cycle is the one cleared in this one, a slot
        // cleared and not written since holds black, and reads black. With p_swept, a slot the controller did
        // not write while its buffer was the back one reads black (from the second swap after the reset on,
        // when both buffers have been swept). Rules out a slot not cleared after its read, or another cleared.
        p_late_black: assert (&f_black_ok && clr_q == f_rd_q
                              && (!f_rd_q || (32'(clr_slot_q) * N + 32'(clr_bank_q) == 32'(f_rd_col_q)
                                              && 32'(clr_bank_q) < N)));
        // A slot the controller wrote holds and reads the colour written, and the reads go through the columns
        // in order from 0 after each swap. Rules out a read of the wrong bank, slot or buffer, a colour lost.
        p_read_colour: assert (&f_colour_ok && f_reads_q <= 10'd640
                               && (f_reads_q == 10'd640
                                   || (32'(rd_slot_q) * N + 32'(rd_bank_q) == 32'(f_reads_q) && 32'(rd_bank_q) < N)));
        // Each buffer becomes the back one all black (the VGA block swept it while it was shown).
        p_swept: assert (&f_swept_ok);
      end
    end
  end
`endif
endmodule
