// ts_path_unit: one sphere unit of the artix path preset with everything that feeds it: the issue port that chooses
// the next pass (a bounced ray's first pass, a walk's next level, or a sample's camera ray), the pass's slots (a
// camera ray's tile list, every sphere of a world without a hierarchy, or the walker's levels, ts_path_walk), the
// sphere unit (ts_artix_sphere_unit, PATH = 1), each path's ray and best hit between passes, and the unit's turn at
// the bounce stage the units share. Unit U (`unit_id`, a constant) of N traces the columns U, U + N, ... of each
// line; its pixel k is column U + k N. C++ model: artix::unit_finish_cycles and artix::render_path_line
// (src/tripsitter/device/artix_units.cpp); docs/device.md, "Path tracing on the artix datapath", and docs/rtl.md,
// "Path tracing blocks". Cycle c is counted from the line window's first cycle (`start`), the model's cycle 0.
//
// A path is a sample's rays, one after another. A path's number (0 .. IDS - 1) is its own from its camera ray's
// take to its end: the bounce stage keeps the path's random stream and throughput under it (ts_path_bounce), and
// the unit its ray's state (origin, direction, the sphere it leaves, whether it went in, the rays so far, and the
// path's names, which the unit gives its camera ray and only carries after: its tag, {path number, column,
// sample}) from the pass that starts the ray until the path's next ray starts, with the hit merged over the ray's
// passes (a walk's levels) beside it. A path has one ray at a time, so its number is its ray's place. Numbers are
// counted out fresh after a flush, then taken back from the paths cut, then from those the stage ended
// (`end_path`), each kind in a queue of its own (both may end a path in one cycle).
//
// The issue port. When the port is free in cycle c (no pass issuing, the walker ready), it takes the bounced ray or
// the walk's next level known first, else the next camera ray, else nothing. A bounced ray arrives from the bounce
// stage (`ray_valid`) in the cycle before it is known and a walk's next level is queued in the cycle its level's hit
// is known (WalkWait: known in the next), each in a queue of its own and in the order known, so the one known first
// is at a front: the earlier pushed, a bounced ray on a tie (its pass was taken before the level's; the model's
// order queued). A camera ray is a sample of the next pixel that takes samples this frame (`px_takes`; a converged
// pixel takes none and no cycle of the port), `spp` samples a pixel, in order, taken only while the unit holds
// fewer than IDS paths (DeviceUnits::paths): a path is the unit's from its camera ray's take to its end, the cut or
// the bounce stage's word that it is over (`end_valid`, with its light).
//
// A pass's slots: a camera ray's max(n, MinPass) slots from its tile's list as ts_artix_unit's; a bounced ray in a
// world without a hierarchy max(spheres, MinPass) slots, slot i sphere i, the sphere the ray leaves a far pair when
// it went in and a slot without a pair otherwise; with a hierarchy (`walks`) the walker's (ts_path_walk: the far pair
// first, then each level's spheres and bounds). A slot's way: cycle c its issue (the tile list read), c + 1 its
// sphere or bound read from scene memory (`mem_addr`, `mem_bound`) with the ray's state by its path number, c + 2
// both at the sphere unit (SceneReadCycles). The pass's closest hit comes out HitLatency cycles after the cycle
// following its last slot, the model's `known`, with its path number from the passes in flight.
//
// A pass's hit. It is merged with its ray's best so far (closer, or as close with the lower index). A walk's level
// with another to come (the walker's `result_more`) keeps it and queues the next level. Otherwise the ray's search
// is over: a hit at the path's last ray (`depth`) is a cut (`cut_valid`, with the ray's tag: the sample ends with
// no light); anything else, a hit or a miss, goes to the bounce stage in the unit's turn: the cycles c with
// c mod N = U, one hit each, in the order known (a queue of them, the one known in a turn taken in it), the model's
// shared_bounce. A hit waiting for the turn waits as its path's number: its ray and merged hit stay in their places
// until the turn reads them.
//
// Queues (ts_artix_fifo, LUT RAM): passes in flight, 16 (a pass holds the port at least MinPass cycles and is in
// flight at most 2 + HitLatency + 1 cycles after its last slot); bounced rays, walks' next levels, hits waiting for
// the unit's turn and path numbers given back, IDS each: a path is in one of them at most once, and the unit holds
// IDS at most. `overflow` (sticky) would say one of them overflowed, or a pass's hit came with no pass in flight or
// for another walk than the walker's. `start` is the window's first cycle, `flush` its
// last: everything in flight is dropped after it.
module ts_path_unit #(
    parameter int N = 9,       // units sharing the bounce stage
    parameter int IDS = ts_artix_pkg::Paths,  // paths the unit holds (DeviceUnits::paths), a power of two
    localparam int Slots = (ts_artix_pkg::LineWidth + N - 1) / N,  // the busiest unit's pixels a line
    localparam int SlotW = $clog2(Slots),
    localparam int AW = ts_artix_pkg::SphereAW,
    localparam int DirW = ts_artix_pkg::DirW,
    localparam int OriginW = ts_artix_pkg::OriginW,
    localparam int IdW = $clog2(IDS),
    localparam int TagW = IdW + 10 + 5  // a path's names: {number, column, sample}
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic [9:0]             unit_id,   // U: a constant (a port, so that all units are one module)
    input  logic                   start,
    input  logic                   flush,
    // The world shown and the frame's path rules.
    input  logic [AW:0]            spheres,   // 0 .. MaxSpheres
    input  logic                   walks,     // the world has a hierarchy: bounced rays walk it
    input  logic [AW-1:0]          root_first_sphere,
    input  logic [7:0]             root_spheres,
    input  logic [AW-1:0]          root_first_child,
    input  logic [7:0]             root_children,
    input  logic [3:0]             depth,     // rays a path, 1 ..
    input  logic [4:0]             spp,       // samples a pixel that takes samples, 1 .. 16
    // The next row's pixels, in order (the camera's direction, whether the pixel takes this frame's samples).
    input  logic                   px_we,
    input  logic [SlotW-1:0]       px_slot,
    input  logic                   px_takes,
    input  logic [3*DirW-1:0]      px_d,
    // The tile lists of this row (ts_artix_tiles, one read port): a registered read.
    output logic [4:0]             tile,
    output logic [AW-1:0]          tile_pos,
    input  logic [AW:0]            tile_count,
    input  logic [AW-1:0]          tile_sphere,
    // Scene memory (one read port): a sphere, or a hierarchy's node's bound, prepared; a registered read.
    output logic [AW-1:0]          mem_addr,
    output logic                   mem_bound,
    input  logic [3*ts_artix_pkg::CoordW-1:0] mem_c,
    input  logic [ts_artix_pkg::ExpW-1:0]    mem_e,
    input  logic [ts_artix_pkg::R2sW-1:0]    mem_r2s,
    // The hierarchy's node records (the walker's port: a registered read).
    output logic [AW-1:0]          node_addr,
    input  logic [AW-1:0]          node_first_sphere,
    input  logic [7:0]             node_spheres,
    input  logic [AW-1:0]          node_first_child,
    input  logic [7:0]             node_children,
    // From the bounce stage: a bounced ray, known in the next cycle.
    input  logic                   ray_valid,
    input  logic [3*OriginW-1:0]   ray_o,
    input  logic [3*DirW-1:0]      ray_d,
    input  logic [AW-1:0]          ray_from,
    input  logic                   ray_into,
    input  logic [3:0]             ray_rays,  // the rays of the path with this one
    input  logic [TagW-1:0]        ray_tag,
    // From the bounce stage: a path of the unit is over (its light is out with it).
    input  logic                   end_valid,
    input  logic [IdW-1:0]         end_path,
    // To the bounce stage, in the cycle after the unit's turn (the turn's register): a ray's closest hit (or its
    // miss) with the ray. Every bit 0 in the other cycles.
    output logic                   stage_valid,
    output logic [3*OriginW-1:0]   stage_o,
    output logic [3*DirW-1:0]      stage_d,
    output logic [3:0]             stage_rays,
    output logic [TagW-1:0]        stage_tag,
    output logic                   stage_hit,
    output logic [AW-1:0]          stage_index,
    output logic                   stage_far,
    output logic [ts_artix_pkg::TdW-1:0]     stage_td,
    output logic [ts_artix_pkg::DirFrac-1:0] stage_beta,  // b d's fraction, its low bits
    output logic [3*ts_artix_pkg::HitFW-1:0] stage_f,     // each f_k's low HitFW bits (a hit's fit)
    output logic [ts_artix_pkg::SqrtW-1:0]   stage_s,
    output logic [ts_artix_pkg::ExpW-1:0]    stage_e,
    // A path cut at its last ray's hit.
    output logic                   cut_valid,
    output logic [TagW-1:0]        cut_tag,
    output logic                   overflow
);
  localparam int MinPass = ts_artix_pkg::MinPass;
  localparam int TileShift = $clog2(ts_artix_pkg::TileColumns);
  localparam int IW = AW + 1;  // a slot's index in its pass: 0 .. MaxSpheres - 1 (+1 spare)
  localparam int TdW = ts_artix_pkg::TdW;
  localparam int BdW = ts_artix_pkg::BdW;
  localparam int FW = ts_artix_pkg::FW;
  localparam int HitFW = ts_artix_pkg::HitFW;
  localparam int BetaW = ts_artix_pkg::DirFrac;
  localparam int SqrtW = ts_artix_pkg::SqrtW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int CycW = 12;  // a cycle of the line window (3,200 < 2^12)

  if (MinPass < 2) begin : g_bad_min_pass
    $error("ts_path_unit: a pass's first slot must not be its last (MinPass >= 2)");
  end
  if (N < 1 || N > 16) begin : g_bad_n
    $error("ts_path_unit: the turn at the bounce stage counts up to 16 units");
  end
  if ((1 << IdW) != IDS || IDS < 2) begin : g_bad_ids
    $error("ts_path_unit: IDS must be a power of two, at least 2");
  end

  // ---- a path's ray, and a hit ---------------------------------------------------------------------------------
  typedef struct packed {
    logic [3*OriginW-1:0] o;
    logic [3*DirW-1:0]    d;
    logic                 leaves;  // the ray leaves sphere `from` (not a camera ray)
    logic [AW-1:0]        from;
    logic                 into;    // ... and went into it
    logic [3:0]           rays;
    logic [TagW-1:0]      tag;
  } ray_t;
  typedef struct packed {
    logic             hit;
    logic [AW-1:0]    index;
    logic             far_side;  // the far side of the sphere the ray is in
    logic [TdW-1:0]   td;
    logic [BetaW-1:0] beta;  // b d's low bits: all the bounce stage reads of it
    logic [3*HitFW-1:0] f;   // each f_k's low HitFW bits: a hit's f_k fits them
    logic [SqrtW-1:0] s;
    logic [ExpW-1:0]  e;
  } hit_t;
  // Their widths, field by field (Yosys 0.23 takes no $bits of a type).
  localparam int RayW = 3 * OriginW + 3 * DirW + 1 + AW + 1 + 4 + TagW;
  localparam int HitW = 1 + AW + 1 + TdW + BetaW + 3 * HitFW + SqrtW + ExpW;

  // ---- the line's cycle and the unit's turn at the bounce stage ---------------------------------------------------
  logic [CycW-1:0] cyc_q;
  logic [3:0]      phase_q;
  wire [CycW-1:0]  cyc = start ? '0 : cyc_q;
  wire [3:0]       phase = start ? 4'd0 : phase_q;
  wire             turn = phase == unit_id[3:0];
  always_ff @(posedge clk) begin
    cyc_q   <= cyc + CycW'(1);
    phase_q <= phase == 4'(N - 1) ? 4'd0 : phase + 4'd1;
  end

  // ---- the pixels: two banks of directions, and of the list of pixels that take samples -------------------------
  // The list holds each taking pixel's slot and column (U + k N, counted as the pixels are written: all of the
  // unit's, in order, from the window's first cycle on); its first entry and its length are registers, so that the
  // window's first cycle can take its first camera ray.
  localparam int TakerW = SlotW + 10;
  logic [3*DirW-1:0] dirs [2 * (1 << SlotW)];
  logic [TakerW-1:0] takers [2 * (1 << SlotW)];
  logic [SlotW:0]    takers_n_q [2];
  logic [TakerW-1:0] takers_first_q [2];
  logic              bank_q;  // the bank of this row (the other is written)
  wire               rbank = start ? !bank_q : bank_q;
  wire [SlotW:0]     wn = start ? '0 : takers_n_q[!rbank];  // the written bank's length (emptied as it is given up)
  logic [9:0]        wcol_q;  // the column of the next pixel written
  wire  [9:0]        wcol = rst || start ? unit_id : wcol_q;
  wire [TakerW-1:0]  px_taker = {px_slot, wcol};
  always_ff @(posedge clk) wcol_q <= wcol + (px_we ? 10'(N) : 10'd0);
  always_ff @(posedge clk) begin
    if (px_we) dirs[{!rbank, px_slot}] <= px_d;
    if (px_we && px_takes) begin
      takers[{!rbank, wn[SlotW-1:0]}] <= px_taker;
      if (wn == '0) takers_first_q[!rbank] <= px_taker;
    end
    if (start || px_we && px_takes) takers_n_q[!rbank] <= wn + (SlotW + 1)'(px_we && px_takes);
    if (rst) begin
      bank_q     <= 1'b0;
      takers_n_q[0] <= '0;
      takers_n_q[1] <= '0;
    end else if (start) begin
      bank_q <= !bank_q;
    end
  end

  // ---- the queues of passes: bounced rays, and walks' next levels ------------------------------------------------
  logic            b_empty, b_pop, b_overflow;
  logic [CycW-1:0] b_stamp;
  ray_t            b_front;
  ts_artix_fifo #(.W(CycW + RayW), .DEPTH(IDS)) bounced (
      .clk, .rst, .clear(flush), .push(ray_valid),
      .push_data({cyc, ray_o, ray_d, 1'b1, ray_from, ray_into, ray_rays, ray_tag}),
      .pop(b_pop), .front({b_stamp, b_front}), .empty(b_empty), .overflow(b_overflow)
  );
  logic            l_empty, l_pop, l_push, l_overflow;
  logic [CycW-1:0] l_stamp;
  logic [IdW-1:0]  l_front, l_push_id;
  ts_artix_fifo #(.W(CycW + IdW), .DEPTH(IDS)) levels (
      .clk, .rst, .clear(flush), .push(l_push), .push_data({cyc, l_push_id}),
      .pop(l_pop), .front({l_stamp, l_front}), .empty(l_empty), .overflow(l_overflow)
  );

  // ---- path numbers: the fresh ones counted out, then the ones given back by cuts, then by the stage's ends --------
  logic [IdW:0]   pfresh_q;
  logic           pc_empty, pe_empty, pc_overflow, pe_overflow, path_take, cut;
  logic [IdW-1:0] pc_front, pe_front, path_new, cut_path;
  ts_artix_fifo #(.W(IdW), .DEPTH(IDS)) cut_paths (
      .clk, .rst, .clear(flush), .push(cut), .push_data(cut_path),
      .pop(path_take && pfresh_q[IdW] && !pc_empty), .front(pc_front), .empty(pc_empty), .overflow(pc_overflow)
  );
  ts_artix_fifo #(.W(IdW), .DEPTH(IDS)) ended_paths (
      .clk, .rst, .clear(flush), .push(end_valid), .push_data(end_path),
      .pop(path_take && pfresh_q[IdW] && pc_empty), .front(pe_front), .empty(pe_empty), .overflow(pe_overflow)
  );
  assign path_new = !pfresh_q[IdW] ? pfresh_q[IdW-1:0] : !pc_empty ? pc_front : pe_front;
  always_ff @(posedge clk) begin
    if (rst || flush) pfresh_q <= '0;
    else if (path_take && !pfresh_q[IdW]) pfresh_q <= pfresh_q + (IdW + 1)'(1);
  end

  // ---- the issue port -----------------------------------------------------------------------------------------------
  logic            run_q;       // inside the window
  logic            busy_q;      // a camera or flat pass is issuing: slot_q is its next slot
  logic            camera_q;    // ... a camera ray's
  logic [IW-1:0]   slot_q, slot_p1_q;
  logic [AW:0]     count_q;     // its camera list's length (from its second slot on)
  logic            counted_q;
  logic [AW-1:0]   pfrom_q;     // a flat pass's ray: the sphere it leaves, and whether it went in
  logic            pleaves_q, pinto_q;
  logic [4:0]      tile_q;
  // The camera's next sample: its pixel's list entry, the sample, and the list's position after it.
  logic [TakerW-1:0] ct_q;
  logic [SlotW:0]    cpos_q;
  logic [4:0]        csample_q;
  logic              cleft_q;    // camera samples are left
  logic              walker_ready;

  wire [TakerW-1:0] cam = start ? takers_first_q[rbank] : ct_q;
  wire              cam_left = start ? takers_n_q[rbank] != '0 : cleft_q;
  wire [SlotW:0]    cam_pos = start ? (SlotW + 1)'(1) : cpos_q;
  wire [4:0]        cam_sample = start ? 5'd0 : csample_q;
  wire [SlotW-1:0]  cam_k = cam[TakerW-1-:SlotW];
  wire [9:0]        cam_col = cam[9:0];
  wire take = (run_q || start) && !busy_q && walker_ready && !flush;
  wire take_b = take && !start && !b_empty && (l_empty || b_stamp <= l_stamp);
  wire take_l = take && !start && !l_empty && !take_b;
  wire take_cam = take && !take_b && !take_l && cam_left && !full_q;
  wire take_walk = take_b && walks;
  wire take_flat = take_b && !walks;
  assign b_pop = take_b;
  assign l_pop = take_l;
  assign path_take = take_cam;
  // A new ray's place: a camera ray's new path number, a bounced ray's path's.
  wire [IdW-1:0] b_path = b_front.tag[TagW-1-:IdW];
  wire last_sample = cam_sample == spp - 5'd1;

  // A camera or flat pass's last slot (its first is never its last: MinPass > 1), from the issuing pass's registers.
  wire [AW:0] pass_count = camera_q ? (counted_q ? count_q : tile_count) : spheres;
  wire        last = busy_q && slot_q >= IW'(MinPass - 1) && slot_p1_q >= IW'(pass_count);
  wire [IW-1:0] slot = busy_q ? slot_q : '0;

  assign tile     = busy_q ? tile_q : 5'(cam_col >> TileShift);
  assign tile_pos = slot[AW-1:0];

  logic [IdW-1:0] pass_id_q;  // the pass issuing (its slots at stage 1)

  // The unit holds IDS paths when no path number is free (none fresh, none given back): a camera ray waits for one
  // to end (its cut, or the bounce stage's word, gives its number back for the next cycle).
  wire full_q = pfresh_q[IdW] && pc_empty && pe_empty;
  always_ff @(posedge clk) begin
    if (rst || flush) begin
      run_q     <= 1'b0;
      busy_q    <= 1'b0;
      counted_q <= 1'b0;
      cleft_q   <= 1'b0;
    end else begin
      if (start) run_q <= 1'b1;
      busy_q    <= (busy_q || take_cam || take_flat) && !last;
      counted_q <= busy_q && camera_q;
      if (take_cam) cleft_q <= !last_sample || cam_pos < takers_n_q[rbank];
      else if (start) cleft_q <= cam_left;
    end
    if (busy_q && camera_q && !counted_q) count_q <= tile_count;
    if (take_cam || take_flat) begin
      camera_q <= take_cam;
      tile_q   <= tile;
      pfrom_q  <= b_front.from;
      pleaves_q <= take_flat;
      pinto_q  <= take_flat && b_front.into;
    end
    slot_q    <= slot + IW'(1);
    slot_p1_q <= slot + IW'(2);
    if (take_b) pass_id_q <= b_path;
    if (take_cam) pass_id_q <= path_new;
    if (take_l) pass_id_q <= l_front;
    // The camera's next sample: the same pixel's next, or the list's next pixel.
    if (start || take_cam) begin
      ct_q      <= take_cam && last_sample ? takers[{rbank, cam_pos[SlotW-1:0]}] : cam;
      cpos_q    <= take_cam && last_sample ? cam_pos + (SlotW + 1)'(1) : cam_pos;
      csample_q <= !take_cam ? cam_sample : last_sample ? 5'd0 : cam_sample + 5'd1;
    end
  end

  // ---- stage 1: the slot's sphere, and the ray by its number --------------------------------------------------------
  // A new ray's state (a camera sample's or a bounced ray's) is written in its pass's first slot.
  logic [RayW-1:0] rays_mem [IDS];  // ray_t's, flat (Yosys 0.23 reads no field of a memory's word)
  logic           new_q;        // the pass taken last cycle starts a ray (its first slot is at stage 1 now)
  logic           new_cam_q;
  ray_t           new_b_q;
  logic [IdW-1:0] new_path_q;
  logic [9:0]     new_col_q;
  logic [4:0]     new_sample_q;
  logic [3*DirW-1:0] dir1_q;
  always_ff @(posedge clk) begin
    new_q        <= !rst && !flush && (take_b || take_cam);
    new_cam_q    <= take_cam;
    new_b_q      <= b_front;
    new_path_q   <= path_new;
    new_col_q    <= cam_col;
    new_sample_q <= cam_sample;
    dir1_q       <= dirs[{rbank, cam_k}];
  end
  ray_t new_ray;
  always_comb begin
    new_ray = new_b_q;
    if (new_cam_q) begin
      new_ray.o      = '0;
      new_ray.d      = dir1_q;
      new_ray.leaves = 1'b0;
      new_ray.from   = '0;
      new_ray.into   = 1'b0;
      new_ray.rays   = 4'd1;
      new_ray.tag    = {new_path_q, new_col_q, new_sample_q};
    end
  end
  // The sphere a ray leaves, apart: a walk's next level reads it (the ray's other reads are the pass's, the hit's and
  // the turn's).
  logic [AW-1:0] from_mem [IDS];
  always_ff @(posedge clk) begin
    if (new_q) rays_mem[pass_id_q] <= new_ray;
    if (new_q) from_mem[pass_id_q] <= new_ray.from;
  end
  ray_t s1_ray;
  assign s1_ray = new_q ? new_ray : rays_mem[pass_id_q];

  // The slot at stage 1: a camera or flat pass's (issued last cycle), or the walker's.
  logic          s1_valid_q, s1_first_q, s1_end_q, s1_camera_q;
  logic [IW-1:0] s1_slot_q;
  logic          w_valid, w_first, w_end, w_pair, w_far, w_bound;
  logic [AW-1:0] w_index;
  always_ff @(posedge clk) begin
    if (rst || flush) s1_valid_q <= 1'b0;
    else s1_valid_q <= busy_q || take_cam || take_flat;
    s1_first_q  <= !busy_q;
    s1_end_q    <= last;
    s1_camera_q <= busy_q ? camera_q : take_cam;
    s1_slot_q   <= slot;
  end
  logic [AW:0] s1_count;
  assign s1_count = s1_first_q ? tile_count : count_q;
  wire [AW-1:0] flat_index = s1_slot_q[AW-1:0];
  wire flat_own = pleaves_q && pfrom_q == flat_index;  // the sphere the ray leaves
  wire s1_valid = s1_valid_q || w_valid;
  wire s1_first = s1_valid_q ? s1_first_q : w_first;
  wire s1_end   = s1_valid_q ? s1_end_q : w_end;
  wire s1_bound = !s1_valid_q && w_valid && w_bound;
  wire s1_far   = s1_valid_q ? !s1_camera_q && flat_own && pinto_q : w_valid && w_far;
  wire [AW-1:0] s1_index = s1_valid_q ? (s1_camera_q ? tile_sphere : flat_index) : w_index;
  wire s1_pair  = s1_valid_q ? (s1_camera_q ? (AW + 1)'(s1_slot_q) < s1_count
                                            : (AW + 1)'(s1_slot_q) < spheres && (!flat_own || pinto_q))
                             : w_valid && w_pair;
  assign mem_addr  = s1_index;
  assign mem_bound = s1_bound;

  // ---- stage 2: the sphere unit ---------------------------------------------------------------------------------------
  logic          s2_valid_q, s2_first_q, s2_pair_q, s2_end_q, s2_far_q, s2_bound_q;
  logic [AW-1:0] s2_index_q;
  logic [3*OriginW-1:0] s2_o_q;
  logic [3*DirW-1:0]    s2_d_q;
  always_ff @(posedge clk) begin
    if (rst || flush) s2_valid_q <= 1'b0;
    else s2_valid_q <= s1_valid;
    s2_first_q <= s1_first;
    s2_pair_q  <= s1_pair;
    s2_end_q   <= s1_end;
    s2_far_q   <= s1_far;
    s2_bound_q <= s1_bound;
    s2_index_q <= s1_index;
    s2_o_q     <= s1_ray.o;
    s2_d_q     <= s1_ray.d;
  end

  // The pass's path number (and whether it is a walk's) waits for its hit.
  logic           flight_empty, flight_overflow, flight_walk;
  logic [IdW-1:0] flight_id;
  logic           hit_valid;
  ts_artix_fifo #(.W(IdW + 1), .DEPTH(16)) in_flight (
      .clk, .rst, .clear(flush), .push(s1_valid && s1_first), .push_data({pass_id_q, !s1_valid_q}),
      .pop(hit_valid), .front({flight_id, flight_walk}), .empty(flight_empty), .overflow(flight_overflow)
  );

  // The sphere unit's hit as the bounce stage reads it: b d's fraction and each f_k's low HitFW bits (the rest of
  // a hit's is sign).
  hit_t          unit_hit;
  logic          entered_valid, entered;
  /* verilator lint_off UNUSEDSIGNAL */  // b d's integer part, and f_k's sign beyond a hit's HitFW bits
  logic [BdW-1:0]  unit_bd;
  logic [3*FW-1:0] unit_f;
  /* verilator lint_on UNUSEDSIGNAL */
  for (genvar k = 0; k < 3; k++) begin : g_f
    assign unit_hit.f[k*HitFW+:HitFW] = unit_f[k*FW+:HitFW];
  end
  assign unit_hit.beta = unit_bd[BetaW-1:0];
  ts_artix_sphere_unit #(.CARRY_W(AW), .PATH(1)) unit (
      .clk, .rst(rst || flush),
      .in_first(s2_valid_q && s2_first_q), .in_pair(s2_valid_q && s2_pair_q), .in_end(s2_valid_q && s2_end_q),
      .in_o(s2_o_q), .in_d(s2_d_q), .in_c(mem_c), .in_e(mem_e), .in_r2s(mem_r2s), .in_carry(s2_index_q),
      .in_far(s2_valid_q && s2_far_q), .in_bound(s2_valid_q && s2_bound_q), .in_index(s2_index_q),
      .out_valid(hit_valid), .out_hit(unit_hit.hit), .out_td(unit_hit.td), .out_bd(unit_bd),
      .out_f(unit_f), .out_s(unit_hit.s), .out_e(unit_hit.e), .out_carry(unit_hit.index),
      .out_far(unit_hit.far_side), .out_entered_valid(entered_valid), .out_entered(entered)
  );

  // ---- the walker ---------------------------------------------------------------------------------------------------
  wire [AW-1:0] level_from = from_mem[l_front];
  logic           walker_overflow, result_more;
  /* verilator lint_off UNUSEDSIGNAL */  // the walker's id of each result: the passes in flight give it too
  logic [IdW-1:0] result_id;
  /* verilator lint_on UNUSEDSIGNAL */
  ts_path_walk #(.IDS(IDS)) walker (
      .clk, .rst(rst || flush),
      .root_first_sphere, .root_spheres, .root_first_child, .root_children,
      .node_addr, .node_first_sphere, .node_spheres, .node_first_child, .node_children,
      .start(take_walk || take_l), .start_root(take_walk), .start_id(take_l ? l_front : b_path),
      .start_from(take_l ? level_from : b_front.from), .start_into(b_front.into), .ready(walker_ready),
      .slot_valid(w_valid), .slot_first(w_first), .slot_end(w_end), .slot_pair(w_pair), .slot_far(w_far),
      .slot_bound(w_bound), .slot_index(w_index),
      .entered_valid, .entered, .result_valid(hit_valid && flight_walk), .result_id, .result_more,
      .overflow(walker_overflow)
  );

  // ---- a pass's hit: merged with the ray's best; the next level, the cut, or the bounce stage ----------------------
  logic [HitW-1:0] best_mem [IDS];  // hit_t's, flat
  logic [IDS-1:0] best_valid_q;  // the ray's best holds a pass's hit (a walk's earlier level)
  hit_t best;
  assign best = best_mem[flight_id];
  wire keep_best = best_valid_q[flight_id] && best.hit
                   && (!unit_hit.hit || $signed(best.td) < $signed(unit_hit.td)
                       || (best.td == unit_hit.td && best.index < unit_hit.index));
  hit_t merged;
  assign merged = keep_best ? best : unit_hit;
  wire more = hit_valid && flight_walk && result_more;
  wire done = hit_valid && !more;
  ray_t done_ray;
  assign done_ray = rays_mem[flight_id];
  // Whether the merged hit is a hit needs no comparison: the best so far, if a hit, loses only to a closer hit.
  // (Written so, the cut is not behind t d's compare: it feeds the queues' counts.)
  wire merged_hit = (best_valid_q[flight_id] && best.hit) || unit_hit.hit;
  assign cut = done && merged_hit && done_ray.rays == depth;
  wire to_stage = done && !cut;
  always_ff @(posedge clk) begin
    if (more || to_stage) best_mem[flight_id] <= merged;  // a stage-bound hit waits there for the turn
    for (int i = 0; i < IDS; i++) begin
      if (more && flight_id == IdW'(i)) best_valid_q[i] <= 1'b1;
      else if (new_q && pass_id_q == IdW'(i) && !(more && flight_id == IdW'(i))) best_valid_q[i] <= 1'b0;
    end
    if (rst) best_valid_q <= '0;
  end
  assign l_push    = more;
  assign l_push_id = flight_id;
  assign cut_valid = cut;
  assign cut_tag   = done_ray.tag;
  assign cut_path  = done_ray.tag[TagW-1-:IdW];

  // Hits waiting for the unit's turn, as their paths' numbers: the one arriving in a turn with none waiting goes
  // straight on.
  logic           st_empty, st_overflow;
  logic [IdW-1:0] st_path;
  wire            st_pop = turn && !st_empty;
  ts_artix_fifo #(.W(IdW), .DEPTH(IDS)) waiting (
      .clk, .rst, .clear(flush), .push(to_stage && !(turn && st_empty)), .push_data(flight_id),
      .pop(st_pop), .front(st_path), .empty(st_empty), .overflow(st_overflow)
  );
  ray_t out_ray;
  assign out_ray = st_empty ? done_ray : rays_mem[st_path];
  hit_t out_hit;
  assign out_hit = st_empty ? merged : best_mem[st_path];
  // The turn's register: what the unit hands on in its turn is on the stage port in the next cycle, where the
  // stage takes it. Every bit of it is 0 in the other cycles (a synchronous reset, the flip-flops' own), so that the
  // core merges the units' ports with an OR instead of choosing one.
  wire gives = run_q && turn && (!st_empty || to_stage);
  always_ff @(posedge clk) begin
    if (rst || flush || !gives) begin
      stage_valid <= 1'b0;
      {stage_o, stage_d, stage_rays, stage_tag, stage_hit, stage_index, stage_far, stage_td, stage_beta, stage_f,
       stage_s, stage_e} <= '0;
    end else begin
      stage_valid <= 1'b1;
      stage_o     <= out_ray.o;
      stage_d     <= out_ray.d;
      stage_rays  <= out_ray.rays;
      stage_tag   <= out_ray.tag;
      stage_hit   <= out_hit.hit;
      stage_index <= out_hit.index;
      stage_far   <= out_hit.far_side;
      stage_td    <= out_hit.td;
      stage_beta  <= out_hit.beta;
      stage_f     <= out_hit.f;
      stage_s     <= out_hit.s;
      stage_e     <= out_hit.e;
    end
  end

  always_ff @(posedge clk) begin
    if (rst) overflow <= 1'b0;
    else if (b_overflow || l_overflow || pc_overflow || pe_overflow
             || flight_overflow || walker_overflow
             || st_overflow || (hit_valid && flight_empty) || (hit_valid && flight_walk && result_id != flight_id))
      overflow <= 1'b1;
  end

  // Not needed: a stage-bound ray's `leaves`, `from` and `into` (the hit's sphere is the next ray's), a new ray's
  // rays count (a camera ray's is 1), the stage's own copy of the ray's `leaves`.
  /* verilator lint_off UNUSEDSIGNAL */
  logic unused;
  assign unused = out_ray.leaves ^ ^out_ray.from ^ out_ray.into ^ b_front.leaves ^ ^b_front.rays ^ ^b_front.o
                  ^ ^b_front.d ^ ^b_front.tag[TagW-IdW-1:0] ^ s1_ray.leaves ^ ^s1_ray.from ^ s1_ray.into
                  ^ ^s1_ray.rays ^ ^s1_ray.tag;
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
