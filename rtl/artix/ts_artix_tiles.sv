// ts_artix_tiles: the camera rays' tile lists of a line. C++ model: artix::row_tiles (src/tripsitter/device/
// artix_units.cpp), bit for bit: for a row and each of the Tiles (20) tiles of TileColumns (32) columns, the indices,
// ascending, of the spheres whose cull bounds hold the row and whose columns meet the tile. docs/device.md, "The
// artix preset", says why the units' camera rays need test only these.
//
// The world's bounds. ts_artix_cull's answer for each sphere is written here as the world enters, into the back of
// two copies, as scene memory keeps the world (rtl/receiver/ts_scene_memory.sv); `swap` (one cycle, in vertical
// blanking, with scene memory's swap) makes it the front copy. A sphere is kept as its first and last tile
// (col / 32) and its rows: 28 bits, one RAMB18 for both copies. A sphere culled everywhere is kept as rows 511..0,
// which hold no row.
//
// Building. `build` (one cycle) starts the lists of row build_row over the front copy's spheres 0 .. build_count - 1
// (build_count <= MaxSpheres), into the list bank the ports do not read. The lists are built two tiles at a time,
// tile-major: pass p = 0..9 reads every sphere's bounds in order and appends the sphere to tile 2p's list through
// one port of the list memory and to tile 2p + 1's through the other, when it meets them. So the lists come out
// ascending, each pass needs one counter per tile of its pair, and both ports of the bank are written every cycle.
// A build pulsed in cycle t keeps `busy` high in cycles t + 1 .. t + 10 max(build_count, 1) + 2 and its lists are
// whole from the next cycle on: 2,562 cycles for 256 spheres, however many entries they make (5,120 at most).
//
// Reading. `flip` (one cycle) makes the lists last built the ones read. NREAD ports, each a registered read like
// block RAM: the tile rd_tile (0..19) and position rd_pos in cycle t give, in cycle t + 1, rd_count, that tile's
// list length (0..256), and rd_sphere, its entry at rd_pos (meaningless when rd_pos >= rd_count). A read in the
// flip's cycle still gets the lists read before it.
//
// The lead's line: flip and build together at a line's start (the lists built on the last line are read on this
// one while the next row's are built), the next pulse 3,200 cycles later. What is required: no flip while busy,
// and no build while busy (it is ignored); the world's swap before the build of a frame's first row (a build reads
// the copy that was the front when it was pulsed, whatever swaps during it).
//
// Memories. A list bank is one memory of Tiles x 256 entries of 8 bits (tile t's list at t 256 ..), 5,120 entries
// because 256 spheres may each meet all 20 tiles: three RAMB18 (2K x 9). Block RAM has two ports, so each pair of
// read ports has its own replica of both banks, as scene memory does: in the bank being built both ports write
// (the build's two tiles), in the bank being read they are the pair's read ports. The builder writes every replica
// alike. NREAD = 12: 6 replicas x 2 banks x 3 RAMB18 = 36 RAMB18 (18 RAMB36), and the bounds one more RAMB18. The
// lengths are two small LUT memories (even and odd tiles, 32 x 9 bits each: both banks' 10 tiles of the parity),
// written at the end of each pass, read by every port without a block RAM's port limit.
//
// The package's facts are named ts_artix_pkg::X, not imported: Yosys 0.23 cannot parse `import`.
module ts_artix_tiles #(
    parameter int NREAD = 12  // read ports: one per sphere unit
) (
    input  logic                                            clk,
    input  logic                                            rst,
    // The world's bounds, as the cull gives them, into the back copy.
    input  logic                                            we,
    input  logic [ts_artix_pkg::SphereAW-1:0]               waddr,
    input  logic                                            wempty,     // culled everywhere: the bounds are ignored
    input  logic [9:0]                                      wcol_lo,    // else col_lo <= col_hi <= 639
    input  logic [9:0]                                      wcol_hi,
    input  logic [8:0]                                      wrow_lo,    // and row_lo <= row_hi <= 479
    input  logic [8:0]                                      wrow_hi,
    input  logic                                            swap,
    // A line's lists.
    input  logic                                            build,
    input  logic [8:0]                                      build_row,  // 0..479
    input  logic [ts_artix_pkg::SphereAW:0]                 build_count,
    output logic                                            busy,
    input  logic                                            flip,
    // Read port i's fields at [i*W +: W].
    input  logic [NREAD*$clog2(ts_artix_pkg::Tiles)-1:0]    rd_tile,
    input  logic [NREAD*ts_artix_pkg::SphereAW-1:0]         rd_pos,
    output logic [NREAD*(ts_artix_pkg::SphereAW+1)-1:0]     rd_count,
    output logic [NREAD*ts_artix_pkg::SphereAW-1:0]         rd_sphere
);
  localparam int Tiles = ts_artix_pkg::Tiles;
  localparam int TileColumns = ts_artix_pkg::TileColumns;
  localparam int MaxSpheres = ts_artix_pkg::MaxSpheres;
  localparam int SphereAW = ts_artix_pkg::SphereAW;
  localparam int TileW = $clog2(Tiles);            // 5
  localparam int ColShift = $clog2(TileColumns);   // a column's tile is col >> 5
  localparam int CountW = SphereAW + 1;            // 0..256
  localparam int EntryAW = TileW + SphereAW;       // {tile, position}
  localparam int Entries = Tiles * MaxSpheres;     // 5,120
  localparam int Passes = Tiles / 2;
  localparam int PassW = TileW - 1;
  localparam int RowW = 9;
  localparam int BoundsW = 2 * TileW + 2 * RowW;
  localparam int Replicas = (NREAD + 1) / 2;

  if (Tiles % 2 != 0 || Tiles * TileColumns != 640 || 1 << ColShift != TileColumns ||
      MaxSpheres != 1 << SphereAW) begin : g_bad_package
    $error("ts_artix_tiles: built for an even number of tiles of a power-of-two width across 640 columns");
  end

  // ---- the world's bounds: two copies ----------------------------------------------------------------------------
  logic front_q;  // the bounds copy the builds read
  always_ff @(posedge clk) begin
    if (rst) front_q <= 1'b0;
    else if (swap) front_q <= ~front_q;
  end

  logic [BoundsW-1:0] bounds_mem [2 * MaxSpheres];
  wire [BoundsW-1:0] wbounds = wempty ? {TileW'(0), TileW'(0), RowW'(511), RowW'(0)}
                                      : {TileW'(wcol_lo >> ColShift), TileW'(wcol_hi >> ColShift), wrow_lo, wrow_hi};
  always_ff @(posedge clk) begin
    if (we) bounds_mem[{~front_q, waddr}] <= wbounds;
  end

  // ---- the builder ---------------------------------------------------------------------------------------------
  // Issue: one sphere of one pass a cycle. Stage 1: its bounds, read. Stage 2: the tiles it meets, written.
  logic                 busy_q;
  logic                 copy_q;      // the bounds copy of this build
  logic [RowW-1:0]      row_q;
  logic [CountW-1:0]    count_q;
  logic                 issuing_q;
  logic [PassW-1:0]     pass_q;
  logic [CountW-1:0]    index_q;
  logic                 read_q;      // the list bank the ports read

  wire [CountW-1:0] last_index = count_q == '0 ? '0 : count_q - CountW'(1);  // a world of none still makes a pass
  wire issue_last = index_q == last_index;
  wire build_done;

  always_ff @(posedge clk) begin
    if (rst) read_q <= 1'b0;
    else if (flip) read_q <= ~read_q;
  end

  // The builder runs on a gated clock (ts_clock_gate) with an edge only from a build to its end, or in reset:
  // 10 max(build_count, 1) + 3 cycles a line.
  logic gclk;
  ts_clock_gate gate (.clk, .en(rst || build || busy_q), .gclk);

  always_ff @(posedge gclk) begin
    if (rst) begin
      busy_q <= 1'b0;
      issuing_q <= 1'b0;
    end else begin
      if (build && !busy_q) begin
        busy_q <= 1'b1;
        issuing_q <= 1'b1;
      end else begin
        if (issuing_q && issue_last && pass_q == PassW'(Passes - 1)) issuing_q <= 1'b0;
        if (build_done) busy_q <= 1'b0;
      end
    end
  end

  always_ff @(posedge gclk) begin
    if (build && !busy_q) begin
      copy_q <= front_q;
      row_q <= build_row;
      count_q <= build_count;
      pass_q <= '0;
      index_q <= '0;
    end else if (issuing_q) begin
      if (issue_last) begin
        index_q <= '0;
        pass_q <= pass_q + PassW'(1);
      end else begin
        index_q <= index_q + CountW'(1);
      end
    end
  end
  assign busy = busy_q;

  // Stage 1.
  logic                 v1_q, first1_q, last1_q, sphere1_q;
  logic [PassW-1:0]     pass1_q;
  logic [SphereAW-1:0]  index1_q;
  logic [BoundsW-1:0]   bounds1_q;
  always_ff @(posedge gclk) begin
    if (rst) v1_q <= 1'b0;
    else v1_q <= issuing_q;
    first1_q <= index_q == '0;
    last1_q <= issue_last;
    sphere1_q <= index_q < count_q;
    pass1_q <= pass_q;
    index1_q <= index_q[SphereAW-1:0];
    bounds1_q <= bounds_mem[{copy_q, index_q[SphereAW-1:0]}];
  end

  // Stage 2: does the sphere meet the row, and tiles 2p and 2p + 1?
  wire [TileW-1:0] tile_lo = bounds1_q[BoundsW-1-:TileW];
  wire [TileW-1:0] tile_hi = bounds1_q[BoundsW-TileW-1-:TileW];
  wire [RowW-1:0]  row_lo = bounds1_q[2*RowW-1-:RowW];
  wire [RowW-1:0]  row_hi = bounds1_q[RowW-1:0];
  wire [TileW-1:0] even_tile = {pass1_q, 1'b0};
  wire [TileW-1:0] odd_tile = {pass1_q, 1'b1};
  wire in_row = sphere1_q && row_lo <= row_q && row_q <= row_hi;
  logic                 v2_q, first2_q, last2_q, hit_even2_q, hit_odd2_q;
  logic [PassW-1:0]     pass2_q;
  logic [SphereAW-1:0]  index2_q;
  always_ff @(posedge gclk) begin
    if (rst) v2_q <= 1'b0;
    else v2_q <= v1_q;
    first2_q <= first1_q;
    last2_q <= last1_q;
    hit_even2_q <= in_row && tile_lo <= even_tile && even_tile <= tile_hi;
    hit_odd2_q <= in_row && tile_lo <= odd_tile && odd_tile <= tile_hi;
    pass2_q <= pass1_q;
    index2_q <= index1_q;
  end

  // Stage 2's writes: the entry at the tile's next position, and at the pass's end the two lengths.
  logic [CountW-1:0] fill_even_q, fill_odd_q;
  wire [CountW-1:0] fill_even = first2_q ? '0 : fill_even_q;
  wire [CountW-1:0] fill_odd = first2_q ? '0 : fill_odd_q;
  wire [CountW-1:0] length_even = fill_even + CountW'(hit_even2_q);
  wire [CountW-1:0] length_odd = fill_odd + CountW'(hit_odd2_q);
  wire we_even = v2_q && hit_even2_q;
  wire we_odd = v2_q && hit_odd2_q;
  wire [EntryAW-1:0] waddr_even = {pass2_q, 1'b0, fill_even[SphereAW-1:0]};
  wire [EntryAW-1:0] waddr_odd = {pass2_q, 1'b1, fill_odd[SphereAW-1:0]};
  wire we_lengths = v2_q && last2_q;
  assign build_done = we_lengths && pass2_q == PassW'(Passes - 1);
  always_ff @(posedge gclk) begin
    if (v2_q) begin
      fill_even_q <= length_even;
      fill_odd_q <= length_odd;
    end
  end

  // ---- the lengths -----------------------------------------------------------------------------------------------
  // Address {bank, tile / 2}.
  logic [CountW-1:0] length_even_mem [2 << PassW];
  logic [CountW-1:0] length_odd_mem [2 << PassW];
  always_ff @(posedge clk) begin
    if (we_lengths) begin
      length_even_mem[{~read_q, pass2_q}] <= length_even;
      length_odd_mem[{~read_q, pass2_q}] <= length_odd;
    end
  end

  logic read_sel_q;  // read_q at the last read: the bank the entries just read came from
  always_ff @(posedge clk) read_sel_q <= read_q;

  for (genvar p = 0; p < NREAD; p++) begin : g_count
    wire [TileW-1:0] tile = rd_tile[p*TileW+:TileW];
    logic [CountW-1:0] length_q;
    always_ff @(posedge clk) begin
      length_q <= tile[0] ? length_odd_mem[{read_q, tile[TileW-1:1]}] : length_even_mem[{read_q, tile[TileW-1:1]}];
    end
    assign rd_count[p*CountW+:CountW] = length_q;
  end

  // ---- the lists: per pair of read ports, both banks -----------------------------------------------------------
  (* mem2reg *) logic [SphereAW-1:0] rd_entry [NREAD];
  for (genvar g = 0; g < Replicas; g++) begin : g_replica
    localparam int PortA = 2 * g;
    localparam int PortB = 2 * g + 1 < NREAD ? 2 * g + 1 : 2 * g;  // the last replica of an odd NREAD: A only
    wire [EntryAW-1:0] raddr_a = {rd_tile[PortA*TileW+:TileW], rd_pos[PortA*SphereAW+:SphereAW]};
    wire [EntryAW-1:0] raddr_b = {rd_tile[PortB*TileW+:TileW], rd_pos[PortB*SphereAW+:SphereAW]};
    (* mem2reg *) logic [SphereAW-1:0] qa [2];
    /* verilator lint_off UNUSEDSIGNAL */
    (* mem2reg *) logic [SphereAW-1:0] qb [2];  // unused in the last replica when NREAD is odd
    /* verilator lint_on UNUSEDSIGNAL */
    for (genvar b = 0; b < 2; b++) begin : g_bank
      logic [SphereAW-1:0] mem [Entries];
      // Bank b is built while the ports read the other one; then its ports are the builder's two write ports.
      wire built = (b == 1) ? ~read_q : read_q;
      wire [EntryAW-1:0] addr_a = built ? waddr_even : raddr_a;
      wire [EntryAW-1:0] addr_b = built ? waddr_odd : raddr_b;
      always_ff @(posedge clk) begin
        if (built && we_even) mem[addr_a] <= index2_q;
        qa[b] <= mem[addr_a];
      end
      always_ff @(posedge clk) begin
        if (built && we_odd) mem[addr_b] <= index2_q;
        qb[b] <= mem[addr_b];
      end
    end
    assign rd_entry[PortA] = qa[read_sel_q];
    if (2 * g + 1 < NREAD) begin : g_port_b
      assign rd_entry[PortB] = qb[read_sel_q];
    end
  end
  for (genvar p = 0; p < NREAD; p++) begin : g_entry
    assign rd_sphere[p*SphereAW+:SphereAW] = rd_entry[p];
  end
endmodule
