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
// nothing in flight, or (CHECK_COL = 1) a colour in the window whose done_col is not the column expected, which is
// then not written. The controller itself needs no done_col: done pulses come in start order, so it counts them;
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
    logic               go, stale_done, fresh_done, col_ok, write, error;

    assign next_col = open ? 11'(i) : next_col_q;
    assign want_col = open ? 11'(i) : want_col_q;
    assign on_time  = open ? '0 : on_time_q;
    assign stale    = open ? flight_q : stale_q;

    assign go         = ready[i] && may_start && next_col < 11'd640;
    assign stale_done = done[i] && stale != '0;
    assign fresh_done = done[i] && stale == '0;
    // On time: a done pulse of this window's pixel inside the window (done pulses come in start order, so it is
    // the pixel in slot on_time), with the column expected.
    assign col_ok = CHECK_COL == 0 || done_col[i*10+:10] == want_col[9:0];
    assign write  = fresh_done && in_window && col_ok;
    assign error  = done[i] && flight_q == '0 && !go || fresh_done && in_window && !col_ok;

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
          flight_q <= flight_q + FlightW'(go) - FlightW'(done[i]);
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
endmodule
