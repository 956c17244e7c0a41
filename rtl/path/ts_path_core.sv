// ts_path_core: the artix path preset's tracing core: N path units (ts_path_unit) and the one bounce stage they share
// (ts_path_bounce), joined by the turn, and each unit's pixels (ts_path_pixels). C++ model: artix::render_path_line
// and artix::unit_finish_cycles with DeviceUnits::shared_bounce and pixel_port (src/tripsitter/device/
// artix_units.cpp); docs/rtl.md, "Path tracing blocks".
//
// Unit u traces the columns u, u + N, ... of a line. In the line's cycle c the turn is unit c mod N's (each unit
// counts it too, from `start`): the unit registers what it hands on then, a ray's closest hit or miss (the turn's
// register, all 0 in every other cycle), and in the next cycle the core passes that unit's port to the stage (the
// OR of all units' ports: the others are 0), which gives back 49 cycles later
// the path's next ray, to the unit named with it, or the path's end. That is the schedule's 51 cycles
// (ts_artix_pkg::BounceLatency): the register, the stage, and the unit's cycle before the ray is known in its
// queue.
//
// Each unit has its own ports to the memories the device replicates (the row's tile lists, scene memory, node
// memory: unit u's field of a port at [u W +: W]); the stage has the surfaces' port. A sample ends in one of two
// places: the stage (`end_valid` with its light: the sky's, or 0 for a path absorbed; the schedule's cycle is the next)
// or its unit's cut at the path's last ray (`cut_valid[u]`, no light, with the path's tag {number, column,
// sample}). Either way it goes through its unit's pixel port into the column's entry (ts_path_pixels, one a unit:
// the stage's light in the cycle it is out, a cut in the first cycle no light takes). The next row's pixels come
// with their frame-memory entries (which say whether each takes this frame's samples); the last window's row is read
// back (`rd_*`: a column's entry and whether it is final, the cycle after it is asked). `start` is the line
// window's first cycle, `flush` its last: everything in flight is dropped after it, in the units, the stage and the
// pixels' ports. `overflow` (sticky): a unit's or a pixel port's queue.
module ts_path_core #(
    parameter int N = ts_artix_pkg::Units,
    parameter int IDS = ts_artix_pkg::Paths,
    localparam int Slots = (ts_artix_pkg::LineWidth + N - 1) / N,
    localparam int SlotW = $clog2(Slots),
    localparam int UW = N > 1 ? $clog2(N) : 1,
    localparam int IdW = $clog2(IDS),
    localparam int TagW = IdW + 10 + 5,
    localparam int AW = ts_artix_pkg::SphereAW,
    localparam int DirW = ts_artix_pkg::DirW,
    localparam int OriginW = ts_artix_pkg::OriginW,
    localparam int CoordW = ts_artix_pkg::CoordW,
    localparam int ExpW = ts_artix_pkg::ExpW,
    localparam int R2sW = ts_artix_pkg::R2sW
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic                   start,
    input  logic                   flush,
    // The world shown, the frame's path rules, the line's row and the frame's first sample index (frame x spp).
    input  logic [AW:0]            spheres,
    input  logic                   walks,
    input  logic [AW-1:0]          root_first_sphere,
    input  logic [7:0]             root_spheres,
    input  logic [AW-1:0]          root_first_child,
    input  logic [7:0]             root_children,
    input  logic [3:0]             depth,
    input  logic [4:0]             spp,
    input  logic [8:0]             row,
    input  logic [31:0]            sample_base,
    // The next row's pixels, each to its unit (column px_col = px_unit + px_slot N), in order, each with its camera
    // direction and its entry in frame memory; with the epoch and samples per pixel of the next row's frame (at a
    // frame's last row, the next frame's).
    input  logic [4:0]             px_epoch,
    input  logic [4:0]             px_spp,
    input  logic                   px_we,
    input  logic [UW-1:0]          px_unit,
    input  logic [SlotW-1:0]       px_slot,
    input  logic [9:0]             px_col,
    input  logic [3*DirW-1:0]      px_d,
    input  logic [63:0]            px_entry,
    // Each unit's tile lists (a registered read).
    output logic [N*5-1:0]         tile,
    output logic [N*AW-1:0]        tile_pos,
    input  logic [N*(AW+1)-1:0]    tile_count,
    input  logic [N*AW-1:0]        tile_sphere,
    // Each unit's scene memory: a sphere, or a hierarchy's node's bound (a registered read).
    output logic [N*AW-1:0]        mem_addr,
    output logic [N-1:0]           mem_bound,
    input  logic [N*3*CoordW-1:0]  mem_c,
    input  logic [N*ExpW-1:0]      mem_e,
    input  logic [N*R2sW-1:0]      mem_r2s,
    // Each unit's node memory (a registered read).
    output logic [N*AW-1:0]        node_addr,
    input  logic [N*AW-1:0]        node_first_sphere,
    input  logic [N*8-1:0]         node_spheres,
    input  logic [N*AW-1:0]        node_first_child,
    input  logic [N*8-1:0]         node_children,
    // The stage's surfaces (ts_path_bounce: asked in a hit's cycle 0, on the ports in its cycle 2).
    output logic [AW-1:0]          surf_addr,
    input  logic [1:0]             surf_material,
    input  logic [3*17-1:0]        surf_albedo,
    input  logic [15:0]            surf_fuzz,
    input  logic [17:0]            surf_eta_enter,
    input  logic [17:0]            surf_eta_leave,
    input  logic [14:0]            surf_r0,
    input  logic                   surf_straight,
    input  logic [ts_artix_pkg::RinvW-1:0] surf_rinv,
    // A sample's end at the stage, and the units' cuts.
    output logic                   end_valid,
    output logic [UW-1:0]          end_unit,
    output logic [9:0]             end_col,
    output logic [4:0]             end_sample,
    output logic [3*18-1:0]        end_light,
    output logic [N-1:0]           cut_valid,
    output logic [N*TagW-1:0]      cut_tag,
    // The last window's row: column rd_col (unit rd_unit's) final or not, and its entry, the cycle after.
    input  logic [UW-1:0]          rd_unit,
    input  logic [9:0]             rd_col,
    output logic                   rd_final,
    output logic [63:0]            rd_entry,
    output logic                   overflow
);
  localparam int TdW = ts_artix_pkg::TdW;
  localparam int BetaW = ts_artix_pkg::DirFrac;
  localparam int HitFW = ts_artix_pkg::HitFW;
  localparam int SqrtW = ts_artix_pkg::SqrtW;
  // A unit's stage port, flat: {o, d, rays, tag, hit, index, far, td, beta, f, s, e}.
  localparam int PortW = 3 * OriginW + 3 * DirW + 4 + TagW + 1 + AW + 1 + TdW + BetaW + 3 * HitFW + SqrtW + ExpW;

  if (N > 16) begin : g_bad_n
    $error("ts_path_core: the units' turn counts up to 16 units");
  end

  // ---- the turn: in cycle c, the port unit c - 1 mod N registered in its turn, into the stage ------------------
  logic [3:0]    phase_q;
  logic [UW-1:0] last_q;
  wire  [3:0]    phase = start ? 4'd0 : phase_q;
  always_ff @(posedge clk) begin
    phase_q <= phase == 4'(N - 1) ? 4'd0 : phase + 4'd1;
    last_q  <= phase[UW-1:0];
  end

  logic [N-1:0]       stage_valid;
  logic [N*PortW-1:0] ports;  // unit u's at [u PortW +: PortW] (Yosys 0.23 keeps no array of them as wires)
  logic [N-1:0]       unit_overflow, pixels_overflow;
  logic [N-1:0]       takes, final_q;
  logic [N*64-1:0]    entries;  // unit u's read at [u 64 +: 64]

  // The stage's ends (with their light), to the unit's pixel port in the next cycle: the schedule's.
  logic [N-1:0]  lit_q;
  logic [9:0]    lit_col_q;
  logic [53:0]   lit_light_q;

  // The stage's next ray (or end), broadcast to the units with the unit it is for.
  logic                 ray_valid, st_end_valid;
  logic [UW-1:0]        out_unit;
  logic [IdW-1:0]       out_path;
  logic [9:0]           out_col;
  logic [4:0]           out_sample;
  logic [3:0]           out_rays;
  logic [3*OriginW-1:0] out_o;
  logic [3*DirW-1:0]    out_d;
  logic [AW-1:0]        out_from;
  logic                 out_into;

  for (genvar u = 0; u < N; u++) begin : g_unit
    logic [3*OriginW-1:0] o;
    logic [3*DirW-1:0]    d;
    logic [3:0]           rays;
    logic [TagW-1:0]      tag;
    logic                 hit, far;
    logic [AW-1:0]        index;
    logic [TdW-1:0]       td;
    logic [BetaW-1:0]     beta;
    logic [3*HitFW-1:0]   f;
    logic [SqrtW-1:0]     s;
    logic [ExpW-1:0]      e;
    ts_path_unit #(
        .N  (N),
        .IDS(IDS)
    ) u_unit (
        .clk,
        .rst,
        .unit_id          (10'(u)),
        .start,
        .flush,
        .spheres,
        .walks,
        .root_first_sphere,
        .root_spheres,
        .root_first_child,
        .root_children,
        .depth,
        .spp,
        .px_we            (px_we && px_unit == UW'(u)),
        .px_slot,
        .px_takes         (takes[u]),
        .px_d,
        .tile             (tile[u*5+:5]),
        .tile_pos         (tile_pos[u*AW+:AW]),
        .tile_count       (tile_count[u*(AW+1)+:AW+1]),
        .tile_sphere      (tile_sphere[u*AW+:AW]),
        .mem_addr         (mem_addr[u*AW+:AW]),
        .mem_bound        (mem_bound[u]),
        .mem_c            (mem_c[u*3*CoordW+:3*CoordW]),
        .mem_e            (mem_e[u*ExpW+:ExpW]),
        .mem_r2s          (mem_r2s[u*R2sW+:R2sW]),
        .node_addr        (node_addr[u*AW+:AW]),
        .node_first_sphere(node_first_sphere[u*AW+:AW]),
        .node_spheres     (node_spheres[u*8+:8]),
        .node_first_child (node_first_child[u*AW+:AW]),
        .node_children    (node_children[u*8+:8]),
        .ray_valid        (ray_valid && out_unit == UW'(u)),
        .ray_o            (out_o),
        .ray_d            (out_d),
        .ray_from         (out_from),
        .ray_into         (out_into),
        .ray_rays         (out_rays),
        .ray_tag          ({out_path, out_col, out_sample}),
        .end_valid        (st_end_valid && out_unit == UW'(u)),
        .end_path         (out_path),
        .stage_valid      (stage_valid[u]),
        .stage_o          (o),
        .stage_d          (d),
        .stage_rays       (rays),
        .stage_tag        (tag),
        .stage_hit        (hit),
        .stage_index      (index),
        .stage_far        (far),
        .stage_td         (td),
        .stage_beta       (beta),
        .stage_f          (f),
        .stage_s          (s),
        .stage_e          (e),
        .cut_valid        (cut_valid[u]),
        .cut_tag          (cut_tag[u*TagW+:TagW]),
        .overflow         (unit_overflow[u])
    );
    assign ports[u*PortW+:PortW] = {o, d, rays, tag, hit, index, far, td, beta, f, s, e};

    ts_path_pixels #(.N(N)) u_pixels (
        .clk,
        .rst,
        .start,
        .flush,
        .epoch    (px_epoch),
        .spp      (px_spp),
        .ld_we    (px_we && px_unit == UW'(u)),
        .ld_col   (px_col),
        .ld_entry (px_entry),
        .ld_takes (takes[u]),
        .lit_valid(lit_q[u]),
        .lit_col  (lit_col_q),
        .lit_light(lit_light_q),
        .cut_valid(cut_valid[u]),
        .cut_col  (cut_tag[u*TagW+5+:10]),
        .rd_col,
        .rd_final (final_q[u]),
        .rd_entry (entries[u*64+:64]),
        .overflow (pixels_overflow[u])
    );
  end

  logic [UW-1:0] rd_unit_q;
  always_ff @(posedge clk) begin
    for (int u = 0; u < N; u++) lit_q[u] <= st_end_valid && !flush && out_unit == UW'(u);
    lit_col_q <= out_col;
    lit_light_q <= end_light;
    rd_unit_q <= rd_unit;
  end
  assign rd_final = final_q[rd_unit_q];
  assign rd_entry = entries[rd_unit_q*64+:64];

  // Only the unit whose turn was last cycle has anything on its port (every other's register is all 0): the ports
  // are merged by an OR.
  wire [UW-1:0]     in_unit = last_q;
  wire              in_valid = |stage_valid;
  logic [PortW-1:0] in_q;
  always_comb begin
    in_q = '0;
    for (int u = 0; u < N; u++) in_q = in_q | ports[u*PortW+:PortW];
  end
  logic [3*OriginW-1:0] in_o;
  logic [3*DirW-1:0]    in_d;
  logic [3:0]           in_rays;
  logic [IdW-1:0]       in_path;
  logic [9:0]           in_col;
  logic [4:0]           in_sample;
  logic                 in_hit, in_far;
  logic [AW-1:0]        in_index;
  logic [TdW-1:0]       in_td;
  logic [BetaW-1:0]     in_beta;
  logic [3*HitFW-1:0]   in_f;
  logic [SqrtW-1:0]     in_s;
  logic [ExpW-1:0]      in_e;
  assign {in_o, in_d, in_rays, in_path, in_col, in_sample, in_hit, in_index, in_far, in_td, in_beta, in_f, in_s,
          in_e} = in_q;

  ts_path_bounce #(
      .N  (N),
      .IDS(IDS)
  ) u_stage (
      .clk,
      .rst,
      .flush,
      .row,
      .sample_base,
      .in_valid,
      .in_unit,
      .in_path,
      .in_col,
      .in_sample,
      .in_rays,
      .in_o,
      .in_d,
      .in_hit,
      .in_index,
      .in_far,
      .in_td,
      .in_beta,
      .in_f,
      .in_s,
      .in_e,
      .surf_addr,
      .surf_material,
      .surf_albedo,
      .surf_fuzz,
      .surf_eta_enter,
      .surf_eta_leave,
      .surf_r0,
      .surf_straight,
      .surf_rinv,
      .ray_valid,
      .end_valid     (st_end_valid),
      .out_unit,
      .out_path,
      .out_col,
      .out_sample,
      .out_rays,
      .out_o,
      .out_d,
      .out_from,
      .out_into,
      .out_light     (end_light)
  );
  assign end_valid  = st_end_valid;
  assign end_unit   = out_unit;
  assign end_col    = out_col;
  assign end_sample = out_sample;

  always_ff @(posedge clk) begin
    if (rst) overflow <= 1'b0;
    else if (|unit_overflow || |pixels_overflow) overflow <= 1'b1;
  end
endmodule
