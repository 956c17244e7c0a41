// Frame memory's port: a line period's read-modify-write of the accumulators through the Xilinx MIG 7 Series
// controller's user interface (UG586: app_en/app_cmd/app_addr/app_rdy for commands, app_wdf_* for write data,
// app_rd_data* for read data, returned in order), in the controller's clock (ui_clk: a quarter of the DDR3L's
// 325 MHz). Its C++ model is dram::line_requests (src/tripsitter/device/frame_dram.h): in display line i the entries
// of line i + 2 (mod 525) are read, those of line i - 1 written back, in alternating runs of RUN bursts, reads
// first. A burst is 16 bytes, two 64-bit entries (the first in the low bits); line r's burst b is at byte
// r * 5,120 + b * 16, app_addr counting the part's 16-bit words.
//
// The line buffers are the top's (dual-clock block RAM between this clock and the device's): read data goes out
// through load_* as it returns; write data comes in on store_data a clock after store_burst/store_row name it,
// which they do for the next write to make in every clock, so the data is there whenever the controller takes it.
//
// A line's traffic starts at `line_start` (the display line's start, brought into this clock by the top) and is
// done when its last read has returned. A line_start while the last line's traffic is unfinished counts a late
// line and waits for it (the schedule then runs behind the beam: the entries are not where the device wants them).
module ts_path_frame_port #(
    parameter int RUN = 32,         // bursts of one direction before the bus turns around
    parameter int ADDR_W = 28,      // app_addr of the Arty A7-100T's MT41K128M16 (rank, bank, row, column)
    parameter int CNT_W = 16,
    localparam int Bursts = 320,    // a line: 640 entries of 64 bits, 128 bits a burst
    localparam int BW = 9,          // a burst's index in its line
    localparam int Rows = 480,
    localparam int Lines = 525
) (
    input  logic              clk,
    input  logic              rst,
    input  logic              line_start,
    input  logic [9:0]        line,           // 0..524, with line_start
    // the controller's user interface
    output logic              app_en,
    output logic [2:0]        app_cmd,        // 3'b001 read, 3'b000 write
    output logic [ADDR_W-1:0] app_addr,
    input  logic              app_rdy,
    output logic              app_wdf_wren,
    output logic              app_wdf_end,
    output logic [127:0]      app_wdf_data,
    input  logic              app_wdf_rdy,
    input  logic              app_rd_data_valid,
    input  logic [127:0]      app_rd_data,
    // the line buffers
    output logic              load_we,
    output logic [8:0]        load_row,
    output logic [BW-1:0]     load_burst,
    output logic [127:0]      load_data,
    output logic [8:0]        store_row,
    output logic [BW-1:0]     store_burst,
    input  logic [127:0]      store_data,
    output logic              busy,
    output logic [CNT_W-1:0]  late_lines
);
  // ---- the line's schedule ---------------------------------------------------------------------------------------
  logic          pending;        // a line_start not yet begun
  logic [9:0]    pending_line;
  logic          reads, writes;  // this line reads a row, writes one
  logic [8:0]    read_row, write_row;
  logic [BW:0]   r, w;           // requests made
  logic [BW:0]   back;           // reads returned
  logic          writing;        // the run's direction
  logic [$clog2(RUN)-1:0] k;     // requests made in this run

  logic read_left, write_left, want_read, want_write, fire, fire_read, fire_write, begin_line, done;
  assign read_left  = reads && r != (BW + 1)'(Bursts);
  assign write_left = writes && w != (BW + 1)'(Bursts);
  assign want_read  = read_left && (!writing || !write_left);
  assign want_write = write_left && (writing || !read_left);
  // A write's command and its data go together: offered only when the data FIFO has room, taken in one clock.
  assign app_en       = want_read || (want_write && app_wdf_rdy);
  assign app_wdf_wren = want_write && app_rdy;
  assign app_wdf_end  = app_wdf_wren;
  assign fire_read    = want_read && app_rdy;
  assign fire_write   = want_write && app_rdy && app_wdf_rdy;
  assign fire         = fire_read || fire_write;
  assign done         = !read_left && !write_left && (!reads || back == (BW + 1)'(Bursts));
  assign busy         = !done;
  assign begin_line   = pending && done;

  // The rows of a display line's traffic: line + 2 read (mod 525) when a row of the frame, line - 1 written.
  logic [9:0] next_read_line;
  assign next_read_line = pending_line >= 10'(Lines - 2) ? pending_line - 10'(Lines - 2) : pending_line + 10'd2;

  always_ff @(posedge clk) begin
    if (rst) begin
      pending <= 1'b0;
      reads <= 1'b0;
      writes <= 1'b0;
      late_lines <= '0;
    end else begin
      if (line_start) begin
        pending <= 1'b1;
        pending_line <= line;
        if (!done || pending) late_lines <= late_lines + 1'b1;
      end else if (begin_line) begin
        pending <= 1'b0;
      end
      if (begin_line) begin
        reads <= next_read_line < 10'(Rows);
        writes <= pending_line != 10'd0 && pending_line <= 10'(Rows);
        read_row <= 9'(next_read_line);
        write_row <= 9'(pending_line - 10'd1);
      end
    end
  end

  // The counters, their next values (and the row's) driving the write data's address a clock ahead.
  logic [BW:0] w_d;
  assign w_d = begin_line ? '0 : w + (BW + 1)'(fire_write);
  always_ff @(posedge clk) begin
    if (rst || begin_line) begin
      r <= '0;
      back <= '0;
      writing <= 1'b0;
      k <= '0;
    end else begin
      if (fire_read) r <= r + 1'b1;
      if (app_rd_data_valid) back <= back + 1'b1;
      if (fire) begin
        // a run ends after RUN requests, or when its direction has none left
        if (k == ($clog2(RUN))'(RUN - 1) || (fire_read ? r + 1'b1 == (BW + 1)'(Bursts) : w + 1'b1 == (BW + 1)'(Bursts))) begin
          k <= '0;
          writing <= fire_read;
        end else begin
          k <= k + 1'b1;
        end
      end
    end
    w <= rst ? '0 : w_d;
  end

  // ---- the requests' addresses ------------------------------------------------------------------------------------
  // A row is 5,120 bytes, 2,560 words: row * 2048 + row * 512; a burst 8 words.
  logic [8:0]    req_row;
  logic [BW-1:0] req_burst;
  assign req_row   = want_write ? write_row : read_row;
  assign req_burst = want_write ? BW'(w) : BW'(r);
  assign app_cmd   = want_write ? 3'b000 : 3'b001;
  assign app_addr  = (ADDR_W'(req_row) << 11) + (ADDR_W'(req_row) << 9) + (ADDR_W'(req_burst) << 3);
  assign app_wdf_data = store_data;
  assign store_row    = begin_line ? 9'(pending_line - 10'd1) : write_row;
  assign store_burst  = BW'(w_d);

  assign load_we    = app_rd_data_valid;
  assign load_row   = read_row;
  assign load_burst = BW'(back);
  assign load_data  = app_rd_data;
endmodule
