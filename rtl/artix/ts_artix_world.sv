// ts_artix_world: what the artix device prepares of a world as the receiver writes it into scene memory, once per
// world rather than once per pair: each sphere's scale and constants (ts_artix_prepare: e, r^2 / 4^e, 1 / r) into a
// memory beside scene memory, and its cull bounds (ts_artix_cull) into the tile lists' bounds memory
// (ts_artix_tiles). C++ model: artix::prepare_world (src/tripsitter/device/artix_units.cpp).
//
// The receiver writes a sphere every 48 clocks while it commits an accepted world (ts_receiver.sv); the cull takes
// a few hundred clocks a sphere. So the writes wait in a queue (the world's 256 spheres at most) and the engine
// takes them one at a time, starting the constants and the bounds together and writing both when both are done.
// A new world (begin_write) empties the queue: a sphere being worked on still finishes and writes its old values
// into the back copy, where the new world's sphere of that index overwrites them later, or no one reads them.
// `idle` is high when every write received has been prepared; the device swaps a world in only then (a world whose
// preparation spans a vertical blanking is shown a frame later, as one whose commit spans it: ts_receiver.sv).
//
// The queue and the engine run on a gated clock (ts_clock_gate) with an edge only while there is work: a write
// or a new world at the ports, a sphere queued or being prepared, prepare or cull not yet ready, or reset. They
// work while a world arrives and sleep the rest of the time; the constants memory is on the device's clock.
//
// The constants memory has two copies, the front one read by the units and the back one written, swapped with
// scene memory (`swap`: the blanking's swap of a pending world). Its read ports (NREAD, one per unit) are
// registered reads, as scene memory's; each port has its own replica (a simple dual-port block RAM of both copies,
// 512 x 59 bits: one RAMB36), so the engine writes every replica at once.
module ts_artix_world #(
    parameter int NREAD = 12,
    localparam int AW = ts_artix_pkg::SphereAW,
    localparam int CoordW = ts_artix_pkg::CoordW,
    localparam int RadiusW = ts_artix_pkg::RadiusW,
    localparam int ConstW = ts_artix_pkg::ExpW + ts_artix_pkg::R2sW + ts_artix_pkg::RinvW
) (
    input  logic                  clk,
    input  logic                  rst,
    // The receiver's writes to scene memory's back copy (ts_receiver's sm_* ports).
    input  logic                  begin_write,
    input  logic                  we,
    input  logic [AW-1:0]         waddr,
    input  logic [CoordW-1:0]     wx,
    input  logic [CoordW-1:0]     wy,
    input  logic [CoordW-1:0]     wz,
    input  logic [RadiusW-1:0]    wr,
    input  logic                  swap,
    output logic                  idle,
    // The bounds of sphere bounds_addr, into the tile lists' back copy.
    output logic                  bounds_we,
    output logic [AW-1:0]         bounds_addr,
    output logic                  bounds_empty,
    output logic [9:0]            bounds_col_lo,
    output logic [9:0]            bounds_col_hi,
    output logic [8:0]            bounds_row_lo,
    output logic [8:0]            bounds_row_hi,
    // The constants of the front copy: e, r2s, rinv of sphere rd_addr, the clock after.
    input  logic [NREAD*AW-1:0]   rd_addr,
    output logic [NREAD*ConstW-1:0] rd_const
);
  localparam int EntryW = AW + 3 * CoordW + RadiusW;

  // ---- the queue of spheres written ---------------------------------------------------------------------------
  // It cannot overflow: it holds a world's spheres at most, and a new world empties it.
  logic              queue_empty, queue_pop, unused_overflow;
  logic [EntryW-1:0] front;
  ts_artix_fifo #(.W(EntryW), .DEPTH(ts_artix_pkg::MaxSpheres)) queue (
      .clk(gclk), .rst, .clear(begin_write),
      .push(we), .push_data({waddr, wx, wy, wz, wr}),
      .pop(queue_pop), .front, .empty(queue_empty), .overflow(unused_overflow)
  );

  logic [AW-1:0]      f_addr;
  logic [CoordW-1:0]  f_x, f_y, f_z;
  logic [RadiusW-1:0] f_r;
  assign {f_addr, f_x, f_y, f_z, f_r} = front;

  // ---- the engine: one sphere at a time --------------------------------------------------------------------------
  logic gclk;
  logic busy_q, const_done_q, bounds_done_q;
  logic [AW-1:0] addr_q;
  logic prep_ready, prep_done, cull_ready, cull_done;
  logic [ts_artix_pkg::ExpW-1:0]  prep_e;
  logic [ts_artix_pkg::R2sW-1:0]  prep_r2s;
  logic [ts_artix_pkg::RinvW-1:0] prep_rinv;
  logic [ConstW-1:0] const_q;
  logic cull_empty;
  logic [9:0] cull_col_lo, cull_col_hi;
  logic [8:0] cull_row_lo, cull_row_hi;

  assign queue_pop = !busy_q && !queue_empty && prep_ready && cull_ready && !begin_write;

  ts_artix_prepare prepare (
      .clk(gclk), .rst, .start(queue_pop), .in_r(f_r), .ready(prep_ready),
      .done(prep_done), .out_e(prep_e), .out_r2s(prep_r2s), .out_rinv(prep_rinv)
  );
  ts_artix_cull cull (
      .clk(gclk), .rst, .start(queue_pop), .ready(cull_ready),
      .cx(f_x), .cy(f_y), .cz(f_z), .r(f_r),
      .done(cull_done), .empty(cull_empty),
      .col_lo(cull_col_lo), .col_hi(cull_col_hi), .row_lo(cull_row_lo), .row_hi(cull_row_hi)
  );

  ts_clock_gate gate (
      .clk, .en(rst || begin_write || we || !queue_empty || busy_q || !prep_ready || !cull_ready), .gclk
  );

  // Both results in: the constants into the memory, the bounds to the tile lists, in one cycle.
  logic finish;
  assign finish = busy_q && (const_done_q || prep_done) && (bounds_done_q || cull_done);

  always_ff @(posedge gclk) begin
    if (rst) begin
      busy_q        <= 1'b0;
      const_done_q  <= 1'b0;
      bounds_done_q <= 1'b0;
    end else if (queue_pop) begin
      busy_q        <= 1'b1;
      const_done_q  <= 1'b0;
      bounds_done_q <= 1'b0;
    end else if (finish) begin
      busy_q <= 1'b0;
    end else begin
      if (prep_done) const_done_q <= 1'b1;
      if (cull_done) bounds_done_q <= 1'b1;
    end
    if (queue_pop) addr_q <= f_addr;
    if (prep_done) const_q <= {prep_e, prep_r2s, prep_rinv};
  end

  // The bounds are held from the cull's done to the write.
  logic       b_empty_q;
  logic [9:0] b_col_lo_q, b_col_hi_q;
  logic [8:0] b_row_lo_q, b_row_hi_q;
  always_ff @(posedge gclk) begin
    if (cull_done) begin
      b_empty_q  <= cull_empty;
      b_col_lo_q <= cull_col_lo;
      b_col_hi_q <= cull_col_hi;
      b_row_lo_q <= cull_row_lo;
      b_row_hi_q <= cull_row_hi;
    end
  end

  assign bounds_we     = finish;
  assign bounds_addr   = addr_q;
  assign bounds_empty  = bounds_done_q ? b_empty_q : cull_empty;
  assign bounds_col_lo = bounds_done_q ? b_col_lo_q : cull_col_lo;
  assign bounds_col_hi = bounds_done_q ? b_col_hi_q : cull_col_hi;
  assign bounds_row_lo = bounds_done_q ? b_row_lo_q : cull_row_lo;
  assign bounds_row_hi = bounds_done_q ? b_row_hi_q : cull_row_hi;

  logic [ConstW-1:0] const_w;
  assign const_w = const_done_q ? const_q : {prep_e, prep_r2s, prep_rinv};
  assign idle    = !busy_q && queue_empty && !we;

  // ---- the constants memory ------------------------------------------------------------------------------------
  logic front_q;  // the copy the units read
  always_ff @(posedge clk) begin
    if (rst) front_q <= 1'b0;
    else if (swap) front_q <= !front_q;
  end

  for (genvar p = 0; p < NREAD; p++) begin : g_replica
    logic [ConstW-1:0] mem [2 * ts_artix_pkg::MaxSpheres];
    logic [ConstW-1:0] rd_q;
    always_ff @(posedge clk) begin
      if (finish) mem[{!front_q, addr_q}] <= const_w;
      rd_q <= mem[{front_q, rd_addr[p*AW+:AW]}];
    end
    assign rd_const[p*ConstW+:ConstW] = rd_q;
  end
endmodule
