// ts_receiver_top: the device's link end as one block: SPI slave -> receiver -> scene memory (two copies).
// From the pins to the workers' read ports; the C++ model of the whole is device::Receiver with the front
// SceneMemory that Device::swap_if_pending fills (src/tripsitter/device/receiver.h, scene_memory.h).
//
// This is what the co-simulation test drives (rtl/receiver/receiver_rtl_test.cpp) and what the device's top
// instantiates: `vblank_swap` comes from the VGA block's vertical blanking, the read ports go to the workers.
// Parameters as ts_receiver (WIRE, preset formats, MAX_SPHERES) and ts_scene_memory (NREAD).
module ts_receiver_top #(
    parameter int WIRE = 3,
    parameter int FRAC = 4,
    parameter int X_W = 24,
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int MAX_SPHERES = 4096,
    parameter int NREAD = 2,
    parameter int CNT_W = 64,
    parameter int HIERARCHY = 0,
    parameter int IOR_MIN = 0,
    parameter int IOR_MAX = 65535,
    parameter int AW = $clog2(MAX_SPHERES)  // derived: leave as it is
) (
    input  logic                 clk,
    input  logic                 rst,
    // SPI, mode 0, from the host (asynchronous).
    input  logic                 sclk,
    input  logic                 mosi,
    input  logic                 cs_n,
    output logic                 ready,          // the ready line to the host
    input  logic                 end_of_stream,  // the host went away (stream transport only)
    input  logic                 vblank_swap,
    // ReceiverStats and extras (ts_receiver).
    output logic [CNT_W-1:0]     worlds_accepted,
    output logic [CNT_W-1:0]     worlds_replaced,
    output logic [CNT_W-1:0]     frames_rejected,
    output logic [CNT_W-1:0]     garbage_runs,
    output logic [CNT_W-1:0]     bytes_dropped,
    output logic [CNT_W-1:0]     worlds_missing,
    output logic [CNT_W-1:0]     worlds_replayed,
    output logic [CNT_W-1:0]     sessions,
    output logic [CNT_W-1:0]     bytes_received,
    output logic [CNT_W-1:0]     overflow_bytes,
    output logic                 idle,
    output logic                 spi_byte_cut,   // chip select rose inside a byte
    // The front copy, for the workers.
    output logic                 front_valid,
    output logic [AW:0]          front_count,
    output logic [31:0]          front_sequence,
    input  logic [NREAD*AW-1:0]  rd_addr,
    output logic [NREAD*X_W-1:0] rd_x,
    output logic [NREAD*Y_W-1:0] rd_y,
    output logic [NREAD*Z_W-1:0] rd_z,
    output logic [NREAD*R_W-1:0] rd_r,
    output logic [NREAD-1:0]     rd_metal,
    output logic [NREAD*24-1:0]  rd_albedo
);
  logic byte_valid;
  logic [7:0] byte_data;
  ts_spi_rx u_spi (
      .clk, .rst, .sclk, .mosi, .cs_n,
      .byte_valid, .byte_data,
      .byte_cut(spi_byte_cut)
  );

  logic sm_begin, sm_we, sm_wmetal, sm_commit, sm_replaced;
  logic [AW-1:0] sm_waddr;
  logic [X_W-1:0] sm_wx;
  logic [Y_W-1:0] sm_wy;
  logic [Z_W-1:0] sm_wz;
  logic [R_W-1:0] sm_wr;
  logic [23:0] sm_walbedo;
  logic [AW:0] sm_count;
  logic [31:0] sm_sequence;
  ts_receiver #(
      .WIRE(WIRE), .FRAC(FRAC), .X_W(X_W), .Y_W(Y_W), .Z_W(Z_W), .R_W(R_W),
      .MAX_SPHERES(MAX_SPHERES), .CNT_W(CNT_W), .HIERARCHY(HIERARCHY),
      .IOR_MIN(IOR_MIN), .IOR_MAX(IOR_MAX)
  ) u_rx (
      .clk, .rst, .byte_valid, .byte_data, .end_of_stream,
      .sm_begin, .sm_we, .sm_waddr, .sm_wx, .sm_wy, .sm_wz, .sm_wr, .sm_wmetal, .sm_walbedo,
      .sm_commit, .sm_count, .sm_sequence, .sm_replaced,
      .worlds_accepted, .worlds_replaced, .frames_rejected, .garbage_runs, .bytes_dropped,
      .worlds_missing, .worlds_replayed, .sessions, .bytes_received, .overflow_bytes, .idle
  );

  logic pending;
  ts_scene_memory #(
      .X_W(X_W), .Y_W(Y_W), .Z_W(Z_W), .R_W(R_W), .MAX_SPHERES(MAX_SPHERES), .NREAD(NREAD)
  ) u_scene (
      .clk, .rst,
      .begin_write(sm_begin), .we(sm_we), .waddr(sm_waddr),
      .wx(sm_wx), .wy(sm_wy), .wz(sm_wz), .wr(sm_wr), .wmetal(sm_wmetal), .walbedo(sm_walbedo),
      .commit(sm_commit), .commit_count(sm_count), .commit_sequence(sm_sequence),
      .replaced(sm_replaced),
      .vblank_swap, .ready, .pending,
      .front_valid, .front_count, .front_sequence,
      .rd_addr, .rd_x, .rd_y, .rd_z, .rd_r, .rd_metal, .rd_albedo
  );
  /* verilator lint_off UNUSEDSIGNAL */
  wire unused_pending = pending;  // ready carries it to the host; kept as a port of scene memory for the device
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
