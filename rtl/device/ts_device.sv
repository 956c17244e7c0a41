// ts_device: the whole device (the report's FPGA) as one top, pin for pin: the SPI link and its ready line in, the
// VGA connector out. Its C++ model is device::Device (src/tripsitter/device/device.h): receiver and scene memory
// (ts_receiver_top), N workers (ts_worker) and the back end of controller, line buffers and VGA timing (ts_scanout).
//
// Pins of a board (docs/rtl.md, "To a real board"): clk (100 MHz), rst (synchronous, active high), spi_sclk,
// spi_mosi, spi_cs_n from the host and spi_ready back to it; vga_r, vga_g, vga_b (4 bits each, to the resistor
// ladders) and vga_hsync_n, vga_vsync_n. The other outputs, and end_of_stream (tied low on a board), are for
// simulation and a logic analyser.
//
// Data flow: the receiver writes a checked world into scene memory's back copy; ts_scanout pulses frame_start in the
// first cycle of vertical blanking, where a waiting world becomes the front copy (the model's swap_if_pending at
// line 480, column 0); the workers read the front copy, each through its own registered read port.
module ts_device #(
    // The preset's scene memory formats (device/preset.h): widths of x, y, z and the radius, fractional bits.
    parameter int FRAC = 4,
    parameter int X_W = 24,
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int MAX_SPHERES = 4096,
    parameter int WIRE = 3,                       // link::WireVersion: 1, 2 or 3
    // The workers.
    parameter int N = 10,
    parameter int SQRT_ITERATIONS = 16,
    parameter int PIPELINED = 1,                  // wide: pipelined; board-2023: one pixel at a time
    parameter int MAX_BOUNCES = 3,
    parameter int LEAD_CYCLES = 3200,
    // The cycle costs (CycleCosts) the worker is built to, which the controller's schedule needs.
    parameter int PIXEL_SETUP = 2,
    parameter int SPHERE_TEST = 12,
    parameter int SQRT_CYCLES_PER_ITERATION = 1,
    parameter int CLOSEST_UPDATE = 1,
    parameter int SHADE = 4,
    parameter int CNT_W = 32,                     // width of the receiver's counters
    localparam int AW = $clog2(MAX_SPHERES)
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             spi_sclk,
    input  logic             spi_mosi,
    input  logic             spi_cs_n,
    output logic             spi_ready,
    input  logic             end_of_stream,       // simulation: the stream transport's host went away (a board ties it low)
    output logic [3:0]       vga_r,
    output logic [3:0]       vga_g,
    output logic [3:0]       vga_b,
    output logic             vga_hsync_n,
    output logic             vga_vsync_n,
    // For simulation: the first cycle of each pixel clock's sample on the pins, the beam, the receiver's state and
    // counters (device::ReceiverStats), the world in scene memory's front copy.
    output logic             vga_strobe,
    output logic [9:0]       beam_line,
    output logic [9:0]       beam_column,
    output logic             receiver_idle,
    output logic [CNT_W-1:0] worlds_accepted,
    output logic [CNT_W-1:0] worlds_replaced,
    output logic [CNT_W-1:0] frames_rejected,
    output logic [CNT_W-1:0] garbage_runs,
    output logic [CNT_W-1:0] bytes_dropped,
    output logic [CNT_W-1:0] worlds_missing,
    output logic [CNT_W-1:0] worlds_replayed,
    output logic [CNT_W-1:0] sessions,
    output logic             shown_valid,
    output logic [31:0]      shown_sequence,
    output logic             late_valid,
    output logic [9:0]       late_pixels
);
  // One pass over one sphere, from the pair entering the sphere test to the closest-hit register (the model's
  // per_sphere_cycles), and the cycles from a pixel's last pass to its colour (drain_cycles).
  localparam int PerSphere = SPHERE_TEST + SQRT_ITERATIONS * SQRT_CYCLES_PER_ITERATION + CLOSEST_UPDATE;
  localparam int Drain = PIPELINED != 0 ? PIXEL_SETUP + PerSphere + SHADE : 0;

  // ---- Receiver and scene memory -------------------------------------------------------------------------
  logic              frame_start;
  logic              front_valid;
  logic [AW:0]       front_count;
  logic [N*AW-1:0]   rd_addr;
  logic [N*X_W-1:0]  rd_x;
  logic [N*Y_W-1:0]  rd_y;
  logic [N*Z_W-1:0]  rd_z;
  logic [N*R_W-1:0]  rd_r;
  logic [N-1:0]      rd_metal;
  logic [N*24-1:0]   rd_albedo;
  logic [CNT_W-1:0]  unused_received, unused_overflow;
  logic              unused_cut;

  ts_receiver_top #(
      .WIRE(WIRE), .FRAC(FRAC), .X_W(X_W), .Y_W(Y_W), .Z_W(Z_W), .R_W(R_W), .MAX_SPHERES(MAX_SPHERES),
      .NREAD(N), .CNT_W(CNT_W)
  ) receiver (
      .clk, .rst,
      .sclk(spi_sclk), .mosi(spi_mosi), .cs_n(spi_cs_n), .ready(spi_ready),
      .end_of_stream,
      .vblank_swap(frame_start),
      .worlds_accepted, .worlds_replaced, .frames_rejected, .garbage_runs, .bytes_dropped, .worlds_missing,
      .worlds_replayed, .sessions, .bytes_received(unused_received), .overflow_bytes(unused_overflow),
      .idle(receiver_idle), .spi_byte_cut(unused_cut),
      .front_valid, .front_count, .front_sequence(shown_sequence),
      .rd_addr, .rd_x, .rd_y, .rd_z, .rd_r, .rd_metal, .rd_albedo
  );

  // ---- Workers ---------------------------------------------------------------------------------------------
  // Without a world every pixel is background: the workers see no spheres.
  wire [AW:0] spheres = front_valid ? front_count : '0;
  assign shown_valid = front_valid;

  logic [N-1:0]    start, ready, done;
  logic [N*10-1:0] col, done_col;
  logic [N*9-1:0]  row;
  logic [N*12-1:0] colour;
  logic            flush;

  for (genvar w = 0; w < N; w++) begin : g_worker
    logic [1:0] unused_bounces;
    logic       unused_rd;  // every worker has its own read port: the read strobe only matters when shared
    ts_worker #(
        .X_W(X_W), .Y_W(Y_W), .Z_W(Z_W), .R_W(R_W), .SQRT_ITERATIONS(SQRT_ITERATIONS),
        .SQRT_CYCLES_PER_ITERATION(SQRT_CYCLES_PER_ITERATION), .MAX_BOUNCES(MAX_BOUNCES), .AW(AW),
        .PIPELINED(PIPELINED)
    ) worker (
        .clk, .rst, .flush,
        .start(start[w]), .col(col[w*10+:10]), .row(row[w*9+:9]), .ready(ready[w]),
        .sphere_addr(rd_addr[w*AW+:AW]), .sphere_rd(unused_rd),
        .sphere_x(rd_x[w*X_W+:X_W]), .sphere_y(rd_y[w*Y_W+:Y_W]), .sphere_z(rd_z[w*Z_W+:Z_W]),
        .sphere_r(rd_r[w*R_W+:R_W]), .sphere_metal(rd_metal[w]), .sphere_albedo(rd_albedo[w*24+:24]),
        .sphere_count(spheres),
        .done(done[w]), .done_col(done_col[w*10+:10]), .colour(colour[w*12+:12]), .bounces(unused_bounces)
    );
  end

  // ---- Controller, line buffers, VGA -----------------------------------------------------------------------
  // The least a pixel can take (DevicePreset::pixel_occupancy(spheres, 0)): the controller's bound for a line's
  // demand. Pipelined, one issue slot per sphere (at least one); otherwise set-up, a pass and shading.
  logic [15:0] least_cycles;
  always_comb begin
    if (PIPELINED != 0) least_cycles = spheres == '0 ? 16'd1 : 16'(spheres);
    else least_cycles = 16'(PIXEL_SETUP + SHADE) + 16'(spheres) * 16'(PerSphere);
  end

  logic [11:0] rgb;
  logic        unused_protocol_error;
  ts_scanout #(
      .N(N), .LEAD_CYCLES(LEAD_CYCLES), .DRAIN(Drain), .FLUSH(1)
  ) scanout (
      .clk, .rst, .least_cycles,
      .start, .col, .row, .ready, .done, .done_col, .colour, .flush,
      .line(beam_line), .column(beam_column), .frame_start,
      .vga_rgb(rgb), .vga_hsync_n, .vga_vsync_n, .vga_strobe,
      .late_valid, .late_pixels, .protocol_error(unused_protocol_error)
  );
  assign vga_r = rgb[11:8];
  assign vga_g = rgb[7:4];
  assign vga_b = rgb[3:0];
endmodule
