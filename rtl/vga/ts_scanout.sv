// ts_scanout: the device's back end, from the workers' colours to the VGA connector: the controller
// (ts_controller), the two line buffers (ts_line_buffers) and the VGA block (ts_vga_timing), wired as in the C++
// model's Device (src/tripsitter/device/device.h/.cpp). The device's top instantiates this with its N workers on
// the worker ports and scene memory swapping on frame_start.
//
// Timing against the model: the beam counters (line, column, phase) are the model's Device::tick position, four
// device cycles per pixel clock, from line 480 column 0 after reset; the controller works on line L + 1 in the
// last LEAD_CYCLES cycles of line L; the buffers swap after each line's last cycle; the pins carry the model's
// sample of each pixel clock two device cycles after the counters reach it (vga_strobe marks its first cycle).
module ts_scanout #(
    parameter int N = 10,
    parameter int LEAD_CYCLES = 3000,
    parameter int DRAIN = 0,
    parameter int FLUSH = 0,      // ts_controller: 1 when the workers honour flush
    parameter int CHECK_COL = 1,  // ts_controller: 1 checks each colour's done_col
    parameter int BLOCK_RAM = 0   // ts_line_buffers: 1 asks for block RAM whatever N
) (
    input  logic            clk,
    input  logic            rst,
    input  logic [15:0]     least_cycles,  // DevicePreset::pixel_occupancy(spheres, 0) of the world shown, >= 1
    // The workers (ts_controller's contract).
    output logic [N-1:0]    start,
    output logic [N*10-1:0] col,
    output logic [N*9-1:0]  row,
    input  logic [N-1:0]    ready,
    input  logic [N-1:0]    done,
    input  logic [N*10-1:0] done_col,
    input  logic [N*12-1:0] colour,
    output logic            flush,
    // The beam.
    output logic [9:0]      line,
    output logic [9:0]      column,
    output logic            frame_start,  // first cycle of vertical blanking: scene memory swaps here
    // The connector.
    output logic [11:0]     vga_rgb,
    output logic            vga_hsync_n,
    output logic            vga_vsync_n,
    output logic            vga_strobe,
    // Statistics (ts_controller).
    output logic            late_valid,
    output logic [9:0]      late_pixels,
    output logic            protocol_error
);
  localparam int Slots = (640 + N - 1) / N;
  localparam int SlotW = Slots > 1 ? $clog2(Slots) : 1;

  logic [1:0]        phase;
  logic              pix_en, visible, line_end, rd_en;
  logic [11:0]       rd_data;
  logic [N-1:0]      wr_en;
  logic [N*SlotW-1:0] wr_slot;
  logic [N*12-1:0]   wr_colour;

  ts_vga_timing u_timing (
      .clk,
      .rst,
      .phase,
      .column,
      .line,
      .pix_en,
      .visible,
      .line_end,
      .frame_start,
      .rd_en,
      .rd_data,
      .vga_rgb,
      .vga_hsync_n,
      .vga_vsync_n,
      .vga_strobe
  );

  ts_line_buffers #(.N(N), .BLOCK_RAM(BLOCK_RAM)) u_buffers (
      .clk,
      .rst,
      .swap(line_end),
      .wr_en,
      .wr_slot,
      .wr_colour,
      .rd_en,
      .rd_data
  );

  ts_controller #(.N(N), .LEAD_CYCLES(LEAD_CYCLES), .DRAIN(DRAIN), .FLUSH(FLUSH), .CHECK_COL(CHECK_COL)) u_controller (
      .clk,
      .rst,
      .phase,
      .column,
      .line,
      .least_cycles,
      .start,
      .col,
      .row,
      .ready,
      .done,
      .done_col,
      .colour,
      .flush,
      .wr_en,
      .wr_slot,
      .wr_colour,
      .late_valid,
      .late_pixels,
      .protocol_error
  );

  // pix_en and visible are for a top that wants them; the scan-out itself does not.
  logic unused;
  assign unused = pix_en ^ visible;
endmodule
