// ts_artix_shade_reflect: the artix preset's shading, reflection and tint, one per sphere unit. C++ model: the body
// of artix::trace_pixel_with's loop after a pass's closest hit (src/tripsitter/device/artix_kernel.h), bit for bit:
// artix::reflect with the tint's products when the pass hit a metal with bounces to spare, otherwise
// core::tint_colour (core/sphere_kernel.h, with artix::TintArith) of artix::normal_colour, or of the background
// 12'h036 (core::kBackground) when the pass hit nothing. docs/device.md, "The artix preset", gives the arithmetic.
//
// Ports. An event is one pass's end: in_valid for one cycle, call it K, at most once every MinPass cycles (a pass
// holds its unit's issue port at least that long, so its closest hit is known at least that long after the last).
// With it: the pass's ray (in_o raw, in_d times 2^17), whether it hit a sphere in front of the origin (in_hit),
// and then the closest hit's artix::Quadratic as the sphere unit gives it (in_bd, in_f, in_s, in_td) and the hit
// sphere's fields (artix::UnitSphere: in_e, in_r, in_rinv, in_metal, in_albedo); the pixel's bounces so far, the
// products of the albedos it reflected off (in_tint: 1, 1, 1 before any reflection) and a tag (TAG_W bits: the
// caller's, e.g. the column). Vectors hold component k, or channel k (red first), at [k*W +: W]. Without in_hit the
// quadratic's and the sphere's fields are ignored.
//   A metal hit with in_bounces < MaxBounces reflects: out_ray_valid for one cycle in cycle K + ReflectLatency, with
//     artix::reflect's ray (out_ray_o, out_ray_d), in_bounces + 1, the tint times the sphere's albedo channel by
//     channel, and the tag. Which sphere the new ray excludes is the caller's business.
//   Anything else is shaded: out_colour_valid for one cycle in cycle K + ShadeLatency - 1 (the line buffer's write
//     lands at the clock edge that ends it), with the colour (r, g, b nibbles, high to low, as core::Rgb444) and
//     the tag.
// Both kinds keep their exact latency whatever came before, so a colour and an earlier event's ray can come out
// in the same cycle.
//
// Channels in turn. Each channel's arithmetic is the same, and an event comes at most every MinPass = 3 cycles, so
// one datapath serves the three channels in three successive cycles: channel k of the event of cycle K is in
// stage j's registers in cycle K + k + j + 1, and each product kind (beta d, s d, Q rinv, d.n, (d.n) n, t d) is one
// DSP48E1 for all three. Channel 0's fields are taken from the ports in cycle K, channels 1 and 2's from registers
// in K + 1 and K + 2; the event's own fields are registered once in K and serve all three. The results of an
// event's channels meet in the output registers.
//
// The arithmetic (z = max(0, -e), e+ = max(e, 0); scaled_normal in artix_kernel.cpp). The model's normal is
// n_k = Q_k / R with Q_k = -(f'_k 2^z + s d_k 2^e+), f'_k = f_k - floor(beta d_k / 2^17), R = r 2^(17 + z), and
// beta = b d - round(b d / 2^17) 2^17, which is b d's low 17 bits read as a signed number. Here
//     u = floor(beta d_k / 2^17) 2^z,  p = s 2^e+ d_k,  nh = f_k 2^z + p:  Q_k = u - nh,
//     y = R - nh:  W = 7 (Q_k + R) = 7 u + 7 y
// and the channel, min(14, floor(W / R)) (0 when W < 0), is a four-bit restoring division: four steps saturate at
// 15 by themselves, and a negative W never leaves a step's difference non-negative, so it gives 0 by itself. R is
// r 2^z shifted up by 17, so W >= j R exactly when floor(W / 2^17) >= j r 2^z: the division takes W's top 27 bits
// and r 2^z (21 bits: r 2^-e < 2^17 when e < 0). The tint, floor(c T_k / 255^bounces) for the channel c (c itself
// without reflections, whatever the tint), is a second four-step division (its quotient is at most c < 16). The
// reflection is artix::normal's and artix::reflect's: n_k = the top of Q_k times rinv, saturated; d.n accumulated
// over the channels, saturated; then
//     d'_k = d_k - round((d.n) n_k / 2^16) = floor((d_k 2^16 + 2^15 - 1 + (-(d.n)) n_k) / 2^16), saturated,
//     o'_k = o_k + round(t d_k / 2^17) = floor((o_k 2^17 + 2^16 + t d_k) / 2^17),  t = round(t d / 2^17)
// (each a product and the post-adder's C, whose low bits are the constant). The tint's product T_k a_k and the
// colour's c T_k are shifts and adds in LUTs; T_k a_k takes T_k's low 8 (MaxBounces - 1) bits, since a pixel that
// reflects has reflected at most MaxBounces - 1 times (the model's tint is then below 255^(MaxBounces - 1)).
//
// Pipeline (a channel's stage j, in cycle K + k + j + 1):
//   0   per event: beta, s 2^e+ and t (the DSP48E1s' A operands), r, z, e+; per channel: d_k, o_k 2^17 + 2^16, f_k
//   1   beta d_k, p, t d_k + o_k 2^17 + 2^16 (DSP 25 x 18 each); f_k 2^z, r 2^z; T_k a_k's pair sums
//   2   u; nh = f_k 2^z + p; y = R - f_k 2^z - p; o'_k (the bits of stage 1's sum); T_k a_k
//   3   W / 2^17 = (8 u - u + 8 y - y) / 2^17; Q_k = u - nh
//   4   the channel's quotient bits 3, 2 (two restoring steps); Q_k / 2^(18 + e+) and rinv (the DSP's operands)
//   5   bits 1, 0 and the channel: the background on a miss, 14 at most; the normal's product
//   6   c T_k (T_k 1 without reflections); n_k saturated
//   7   the tint's quotient bits 3, 2; d.n += n_k d_k (DSP 18 x 18, restarting at channel 0)
//   8   bits 1, 0: the colour's channel, into the colour; -(d.n) / 2^17 saturated (after channel 2, held)
//   11  d_k 2^16 + 2^15 - 1 + (-(d.n)) n_k (DSP 18 x 18 and its post-adder)
//   12  d'_k saturated
//   ... delays to the latencies: the colour is stage ShadeLatency - 1 - 3 = 8 (channel 2 in cycle K + 11), the ray
//       stage ReflectLatency - 3 = 17 (in cycle K + 20). A generate check stops a build whose datapath is longer.
//
// Widths (signed unless said). They hold the model's values for a hit: f_k 2^(-17-e) fits 18 bits (else a miss),
// so |f_k| < 2^(34 + e) and |f_k 2^z| < 2^38; |s 2^e+| < 2^21; |Q_k| < 2^40 and the normal's operand 18 bits (the
// model's checks); t 25 bits; o' 24 bits. Their derivations are beside each localparam.
//
// The package's facts are named ts_artix_pkg::X, not imported: Yosys 0.23 cannot parse `import`.
module ts_artix_shade_reflect #(
    parameter int TAG_W = 10
) (
    input  logic                                     clk,
    input  logic                                     rst,
    input  logic                                     in_valid,
    input  logic [3*ts_artix_pkg::OriginW-1:0]       in_o,        // raw, signed
    input  logic [3*ts_artix_pkg::DirW-1:0]          in_d,        // times 2^17, signed
    input  logic                                     in_hit,
    /* verilator lint_off UNUSEDSIGNAL */  // b d's fraction only, beta (see The arithmetic)
    input  logic [ts_artix_pkg::BdW-1:0]             in_bd,       // signed
    /* verilator lint_on UNUSEDSIGNAL */
    /* verilator lint_off UNUSEDSIGNAL */  // a hit's f_k fits 39 bits (see Widths): the rest is its sign
    input  logic [3*ts_artix_pkg::FW-1:0]            in_f,        // signed
    /* verilator lint_on UNUSEDSIGNAL */
    input  logic [ts_artix_pkg::SqrtW-1:0]           in_s,
    input  logic [ts_artix_pkg::TdW-1:0]             in_td,       // signed, > 0 with in_hit
    input  logic [ts_artix_pkg::ExpW-1:0]            in_e,        // signed, -16..4
    input  logic [ts_artix_pkg::RadiusW-1:0]         in_r,        // >= 1
    input  logic [ts_artix_pkg::RinvW-1:0]           in_rinv,
    input  logic                                     in_metal,
    input  logic [23:0]                              in_albedo,   // bytes, red at [7:0]
    input  logic [$clog2(ts_artix_pkg::MaxBounces+1)-1:0] in_bounces,  // 0..MaxBounces
    input  logic [3*8*ts_artix_pkg::MaxBounces-1:0]  in_tint,     // each at most 255^in_bounces
    input  logic [TAG_W-1:0]                         in_tag,
    output logic                                     out_ray_valid,
    output logic [3*ts_artix_pkg::OriginW-1:0]       out_ray_o,
    output logic [3*ts_artix_pkg::DirW-1:0]          out_ray_d,
    output logic [$clog2(ts_artix_pkg::MaxBounces+1)-1:0] out_ray_bounces,
    output logic [3*8*ts_artix_pkg::MaxBounces-1:0]  out_ray_tint,
    output logic [TAG_W-1:0]                         out_ray_tag,
    output logic                                     out_colour_valid,
    output logic [11:0]                              out_colour,
    output logic [TAG_W-1:0]                         out_colour_tag,
    output logic                                     busy         // see Busy, at the end
);
  localparam int OriginW = ts_artix_pkg::OriginW;
  localparam int DirW = ts_artix_pkg::DirW;
  localparam int DirFrac = ts_artix_pkg::DirFrac;
  localparam int FW = ts_artix_pkg::FW;
  localparam int SqrtW = ts_artix_pkg::SqrtW;
  localparam int TdW = ts_artix_pkg::TdW;
  localparam int ExpW = ts_artix_pkg::ExpW;
  localparam int RadiusW = ts_artix_pkg::RadiusW;
  localparam int RinvW = ts_artix_pkg::RinvW;
  localparam int MaxBounces = ts_artix_pkg::MaxBounces;

  localparam int Channels = 3;
  localparam int BounceW = $clog2(MaxBounces + 1);
  localparam int TintW = 8 * MaxBounces;          // a product of up to MaxBounces albedo bytes
  localparam int ReflTintW = MaxBounces > 1 ? 8 * (MaxBounces - 1) : 1;  // a reflecting pixel's: one bounce fewer
  localparam int BetaW = DirFrac;                 // beta in [-2^16, 2^16)
  localparam int ZW = 5;                          // z = max(0, -e): 0..16
  localparam int EpW = 3;                         // e+ = max(e, 0): 0..4
  localparam int FzW = 39;                        // f_k and f_k 2^z of a hit: |.| < 2^38
  localparam int SsW = SqrtW + 5;                 // s 2^e+ < 2^21, as a signed A operand
  localparam int TW = 25;                         // t = round(t d / 2^17): the model checks 25 bits
  localparam int P1W = BetaW + DirW;              // beta d_k
  localparam int U0W = P1W - DirFrac;             // floor(beta d_k / 2^17): 18 bits (|.| <= 2^16)
  localparam int UW = 34;                         // u = that 2^z: |u| <= 2^32
  localparam int P2W = SsW + DirW;                // p = s 2^e+ d_k: |p| < 2^38
  localparam int P6W = TW + DirW;                 // o_k 2^17 + 2^16 + t d_k: below 2^40 + 2^16 + 2^41 < 2^42
  localparam int RpW = RadiusW;                   // r 2^z < 2^21 (r 2^-e < 2^17 when e < 0)
  localparam int NhW = 40;                        // nh = f_k 2^z + p: |.| < 2^39
  localparam int YW = 42;                         // y = Q_k + R - u: |.| < 2^40 + 2^38 + 2^32
  localparam int QW = 41;                         // |Q_k| < 2^40 (the model's check)
  localparam int WW = 44;                         // W = 7 (Q_k + R): |.| < 7 (2^40 + 2^38) < 2^43
  localparam int WpW = WW - DirFrac;              // floor(W / 2^17)
  localparam int DivW = WpW + 1;                  // W / 2^17 less a multiple of r 2^z below 2^24
  localparam int TopW = DirW;                     // Q_k / 2^(18 + e+): the model checks 18 bits
  localparam int RinvSW = RinvW + 1;              // rinv <= 2^18 as a signed A operand
  localparam int P3W = RinvSW + TopW;             // the normal's product, |.| <= 2^35
  localparam int NW = P3W - (DirFrac - 1);        // that / 2^16, before saturation
  localparam int AccW = 2 * DirW + 1;             // d.n: three products each below 2^34
  localparam int DnW = AccW - DirFrac;            // d.n / 2^17, before saturation
  localparam int P5W = 2 * DirW + 1;              // d_k 2^16 + 2^15 - 1 - (d.n) n_k: |.| < 2^33 + 2^16 + 2^34
  localparam int DoutW = P5W - (DirFrac - 1);     // that / 2^16, before saturation
  localparam int XW = TintW + 4;                  // c T_k < 15 255^MaxBounces
  localparam int ScaleW = TintW;                  // 255^bounces
  localparam logic [11:0] Background = 12'h036;   // core::kBackground
  localparam logic signed [DirW-1:0] DirMax = DirW'((1 << DirFrac) - 1);

  // Where each result leaves the datapath, and what pads it to the latencies the line's schedule counts on.
  localparam int ColourOut = ts_artix_pkg::ShadeLatency - 1 - Channels;  // channel 2's colour stage: K + 11
  localparam int RayOut = ts_artix_pkg::ReflectLatency - Channels;       // channel 2's ray stage: K + 20
  localparam int ColourDone = 8;                  // the stage that holds a channel's colour
  localparam int RayDone = 12;                    // the stage that holds d'_k
  localparam int ColourPad = ColourOut - ColourDone;
  localparam int RayPad = RayOut - RayDone;
  localparam int Stages = RayOut;                 // the slots' valid and channel, stages 0 .. RayOut - 1

  if (ts_artix_pkg::MinPass < Channels) begin : g_bad_rate
    $error("ts_artix_shade_reflect: events closer than 3 cycles would overrun the channels' shared multipliers");
  end
  if (ColourPad < 0) begin : g_bad_colour_latency
    $error("ts_artix_shade_reflect: the colour's datapath is longer than ShadeLatency allows");
  end
  if (RayPad < 0) begin : g_bad_ray_latency
    $error("ts_artix_shade_reflect: the reflection's datapath is longer than ReflectLatency allows");
  end
  if (DirFrac != 17 || DirW != 18 || SqrtW != 17 || RadiusW > 21 || RinvW != 19 || OriginW != 24) begin : g_bad_package
    $error("ts_artix_shade_reflect: its widths are derived for the package's formats of this version");
  end

  // 255^b for b = 0..MaxBounces, the tint's divisors, b's at [b*ScaleW +: ScaleW]: a table made at elaboration.
  function automatic logic [(MaxBounces+1)*ScaleW-1:0] scale_table();
    logic [ScaleW-1:0] power;
    power = ScaleW'(1);
    scale_table = '0;
    for (int b = 0; b <= MaxBounces; b++) begin
      scale_table[b*ScaleW+:ScaleW] = power;
      power = ScaleW'(power * ScaleW'(255));
    end
  endfunction
  localparam logic [(MaxBounces+1)*ScaleW-1:0] Scales = scale_table();
  function automatic logic [ScaleW-1:0] scale_of(input logic [BounceW-1:0] b);
    scale_of = '0;
    for (int i = 0; i <= MaxBounces; i++) if (b == BounceW'(i)) scale_of = Scales[i*ScaleW+:ScaleW];
  endfunction
  // One restoring step of the channel's division: {the quotient bit, what remains}. The difference's sign is the
  // comparison, so a step is one carry chain and a multiplexer.
  function automatic logic [WpW:0] colour_step(input logic signed [WpW-1:0] rem, input logic [RpW+2:0] div);
    logic signed [DivW-1:0] diff;
    diff = DivW'(rem) - DivW'($signed({1'b0, div}));
    colour_step = diff[DivW-1] ? {1'b0, rem} : {1'b1, WpW'(diff)};
  endfunction
  // One restoring step of the tint's division, the same way.
  function automatic logic [XW:0] tint_step(input logic [XW-1:0] rem, input logic [XW-1:0] div);
    logic [XW:0] diff;
    diff = {1'b0, rem} - {1'b0, div};
    tint_step = diff[XW] ? {1'b0, rem} : {1'b1, diff[XW-1:0]};
  endfunction
  // v saturated to +-(2^17 - 1), as the model clamps a direction or a normal.
  function automatic logic signed [DirW-1:0] saturate(input logic signed [31:0] v);
    saturate = v > 32'(DirMax) ? DirMax : v < -32'(DirMax) ? -DirMax : DirW'(v);
  endfunction

  // ---- the slot: channel 0 from the ports, channels 1 and 2 from the event's registers ------------------------
  logic sel1_q, sel2_q;  // the slot is the event's channel 1, 2
  always_ff @(posedge clk) begin
    if (rst) begin
      sel1_q <= 1'b0;
      sel2_q <= 1'b0;
    end else begin
      sel1_q <= in_valid;
      sel2_q <= sel1_q;
    end
  end

  // Per channel: channels 1 and 2 held from cycle K (a register's enable, no multiplexer), then one three-way
  // multiplexer a bit for the slot.
  localparam int ChanW = OriginW + DirW + FzW + TintW + 8;
  (* mem2reg *) logic [ChanW-1:0] in_chan [Channels];
  for (genvar k = 0; k < Channels; k++) begin : g_in_chan
    assign in_chan[k] = {in_o[k*OriginW+:OriginW], in_d[k*DirW+:DirW], in_f[k*FW+:FzW], in_tint[k*TintW+:TintW],
                         in_albedo[k*8+:8]};
  end
  logic [ChanW-1:0] chan1_q, chan2_q;
  always_ff @(posedge clk) begin
    if (in_valid) begin
      chan1_q <= in_chan[1];
      chan2_q <= in_chan[2];
    end
  end

  logic                       slot_valid;
  logic [1:0]                 slot_ch;
  logic signed [OriginW-1:0]  slot_o;
  logic signed [DirW-1:0]     slot_d;
  logic signed [FzW-1:0]      slot_f;
  logic [TintW-1:0]           slot_tint;
  logic [7:0]                 slot_albedo;
  assign slot_valid = in_valid | sel1_q | sel2_q;
  assign slot_ch = in_valid ? 2'd0 : sel1_q ? 2'd1 : 2'd2;
  assign {slot_o, slot_d, slot_f, slot_tint, slot_albedo} = in_valid ? in_chan[0] : sel1_q ? chan1_q : chan2_q;

  // ---- the slots' valid and channel, stage by stage -----------------------------------------------------------
  logic [Stages-1:0] v_q;
  (* mem2reg *) logic [1:0]        ch_q [Stages];
  always_ff @(posedge clk) begin
    if (rst) v_q <= '0;
    else v_q <= Stages'({v_q, slot_valid});
    ch_q[0] <= slot_ch;
    for (int j = 1; j < Stages; j++) ch_q[j] <= ch_q[j-1];
  end

  // ---- 0, per event: loaded in cycle K, read by channel k in K + k + 1 (k = 0..2) --------------------------------
  // The next event loads them no earlier than K + 3, so they serve as every channel's stage 0: the DSP48E1s' A
  // operands (beta, s 2^e+, t) are loaded once an event, by their enable, and what a later stage j needs of the
  // event is these registers delayed by j.
  logic signed [BetaW-1:0]   beta0_q;
  logic signed [SsW-1:0]     ss0_q;
  logic signed [TW-1:0]      t0_q;
  logic [RadiusW-1:0]        r0_q;
  logic [ZW-1:0]             z0_q;
  logic [EpW-1:0]            ep0_q;
  logic [RinvW-1:0]          rinv0_q;
  logic                      hit0_q, reflect0_q;
  logic [BounceW-1:0]        bounces0_q;
  logic [TAG_W-1:0]          tag0_q;

  logic signed [ExpW-1:0] in_se;
  logic [EpW-1:0]         in_ep;
  /* verilator lint_off UNUSEDSIGNAL */  // t d's top: a hit's t fits 25 bits (the model's check)
  logic signed [TdW-1:0]  td_rounded;
  /* verilator lint_on UNUSEDSIGNAL */
  assign in_se = $signed(in_e);
  assign in_ep = in_se < 0 ? '0 : EpW'(in_se);
  assign td_rounded = $signed(in_td) + TdW'(1 << (DirFrac - 1));
  always_ff @(posedge clk) begin
    if (in_valid) begin
      beta0_q    <= $signed(in_bd[BetaW-1:0]);
      ss0_q      <= $signed(SsW'(in_s) << in_ep);  // below 2^21: the sign bit is 0
      t0_q       <= TW'(td_rounded >>> DirFrac);
      r0_q       <= in_r;
      z0_q       <= in_se < 0 ? ZW'(-in_se) : '0;
      ep0_q      <= in_ep;
      rinv0_q    <= in_rinv;
      hit0_q     <= in_hit;
      reflect0_q <= in_hit && in_metal && in_bounces < BounceW'(MaxBounces);
      bounces0_q <= in_bounces;
      tag0_q     <= in_tag;
    end
  end

  // ---- 0, per channel: the slot's operands --------------------------------------------------------------------
  logic signed [P6W-1:0]     oc0_q;     // o_k 2^17 + 2^16
  logic signed [DirW-1:0]    d0_q;
  logic signed [FzW-1:0]     f0_q;
  logic [TintW-1:0]          tint0_q;
  logic [7:0]                albedo0_q;
  always_ff @(posedge clk) begin
    oc0_q     <= (P6W'(slot_o) <<< DirFrac) | P6W'(1 << (DirFrac - 1));
    d0_q      <= slot_d;
    f0_q      <= slot_f;
    tint0_q   <= slot_tint;
    albedo0_q <= slot_albedo;
  end

  // ---- 1: the products, f_k 2^z, r 2^z ------------------------------------------------------------------------
  logic signed [P1W-1:0] p1_q;
  logic signed [P2W-1:0] p2_q;
  logic signed [P6W-1:0] p6_q;
  logic signed [FzW-1:0] fz1_q;
  logic [RpW-1:0]        rp1_q;
  logic [ZW-1:0]         z1_q;
  always_ff @(posedge clk) begin
    p1_q  <= beta0_q * d0_q;
    p2_q  <= ss0_q * d0_q;
    p6_q  <= oc0_q + t0_q * d0_q;
    fz1_q <= f0_q <<< z0_q;
    rp1_q <= r0_q << z0_q;
    z1_q  <= z0_q;
  end

  // ---- 2: u, nh, y --------------------------------------------------------------------------------------------
  logic signed [U0W-1:0] u0;
  logic signed [UW-1:0]  u2_q;
  logic signed [NhW-1:0] nh2_q;
  logic signed [YW-1:0]  y2_q;
  assign u0 = U0W'(p1_q >>> DirFrac);
  always_ff @(posedge clk) begin
    u2_q  <= UW'(u0) <<< z1_q;
    nh2_q <= NhW'(fz1_q) + NhW'(p2_q);
    y2_q  <= (YW'($signed({1'b0, rp1_q})) <<< DirFrac) - YW'(fz1_q) - YW'(p2_q);
  end

  // ---- 3: W / 2^17 and Q_k ------------------------------------------------------------------------------------
  logic signed [WW-1:0]  w_full;
  /* verilator lint_off UNUSEDSIGNAL */  // W's low 17 bits: only their carry counts
  logic signed [WW-1:0]  w_top;
  /* verilator lint_on UNUSEDSIGNAL */
  logic signed [WpW-1:0] w3_q;
  logic signed [QW-1:0]  q3_q;
  assign w_full = ((WW'(u2_q) <<< 3) - WW'(u2_q)) + ((WW'(y2_q) <<< 3) - WW'(y2_q));
  assign w_top = w_full >>> DirFrac;
  always_ff @(posedge clk) begin
    w3_q <= w_top[WpW-1:0];
    q3_q <= QW'(u2_q) - QW'(nh2_q);
  end

  // r 2^z, e+, rinv, the hit and the tint wait for their stages.
  logic [RpW-1:0]     rp3, rp4;
  logic [EpW-1:0]     ep3;
  logic [RinvW-1:0]   rinv3;
  logic               hit4;
  logic [TintW-1:0]   tint5;
  logic [BounceW-1:0] bounces5;
  ts_artix_delay #(.W(RpW), .N(2)) rp_delay_3 (.clk, .in(rp1_q), .out(rp3));
  ts_artix_delay #(.W(RpW), .N(1)) rp_delay_4 (.clk, .in(rp3), .out(rp4));
  ts_artix_delay #(.W(EpW), .N(3)) ep_delay (.clk, .in(ep0_q), .out(ep3));
  ts_artix_delay #(.W(RinvW), .N(3)) rinv_delay (.clk, .in(rinv0_q), .out(rinv3));
  ts_artix_delay #(.W(1), .N(4)) hit_delay (.clk, .in(hit0_q), .out(hit4));
  ts_artix_delay #(.W(TintW), .N(5)) tint_delay (.clk, .in(tint0_q), .out(tint5));
  ts_artix_delay #(.W(BounceW), .N(5)) bounces_delay_5 (.clk, .in(bounces0_q), .out(bounces5));

  // ---- 4: the channel's quotient bits 3, 2; the normal's operands ---------------------------------------------
  logic [WpW:0]              step3, step2;
  logic [1:0]                qhi4_q;
  logic signed [WpW-1:0]     rem4_q;
  logic signed [TopW-1:0]    top4_q;
  logic signed [RinvSW-1:0]  rinv4_q;
  /* verilator lint_off UNUSEDSIGNAL */  // the top's bits above 18 are its sign (the model's check)
  logic signed [QW-1:0]      top_full;
  /* verilator lint_on UNUSEDSIGNAL */
  assign step3 = colour_step(w3_q, (RpW + 3)'(rp3) << 3);
  assign step2 = colour_step(step3[WpW-1:0], (RpW + 3)'(rp3) << 2);
  assign top_full = q3_q >>> (DirFrac + 1 + 32'(ep3));
  always_ff @(posedge clk) begin
    qhi4_q  <= {step3[WpW], step2[WpW]};
    rem4_q  <= step2[WpW-1:0];
    top4_q  <= top_full[TopW-1:0];
    rinv4_q <= $signed({1'b0, rinv3});
  end

  // ---- 5: the channel; the normal's product -------------------------------------------------------------------
  logic [WpW:0]          step1, step0;
  logic [3:0]            quot, base5_q;
  logic signed [P3W-1:0] p3_q;
  assign step1 = colour_step(rem4_q, (RpW + 3)'(rp4) << 1);
  assign step0 = colour_step(step1[WpW-1:0], (RpW + 3)'(rp4));
  assign quot = {qhi4_q, step1[WpW], step0[WpW]};
  always_ff @(posedge clk) begin
    if (!hit4) base5_q <= Background[4*(2-ch_q[4])+:4];
    else if (quot == 4'd15) base5_q <= 4'd14;
    else base5_q <= quot;
    p3_q <= rinv4_q * top4_q;
  end

  // ---- 6: c T_k; n_k ------------------------------------------------------------------------------------------
  logic [TintW-1:0]       tint_used;
  logic [XW-1:0]          x6_q;
  logic signed [DirW-1:0] n6_q;
  logic signed [NW-1:0]   n_full;
  /* verilator lint_off UNUSEDSIGNAL */  // the product's low 16 bits are the model's shift
  logic signed [P3W-1:0]  p3_shifted;
  /* verilator lint_on UNUSEDSIGNAL */
  assign tint_used = bounces5 == '0 ? TintW'(1) : tint5;  // the model shades without the tint then
  assign p3_shifted = p3_q >>> (DirFrac - 1);
  assign n_full = p3_shifted[NW-1:0];
  always_ff @(posedge clk) begin
    x6_q <= ((base5_q[0] ? XW'(tint_used) : '0) + (base5_q[1] ? XW'(tint_used) << 1 : '0)) +
            ((base5_q[2] ? XW'(tint_used) << 2 : '0) + (base5_q[3] ? XW'(tint_used) << 3 : '0));
    n6_q <= saturate(32'(n_full));
  end

  // ---- 7: the tint's quotient bits 3, 2; d.n ------------------------------------------------------------------
  logic [BounceW-1:0]     bounces6, bounces7;
  logic signed [DirW-1:0] d6;
  ts_artix_delay #(.W(BounceW), .N(1)) bounces_delay_6 (.clk, .in(bounces5), .out(bounces6));
  ts_artix_delay #(.W(BounceW), .N(1)) bounces_delay_7 (.clk, .in(bounces6), .out(bounces7));
  ts_artix_delay #(.W(DirW), .N(6)) d_delay_6 (.clk, .in(d0_q), .out(d6));

  logic [XW-1:0]         scale6, scale7;
  logic [XW:0]           tstep3, tstep2;
  logic [1:0]            thi7_q;
  logic [XW-1:0]         trem7_q;
  logic signed [AccW-1:0] acc7_q;
  assign scale6 = XW'(scale_of(bounces6));
  assign tstep3 = tint_step(x6_q, scale6 << 3);
  assign tstep2 = tint_step(tstep3[XW-1:0], scale6 << 2);
  always_ff @(posedge clk) begin
    thi7_q  <= {tstep3[XW], tstep2[XW]};
    trem7_q <= tstep2[XW-1:0];
    acc7_q  <= (ch_q[6] == 2'd0 ? '0 : acc7_q) + AccW'(n6_q * d6);
  end

  // ---- 8: the tint's bits 1, 0: the channel's colour; d.n / 2^17 after channel 2 ------------------------------
  logic [XW:0]           tstep1, tstep0;
  logic [3:0]            colour8;
  logic signed [DirW-1:0] ndn8_q;  // -(d.n): the product below then adds, as the DSP48E1's post-adder does
  /* verilator lint_off UNUSEDSIGNAL */  // d.n's low 17 bits are the model's shift
  logic signed [AccW-1:0] acc_shifted;
  /* verilator lint_on UNUSEDSIGNAL */
  assign scale7 = XW'(scale_of(bounces7));
  assign tstep1 = tint_step(trem7_q, scale7 << 1);
  assign tstep0 = tint_step(tstep1[XW-1:0], scale7);
  assign colour8 = {thi7_q, tstep1[XW], tstep0[XW]};
  assign acc_shifted = acc7_q >>> DirFrac;
  always_ff @(posedge clk) begin
    if (v_q[7] && ch_q[7] == 2'd2) ndn8_q <= -saturate(32'($signed(acc_shifted[DnW-1:0])));
  end

  // ---- 11: d_k 2^16 + 2^15 - 1 + (-(d.n)) n_k -----------------------------------------------------------------
  logic signed [DirW-1:0] n10, d10;
  logic signed [P5W-1:0]  p5_q;
  ts_artix_delay #(.W(DirW), .N(4)) n_delay (.clk, .in(n6_q), .out(n10));
  ts_artix_delay #(.W(DirW), .N(4)) d_delay_10 (.clk, .in(d6), .out(d10));
  always_ff @(posedge clk) begin
    p5_q <= ((P5W'(d10) <<< (DirFrac - 1)) | P5W'((1 << (DirFrac - 2)) - 1)) + ndn8_q * n10;  // no carry: an or
  end

  // ---- 12: d'_k -----------------------------------------------------------------------------------------------
  logic signed [DirW-1:0] d_out;
  /* verilator lint_off UNUSEDSIGNAL */  // the low 16 bits are the model's shift
  logic signed [P5W-1:0]  p5_shifted;
  /* verilator lint_on UNUSEDSIGNAL */
  assign p5_shifted = p5_q >>> (DirFrac - 1);
  assign d_out = saturate(32'($signed(p5_shifted[DoutW-1:0])));

  // ---- the tint's product T_k a_k (stages 1, 2), in LUTs: a sum of shifted copies of T_k ----------------------
  (* mem2reg *) logic [TintW-1:0] pair1_q [4];
  logic [TintW-1:0] tint2_q;
  always_ff @(posedge clk) begin
    for (int i = 0; i < 4; i++) begin
      pair1_q[i] <= (albedo0_q[2*i] ? TintW'(tint0_q[ReflTintW-1:0]) << (2 * i) : '0) +
                    (albedo0_q[2*i+1] ? TintW'(tint0_q[ReflTintW-1:0]) << (2 * i + 1) : '0);
    end
    tint2_q <= (pair1_q[0] + pair1_q[1]) + (pair1_q[2] + pair1_q[3]);
  end

  // ---- the colour: channel 2's at stage ColourOut ------------------------------------------------------------
  logic [3:0]       colour_pad;
  logic [TAG_W-1:0] ctag, rtag;
  logic             creflect, rreflect;
  logic [BounceW-1:0] rbounces;
  if (ColourPad == 0) begin : g_colour_now
    assign colour_pad = colour8;
  end else begin : g_colour_pad
    ts_artix_delay #(.W(4), .N(ColourPad)) colour_delay (.clk, .in(colour8), .out(colour_pad));
  end
  ts_artix_delay #(.W(TAG_W + 1), .N(ColourOut - 1)) colour_tag_delay (.clk, .in({tag0_q, reflect0_q}),
                                                                          .out({ctag, creflect}));
  logic             colour_valid_q;
  logic [11:0]      colour_q;  // a channel's nibble shifts in at the bottom: red is on top after blue
  logic [TAG_W-1:0] colour_tag_q;
  always_ff @(posedge clk) begin
    if (rst) colour_valid_q <= 1'b0;
    else colour_valid_q <= v_q[ColourOut-1] && ch_q[ColourOut-1] == 2'd2 && !creflect;
    if (v_q[ColourOut-1]) colour_q <= {colour_q[7:0], colour_pad};
    colour_tag_q <= ctag;
  end
  assign out_colour_valid = colour_valid_q;
  assign out_colour = colour_q;
  assign out_colour_tag = colour_tag_q;

  // ---- the ray: channel k's fields at stage RayOut, channel 2's with the event's -----------------------------
  logic signed [DirW-1:0]    d_pad;
  logic [OriginW-1:0]        o_pad;
  logic [TintW-1:0]          tint_pad;
  /* verilator lint_off UNUSEDSIGNAL */  // o'_k: the sum's bits 17..40 (the model's check: 24 bits)
  logic signed [P6W-1:0]     p6_shifted;
  /* verilator lint_on UNUSEDSIGNAL */
  assign p6_shifted = p6_q >>> DirFrac;
  if (RayPad == 0) begin : g_ray_now
    assign d_pad = d_out;
  end else begin : g_ray_pad
    ts_artix_delay #(.W(DirW), .N(RayPad)) d_out_delay (.clk, .in(d_out), .out(d_pad));
  end
  ts_artix_delay #(.W(OriginW), .N(RayOut - 2)) o_out_delay (.clk, .in(p6_shifted[OriginW-1:0]), .out(o_pad));
  ts_artix_delay #(.W(TintW), .N(RayOut - 3)) tint_out_delay (.clk, .in(tint2_q), .out(tint_pad));
  ts_artix_delay #(.W(TAG_W + 1 + BounceW), .N(RayOut - 1)) ray_tag_delay (
      .clk, .in({tag0_q, reflect0_q, bounces0_q}), .out({rtag, rreflect, rbounces}));

  logic                   ray_valid_q;
  logic [3*OriginW-1:0]   ray_o_q;
  logic [3*DirW-1:0]      ray_d_q;
  logic [3*TintW-1:0]     ray_tint_q;
  logic [BounceW-1:0]     ray_bounces_q;
  logic [TAG_W-1:0]       ray_tag_q;
  always_ff @(posedge clk) begin
    if (rst) ray_valid_q <= 1'b0;
    else ray_valid_q <= v_q[RayOut-1] && ch_q[RayOut-1] == 2'd2 && rreflect;
    for (int k = 0; k < Channels; k++) begin
      if (v_q[RayOut-1] && ch_q[RayOut-1] == 2'(k)) begin
        ray_o_q[k*OriginW+:OriginW] <= o_pad;
        ray_d_q[k*DirW+:DirW]       <= d_pad;
        ray_tint_q[k*TintW+:TintW]  <= tint_pad;
      end
    end
    ray_bounces_q <= rbounces + BounceW'(1);
    ray_tag_q     <= rtag;
  end
  assign out_ray_valid = ray_valid_q;
  assign out_ray_o = ray_o_q;
  assign out_ray_d = ray_d_q;
  assign out_ray_tint = ray_tint_q;
  assign out_ray_bounces = ray_bounces_q;
  assign out_ray_tag = ray_tag_q;

  // Busy: a register here may change at the next clock edge only while an event is on its way (its channels in the
  // stages, or still to be taken from chan1_q, chan2_q) or an output is valid (it falls at that edge); otherwise
  // every register holds or reloads a value no output is read with (the delays' words and pointers included).
  assign busy = |v_q || sel1_q || sel2_q || colour_valid_q || ray_valid_q;
endmodule
