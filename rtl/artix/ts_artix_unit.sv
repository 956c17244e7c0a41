// ts_artix_unit: one of the artix preset's sphere units with everything that feeds it: the issue port that chooses
// the next pass, the pass's slots through the tile list and scene memory, the sphere unit (ts_artix_sphere_unit),
// the shading and reflection block (ts_artix_shade_reflect) and the queue of reflected rays. Unit U (the `unit_id`
// input, a constant) of N traces the columns U, U + N, U + 2N, ... of each line; its pixel k is column U + k N, and
// its colours go to bank U of the line buffers (ts_line_buffers), slot k.
//
// C++ model: artix::unit_finish_cycles (src/tripsitter/device/artix_units.cpp) for the schedule and
// artix::trace_pixel_with for the colours; docs/device.md, "The artix preset", and docs/rtl.md. Cycle c below is
// counted from the line window's first cycle (`start`), the model's cycle 0.
//
// The issue port. When the port is free in cycle c (no pass is issuing), it takes the oldest reflected ray that is
// waiting, else the next camera ray, else nothing. A reflected ray enters the queue in the cycle its hit is
// known plus ReflectLatency, the model's `known`, and may be taken in that very cycle (the queue's front is
// bypassed by the ray arriving). A pass that tests n spheres issues max(n, MinPass) slots, one a cycle, and the
// port is free again in the cycle after the last: a camera ray tests its tile's list (ts_artix_tiles: slot i
// reads the list's entry i, and the count comes back with entry 0, so a pass's length is known from its second
// slot on, and a pass is never shorter than three), a reflected ray every sphere of the world but the one it
// leaves (slot i reads sphere i; the left sphere's slot carries no pair).
//
// A slot's way: cycle c the port issues it (the tile list read, or nothing); c + 1 its sphere index is known and
// scene memory is read; c + 2 the sphere's fields and the slot's flags reach the sphere unit (SceneReadCycles).
// The pass's closest hit comes out HitLatency cycles after the cycle following its last slot (ts_artix_sphere_unit),
// where the pass's record (its pixel, ray, reflections so far and tint) leaves the in-flight queue, in order, and
// goes with the hit to the shading and reflection block: a reflected ray comes back ReflectLatency cycles later
// into the queue, a colour ShadeLatency - 1 cycles later to the line buffer (there at ShadeLatency, the model's
// finish). So every pass issues, and every colour lands, in the model's cycle.
//
// Queues. Passes in flight: each holds the port at least MinPass cycles and is in flight at most
// 2 + HitLatency + 1 cycles after its last slot, so at most 15 at once. Reflected rays: a camera pass starts only
// when no reflected ray waits, and a waiting ray becomes a pass when it leaves, so the waiting and in-flight
// reflections together never exceed the passes in flight when the last camera pass started, plus that one:
// with those in flight before their reflection arrives (ReflectLatency more), at most 22. Both queues have 32
// entries; `overflow` (sticky) would say otherwise.
//
// The window. `start` is the window's first cycle: the unit takes its first pass in it, with the directions
// written for this row (two banks: `dir_we` writes the next row's while this one is read). `flush` is the
// window's last cycle: a colour due in it is still written, everything else in flight is dropped after it.
//
// The clock. Everything here but the direction banks' write port runs on a gated clock (ts_clock_gate, a
// BUFGCE): it has an edge in the cycles of `start`, `flush` and reset, and while the unit has work, that is while a
// pass issues or its camera rays are not all taken, a slot is at stage 1 or 2, a pass is in flight (its record is
// queued from its first slot to its hit, so the sphere unit holds no slot of any other), a reflected ray waits,
// or the shading block is busy. In any other cycle no register of the unit would change but to a value nothing reads
// before the next of those events: the unit's outputs and schedule are the same, and an idle unit costs neither
// power nor simulation time (docs/rtl.md, "The artix device").
module ts_artix_unit #(
    parameter int N = 12,  // units
    localparam int Slots = (ts_artix_pkg::LineWidth + N - 1) / N,  // the busiest unit's pixels a line
    localparam int SlotW = $clog2(Slots),
    localparam int SphereAW = ts_artix_pkg::SphereAW,
    localparam int DirW = ts_artix_pkg::DirW,
    localparam int CoordW = ts_artix_pkg::CoordW
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic [9:0]             unit_id,      // U: a constant (a port, so that all units are one module)
    input  logic                   start,
    input  logic                   flush,
    input  logic [SphereAW:0]      spheres,      // the world shown: 0 .. MaxSpheres
    // The next row's directions (ts_artix_camera), pixel k's in slot k.
    input  logic                   dir_we,
    input  logic [SlotW-1:0]       dir_slot,
    input  logic [3*DirW-1:0]      dir_d,
    // The tile lists of this row (ts_artix_tiles, one read port): a registered read.
    output logic [4:0]             tile,
    output logic [SphereAW-1:0]    tile_pos,
    input  logic [SphereAW:0]      tile_count,
    input  logic [SphereAW-1:0]    tile_sphere,
    // Scene memory (one read port): a registered read of the sphere and its per-world constants.
    output logic [SphereAW-1:0]    sphere_addr,
    input  logic [3*CoordW-1:0]    sphere_c,
    input  logic [ts_artix_pkg::RadiusW-1:0] sphere_r,
    input  logic [ts_artix_pkg::ExpW-1:0]    sphere_e,
    input  logic [ts_artix_pkg::R2sW-1:0]    sphere_r2s,
    input  logic [ts_artix_pkg::RinvW-1:0]   sphere_rinv,
    input  logic                   sphere_metal,
    input  logic [23:0]            sphere_albedo,
    // Bank U of the line buffers.
    output logic                   px_we,
    output logic [SlotW-1:0]       px_slot,
    output logic [11:0]            px_colour,
    output logic                   overflow
);
  localparam int OriginW = ts_artix_pkg::OriginW;
  localparam int RadiusW = ts_artix_pkg::RadiusW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int RinvW = ts_artix_pkg::RinvW;
  localparam int MinPass = ts_artix_pkg::MinPass;
  localparam int TileShift = $clog2(ts_artix_pkg::TileColumns);
  localparam int IW = SphereAW + 1;            // a slot's index in its pass: 0 .. MaxSpheres - 1 (+1 spare)
  localparam int TintW = 24;                   // a product of up to three albedo bytes
  localparam int RayW = 3 * OriginW + 3 * DirW;
  // A pixel's state between passes: its slot, its ray, the sphere the ray leaves, reflections so far, tint.
  localparam int StateW = SlotW + RayW + SphereAW + 1 + 2 + 3 * TintW;
  localparam int CarryW = SphereAW + RadiusW + RinvW + 1 + 24;  // the hit sphere's index and shading fields

  if (MinPass < 2) begin : g_bad_min_pass
    $error("ts_artix_unit: a pass's first slot must not be its last (MinPass >= 2)");
  end
  if ((1 << TileShift) != ts_artix_pkg::TileColumns) begin : g_bad_tiles
    $error("ts_artix_unit: tiles must be a power of two columns wide");
  end

  // ---- the pixel state --------------------------------------------------------------------------------------
  typedef struct packed {
    logic [SlotW-1:0]      k;
    logic [3*OriginW-1:0]  o;
    logic [3*DirW-1:0]     d;
    logic                  leaves;   // the ray leaves sphere `left` (a reflected ray)
    logic [SphereAW-1:0]   left;
    logic [1:0]            bounces;
    logic [3*TintW-1:0]    tint;
  } state_t;

  // ---- the clock (see The clock) ------------------------------------------------------------------------------
  logic gclk, work, shade_busy;
  ts_clock_gate gate (.clk, .en(rst || start || flush || work), .gclk);

  // ---- the queue of reflected rays --------------------------------------------------------------------------
  logic   refl_valid;  // from the shading and reflection block: a reflected ray, known in this cycle
  state_t refl_state;
  logic   queue_empty, queue_pop, queue_overflow;
  state_t queue_front;
  logic   waiting;     // a reflected ray may be taken this cycle
  state_t waiting_state;
  ts_artix_fifo #(.W(StateW), .DEPTH(32)) queue (
      .clk(gclk), .rst, .clear(flush),
      .push(refl_valid && !(queue_empty && queue_pop)), .push_data(refl_state),
      .pop(queue_pop && !queue_empty), .front(queue_front), .empty(queue_empty), .overflow(queue_overflow)
  );
  assign waiting       = !queue_empty || refl_valid;
  assign waiting_state = queue_empty ? refl_state : queue_front;

  // ---- the issue port ---------------------------------------------------------------------------------------
  logic              run_q;       // inside the window
  logic              busy_q;      // a pass is issuing: slot_q is its next slot
  logic [IW-1:0]     slot_q;
  logic [IW-1:0]     slot_p1_q;   // slot_q + 1
  logic              camera_q;    // the issuing pass is a camera ray's
  logic [SphereAW:0] count_q;     // its camera list's length (from its second slot on)
  logic              counted_q;   // count_q holds the issuing pass's
  logic [SlotW-1:0]  next_k_q;    // the next camera pixel (past the last: the column says it)
  logic [9:0]        next_col_q;  // its column, U + k N
  logic [4:0]        tile_q;      // the issuing camera pass's tile
  logic              dir_bank_q;  // the direction bank of this row

  logic              take, take_reflected, take_camera, last;
  logic              rays_left;   // camera pixels not yet taken (the counters' column is still in the line)
  logic [IW-1:0]     slot;
  logic              camera;
  logic [SphereAW:0] pass_count;
  logic              dir_bank;

  // The camera pixel a pass takes in the window's first cycle is pixel 0.
  logic [SlotW-1:0] camera_k;
  assign camera_k = start ? '0 : next_k_q;

  assign dir_bank       = start ? !dir_bank_q : dir_bank_q;
  assign take           = (run_q || start) && !busy_q && !flush;
  assign take_reflected = take && waiting && !start;
  assign rays_left      = next_col_q < 10'(ts_artix_pkg::LineWidth);
  assign take_camera    = take && !take_reflected && (start || rays_left);
  assign queue_pop      = take_reflected;
  assign slot           = busy_q ? slot_q : '0;
  assign camera         = busy_q ? camera_q : take_camera;
  // A camera pass's length counts its tile list, known from the pass's second slot (the count arrives with entry
  // 0); both kinds take at least MinPass slots, so neither ends before its third.
  // A pass's first slot is never its last (MinPass > 1), so `last` looks only at the issuing pass's registers:
  // slot i is the last when i >= MinPass - 1 and i + 1 >= n (the slots count up from 0 one a cycle, so the first i
  // that satisfies both is max(n, MinPass) - 1).
  assign pass_count = camera_q ? (counted_q ? count_q : tile_count) : spheres;
  assign last       = busy_q && slot_q >= IW'(MinPass - 1) && slot_p1_q >= IW'(pass_count);

  assign tile     = busy_q ? tile_q : 5'((start ? unit_id : next_col_q) >> TileShift);
  assign tile_pos = slot[SphereAW-1:0];

  always_ff @(posedge gclk) begin
    if (rst || flush) begin
      run_q     <= 1'b0;
      busy_q    <= 1'b0;
      counted_q <= 1'b0;
    end else begin
      if (start) run_q <= 1'b1;
      busy_q    <= (busy_q || take_reflected || take_camera) && !last;
      // The count arrives in the cycle after a camera pass's first slot.
      counted_q <= busy_q && camera_q;
    end
    if (rst || start) dir_bank_q <= rst ? 1'b0 : !dir_bank_q;
    // The window's first cycle takes pixel 0 (the counters still hold the last window's end).
    if (take_camera) begin
      next_k_q   <= camera_k + 1'b1;
      next_col_q <= (start ? unit_id : next_col_q) + 10'(N);
    end
    if (take_reflected || take_camera) begin
      camera_q <= take_camera;
      tile_q   <= tile;
    end
    slot_q    <= slot + 1'b1;
    slot_p1_q <= slot + IW'(2);
    if (busy_q && camera_q && !counted_q) count_q <= tile_count;
  end


  // ---- directions: two banks of the unit's pixels ------------------------------------------------------------
  logic [3*DirW-1:0] dirs [2 * (1 << SlotW)];
  logic [3*DirW-1:0] dir1_q;
  // The write port runs on the device's clock: the camera writes whether or not the unit is busy.
  always_ff @(posedge clk) if (dir_we) dirs[{!dir_bank, dir_slot}] <= dir_d;
  always_ff @(posedge gclk) dir1_q <= dirs[{dir_bank, camera_k}];

  // ---- stage 1: the slot's sphere ---------------------------------------------------------------------------
  logic            s1_valid_q, s1_first_q, s1_end_q, s1_camera_q;
  logic [IW-1:0]   s1_slot_q;
  state_t          s1_taken_q;   // a reflected pass's state, taken in its first slot
  logic [SlotW-1:0] s1_k_q;      // a camera pass's pixel
  state_t          pass_q;       // the pass issuing at stage 1
  state_t          s1_pass;
  logic            s1_pair;
  logic [SphereAW-1:0] s1_sphere;

  always_ff @(posedge gclk) begin
    if (rst || flush) s1_valid_q <= 1'b0;
    else s1_valid_q <= busy_q || take_reflected || take_camera;
    s1_first_q  <= !busy_q;
    s1_end_q    <= last;
    s1_camera_q <= camera;
    s1_slot_q   <= slot;
    s1_taken_q  <= waiting_state;
    s1_k_q      <= camera_k;
  end

  // A camera ray: from the origin along its pixel's direction; nothing reflected yet, tint 1.
  always_comb begin
    s1_pass = pass_q;
    if (s1_first_q) begin
      if (s1_camera_q) begin
        s1_pass.k       = s1_k_q;
        s1_pass.o       = '0;
        s1_pass.d       = dir1_q;
        s1_pass.leaves  = 1'b0;
        s1_pass.left    = '0;
        s1_pass.bounces = 2'd0;
        s1_pass.tint    = {3{TintW'(1)}};
      end else begin
        s1_pass = s1_taken_q;
      end
    end
  end
  always_ff @(posedge gclk) if (s1_valid_q) pass_q <= s1_pass;

  // The slot's sphere and whether it is a pair: a camera slot i tests entry i of its list while i < count (the
  // count is the port's output for the pass's first slot, count_q after); a reflected slot i sphere i, unless the
  // ray leaves it.
  logic [SphereAW:0] s1_count;
  assign s1_count  = s1_first_q ? tile_count : count_q;
  assign s1_sphere = s1_camera_q ? tile_sphere : s1_slot_q[SphereAW-1:0];
  assign s1_pair   = s1_camera_q ? (SphereAW + 1)'(s1_slot_q) < s1_count
                                 : (SphereAW + 1)'(s1_slot_q) < spheres && !(s1_pass.leaves && s1_pass.left == s1_sphere);
  assign sphere_addr = s1_sphere;

  // ---- stage 2: the sphere unit -----------------------------------------------------------------------------
  logic            s2_valid_q, s2_first_q, s2_pair_q, s2_end_q;
  logic [SphereAW-1:0] s2_sphere_q;
  logic [3*ts_artix_pkg::OriginW-1:0] s2_o_q;
  logic [3*DirW-1:0]   s2_d_q;
  always_ff @(posedge gclk) begin
    if (rst || flush) s2_valid_q <= 1'b0;
    else s2_valid_q <= s1_valid_q;
    s2_first_q  <= s1_first_q;
    s2_pair_q   <= s1_pair;
    s2_end_q    <= s1_end_q;
    s2_sphere_q <= s1_sphere;
    s2_o_q      <= s1_pass.o;
    s2_d_q      <= s1_pass.d;
  end

  // The pass's record waits for its hit.
  logic   flight_empty, flight_overflow;
  state_t flight_front;
  logic   hit_valid;

  ts_artix_fifo #(.W(StateW), .DEPTH(32)) in_flight (
      .clk(gclk), .rst, .clear(flush),
      .push(s1_valid_q && s1_first_q), .push_data(s1_pass),
      .pop(hit_valid), .front(flight_front), .empty(flight_empty), .overflow(flight_overflow)
  );

  logic                                hit;
  logic [ts_artix_pkg::TdW-1:0]        hit_td;
  logic [ts_artix_pkg::BdW-1:0]        hit_bd;
  logic [3*ts_artix_pkg::FW-1:0]       hit_f;
  logic [ts_artix_pkg::SqrtW-1:0]      hit_s;
  logic [ExpW-1:0]                     hit_e;
  logic [CarryW-1:0]                   hit_carry;
  /* verilator lint_off UNUSEDSIGNAL */  // the path preset's outputs, 0 in the artix preset's unit
  logic unused_far, unused_entered_valid, unused_entered;
  /* verilator lint_on UNUSEDSIGNAL */
  ts_artix_sphere_unit #(.CARRY_W(CarryW)) unit (
      .clk(gclk), .rst(rst || flush),
      .in_first(s2_valid_q && s2_first_q), .in_pair(s2_valid_q && s2_pair_q), .in_end(s2_valid_q && s2_end_q),
      .in_o(s2_o_q), .in_d(s2_d_q),
      .in_c(sphere_c), .in_e(sphere_e), .in_r2s(sphere_r2s),
      .in_carry({s2_sphere_q, sphere_r, sphere_rinv, sphere_metal, sphere_albedo}),
      .in_far(1'b0), .in_bound(1'b0), .in_index('0),
      .out_valid(hit_valid), .out_hit(hit), .out_td(hit_td), .out_bd(hit_bd), .out_f(hit_f), .out_s(hit_s),
      .out_e(hit_e), .out_carry(hit_carry),
      .out_far(unused_far), .out_entered_valid(unused_entered_valid), .out_entered(unused_entered)
  );

  // ---- shading and reflection -------------------------------------------------------------------------------
  logic [SphereAW-1:0] hit_index;
  logic [RadiusW-1:0]  hit_r;
  logic [RinvW-1:0]    hit_rinv;
  logic                hit_metal;
  logic [23:0]         hit_albedo;
  assign {hit_index, hit_r, hit_rinv, hit_metal, hit_albedo} = hit_carry;

  localparam int TagW = SlotW + SphereAW;  // the pixel, and the sphere its reflected ray leaves
  logic                 colour_valid;
  logic [11:0]          colour;
  logic [TagW-1:0]      colour_tag, refl_tag;
  logic [3*OriginW-1:0] refl_o;
  logic [3*DirW-1:0]    refl_d;
  logic [1:0]           refl_bounces;
  logic [3*TintW-1:0]   refl_tint;
  ts_artix_shade_reflect #(.TAG_W(TagW)) shade (
      .clk(gclk), .rst(rst || flush),
      .in_valid(hit_valid), .in_o(flight_front.o), .in_d(flight_front.d),
      .in_hit(hit), .in_bd(hit_bd), .in_f(hit_f), .in_s(hit_s), .in_td(hit_td),
      .in_e(hit_e), .in_r(hit_r), .in_rinv(hit_rinv), .in_metal(hit_metal),
      // Scene memory keeps the wire's order, red in the high byte; the block takes red in the low one.
      .in_albedo({hit_albedo[7:0], hit_albedo[15:8], hit_albedo[23:16]}),
      .in_bounces(flight_front.bounces), .in_tint(flight_front.tint), .in_tag({flight_front.k, hit_index}),
      .out_ray_valid(refl_valid), .out_ray_o(refl_o), .out_ray_d(refl_d), .out_ray_bounces(refl_bounces),
      .out_ray_tint(refl_tint), .out_ray_tag(refl_tag),
      .out_colour_valid(colour_valid), .out_colour(colour), .out_colour_tag(colour_tag), .busy(shade_busy)
  );
  always_comb begin
    refl_state.k       = refl_tag[TagW-1-:SlotW];
    refl_state.o       = refl_o;
    refl_state.d       = refl_d;
    refl_state.leaves  = 1'b1;
    refl_state.left    = refl_tag[SphereAW-1:0];
    refl_state.bounces = refl_bounces;
    refl_state.tint    = refl_tint;
  end

  assign work = busy_q || (run_q && rays_left) || s1_valid_q || s2_valid_q || !flight_empty || !queue_empty
                || shade_busy;

  assign px_we     = colour_valid;
  assign px_slot   = colour_tag[TagW-1-:SlotW];
  assign px_colour = colour;
  assign overflow  = queue_overflow || flight_overflow;

  // Not needed: the colour's sphere index (the tag's low bits are the reflection's); the sphere a pass's ray left
  // (the hit's sphere is the next).
  /* verilator lint_off UNUSEDSIGNAL */
  logic unused;
  assign unused = ^colour_tag[SphereAW-1:0] ^ flight_front.leaves ^ ^flight_front.left;
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
