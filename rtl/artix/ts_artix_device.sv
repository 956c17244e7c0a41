// ts_artix_device: the artix preset's device as one top, pin for pin the same as ts_device (rtl/device/ts_device.sv),
// so that the same test bench and `--device rtl` drive either. Its C++ model is device::Device with artix_preset()
// (src/tripsitter/device/device.h; the line is artix::render_line, src/tripsitter/device/artix_units.h); docs/rtl.md,
// "The artix device", draws the blocks and the cycle schedule of a line.
//
// Blocks: the SPI receiver and scene memory (ts_spi_rx, ts_receiver, ts_scene_memory, as ts_receiver_top wires
// them, with one read port per unit); the world's preparation (ts_artix_world: constants and cull bounds as the
// spheres are written); the tile lists (ts_artix_tiles); the camera's directions (ts_artix_camera); N units
// (ts_artix_unit); the line buffers and the VGA block (ts_line_buffers, ts_vga_timing).
//
// A line L (3,200 cycles: {column, phase}) works on row L + 1 (lines 524 and 0..478), from its first cycle
// (`start` to every unit) to its last (`flush`); the colours land in the back line buffer, which the VGA block shows
// during line L + 1. In the line before (lines 523, 524 and 0..477), the tile lists of that row are built
// (ts_artix_tiles: build at the line's first cycle, flip at the next line's) and the camera generator writes its
// 640 directions into the units' direction banks, one a cycle from the line's first cycle. A world is swapped in at
// the first cycle of vertical blanking (frame_start) when one is pending and its preparation is finished.
module ts_artix_device #(
    parameter int N = 12,      // sphere units
    parameter int WIRE = 3,    // link::WireVersion: 1, 2 or 3
    parameter int CNT_W = 32,  // width of the receiver's counters
    localparam int AW = ts_artix_pkg::SphereAW,
    localparam int CoordW = ts_artix_pkg::CoordW,
    localparam int RadiusW = ts_artix_pkg::RadiusW
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             spi_sclk,
    input  logic             spi_mosi,
    input  logic             spi_cs_n,
    output logic             spi_ready,
    input  logic             end_of_stream,
    output logic [3:0]       vga_r,
    output logic [3:0]       vga_g,
    output logic [3:0]       vga_b,
    output logic             vga_hsync_n,
    output logic             vga_vsync_n,
    // For simulation, as ts_device's.
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
  localparam int DirW = ts_artix_pkg::DirW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int R2sW = ts_artix_pkg::R2sW;
  localparam int RinvW = ts_artix_pkg::RinvW;
  localparam int ConstW = ExpW + R2sW + RinvW;
  localparam int LineCycles = ts_artix_pkg::LeadCycles;  // the whole line: the window is lines' 0..3199
  localparam int Slots = (ts_artix_pkg::LineWidth + N - 1) / N;
  localparam int SlotW = $clog2(Slots);

  // ---- the beam -------------------------------------------------------------------------------------------------
  logic [1:0]  phase;
  logic [9:0]  column, line;
  logic        pix_en, visible, line_end, frame_start, rd_en;
  logic [11:0] rd_data, rgb;
  ts_vga_timing timing (
      .clk, .rst, .phase, .column, .line, .pix_en, .visible, .line_end, .frame_start, .rd_en, .rd_data,
      .vga_rgb(rgb), .vga_hsync_n, .vga_vsync_n, .vga_strobe
  );
  assign vga_r = rgb[11:8];
  assign vga_g = rgb[7:4];
  assign vga_b = rgb[3:0];
  assign beam_line = line;
  assign beam_column = column;

  // The line's events, decoded a cycle ahead from the beam and registered, so that the units' issue logic starts
  // from flip-flops: start (a work line's first cycle), flush (its last), build (a build line's first cycle, with
  // its row) and flip (a build line's last cycle). A work line works on row L + 1 (lines 524, 0..478), a build line
  // builds row L + 2 (lines 523, 524, 0..477).
  logic [11:0] line_cycle;
  logic [9:0]  next_line;
  logic        last_cycle, before_last;
  logic        start, flush, build, flip;
  logic [8:0]  build_row;
  assign line_cycle  = {column, phase};
  assign last_cycle  = line_cycle == 12'(LineCycles - 1);
  assign before_last = line_cycle == 12'(LineCycles - 2);
  assign next_line   = line == 10'd524 ? 10'd0 : line + 10'd1;

  function automatic logic works(input logic [9:0] l);
    works = l == 10'd524 || l < 10'd479;
  endfunction
  function automatic logic builds(input logic [9:0] l);
    builds = l == 10'd523 || l == 10'd524 || l < 10'd478;
  endfunction

  always_ff @(posedge clk) begin
    if (rst) begin
      start <= 1'b0;
      flush <= 1'b0;
      build <= 1'b0;
      flip  <= 1'b0;
    end else begin
      start <= last_cycle && works(next_line);
      flush <= before_last && works(line);
      build <= last_cycle && builds(next_line);
      flip  <= before_last && builds(line);
    end
    if (last_cycle) build_row <= next_line == 10'd523 ? 9'd0 : next_line == 10'd524 ? 9'd1 : 9'(next_line + 10'd2);
  end

  // ---- receiver and scene memory ------------------------------------------------------------------------------
  logic       byte_valid, unused_byte_cut;
  logic [7:0] byte_data;
  ts_spi_rx spi (
      .clk, .rst, .sclk(spi_sclk), .mosi(spi_mosi), .cs_n(spi_cs_n), .byte_valid, .byte_data, .byte_cut(unused_byte_cut)
  );

  logic sm_begin, sm_we, sm_wmetal, sm_commit, sm_replaced, rx_idle;
  logic [AW-1:0]      sm_waddr;
  logic [CoordW-1:0]  sm_wx, sm_wy, sm_wz;
  logic [RadiusW-1:0] sm_wr;
  logic [23:0]        sm_walbedo;
  logic [AW:0]        sm_count;
  logic [31:0]        sm_sequence;
  logic [CNT_W-1:0]   unused_received, unused_overflow;
  ts_receiver #(
      .WIRE(WIRE), .FRAC(ts_artix_pkg::Frac), .X_W(CoordW), .Y_W(CoordW), .Z_W(CoordW), .R_W(RadiusW),
      .MAX_SPHERES(ts_artix_pkg::MaxSpheres), .CNT_W(CNT_W)
  ) receiver (
      .clk, .rst, .byte_valid, .byte_data, .end_of_stream,
      .sm_begin, .sm_we, .sm_waddr, .sm_wx, .sm_wy, .sm_wz, .sm_wr, .sm_wmetal, .sm_walbedo,
      .sm_commit, .sm_count, .sm_sequence, .sm_replaced,
      .worlds_accepted, .worlds_replaced, .frames_rejected, .garbage_runs, .bytes_dropped,
      .worlds_missing, .worlds_replayed, .sessions, .bytes_received(unused_received),
      .overflow_bytes(unused_overflow), .idle(rx_idle)
  );

  // A pending world is swapped in at the blanking only once its preparation is done.
  logic world_idle, pending, swap_now, front_valid;
  logic [AW:0] front_count;
  assign swap_now = frame_start && world_idle && pending;

  logic [N*AW-1:0]      rd_addr;
  logic [N*CoordW-1:0]  rd_x, rd_y, rd_z;
  logic [N*RadiusW-1:0] rd_r;
  logic [N-1:0]         rd_metal;
  logic [N*24-1:0]      rd_albedo;
  ts_scene_memory #(
      .X_W(CoordW), .Y_W(CoordW), .Z_W(CoordW), .R_W(RadiusW), .MAX_SPHERES(ts_artix_pkg::MaxSpheres), .NREAD(N)
  ) scene (
      .clk, .rst,
      .begin_write(sm_begin), .we(sm_we), .waddr(sm_waddr),
      .wx(sm_wx), .wy(sm_wy), .wz(sm_wz), .wr(sm_wr), .wmetal(sm_wmetal), .walbedo(sm_walbedo),
      .commit(sm_commit), .commit_count(sm_count), .commit_sequence(sm_sequence), .replaced(sm_replaced),
      .vblank_swap(frame_start && world_idle), .ready(spi_ready), .pending,
      .front_valid, .front_count, .front_sequence(shown_sequence),
      .rd_addr, .rd_x, .rd_y, .rd_z, .rd_r, .rd_metal, .rd_albedo
  );
  assign shown_valid   = front_valid;
  assign receiver_idle = rx_idle && world_idle;

  // Without a world every pixel is background: the units see no spheres. Registered: the count feeds each unit's
  // last-slot decision and the tile lists' build, and changes only at a swap, in vertical blanking, lines before
  // either reads it.
  logic [AW:0] spheres;
  always_ff @(posedge clk) spheres <= rst || !front_valid ? '0 : front_count;

  // ---- the world's preparation and the tile lists -------------------------------------------------------------
  logic            bounds_we, bounds_empty;
  logic [AW-1:0]   bounds_addr;
  logic [9:0]      bounds_col_lo, bounds_col_hi;
  logic [8:0]      bounds_row_lo, bounds_row_hi;
  logic [N*ConstW-1:0] rd_const;
  ts_artix_world #(.NREAD(N)) world (
      .clk, .rst,
      .begin_write(sm_begin), .we(sm_we), .waddr(sm_waddr), .wx(sm_wx), .wy(sm_wy), .wz(sm_wz), .wr(sm_wr),
      .swap(swap_now), .idle(world_idle),
      .bounds_we, .bounds_addr, .bounds_empty, .bounds_col_lo, .bounds_col_hi, .bounds_row_lo, .bounds_row_hi,
      .rd_addr, .rd_const
  );

  logic [N*5-1:0]    tile;
  logic [N*AW-1:0]   tile_pos, tile_sphere;
  logic [N*(AW+1)-1:0] tile_count;
  // The lists built in a line become the read ones in its last cycle: the units' first reads, in the next line's
  // first cycle, see them (a read in the flip's cycle would not), and reads in the flush cycle are dropped anyway.
  logic unused_tiles_busy;
  ts_artix_tiles #(.NREAD(N)) tiles (
      .clk, .rst,
      .we(bounds_we), .waddr(bounds_addr), .wempty(bounds_empty),
      .wcol_lo(bounds_col_lo), .wcol_hi(bounds_col_hi), .wrow_lo(bounds_row_lo), .wrow_hi(bounds_row_hi),
      .swap(swap_now),
      .build, .build_row, .build_count(spheres), .busy(unused_tiles_busy), .flip,
      .rd_tile(tile), .rd_pos(tile_pos), .rd_count(tile_count), .rd_sphere(tile_sphere)
  );

  // ---- the camera's directions of the next row: column c into unit c mod N, slot c div N ----------------------
  logic       feed_q;       // the generator is fed this cycle
  logic [9:0] feed_col_q;
  logic [8:0] feed_row_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      feed_q <= 1'b0;
    end else if (build) begin
      feed_q     <= 1'b1;
      feed_col_q <= '0;
      feed_row_q <= build_row;
    end else if (feed_q) begin
      feed_q     <= feed_col_q != 10'd639;
      feed_col_q <= feed_col_q + 10'd1;
    end
  end

  logic            dir_valid;
  logic [3*DirW-1:0] dir_d;
  logic            unused_tag;
  ts_artix_camera #(.TAG_W(1)) camera (
      .clk, .rst,
      .in_valid(feed_q), .in_col(feed_col_q), .in_row(feed_row_q), .in_tag(1'b0),
      .out_valid(dir_valid), .out_d(dir_d), .out_tag(unused_tag)
  );
  // The directions come out in column order: count units and slots alongside.
  localparam int UnitW = N > 1 ? $clog2(N) : 1;
  logic [UnitW-1:0] dir_unit_q;
  logic [SlotW-1:0] dir_slot_q;
  always_ff @(posedge clk) begin
    if (rst || build) begin
      dir_unit_q <= '0;
      dir_slot_q <= '0;
    end else if (dir_valid) begin
      dir_unit_q <= dir_unit_q == UnitW'(N - 1) ? '0 : dir_unit_q + 1'b1;
      if (dir_unit_q == UnitW'(N - 1)) dir_slot_q <= dir_slot_q + 1'b1;
    end
  end

  // ---- the units --------------------------------------------------------------------------------------------------
  logic [N-1:0]       px_we, overflow;
  logic [N*SlotW-1:0] px_slot;
  logic [N*12-1:0]    px_colour;
  for (genvar u = 0; u < N; u++) begin : g_unit
    logic [ConstW-1:0] c;
    assign c = rd_const[u*ConstW+:ConstW];
    ts_artix_unit #(.N(N)) unit (
        .clk, .rst, .unit_id(10'(u)), .start, .flush, .spheres,
        .dir_we(dir_valid && dir_unit_q == UnitW'(u)), .dir_slot(dir_slot_q), .dir_d,
        .tile(tile[u*5+:5]), .tile_pos(tile_pos[u*AW+:AW]), .tile_count(tile_count[u*(AW+1)+:AW+1]),
        .tile_sphere(tile_sphere[u*AW+:AW]),
        .sphere_addr(rd_addr[u*AW+:AW]),
        .sphere_c({rd_z[u*CoordW+:CoordW], rd_y[u*CoordW+:CoordW], rd_x[u*CoordW+:CoordW]}),
        .sphere_r(rd_r[u*RadiusW+:RadiusW]),
        .sphere_e(c[ConstW-1-:ExpW]), .sphere_r2s(c[RinvW+:R2sW]), .sphere_rinv(c[RinvW-1:0]),
        .sphere_metal(rd_metal[u]), .sphere_albedo(rd_albedo[u*24+:24]),
        .px_we(px_we[u]), .px_slot(px_slot[u*SlotW+:SlotW]), .px_colour(px_colour[u*12+:12]),
        .overflow(overflow[u])
    );
  end

  ts_line_buffers #(.N(N)) buffers (
      .clk, .rst, .swap(line_end), .wr_en(px_we), .wr_slot(px_slot), .wr_colour(px_colour), .rd_en, .rd_data
  );

  // ---- late pixels: 640 less the colours written in the window --------------------------------------------------
  logic [9:0] written_q;
  logic [$clog2(N+1)-1:0] writes;
  always_comb begin
    writes = '0;
    for (int u = 0; u < N; u++) writes = writes + $bits(writes)'(px_we[u]);
  end
  logic closing_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      written_q  <= '0;
      closing_q  <= 1'b0;
      late_valid <= 1'b0;
    end else begin
      written_q  <= start ? 10'(writes) : written_q + 10'(writes);
      closing_q  <= flush;
      late_valid <= closing_q;
    end
    if (closing_q) late_pixels <= 10'd640 - written_q;
  end

  /* verilator lint_off UNUSEDSIGNAL */  // the receiver's extra counters, the cut-byte pulse, the beam's enables, the
  logic unused;                          // generator's tag and the units' overflow flags (the unit tests read them)
  assign unused = ^unused_received ^ ^unused_overflow ^ unused_byte_cut ^ pix_en ^ visible ^ unused_tag ^ |overflow;
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
