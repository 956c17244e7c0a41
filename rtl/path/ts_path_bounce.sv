// ts_path_bounce: the bounce stage the artix path preset's units share: a path's ray at its closest hit (or its miss)
// in, its next ray or its end out, Latency cycles later, a ray a cycle. C++ model: artix::bounce_stage
// (src/tripsitter/device/artix_path.h), which trace_path_sample takes at every ray but a cut one; docs/device.md,
// "Path tracing on the artix datapath", and docs/rtl.md, "Path tracing blocks".
//
// It holds each path's state between its rays: the sample's random stream and its throughput, in a table of
// 2^(UW + IdW) words, path `path` of unit `unit` at {unit, path} (block RAM: written when a next ray goes out, read
// when the path's next hit comes in, which is a whole pass of its unit later). A path's first ray (rays = 1) has no
// word yet: its stream is seeded from (pixel, sample index) (ts_path_rng's hash; pixel = row x 640 + col, sample
// index = sample_base + sample, sample_base = frame x spp) and its throughput is 1.0 (65536 a channel).
//
// The way (cycle j of a ray: its hit on the ports in cycle 0):
//   0      the ports; the hit sphere's surface asked for (`surf_addr`)
//   1      the entry register; the path's word asked for; the seed's key
//   2      the surface on `surf_*` (SurfaceRead = 2: a registered read and its output register); the hit block
//          (ts_path_hit: the hit point, the outward normal, the normal and the direction at 2^14)
//   5      the path's stream and throughput: the seed's, or the table's word
//   10     the scatter unit (ts_path_scatter, with the stream's next draw) and the light book-keeping
//          (ts_path_light, with the surface's albedo and the direction's up component)
//   12     the throughput times the albedo, and the sky's light times the throughput
//   33     the scattered direction, and whether it is too short to normalise (v.v < 64); the normalisation
//          (ts_path_normalise)
//   48     the unit direction
//   49     out (Latency): a next ray (`ray_valid`: the hit point, the scattered direction or, straight on, the
//          ray's own, the sphere it leaves, whether it went in, the rays with it) and the path's word written; or
//          the path's end (`end_valid`: the sky's light for a miss, 0 for a path absorbed)
// What a ray carries meanwhile waits in delay rings (ts_artix_delay) beside the blocks. `flush`, the line window's
// last cycle (the units' flush), drops every ray in the stage: nothing comes out after it for a ray of that line.
module ts_path_bounce #(
    parameter int N = 9,                      // units sharing the stage
    parameter int IDS = ts_artix_pkg::Paths,  // paths a unit holds, a power of two
    localparam int UW = N > 1 ? $clog2(N) : 1,
    localparam int IdW = $clog2(IDS),
    localparam int AW = ts_artix_pkg::SphereAW,
    localparam int OriginW = ts_artix_pkg::OriginW,
    localparam int DirW = ts_artix_pkg::DirW
) (
    input  logic                 clk,
    input  logic                 rst,
    input  logic                 flush,     // the line window's last cycle: every ray in the stage is dropped
    // The line's row and the frame's first sample index (frame x spp), steady while the line is traced.
    input  logic [8:0]           row,
    input  logic [31:0]          sample_base,
    // In: a unit's ray at its closest hit, or its miss (`in_hit` low), as ts_path_unit's stage port has it.
    input  logic                 in_valid,
    input  logic [UW-1:0]        in_unit,
    input  logic [IdW-1:0]       in_path,
    input  logic [9:0]           in_col,
    input  logic [4:0]           in_sample,
    input  logic [3:0]           in_rays,   // the path's rays with this one
    input  logic [3*OriginW-1:0] in_o,
    input  logic [3*DirW-1:0]    in_d,
    input  logic                 in_hit,
    input  logic [AW-1:0]        in_index,
    input  logic                 in_far,
    input  logic [ts_artix_pkg::TdW-1:0]   in_td,
    input  logic [ts_artix_pkg::DirFrac-1:0]   in_beta,  // b d's fraction (its low bits)
    input  logic [3*ts_artix_pkg::HitFW-1:0]   in_f,     // each f_k's low HitFW bits: a hit's fits them
    input  logic [ts_artix_pkg::SqrtW-1:0] in_s,
    input  logic [ts_artix_pkg::ExpW-1:0]  in_e,
    // The hit sphere's surface (PathSurface) and 1 / r: asked for in a hit's cycle 0, on the ports in its cycle 2.
    output logic [AW-1:0]        surf_addr,
    input  logic [1:0]           surf_material,
    input  logic [3*17-1:0]      surf_albedo,     // r, g, b from the low bits, times 2^16
    input  logic [15:0]          surf_fuzz,
    input  logic [17:0]          surf_eta_enter,
    input  logic [17:0]          surf_eta_leave,
    input  logic [14:0]          surf_r0,
    input  logic                 surf_straight,
    input  logic [ts_artix_pkg::RinvW-1:0] surf_rinv,
    // Out, Latency cycles after the ray came in: its path's next ray, or the path's end, with the path's names.
    output logic                 ray_valid,
    output logic                 end_valid,
    output logic [UW-1:0]        out_unit,
    output logic [IdW-1:0]       out_path,
    output logic [9:0]           out_col,
    output logic [4:0]           out_sample,
    output logic [3:0]           out_rays,  // ray_valid: the path's rays with the next one
    output logic [3*OriginW-1:0] out_o,
    output logic [3*DirW-1:0]    out_d,
    output logic [AW-1:0]        out_from,
    output logic                 out_into,
    output logic [3*18-1:0]      out_light  // end_valid: r, g, b from the low bits, times 2^16
);
  localparam int Latency = 49;
  localparam int HitAt = 2, StateAt = 5, ScatterAt = 10, LightAt = 12, NormaliseAt = 33, LastAt = Latency - 1;
  localparam int StateW = 32 + 3 * 17;  // a path's word: the stream, the throughput
  localparam logic [1:0] Straight = 2'd1, Absorbed = 2'd2;
  localparam logic [16:0] One = 17'd65536;

  // The schedule's count (DeviceUnits::reflect_latency of artix-path): the turn's register before the stage, its
  // Latency, and the cycle its next ray takes to be known in the unit's queue.
  if (ts_artix_pkg::BounceLatency != 1 + Latency + 1) begin : g_bad_latency
    $error("ts_path_bounce: the stage's Latency is not the schedule's BounceLatency less 2");
  end

  logic [LastAt-1:0] v_q;  // v_q[j - 1]: a ray is in cycle j
  always_ff @(posedge clk) begin
    if (rst || flush) v_q <= '0;
    else v_q <= {v_q[LastAt-2:0], in_valid};
  end

  assign surf_addr = in_index;

  // ---- 1: the entry register ------------------------------------------------------------------------------------
  localparam int NameW = UW + IdW + 10 + 5 + 4;  // unit, path, col, sample, rays
  localparam int BetaW = ts_artix_pkg::DirFrac;
  localparam int HitFW = ts_artix_pkg::HitFW;
  localparam int GeoW = 3 * OriginW + 3 * DirW + ts_artix_pkg::TdW + BetaW + 3 * HitFW +
                        ts_artix_pkg::SqrtW + ts_artix_pkg::ExpW + 1;
  logic [NameW-1:0] name1_q;
  logic             hit1_q;
  logic [AW-1:0]    index1_q;
  logic [GeoW-1:0]  geo1_q, geo2_q;
  always_ff @(posedge clk) begin
    name1_q  <= {in_unit, in_path, in_col, in_sample, in_rays};
    hit1_q   <= in_hit;
    index1_q <= in_index;
    geo1_q   <= {in_o, in_d, in_td, in_beta, in_f, in_s, in_e, in_far};
    geo2_q   <= geo1_q;
  end
  logic [UW-1:0]  unit1;
  logic [IdW-1:0] path1;
  logic [9:0]     col1;
  logic [4:0]     sample1;
  logic [3:0]     rays1;
  assign {unit1, path1, col1, sample1, rays1} = name1_q;
  logic [3*DirW-1:0] d1;
  assign d1 = geo1_q[GeoW-1-3*OriginW -: 3*DirW];

  // ---- the path's state: the table's word, or the seed --------------------------------------------------------
  logic [StateW-1:0] paths [2**(UW+IdW)];
  logic [StateW-1:0] word2_q, word3_q;
  logic              write;
  logic [UW+IdW-1:0] write_at;
  logic [StateW-1:0] write_word;
  always_ff @(posedge clk) begin
    if (write) paths[write_at] <= write_word;
    word2_q <= paths[{unit1, path1}];
    word3_q <= word2_q;
  end

  logic [31:0] seed;
  ts_path_rng #(
      .TAG_W(1)
  ) u_seed (
      .clk,
      .rst,
      .seed_valid    (v_q[0]),
      .seed_pixel    (19'({row, 9'd0}) + 19'({row, 7'd0}) + 19'(col1)),
      .seed_sample   (sample_base + {27'd0, sample1}),
      .seed_tag      (1'b0),
      /* verilator lint_off PINCONNECTEMPTY */  // the seeds come out at a fixed cycle; the stream is drawn here
      .seed_out_valid(),
      .seed_out_state(seed),
      .seed_out_tag  (),
      .draw          (1'b0),
      .value         ()
      /* verilator lint_on PINCONNECTEMPTY */
  );
  // The first ray's mark waits for the seed (cycle 1 to 5); the word's for the two cycles from 3.
  logic first5;
  logic [StateW-1:0] word5;
  ts_artix_delay #(.W(1), .N(StateAt - 1)) u_first (.clk, .in(rays1 == 4'd1), .out(first5));
  ts_artix_delay #(.W(StateW), .N(StateAt - 3)) u_word (.clk, .in(word3_q), .out(word5));
  logic [31:0]    stream5;
  logic [3*17-1:0] throughput5;
  assign stream5     = first5 ? seed : word5[StateW-1 -: 32];
  assign throughput5 = first5 ? {One, One, One} : word5[3*17-1:0];

  // The stream's next draw, for the scatter unit (it draws at most once a bounce).
  logic [31:0]     stream9, stream10_q, draw10_q;
  logic [3*17-1:0] throughput10;
  ts_artix_delay #(.W(32), .N(ScatterAt - 1 - StateAt)) u_stream (.clk, .in(stream5), .out(stream9));
  ts_artix_delay #(.W(3 * 17), .N(ScatterAt - StateAt)) u_throughput (.clk, .in(throughput5), .out(throughput10));
  always_ff @(posedge clk) begin
    stream10_q <= stream9;
    draw10_q   <= ts_path_pkg::xorshift32(stream9);
  end

  // ---- 2: the hit point and the normal --------------------------------------------------------------------------
  logic [3*OriginW-1:0] o2;
  logic [3*DirW-1:0]    d2;
  logic [ts_artix_pkg::TdW-1:0]   td2;
  logic [BetaW-1:0]               beta2;
  logic [3*HitFW-1:0]             f2;
  logic [ts_artix_pkg::SqrtW-1:0] s2;
  logic [ts_artix_pkg::ExpW-1:0]  e2;
  logic                           far2;
  assign {o2, d2, td2, beta2, f2, s2, e2, far2} = geo2_q;
  // The hit block's b d (it reads the fraction only) and f_k (sign-extended).
  localparam int FW = ts_artix_pkg::FW;
  logic [ts_artix_pkg::BdW-1:0] bd2;
  logic [3*FW-1:0]              fx2;
  assign bd2 = {(ts_artix_pkg::BdW - BetaW)'(0), beta2};
  for (genvar k = 0; k < 3; k++) begin : g_f
    assign fx2[k*FW+:FW] = {{(FW - HitFW){f2[k*HitFW+HitFW-1]}}, f2[k*HitFW+:HitFW]};
  end

  logic [3*OriginW-1:0] point10;
  logic [3*17-1:0]      normal14, dir14;
  logic                 far10;
  ts_path_hit #(
      .TAG_W(1)
  ) u_hit (
      .clk,
      .rst,
      .in_valid    (v_q[HitAt-1]),
      .in_o        (o2),
      .in_d        (d2),
      .in_td       (td2),
      .in_bd       (bd2),
      .in_f        (fx2),
      .in_s        (s2),
      .in_e        (e2),
      .in_rinv     (surf_rinv),
      .in_far      (far2),
      .in_tag      (far2),
      /* verilator lint_off PINCONNECTEMPTY */  // valid at a fixed cycle; the scatter unit takes the 2^14 normal
      .out_valid   (),
      .out_normal  (),
      /* verilator lint_on PINCONNECTEMPTY */
      .out_point   (point10),
      .out_normal14(normal14),
      .out_dir14   (dir14),
      .out_tag     (far10)
  );

  // The surface, from cycle 2 to the scatter unit and the light.
  localparam int SurfW = 2 + 3 * 17 + 16 + 18 + 18 + 15 + 1;
  logic [1:0]      material10;
  logic [3*17-1:0] albedo10;
  logic [15:0]     fuzz10;
  logic [17:0]     eta_enter10, eta_leave10;
  logic [14:0]     r010;
  logic            straight10;
  ts_artix_delay #(.W(SurfW), .N(ScatterAt - HitAt)) u_surface (
      .clk,
      .in ({surf_material, surf_albedo, surf_fuzz, surf_eta_enter, surf_eta_leave, surf_r0, surf_straight}),
      .out({material10, albedo10, fuzz10, eta_enter10, eta_leave10, r010, straight10})
  );
  logic hit10;
  ts_artix_delay #(.W(1), .N(ScatterAt - 1)) u_hit_mark (.clk, .in(hit1_q), .out(hit10));

  // ---- 10: the scatter unit and the light -------------------------------------------------------------------------
  logic [1:0]      bounce33;
  logic            into33, drew33;
  logic [3*24-1:0] next33;
  ts_path_scatter #(
      .TAG_W(1)
  ) u_scatter (
      .clk,
      .rst,
      .in_valid     (v_q[ScatterAt-1] && hit10),
      .in_material  (material10),
      .in_dir       (dir14),
      .in_normal    (normal14),
      .in_inside    (far10),
      .in_fuzz      (fuzz10),
      .in_eta_enter (eta_enter10),
      .in_eta_leave (eta_leave10),
      .in_r0        (r010),
      .in_straight  (straight10),
      .in_draw      (draw10_q),
      .in_tag       (1'b0),
      /* verilator lint_off PINCONNECTEMPTY */  // valid at a fixed cycle; refractions are the ledger's count only
      .out_valid    (),
      .out_refracted(),
      .out_tag      (),
      /* verilator lint_on PINCONNECTEMPTY */
      .out_bounce   (bounce33),
      .out_into     (into33),
      .out_drew     (drew33),
      .out_next     (next33)
  );

  logic [3*17-1:0] taken12;
  logic [3*18-1:0] light12;
  ts_path_light #(
      .TAG_W(1)
  ) u_light (
      .clk,
      .rst,
      .in_valid      (v_q[ScatterAt-1]),
      .in_throughput (throughput10),
      .in_albedo     (albedo10),
      .in_up         (-dir14[17+:17]),
      .in_tag        (1'b0),
      /* verilator lint_off PINCONNECTEMPTY */  // valid at a fixed cycle
      .out_valid     (),
      .out_tag       (),
      /* verilator lint_on PINCONNECTEMPTY */
      .out_throughput(taken12),
      .out_light     (light12)
  );

  // ---- 33: the stream after the bounce, and the normalisation ---------------------------------------------------
  logic [31:0] stream33;
  ts_artix_delay #(.W(32), .N(NormaliseAt - ScatterAt)) u_stream_wait (.clk, .in(stream10_q), .out(stream33));
  // v.v < 64 only when every |v_k| < 8: then the three squares are summed in 7 bits.
  logic [2:0] small33;
  logic [3*6-1:0] squares33;
  for (genvar k = 0; k < 3; k++) begin : g_short
    logic signed [23:0] c;
    logic [2:0] m;
    assign c = $signed(next33[k*24+:24]);
    assign m = c[23] ? 3'(-c) : c[2:0];
    assign small33[k] = c > -24'sd8 && c < 24'sd8;
    assign squares33[k*6+:6] = 6'(m * m);
  end
  logic short33;
  assign short33 = &small33 && 7'(squares33[0+:6]) + 7'(squares33[6+:6]) + 7'(squares33[12+:6]) < 7'd64;

  logic [3*DirW-1:0] dir48;
  ts_path_normalise #(
      .TAG_W(1)
  ) u_normalise (
      .clk,
      .rst,
      .in_valid (v_q[NormaliseAt-1] && !short33),
      .in_v     (next33),
      .in_tag   (1'b0),
      /* verilator lint_off PINCONNECTEMPTY */  // valid at a fixed cycle
      .out_valid(),
      .out_tag  (),
      /* verilator lint_on PINCONNECTEMPTY */
      .out_d    (dir48)
  );

  // ---- 48: what waited, and out ---------------------------------------------------------------------------------
  // From cycle 1: the path's names, the hit and its sphere, the ray's direction (a straight-on ray's next).
  logic [NameW-1:0]  name48;
  logic              hit48;
  logic [AW-1:0]     index48;
  logic [3*DirW-1:0] d48;
  ts_artix_delay #(.W(NameW + 1 + AW + 3 * DirW), .N(LastAt - 1)) u_names (
      .clk, .in({name1_q, hit1_q, index1_q, d1}), .out({name48, hit48, index48, d48}));
  // From cycle 10: the hit point. From 12: a miss's light, or a hit's throughput times its albedo.
  logic [3*OriginW-1:0] point48;
  logic [3*18-1:0]      kept48;
  logic                 hit12;
  ts_artix_delay #(.W(3 * OriginW), .N(LastAt - ScatterAt)) u_point (.clk, .in(point10), .out(point48));
  ts_artix_delay #(.W(1), .N(LightAt - ScatterAt)) u_hit12 (.clk, .in(hit10), .out(hit12));
  ts_artix_delay #(.W(3 * 18), .N(LastAt - LightAt)) u_kept (
      .clk,
      .in (hit12 ? {1'b0, taken12[34+:17], 1'b0, taken12[17+:17], 1'b0, taken12[0+:17]} : light12),
      .out(kept48)
  );
  // From cycle 33: the bounce, and the stream after it.
  logic [1:0]  bounce48;
  logic        into48, short48;
  logic [31:0] stream48;
  ts_artix_delay #(.W(4 + 32), .N(LastAt - NormaliseAt)) u_bounce (
      .clk,
      .in ({bounce33, into33, short33, drew33 ? ts_path_pkg::xorshift32(stream33) : stream33}),
      .out({bounce48, into48, short48, stream48})
  );

  logic [UW-1:0]  unit48;
  logic [IdW-1:0] path48;
  logic [9:0]     col48;
  logic [4:0]     sample48;
  logic [3:0]     rays48;
  assign {unit48, path48, col48, sample48, rays48} = name48;
  wire live48 = v_q[LastAt-1];
  wire goes48 = hit48 && bounce48 != Absorbed && !(bounce48 != Straight && short48);

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      ray_valid <= 1'b0;
      end_valid <= 1'b0;
    end else begin
      ray_valid <= live48 && goes48;
      end_valid <= live48 && !goes48;
    end
    {out_unit, out_path, out_col, out_sample} <= {unit48, path48, col48, sample48};
    out_rays  <= rays48 + 4'd1;
    out_o     <= point48;
    out_d     <= bounce48 == Straight ? d48 : dir48;
    out_from  <= index48;
    out_into  <= into48;
    out_light <= hit48 ? '0 : kept48;
  end
  // The path's word, for its next ray.
  always_ff @(posedge clk) begin
    write      <= live48 && goes48 && !flush;
    write_at   <= {unit48, path48};
    write_word <= {stream48, kept48[36+:17], kept48[18+:17], kept48[0+:17]};
  end
endmodule
