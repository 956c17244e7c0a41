// ts_artix_sphere_unit: the artix preset's sphere unit, one (ray, sphere) pair a clock, and the closest-hit register
// of its passes. C++ model: artix::quadratic and artix::closest_hit (src/tripsitter/device/artix_kernel.h), bit for
// bit; docs/device.md, "The artix preset", gives the arithmetic and docs/rtl.md the unit's place in the line.
//
// Slots. The unit's engine issues one slot a cycle; a slot reaches these ports SceneReadCycles later, with the
// sphere's fields read from scene memory. A pass is a run of slots: the first has in_first (the closest hit starts
// afresh), each slot that tests a sphere has in_pair (a sphere of the pass's list other than the one the ray
// leaves; the engine sends the list in ascending index, so the strict comparison below keeps the lower index on a
// tie, as the model does), and the pass's last slot has in_end. A slot may carry any of the three: a pass that
// tests n spheres takes max(n, MinPass) slots, and one that tests none still has a first and an end slot. The ray
// (in_o, in_d) is the pass's; the sphere's fields (in_c, in_e, in_r2s and in_carry, what the shading needs of the
// hit sphere) are the pair's.
//
// Result. The pass's closest hit comes out (out_valid for one cycle) exactly HitLatency + 1 - SceneReadCycles
// cycles after its end slot was at the ports: that is HitLatency cycles after the cycle that follows the pass's
// last issue slot, the model's "known" (artix_units.h). out_hit says whether any pair hit in front of the origin;
// then out_td, out_bd, out_f, out_s and out_e are that pair's artix::Quadratic (t d, b d, f, sqrt(D)) and its
// scale, and out_carry the hit sphere's in_carry.
//
// Path tracing (PATH = 1, the artix path preset: artix::walk_closest_hit and with_far_side of
// src/tripsitter/device/artix_units.h and artix_path.h). A pass's pairs need not come in ascending index: in_index
// is the pair's sphere, and of two hits at the same t d the lower index wins, whatever their order (keep_closest's
// rule). A pair with in_far set is the sphere the ray is inside (it went into it at its last bounce): its candidate
// is the far root t d = b d + s 2^(17 + e), when D >= 0 and that is above 0 (artix::far_td), and out_far says the
// pass's hit is such a far side. A slot with in_bound tests a bound of the world's hierarchy instead of a sphere: it
// is never a hit; it is entered when D >= 0 and its far root is above 0 (artix::enters), which out_entered says in
// the cycle out_entered_valid is high, one such report for each bound slot, in the order the slots came, in the cycle
// the pass's result would come out had the slot been its end (so a pass's bounds are all reported by the time its
// result comes out). With PATH = 0 the three inputs are not read and the three outputs are 0.
//
// Pipeline (stage k's registers hold a slot k + 1 cycles after it reached the ports; every product one DSP48E1,
// its 25-bit operand on A and the 18-bit one on B):
//   0      the ports, registered
//   1      oc_k = c_k - o_k                                          25 bits (|oc_k| < 2^23: hit points < 2^22 + 2)
//   2..4   b d = sum oc_k d_k: three products, then two additions     DSP 25 x 18; |b d| < 2^41
//   5      b = round(b d / 2^17)                                      25 bits
//   6, 7   f_k = (oc_k << 17) - b d_k                                DSP 25 x 18 and its post-adder; |f_k| < 2^47
//   8, 9   F_k = f_k >> (17 + e): by the multiple of 4, then the rest (two LUT levels, then one)
//   10     F_k beyond 18 bits, beyond r in the sphere's scale: the pair misses; else F_k's 18 bits
//   11..13 F.F = sum F_k^2: three products, then two additions        DSP 18 x 18; F.F < 3 2^34
//   14     D = r2s - F.F, and whether it is negative (or F saturated)
//   ...    Pad cycles: the slack of the latency the model promises (docs/device.md counts it)
//   15..31 s = floor(sqrt(D)) (ts_artix_isqrt: 17 digit steps)
//   32, 33 s 2^(17 + e) (a shift by 1..21), then t d = b d - s 2^(17 + e) (PATH: b d + s 2^(17 + e) for a far pair
//          or a bound)
//   34     the closest-hit register: a hit (D >= 0, t d > 0) with t d below the pass's best so far replaces it
//          (PATH: or equal to it, with a lower index); on the pass's end slot, the pass's result
// (stages 15 and on come Pad cycles later than their number says).
module ts_artix_sphere_unit
#(
    parameter int CARRY_W = 1,  // the hit sphere's fields the shading needs, carried with each pair
    parameter int PATH = 0      // 1: the artix path preset's unit (above)
) (
    input  logic                   clk,
    input  logic                   rst,
    input  logic                   in_first,
    input  logic                   in_pair,
    input  logic                   in_end,
    input  logic [3*ts_artix_pkg::OriginW-1:0]   in_o,      // component k at [k*ts_artix_pkg::OriginW +: ts_artix_pkg::OriginW], signed
    input  logic [3*ts_artix_pkg::DirW-1:0]      in_d,      // signed, times 2^17
    input  logic [3*ts_artix_pkg::CoordW-1:0]    in_c,      // signed, raw
    input  logic [ts_artix_pkg::ExpW-1:0]        in_e,      // signed, -16..4
    input  logic [ts_artix_pkg::R2sW-1:0]        in_r2s,
    input  logic [CARRY_W-1:0]     in_carry,
    input  logic                   in_far,    // PATH: the pair's candidate is its far root
    input  logic                   in_bound,  // PATH: the slot tests a hierarchy's bound
    input  logic [ts_artix_pkg::SphereAW-1:0]    in_index,  // PATH: the pair's sphere (ties to the lower)
    output logic                   out_valid,
    output logic                   out_hit,
    output logic [ts_artix_pkg::TdW-1:0]         out_td,    // signed
    output logic [ts_artix_pkg::BdW-1:0]         out_bd,    // signed
    output logic [3*ts_artix_pkg::FW-1:0]        out_f,     // signed
    output logic [ts_artix_pkg::SqrtW-1:0]       out_s,
    output logic [ts_artix_pkg::ExpW-1:0]        out_e,     // signed
    output logic [CARRY_W-1:0]     out_carry,
    output logic                   out_far,            // PATH: the hit is the far side of an in_far pair
    output logic                   out_entered_valid,  // PATH: a bound slot's report
    output logic                   out_entered
);
  // The package's facts this block uses (Yosys 0.23 takes package names qualified, not imported).
  localparam int OriginW = ts_artix_pkg::OriginW;
  localparam int DirW = ts_artix_pkg::DirW;
  localparam int DirFrac = ts_artix_pkg::DirFrac;
  localparam int CoordW = ts_artix_pkg::CoordW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int R2sW = ts_artix_pkg::R2sW;
  localparam int OcW = ts_artix_pkg::OcW;
  localparam int BdW = ts_artix_pkg::BdW;
  localparam int BW = ts_artix_pkg::BW;
  localparam int FW = ts_artix_pkg::FW;
  localparam int SqrtW = ts_artix_pkg::SqrtW;
  localparam int TdW = ts_artix_pkg::TdW;
  localparam int SphereAW = ts_artix_pkg::SphereAW;

  localparam int Stages = 35;                                  // registers from the ports to the result (0..34)
  localparam int Latency = ts_artix_pkg::HitLatency + 1 - ts_artix_pkg::SceneReadCycles;   // what the engine's schedule counts on
  localparam int Pad = Latency - Stages;
  localparam int ProdW = OcW + DirW;                           // a 25 x 18 product
  localparam int ScaledW = DirW;                               // F_k: 18 bits signed
  localparam int SqW = 2 * ScaledW;                            // F_k^2 < 2^34, as a signed product
  localparam int FfW = SqW;                                    // F.F < 3 2^34 < 2^36 (non-negative)
  localparam int ShiftW = 5;                                   // 17 + e: 1..21
  localparam int HitFW = 39;                                   // a hit's f_k (below)
  localparam int IndexW = PATH != 0 ? SphereAW : 1;                // the pair's index riding along (PATH)
  localparam int RestW = BdW + 3 * HitFW + SqrtW + ExpW + CARRY_W + 1;  // a hit's fields but t d and its index
  localparam int FlagW = PATH != 0 ? 5 : 3;                         // {first, pair, end}, PATH: then {far, bound}
  localparam int ResultW = 1 + TdW + RestW;

  if (Pad < 0) begin : g_bad_latency
    $error("ts_artix_sphere_unit: the pipeline is longer than the hit latency the schedule counts on");
  end

  // Slot flags: valid (any of them but far) resets; the rest are data.
  logic [14:0] v_q;  // stage k's slot is valid
  (* mem2reg *) logic [FlagW-1:0] flags_q [15];
  logic [FlagW-1:0] in_flags;
  logic             in_valid;
  if (PATH != 0) begin : g_path_flags
    assign in_flags = {in_first, in_pair, in_end, in_far, in_bound};
    assign in_valid = in_first | in_pair | in_end | in_bound;
  end else begin : g_flags_in
    assign in_flags = {in_first, in_pair, in_end};
    assign in_valid = in_first | in_pair | in_end;
    /* verilator lint_off UNUSEDSIGNAL */  // the path preset's inputs, not read by the artix preset's unit
    logic unused_path;
    assign unused_path = ^{in_far, in_bound, in_index};
    /* verilator lint_on UNUSEDSIGNAL */
  end

  // ---- 0: the ports ------------------------------------------------------------------------------------------
  (* mem2reg *) logic signed [OriginW-1:0] o0_q [3];
  (* mem2reg *) logic signed [DirW-1:0]    d0_q [3];
  (* mem2reg *) logic signed [CoordW-1:0]  c0_q [3];
  logic signed [ExpW-1:0]    e0_q;
  logic [R2sW-1:0]           r2s0_q;
  logic [CARRY_W-1:0]        carry0_q;

  always_ff @(posedge clk) begin
    if (rst) v_q[0] <= 1'b0;
    else v_q[0] <= in_valid;
    flags_q[0] <= in_flags;
    for (int k = 0; k < 3; k++) begin
      o0_q[k] <= in_o[k*OriginW+:OriginW];
      d0_q[k] <= in_d[k*DirW+:DirW];
      c0_q[k] <= in_c[k*CoordW+:CoordW];
    end
    e0_q     <= in_e;
    r2s0_q   <= in_r2s;
    carry0_q <= in_carry;
  end

  for (genvar s = 1; s < 15; s++) begin : g_flags
    always_ff @(posedge clk) begin
      if (rst) v_q[s] <= 1'b0;
      else v_q[s] <= v_q[s-1];
      flags_q[s] <= flags_q[s-1];
    end
  end

  // ---- 1: oc = c - o (the pre-adder's work) ------------------------------------------------------------------
  (* mem2reg *) logic signed [OcW-1:0] oc1_q [3];
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) oc1_q[k] <= OcW'(c0_q[k]) - OcW'(o0_q[k]);
  end

  // The direction, the sphere's scale and its r^2 ride alongside until they are used (a name's number is the
  // stage whose slot it holds).
  (* mem2reg *) logic signed [DirW-1:0] d1 [3], d5 [3];
  logic signed [ExpW-1:0] e7, e31;
  logic [R2sW-1:0]        r2s13;
  for (genvar k = 0; k < 3; k++) begin : g_dir
    ts_artix_delay #(.W(DirW), .N(1)) dir_delay_1 (.clk, .in(d0_q[k]), .out(d1[k]));
    ts_artix_delay #(.W(DirW), .N(4)) dir_delay_5 (.clk, .in(d1[k]), .out(d5[k]));
  end
  ts_artix_delay #(.W(ExpW), .N(7)) e_delay_7 (.clk, .in(e0_q), .out(e7));
  ts_artix_delay #(.W(R2sW), .N(13)) r2s_delay (.clk, .in(r2s0_q), .out(r2s13));

  // ---- 2..4: b d = oc . d ------------------------------------------------------------------------------------
  (* mem2reg *) logic signed [ProdW-1:0] m2_q [3];
  logic signed [BdW-1:0]   sum3_q, m3_q, bd4_q;
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) m2_q[k] <= oc1_q[k] * d1[k];
    sum3_q <= BdW'(m2_q[0]) + BdW'(m2_q[1]);
    m3_q   <= BdW'(m2_q[2]);
    bd4_q  <= sum3_q + m3_q;
  end

  // oc waits for f's post-adder.
  (* mem2reg *) logic signed [OcW-1:0] oc6 [3];
  for (genvar k = 0; k < 3; k++) begin : g_oc
    ts_artix_delay #(.W(OcW), .N(5)) oc_delay (.clk, .in(oc1_q[k]), .out(oc6[k]));
  end

  // ---- 5: b = round(b d / 2^17) ------------------------------------------------------------------------------
  logic signed [BdW-1:0] bd_rounded;
  logic signed [BW-1:0]  b5_q;
  logic signed [BdW-1:0] bd5_q;
  assign bd_rounded = bd4_q + BdW'(1 << (DirFrac - 1));
  always_ff @(posedge clk) begin
    b5_q  <= BW'(bd_rounded >>> DirFrac);
    bd5_q <= bd4_q;
  end

  // ---- 6, 7: f = (oc << 17) - b d ----------------------------------------------------------------------------
  (* mem2reg *) logic signed [ProdW-1:0] p6_q [3];
  (* mem2reg *) logic signed [FW-1:0]    f7_q [3];
  logic [ShiftW-1:0]       shift7;
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) p6_q[k] <= b5_q * d5[k];
    for (int k = 0; k < 3; k++) f7_q[k] <= (FW'(oc6[k]) <<< DirFrac) - FW'(p6_q[k]);
  end
  assign shift7 = ShiftW'(DirFrac + 32'(e7));

  // ---- 8, 9: F = f >> (17 + e) -------------------------------------------------------------------------------
  (* mem2reg *) logic signed [FW-1:0] coarse8_q [3], fine9_q [3];
  logic [1:0]           fine_shift8_q;
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) coarse8_q[k] <= f7_q[k] >>> {shift7[ShiftW-1:2], 2'b00};
    fine_shift8_q <= shift7[1:0];
    for (int k = 0; k < 3; k++) fine9_q[k] <= coarse8_q[k] >>> fine_shift8_q;
  end

  // ---- 10: saturation ----------------------------------------------------------------------------------------
  // The model calls F_k beyond r outside +-(2^17 - 1), a miss. Here F_k is beyond when it does not fit 18 bits
  // signed (the bits above are not all its sign); the one value the model adds, -2^17, squares to 2^34 > r2s and
  // so misses through D < 0 just the same.
  (* mem2reg *) logic signed [ScaledW-1:0] scaled10_q [3];
  logic                      beyond10_q;
  logic [2:0]                beyond9;
  for (genvar k = 0; k < 3; k++) begin : g_beyond
    assign beyond9[k] = !(&fine9_q[k][FW-1:ScaledW-1] || ~|fine9_q[k][FW-1:ScaledW-1]);
  end
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) scaled10_q[k] <= fine9_q[k][ScaledW-1:0];
    beyond10_q <= |beyond9;
  end

  // ---- 11..13: F.F -------------------------------------------------------------------------------------------
  (* mem2reg *) logic signed [SqW-1:0] q11_q [3];
  logic [FfW-1:0]        sum12_q, q12_q, ff13_q;
  logic [12:11]          beyond_q;
  always_ff @(posedge clk) begin
    for (int k = 0; k < 3; k++) q11_q[k] <= scaled10_q[k] * scaled10_q[k];
    sum12_q      <= FfW'(q11_q[0]) + FfW'(q11_q[1]);
    q12_q        <= FfW'(q11_q[2]);
    ff13_q       <= sum12_q + q12_q;
    beyond_q[11] <= beyond10_q;
    beyond_q[12] <= beyond_q[11];
  end
  logic beyond13_q;
  always_ff @(posedge clk) beyond13_q <= beyond_q[12];

  // ---- 14: D = r2s - F.F -------------------------------------------------------------------------------------
  logic [R2sW-1:0] disc14_q;
  logic            miss14_q;
  always_ff @(posedge clk) begin
    miss14_q <= beyond13_q || ff13_q > FfW'(r2s13);
    disc14_q <= r2s13 - R2sW'(ff13_q);
  end

  // ---- 15..31: s = floor(sqrt(D)) ----------------------------------------------------------------------------
  // A negative D's root is never used: the pair misses.
  logic             v31;
  logic [FlagW:0]   tag31;  // {flags, miss}
  logic [SqrtW-1:0] s31;
  // The slack the model's latency leaves (Pad cycles) is taken here, where a slot is narrowest: D and four flags.
  logic             pad_v;
  logic [R2sW-1:0]  pad_disc;
  logic [FlagW:0]   pad_tag;
  ts_artix_delay #(.W(R2sW + FlagW + 1), .N(Pad)) pad_delay (
      .clk, .in({miss14_q ? '0 : disc14_q, flags_q[14], miss14_q}), .out({pad_disc, pad_tag})
  );
  if (Pad == 0) begin : g_no_pad
    assign pad_v = v_q[14];
  end else begin : g_pad
    logic [Pad-1:0] pad_v_q;
    always_ff @(posedge clk) begin
      if (rst) pad_v_q <= '0;
      else pad_v_q <= Pad'({pad_v_q, v_q[14]});
    end
    assign pad_v = pad_v_q[Pad-1];
  end

  ts_artix_isqrt #(.WIDTH(R2sW), .TAG_W(FlagW + 1)) isqrt (
      .clk, .rst,
      .in_valid(pad_v), .in_value(pad_disc), .in_tag(pad_tag),
      .out_valid(v31), .out_root(s31), .out_tag(tag31)
  );

  // b d, e, f and the carried fields wait for the square root. Of f only the low HitFW bits are carried: the
  // result is a hit's f, and a hit has F.F <= r2s < 2^34, so |F_k| < 2^17 and |f_k| < 2^(34 + e) <= 2^38.
  logic signed [BdW-1:0]   bd32;
  logic [3*HitFW-1:0]      f7_flat, f33;
  logic [CARRY_W-1:0]      carry33;
  for (genvar k = 0; k < 3; k++) begin : g_f
    assign f7_flat[k*HitFW+:HitFW] = f7_q[k][HitFW-1:0];
  end
  ts_artix_delay #(.W(BdW), .N(27 + Pad)) bd_delay (.clk, .in(bd5_q), .out(bd32));
  ts_artix_delay #(.W(3 * HitFW), .N(26 + Pad)) f_delay (.clk, .in(f7_flat), .out(f33));
  ts_artix_delay #(.W(CARRY_W), .N(33 + Pad)) carry_delay (.clk, .in(carry0_q), .out(carry33));
  ts_artix_delay #(.W(ExpW), .N(24 + Pad)) e_delay_31 (.clk, .in(e7), .out(e31));
  logic [IndexW-1:0] index0_q, index33;
  always_ff @(posedge clk) index0_q <= PATH != 0 ? IndexW'(in_index) : '0;
  ts_artix_delay #(.W(IndexW), .N(33 + Pad)) index_delay (.clk, .in(index0_q), .out(index33));

  // ---- 32, 33: t d = b d - s 2^(17 + e) ----------------------------------------------------------------------
  logic                    v32_q, v33_q;
  logic [FlagW:0]          tag32_q, tag33_q;
  logic [SqrtW-1:0]        s32_q, s33_q;
  logic [SqrtW+20:0]       scaled_s32_q;  // s < 2^17 shifted by up to 21
  logic signed [ExpW-1:0]  e32_q, e33_q;
  logic signed [TdW-1:0]   td33_q;
  logic signed [BdW-1:0]   bd33_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      v32_q <= 1'b0;
      v33_q <= 1'b0;
    end else begin
      v32_q <= v31;
      v33_q <= v32_q;
    end
    tag32_q      <= tag31;
    tag33_q      <= tag32_q;
    s32_q        <= s31;
    s33_q        <= s32_q;
    e32_q        <= e31;
    e33_q        <= e32_q;
    scaled_s32_q <= (SqrtW + 21)'(s31) << (DirFrac + 32'(e31));
    // A far pair or a bound (tag32_q's far and bound flags, PATH) takes the far root.
    td33_q       <= PATH != 0 && |tag32_q[2:1] ? TdW'(bd32) + TdW'(scaled_s32_q) : TdW'(bd32) - TdW'(scaled_s32_q);
    bd33_q       <= bd32;
  end

  // ---- 34: the closest-hit register --------------------------------------------------------------------------
  logic first33, pair33, end33, far33, bound33, miss33, cand_hit, take, nearer;
  if (PATH != 0) begin : g_path_tag
    assign {first33, pair33, end33, far33, bound33, miss33} = tag33_q;
  end else begin : g_tag
    assign {first33, pair33, end33, miss33} = tag33_q;
    assign far33 = 1'b0;
    assign bound33 = 1'b0;
  end
  assign cand_hit = v33_q && pair33 && !miss33 && td33_q > 0;

  logic                   best_valid_q;
  logic signed [TdW-1:0]  best_td_q;
  logic [IndexW-1:0]      best_index_q;
  logic [RestW-1:0]     best_rest_q;  // b d, f, s, e, carry and far of the best hit
  logic [RestW-1:0]     cand_rest;
  assign cand_rest = {bd33_q, f33, s33_q, e33_q, carry33, far33};
  // A slot that opens a pass drops the previous pass's best. The path's ties go to the lower index.
  assign nearer = td33_q < best_td_q || (PATH != 0 && td33_q == best_td_q && index33 < best_index_q);
  assign take = cand_hit && (first33 || !best_valid_q || nearer);

  logic                   next_valid;
  logic signed [TdW-1:0]  next_td;
  logic [RestW-1:0]     next_rest;
  assign next_valid = take || (best_valid_q && !(v33_q && first33));
  assign next_td    = take ? td33_q : best_td_q;
  assign next_rest  = take ? cand_rest : best_rest_q;

  logic               result_v_q;
  logic [ResultW-1:0] result_q;
  always_ff @(posedge clk) begin
    if (rst) begin
      best_valid_q <= 1'b0;
      result_v_q   <= 1'b0;
    end else begin
      best_valid_q <= next_valid;
      result_v_q   <= v33_q && end33;
    end
    best_td_q   <= next_td;
    if (take) best_index_q <= index33;
    best_rest_q <= next_rest;
    result_q    <= {next_valid, next_td, next_rest};
  end

  // A bound's report (PATH).
  logic entered_v_q, entered_q;
  always_ff @(posedge clk) begin
    if (rst) entered_v_q <= 1'b0;
    else entered_v_q <= v33_q && bound33;
    entered_q <= !miss33 && td33_q > 0;
  end
  assign out_entered_valid = entered_v_q;
  assign out_entered = entered_q;

  logic [3*HitFW-1:0] out_f_narrow;
  assign out_valid = result_v_q;
  assign {out_hit, out_td, out_bd, out_f_narrow, out_s, out_e, out_carry, out_far} = result_q;
  for (genvar k = 0; k < 3; k++) begin : g_out_f
    assign out_f[k*FW+:FW] = FW'($signed(out_f_narrow[k*HitFW+:HitFW]));
  end
endmodule
