// ts_controller: the ray-tracing controller. For every visible line it hands the 640 pixels of the next line to
// N workers, interleaved (worker i takes columns i, i + N, i + 2N, ...), each worker's next column as soon as the
// worker is ready, and writes the colours that come back in time into the back line buffer. A pixel not finished
// when its line is due stays black, and once a worker is late its later pixels are not started.
//
// C++ model: src/tripsitter/device/controller.h (schedule_pixels, schedule_line) and the timing of Device::tick /
// start_line in device.cpp: at column 0 of line L the model computes line L + 1 (when it is visible: L = 524 and
// L = 0..478) into the back buffer, which becomes the front one after line L's last pixel clock. The line is due
// at that swap, and the controller starts its work LEAD_CYCLES device cycles before: the window of line L + 1 is
// the device cycles OPEN = 3200 - LEAD_CYCLES .. 3199 of line L, a device cycle of the line being
// 4 column + phase (the {column, phase} of ts_vga_timing). `wide` has LEAD_CYCLES = 3200 (a window is a whole
// line), `board-2023` 3000 (the window opens at column 50).
//
// The worker contract (per worker i; the ports are flat vectors, worker i's field at [i*W +: W]):
//   start (out)      the worker takes column col, row row in this cycle; only while ready is high
//   col[9:0], row[8:0] (out)
//   ready (in)       the worker can take a pixel in this cycle
//   done (in)        one-cycle pulse: the colour of the worker's oldest pixel in flight, done_col, colour[11:0]
// A pixel started in cycle s with occupancy o (DevicePreset::pixel_occupancy: its spheres and reflections) makes
// the worker ready again in cycle s + o, and its done pulse comes in cycle s + o + DRAIN - 1 (DRAIN =
// DevicePreset::drain_cycles(): 35 pipelined, 0 one pixel at a time). A worker may also take pixels earlier than
// that (the pipelined ts_worker is ready again as if the pixel did not reflect) provided each done pulse comes
// where the model's schedule puts it: the window's first start plus the occupancies of the worker's pixels so far,
// plus DRAIN - 1. The controller relies only on that, and on done pulses coming in start order.
//
// The model's rule. Relative to the window's first cycle, worker w's pixel k starts at busy_{k-1} (the sum of the
// occupancies of its pixels 0..k-1: each starts when the previous one frees the worker) and is on time when
// busy_k + drain <= lead, that is when its done pulse falls inside the window; the first late pixel makes every
// later one late. Here:
//   - every worker's pixel 0 starts in the window's first cycle (the worker is ready then: see "Flush") and each
//     next pixel in the cycle its worker is ready again, so the starts are the model's;
//   - a colour whose done pulse comes inside the window is written to its slot of the back buffer (bank i, slot k:
//     column i + k N); a pixel whose done pulse comes later is dropped, and its slot stays black (the line
//     buffers start every line black);
//   - no pixel is started that cannot be on time: a start in line cycle c needs c + least_cycles + DRAIN <= 3200,
//     least_cycles being the occupancy of a pixel without reflections (pixel_occupancy(spheres, 0)). The model
//     starts that pixel in cycle c or later, so it would be late whatever it reflects, and the ones after it too:
//     not starting it changes nothing shown, and keeps the worker from running into the next line's window.
//
// Flush. A pixel started in time whose reflections make it late can keep its worker busy past the window's end,
// into the next line's window, where the model starts that worker afresh (the model's schedule begins every line
// with idle workers). With FLUSH = 1 the controller pulses `flush` in every window's last cycle; a worker that
// honours it still delivers a done pulse due in that cycle, drops every other pixel in flight (no done pulse for
// them) and is ready in the next cycle. Then the RTL equals the model in every case. With FLUSH = 0 (workers
// without the flush input) it equals the model whenever no worker is still busy when a window opens, which the
// least_cycles rule guarantees for pixels without reflections (board-2023 always, wide without metals); otherwise
// the busy worker starts the new line late. Either way the done pulses of pixels started in an earlier window are
// counted (stale) and dropped, never written into the new line.
//
// Statistics: late_pixels, the line's pixels not written (640 - the colours on time; LineResult::late_pixels), with
// late_valid one cycle, two cycles after the window's last cycle. protocol_error is sticky: a done pulse with
// nothing in flight, or (CHECK_COL = 1) a colour in the window whose done_col is not the column expected; neither
// colour is written. The controller itself needs no done_col: done pulses come in start order, so it counts them;
// CHECK_COL = 0 leaves the check out (about 50 LUTs a worker with N = 10).
module ts_controller #(
    parameter int N = 10,             // workers
    parameter int LEAD_CYCLES = 3000, // DevicePreset::lead_cycles, 1..3200
    parameter int DRAIN = 0,          // DevicePreset::drain_cycles()
    parameter int FLUSH = 0,          // 1: the workers honour `flush`
    parameter int CHECK_COL = 1,      // 1: write a colour only with the done_col expected, and flag others
    localparam int Slots = (640 + N - 1) / N,
    localparam int SlotW = Slots > 1 ? $clog2(Slots) : 1
) (
    input  logic              clk,
    input  logic              rst,
    // The beam (ts_vga_timing).
    input  logic [1:0]        phase,
    input  logic [9:0]        column,
    input  logic [9:0]        line,
    input  logic [15:0]       least_cycles,  // pixel_occupancy(spheres, 0) of the world in scene memory, >= 1
    // The workers.
    output logic [N-1:0]      start,
    output logic [N*10-1:0]   col,
    output logic [N*9-1:0]    row,
    input  logic [N-1:0]      ready,
    input  logic [N-1:0]      done,
    input  logic [N*10-1:0]   done_col,
    input  logic [N*12-1:0]   colour,
    output logic              flush,
    // The back line buffer (ts_line_buffers): worker i's colour into slot wr_slot[i] of bank i.
    output logic [N-1:0]      wr_en,
    output logic [N*SlotW-1:0] wr_slot,
    output logic [N*12-1:0]   wr_colour,
    // Statistics.
    output logic              late_valid,
    output logic [9:0]        late_pixels,
    output logic              protocol_error
);
  localparam int LineCycles = 3200;                      // kLineCycles: 800 pixel clocks of 4 device cycles
  localparam int OpenCycle = LineCycles - LEAD_CYCLES;   // first cycle of the window within line L
  localparam int LastStart = LineCycles - DRAIN;         // a start in cycle c needs c + least_cycles <= LastStart
  localparam int CountW = $clog2(Slots + 1);             // a worker's colours on time, 0..Slots
  // Pixels a worker has in flight. By the contract's timing at most DRAIN + 1 (a pixel is done DRAIN + o - 1 cycles
  // after its start, the next starts o >= 1 cycles after it), but a worker may take pixels ahead of the model's
  // schedule and deliver them on it (the pipelined ts_worker takes the next pixel as if nothing reflected): then up
  // to a window's pixels, plus without flush those still in flight from the window before.
  localparam int FlightW = $clog2(2 * Slots + DRAIN + 2);

  // The window. Lines 524 and 0..478 work on the next line (rows 0..479).
  logic [11:0] line_cycle;
  logic        work_line, open, last, active_q, in_window, closing_q;
  logic [8:0]  row_q, row_next, row_now;
  logic [16:0] start_reach;
  logic        may_start;

  assign line_cycle = {column, phase};
  assign work_line  = line == 10'd524 || line < 10'd479;
  assign open       = work_line && line_cycle == 12'(OpenCycle);  // the window's first cycle
  assign last       = line_cycle == 12'(LineCycles - 1);         // the line's last cycle: the line is due after it
  assign in_window  = open || active_q;
  assign row_next   = line == 10'd524 ? 9'd0 : line[8:0] + 9'd1;
  assign row_now    = open ? row_next : row_q;
  // The earliest a pixel started now could be done, counted in cycles from the start of line L.
  assign start_reach = {5'd0, line_cycle} + {1'b0, least_cycles};
  assign may_start   = in_window && start_reach <= 17'(LastStart);
  assign flush       = FLUSH != 0 && in_window && last;

  always_ff @(posedge clk) begin
    if (rst) begin
      active_q  <= 1'b0;
      closing_q <= 1'b0;
      row_q     <= 9'd0;
    end else begin
      active_q  <= in_window && !last;
      closing_q <= in_window && last;
      row_q     <= row_now;
    end
  end

  logic [N*CountW-1:0] on_time_counts;  // worker i's colours on time in the window, flattened
  logic [N-1:0]        errors;

  for (genvar i = 0; i < N; i++) begin : g_worker
    logic [10:0]        next_col_q;  // the worker's next column in this window; 640 or more when it has none left
    logic [10:0]        want_col_q;  // the column of its next colour on time
    logic [CountW-1:0]  on_time_q;   // its colours on time in this window: the slot of the next one
    logic [FlightW-1:0] flight_q;    // its pixels started and not yet done, this window's and older
    logic [FlightW-1:0] stale_q;     // of those, the pixels of earlier windows (all late)

    // In the window's first cycle the worker's state starts afresh: what it still has in flight is stale.
    logic [10:0]        next_col, want_col;
    logic [CountW-1:0]  on_time;
    logic [FlightW-1:0] stale;
    logic               go, stale_done, fresh_done, orphan, col_ok, write, error;

    assign next_col = open ? 11'(i) : next_col_q;
    assign want_col = open ? 11'(i) : want_col_q;
    assign on_time  = open ? '0 : on_time_q;
    assign stale    = open ? flight_q : stale_q;

    assign go         = ready[i] && may_start && next_col < 11'd640;
    assign stale_done = done[i] && stale != '0;
    assign fresh_done = done[i] && stale == '0;
    // On time: a done pulse of this window's pixel inside the window (done pulses come in start order, so it is
    // the pixel in slot on_time), with the column expected.
    // A done pulse with nothing in flight (an orphan) breaks the contract: it is flagged, and neither written nor
    // counted, so it cannot push a later colour into another pixel's slot.
    assign col_ok = CHECK_COL == 0 || done_col[i*10+:10] == want_col[9:0];
    assign orphan = done[i] && flight_q == '0 && !go;
    assign write  = fresh_done && in_window && col_ok && !orphan;
    assign error  = orphan || fresh_done && in_window && !col_ok;

    assign start[i]                = go;
    assign col[i*10+:10]           = next_col[9:0];
    assign row[i*9+:9]             = row_now;
    assign wr_en[i]                = write;
    assign wr_slot[i*SlotW+:SlotW] = on_time[SlotW-1:0];
    assign wr_colour[i*12+:12]     = colour[i*12+:12];
    assign on_time_counts[i*CountW+:CountW] = on_time_q;
    assign errors[i]               = error;

    always_ff @(posedge clk) begin
      if (rst) begin
        next_col_q <= 11'd0;
        want_col_q <= 11'd0;
        on_time_q  <= '0;
        flight_q   <= '0;
        stale_q    <= '0;
      end else begin
        next_col_q <= go ? next_col + 11'(N) : next_col;
        want_col_q <= write ? want_col + 11'(N) : want_col;
        on_time_q  <= write ? on_time + CountW'(1) : on_time;
        if (flush) begin
          // The worker drops whatever it has in flight after this cycle.
          flight_q <= '0;
          stale_q  <= '0;
        end else begin
          flight_q <= flight_q + FlightW'(go) - FlightW'(done[i] && !orphan);
          stale_q  <= stale - FlightW'(stale_done);
        end
      end
    end
  end

  // Late pixels of the window just closed: the colours on time are the workers' counts, which hold until the
  // next window's first write (that window may open in this very cycle: its state starts from the `open` mux,
  // not from these registers).
  logic [10:0] on_time_sum;
  always_comb begin
    on_time_sum = 11'd0;
    for (int i = 0; i < N; i++) on_time_sum = on_time_sum + 11'(on_time_counts[i*CountW+:CountW]);
  end

  always_ff @(posedge clk) begin
    if (rst) begin
      late_valid     <= 1'b0;
      late_pixels    <= 10'd0;
      protocol_error <= 1'b0;
    end else begin
      late_valid <= closing_q;
      if (closing_q) late_pixels <= 10'(11'd640 - on_time_sum);
      if (|errors) protocol_error <= 1'b1;
    end
  end
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs controller, controller_board,
  // controller_noflush). Every input is free: the beam (any line, column and phase in any cycle: they hold for
  // ts_vga_timing's proven beam and for any other), least_cycles, and the workers' ready, done, done_col and
  // colour. Nothing is assumed but the reset. The window, the starts and the writes are specified from the beam
  // and the ports alone. What needs the workers to keep the contract (a done pulse only with a pixel in flight,
  // done pulses in start order, CHECK_COL: the column expected) holds while they have kept it as far as the
  // controller can tell: protocol_error low (f_kept; f_error, the specification's breach, to which p_error_flags
  // holds the flag), and for a write's slot and the on-time rule no breach in this cycle either; and while each
  // worker's pixels in flight have fitted flight_q (f_fits: a worker that keeps the contract has at most two
  // windows' pixels and the drain in flight; a worker that never answers may have more, and flight_q wraps).
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The window of line L + 1, from the beam: it opens in cycle 3200 - LEAD_CYCLES of lines 524 and 0..478 and
  // lasts to the line's last cycle, 3199, included. f_line: the line it opened in. A pixel may start when it could
  // be done by the line's end: cycle + least_cycles + DRAIN <= 3200.
  wire [11:0] f_cycle = {column, phase};
  wire        f_last = f_cycle == 12'd3199;
  wire        f_open = (line == 10'd524 || line <= 10'd478) && f_cycle == 12'(3200 - LEAD_CYCLES);
  logic       f_active_q, f_opened_q, f_close_q, f_close2_q;
  logic [9:0] f_line_q;
  wire        f_window = f_open || f_active_q;
  wire [9:0]  f_line = f_open ? line : f_line_q;
  wire [8:0]  f_row = f_line == 10'd524 ? 9'd0 : 9'(f_line + 10'd1);
  wire [8:0]  f_row_q = f_line_q == 10'd524 ? 9'd0 : 9'(f_line_q + 10'd1);
  wire        f_in_time = 18'(f_cycle) + 18'(least_cycles) + 18'(DRAIN) <= 18'd3200;
  wire        f_flush = FLUSH != 0 && f_window && f_last;

  // Per worker i, whose columns are i, i + N, ... below 640 (Cols of them): this window's starts and writes, and
  // its pixels in flight (started, not done, not flushed), those of earlier windows (old) and of this one (fresh).
  // A done pulse is the oldest pixel's (the contract: done pulses in start order): an old one's if any, else this
  // window's (the one started in this very cycle included); with none in flight it is an orphan. A colour is on
  // time when it is this window's pixel's, inside the window, with the column expected (CHECK_COL = 1): the next
  // of the worker's columns not yet written.
  localparam int GW = FlightW + 1;
  logic [N-1:0]    f_ready_ok, f_time_ok, f_place_ok, f_eager_ok, f_in_window_ok;
  logic [N-1:0]    f_slot_ok, f_old_ok, f_written_ok, f_column_ok;
  logic [N-1:0]    f_error, f_fits, f_next_ok, f_count_ok, f_flight_ok;
  logic [N*12-1:0] f_writes_vec;  // each worker's writes of the window until this cycle
  for (genvar i = 0; i < N; i++) begin : f_worker
    localparam int Cols = (640 - i + N - 1) / N;
    logic [10:0]   f_starts_q, f_writes_q;
    logic [GW-1:0] f_old_q, f_fresh_q;
    logic          f_fits_q;
    wire [10:0]    f_starts = f_open ? 11'd0 : f_starts_q;
    wire [10:0]    f_writes = f_open ? 11'd0 : f_writes_q;
    wire [GW-1:0]  f_old = f_open ? f_old_q + f_fresh_q : f_old_q;
    wire [GW-1:0]  f_fresh = f_open ? '0 : f_fresh_q;
    wire           f_done_old = done[i] && f_old != '0;
    wire           f_done_fresh = done[i] && f_old == '0 && (f_fresh != '0 || start[i]);
    wire           f_orphan = done[i] && f_old == '0 && f_fresh == '0 && !start[i];
    wire [10:0]    f_next = 11'(i) + 11'(N) * f_starts;    // the worker's next column to start
    wire [10:0]    f_expect = 11'(i) + 11'(N) * f_writes;  // and to write
    wire           f_bad_col = CHECK_COL != 0 && f_done_fresh && f_window && done_col[i*10+:10] != f_expect[9:0];
    wire           f_on_time = f_done_fresh && f_window && !f_bad_col;
    wire [GW:0]    f_next_flight = (GW + 1)'(f_old) + (GW + 1)'(f_fresh) + (GW + 1)'(start[i]);
    always_ff @(posedge clk) begin
      if (rst) begin
        f_starts_q <= 11'd0;
        f_writes_q <= 11'd0;
        f_old_q    <= '0;
        f_fresh_q  <= '0;
        f_fits_q   <= 1'b1;
      end else begin
        f_starts_q <= f_starts + 11'(start[i]);
        f_writes_q <= f_writes + 11'(wr_en[i]);
        if (f_flush) begin
          f_old_q   <= '0;
          f_fresh_q <= '0;
        end else begin
          f_old_q   <= f_old - GW'(f_done_old);
          f_fresh_q <= f_fresh + GW'(start[i]) - GW'(f_done_fresh);
        end
        if (f_next_flight >= (GW + 1)'(2 ** FlightW)) f_fits_q <= 1'b0;
      end
    end
    // Starts: only while ready; only in the window and in time; at the worker's next column (i + N k for its
    // k-th start of the window, below 640) on the row after the window's line; and whenever all that allows one.
    assign f_ready_ok[i] = !start[i] || ready[i];
    assign f_time_ok[i] = !start[i] || (f_window && f_in_time);
    assign f_place_ok[i] = !start[i] || (f_starts < 11'(Cols) && 11'(col[i*10+:10]) == f_next
                                         && row[i*9+:9] == f_row);
    assign f_eager_ok[i] = start[i] || !(ready[i] && f_window && f_in_time && f_starts < 11'(Cols));
    // Writes: only in the window; into slot k for the worker's k-th write of the window, a visible column (i + N k
    // below 640), with the column its done pulse reports; never an old pixel's colour; a colour on time always.
    assign f_in_window_ok[i] = !wr_en[i] || f_window;
    assign f_slot_ok[i] = !wr_en[i] || (11'(wr_slot[i*SlotW+:SlotW]) == f_writes && f_writes < 11'(Cols));
    assign f_column_ok[i] = CHECK_COL == 0 || !wr_en[i] || 11'(done_col[i*10+:10]) == f_expect;
    assign f_old_ok[i] = !wr_en[i] || !f_done_old;
    assign f_written_ok[i] = wr_en[i] == f_on_time && (!wr_en[i] || wr_colour[i*12+:12] == colour[i*12+:12]);
    assign f_error[i] = f_orphan || f_bad_col;
    assign f_fits[i] = f_fits_q;
    assign f_writes_vec[i*12+:12] = 12'(f_writes_q);
    // Invariants: the worker's registers against the specification's counts.
    assign f_next_ok[i] = f_opened_q ? g_worker[i].next_col_q == 11'(i) + 11'(N) * f_starts_q
                                       && f_starts_q <= 11'(Cols)
                                     : f_starts_q == 11'd0 && f_writes_q == 11'd0;
    assign f_count_ok[i] = 11'(g_worker[i].on_time_q) == f_writes_q
                           && (!f_opened_q || g_worker[i].want_col_q == 11'(i) + 11'(N) * f_writes_q)
                           && 12'(f_fresh_q) + 12'(f_writes_q) <= 12'(f_starts_q);
    assign f_flight_ok[i] = g_worker[i].stale_q == f_old_q[FlightW-1:0]
                            && g_worker[i].flight_q == FlightW'(f_old_q + f_fresh_q);
  end

  // The statistics' specification: late_valid two cycles after a window's last cycle, and late_pixels then 640
  // minus the colours written in that window (held until the next); f_err_q: a breach of the contract seen.
  logic [11:0] f_total;
  logic [9:0]  f_late_q;
  logic        f_err_q;
  always_comb begin
    f_total = 12'd0;
    for (int i = 0; i < N; i++) f_total = f_total + f_writes_vec[i*12+:12];
  end
  always_ff @(posedge clk) begin
    if (rst) begin
      f_active_q     <= 1'b0;
      f_opened_q     <= 1'b0;
      f_close_q      <= 1'b0;
      f_close2_q     <= 1'b0;
      f_line_q       <= 10'd524;
      f_late_q       <= 10'd0;
      f_err_q        <= 1'b0;
    end else begin
      f_active_q <= f_window && !f_last;
      f_opened_q <= f_opened_q || f_open;
      f_close_q  <= f_window && f_last;
      f_close2_q <= f_close_q;
      f_line_q   <= f_line;
      if (f_close_q) f_late_q <= 10'(12'd640 - f_total);
      if (|f_error) f_err_q <= 1'b1;
    end
  end
  wire f_kept = !protocol_error && &f_fits;  // the workers have kept the contract so far

  always_comb begin
    if (past_valid) begin
      // The window: the controller's registers follow the beam. (Invariant.)
      p_window_state: assert (active_q == f_active_q && closing_q == f_close_q && row_q == f_row_q
                              && (!active_q || f_opened_q));
      // No start while a worker is not ready: rules out a start into a busy worker.
      p_start_ready: assert (&f_ready_ok);
      // No start outside the window or too late to be on time (cycle + least_cycles + DRAIN > 3200): rules out a
      // pixel started that could not be on time, or that runs into the next line's window.
      p_start_in_time: assert (&f_time_ok);
      // Each start at the worker's next column, i + N k for its k-th start of the window, below 640, on the row
      // after the window's line: rules out a column skipped, repeated or out of the line, a wrong row.
      p_start_column: assert (&f_place_ok);
      // ... and a start whenever the worker is ready and one is allowed: the model's schedule (each pixel starts
      // the cycle its worker is free). Rules out a worker left idle.
      p_start_eager: assert (&f_eager_ok);
      // flush exactly in a window's last cycle, when the workers honour it.
      p_flush: assert (flush == f_flush);
      // A colour is written only inside its window: a pixel done after its window is not written in it (and
      // its slot, black, shows black). Whatever the workers do.
      p_write_in_window: assert (&f_in_window_ok);
      // late_valid two cycles after a window's last cycle.
      p_late_valid: assert (late_valid == f_close2_q);
      // The start counts (invariant).
      p_next_col: assert (&f_next_ok);
      // protocol_error rises exactly after a done pulse with none of the worker's pixels in flight, or (CHECK_COL)
      // a colour in its window with a column other than the one expected. Rules out a breach not flagged, and a
      // worker that keeps the contract flagged (a stale pixel's done pulse taken for an orphan).
      if (&f_fits) p_error_flags: assert (protocol_error == f_err_q);
      // Each write goes to slot k of the worker's bank for its k-th write of the window, a visible column
      // (i + N k < 640): each pixel is written at most once a line (and only in its window), whatever done pulses
      // the workers send. Rules out a slot count that does not restart with the window, or runs past the worker's
      // columns; and the bug this proof found: a done pulse with nothing in flight was flagged but its colour
      // still written, into the next slot, so a worker sending more done pulses in a window than it has columns
      // (CHECK_COL = 1: with done_col 640 and up) wrote past its columns and, after 2^SlotW, into slot 0 again.
      if (&f_fits) p_slot_once: assert (&f_slot_ok);
      // The write counts and the pixels in flight (invariants).
      if (&f_fits) p_write_counts: assert (&f_count_ok);
      if (&f_fits) p_flight_counts: assert (&f_flight_ok);
      if (f_kept) begin
        // late_pixels: 640 minus the colours written in the window that closed last. Rules out a worker's count
        // left out of the sum, the count of another window.
        p_late_count: assert (late_pixels == f_late_q);
        // A written colour is for the column its done pulse reports (CHECK_COL): rules out a colour written into
        // another column's slot.
        p_write_column: assert (&f_column_ok);
        // A colour of an earlier window's pixel (done after its window) is never written: late pixels stay
        // black. Rules out the stale count lost at the window's opening.
        p_old_dropped: assert (&f_old_ok);
        if (!(|f_error)) begin
          // A colour on time is always written, and only such a colour: rules out a flush or a stale count that
          // swallows a pixel of the window.
          p_on_time_written: assert (&f_written_ok);
        end
      end
    end
  end
  // protocol_error is sticky.
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) p_error_sticky: assert (!$past(protocol_error) || protocol_error);
  end
`endif
endmodule
