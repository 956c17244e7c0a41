// ts_path_surface: a sphere's surface as the path preset's bounce reads it (PathSurface), prepared from the wire's
// surface word as the receiver writes the sphere, once per world. C++ model: path_surface
// (src/tripsitter/device/path_kernel.cpp), bit for bit; docs/device.md, "The path preset", gives the fields' use.
//   albedo_k   = a_k 257 + (a_k >> 7) for a byte a_k (0 .. 65536, times 2^-16)
//   ior        = the wire's index of refraction (u4.12) clamped to 1024 .. 32768 (the receiver refuses others)
//   straight   = ior == 4096 (an index of exactly 1: the ray passes on unchanged)
//   eta_enter  = (2^26 + floor(ior / 2)) / ior, rounded down: round(2^14 / (ior / 2^12))
//   eta_leave  = 4 ior (ior / 2^12 times 2^14)
//   r0         = ((ior - 4096)^2 2^14 + floor((ior + 4096)^2 / 2)) / (ior + 4096)^2, rounded down: Schlick's
//                ((n - 1) / (n + 1))^2 times 2^14, rounded
// Material and fuzz pass through. No multiplier: a sphere's record arrives over SPI (at least 64 clocks a byte), so
// one addition a cycle is plenty. The two squares take 16 shift-and-add steps (LSB first, the multiplicand
// shifting up); eta_enter 17 restoring steps (its quotient is below 2^17: 2^26 + ior / 2 < 2^17 ior as ior >=
// 1024), run beside them; r0 15 restoring steps once the squares are done (below 2^15: the dividend is below
// 2^14 S + S / 2 for S = (ior + 4096)^2). A restoring division of N by D with a quotient below 2^Q starts from the
// remainder N >> Q, which is below D, and shifts in N's bits Q - 1 .. 0, subtracting D whenever it can.
//
// Timing (ts_artix_prepare's): ready is high when the block is idle (after reset, and from the done cycle on). A
// start in a cycle t with ready takes the word; done is high in cycle t + Cycles (33) alone, with the outputs valid
// in that cycle (they hold until the cycle after the next start). A start in the done cycle is taken: a surface
// every 33 cycles. A start without ready is ignored.
//   t + 1 .. 16   the squares' steps; eta_enter's first 16
//   t + 17        eta_enter's last step; r0's dividend and divisor loaded
//   t + 18 .. 32  r0's steps
//   t + 33        done
module ts_path_surface (
    input  logic            clk,
    input  logic            rst,
    input  logic            start,
    input  logic [1:0]      in_material,   // the wire's codes: 0 lambertian, 1 metal, 2 dielectric
    input  logic [23:0]     in_albedo,     // r, g, b bytes from the low bits
    input  logic [15:0]     in_fuzz,
    input  logic [15:0]     in_ior,        // u4.12
    output logic            ready,
    output logic            done,
    output logic [1:0]      out_material,
    output logic [3*17-1:0] out_albedo,    // r, g, b from the low bits, times 2^16
    output logic [15:0]     out_fuzz,
    output logic [17:0]     out_eta_enter, // times 2^14
    output logic [17:0]     out_eta_leave,
    output logic [14:0]     out_r0,        // times 2^14
    output logic            out_straight
);
  localparam int SquareSteps = 16, EtaSteps = 17, R0Steps = 15;
  localparam int Cycles = EtaSteps + 1 + R0Steps;
  localparam logic [15:0] IorMin = 16'd1024, IorMax = 16'd32768, One = 16'd4096;

  logic [5:0] step_q;  // 0: idle; else the cycle of the work, 1 .. Cycles
  logic       busy;
  assign busy  = step_q != '0;
  assign ready = !busy || step_q == 6'(Cycles);
  assign done  = step_q == 6'(Cycles);
  wire   take  = start && ready;

  // The clamped index, its distance from 1 and its sum with 1 (both below 2^16).
  wire [15:0] ior  = in_ior < IorMin ? IorMin : in_ior > IorMax ? IorMax : in_ior;
  wire [15:0] diff = ior >= One ? ior - One : One - ior;
  wire [16:0] sum  = {1'b0, ior} + 17'(One);

  // The squares: LSB first, the multiplicand shifting up.
  logic [15:0] dm_q;                // diff's bits still to take
  logic [16:0] sm_q;
  logic [31:0] dx_q, dsq_q;         // diff 2^i; diff^2 so far (below 2^30)
  logic [32:0] sx_q, ssq_q;         // sum 2^i; sum^2 so far (below 2^31)
  // eta_enter: N = 2^26 + floor(ior / 2), D = ior.
  logic [26:0] en_q;                // N, its bits shifted in from the top
  logic [15:0] er_q;                // the remainder, below D <= 2^15
  logic [15:0] ed_q;
  logic [16:0] eq_q;
  // r0: N = diff^2 2^14 + floor(sum^2 / 2), D = sum^2.
  logic [44:0] rn_q;
  logic [30:0] rr_q;                // the remainder, below D < 2^31
  logic [30:0] rd_q;
  logic [14:0] rq_q;

  wire [16:0] er_next = {er_q, en_q[26]};
  wire [31:0] rr_next = {rr_q, rn_q[44]};
  wire [43:0] r0_num  = {dsq_q[29:0], 14'd0} + 44'(ssq_q[30:1]);

  always_ff @(posedge clk) begin
    if (rst) step_q <= '0;
    else if (take) step_q <= 6'd1;
    else if (step_q == 6'(Cycles)) step_q <= '0;
    else if (busy) step_q <= step_q + 6'd1;
  end

  always_ff @(posedge clk) begin
    if (take) begin
      out_material  <= in_material;
      for (int k = 0; k < 3; k++)
        out_albedo[k*17+:17] <= {1'b0, in_albedo[k*8+:8], 8'd0} + {9'd0, in_albedo[k*8+:8]}
                                + {16'd0, in_albedo[k*8+7]};
      out_fuzz      <= in_fuzz;
      out_eta_leave <= {ior, 2'b00};
      out_straight  <= ior == One;
      dm_q  <= diff;
      sm_q  <= sum;
      dx_q  <= {16'd0, diff};
      sx_q  <= {16'd0, sum};
      dsq_q <= '0;
      ssq_q <= '0;
      // 2^26 + floor(ior / 2), its top 10 bits (>> 17) the first remainder.
      {er_q, en_q} <= {16'd0, 27'(28'h4000000 + 28'(ior[15:1]))} << 10;
      ed_q  <= ior;
      eq_q  <= '0;
    end else begin
      if (step_q >= 6'd1 && step_q <= 6'(SquareSteps)) begin
        dsq_q <= dsq_q + (dm_q[0] ? dx_q : '0);
        ssq_q <= ssq_q + (sm_q[0] ? sx_q : '0);
        dm_q  <= dm_q >> 1;
        sm_q  <= sm_q >> 1;
        dx_q  <= dx_q << 1;
        sx_q  <= sx_q << 1;
      end
      if (step_q >= 6'd1 && step_q <= 6'(EtaSteps)) begin
        en_q <= en_q << 1;
        er_q <= 16'(er_next >= {1'b0, ed_q} ? er_next - {1'b0, ed_q} : er_next);
        eq_q <= {eq_q[15:0], er_next >= {1'b0, ed_q}};
      end
      if (step_q == 6'(EtaSteps)) begin
        // The squares are done: r0's dividend, its top 30 bits (>> 15) the first remainder.
        rd_q <= ssq_q[30:0];
        {rr_q, rn_q} <= {31'd0, 1'b0, r0_num} << 30;
        rq_q <= '0;
      end
      if (step_q > 6'(EtaSteps) && step_q < 6'(Cycles)) begin
        rn_q <= rn_q << 1;
        rr_q <= 31'(rr_next >= {1'b0, rd_q} ? rr_next - {1'b0, rd_q} : rr_next);
        rq_q <= {rq_q[13:0], rr_next >= {1'b0, rd_q}};
      end
    end
  end
  assign out_eta_enter = {1'b0, eq_q};
  assign out_r0        = rq_q;

  // Not read: the squares' top bits (diff^2 < 2^30, sum^2 < 2^31).
  /* verilator lint_off UNUSEDSIGNAL */
  logic unused;
  assign unused = ^dsq_q[31:30] ^ ssq_q[32];
  /* verilator lint_on UNUSEDSIGNAL */
endmodule
