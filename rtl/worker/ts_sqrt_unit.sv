// The device's square-root unit as a datapath: the digit recurrence of Zhou & Hu, "A novel square root
// algorithm and its FPGA simulation" (J. Phys.: Conf. Ser. 1314, 2019), bit for bit the C++ model's
// device::SqrtUnit::operator() (src/tripsitter/device/sqrt_unit.h/.cpp; docs/device.md, "Square-root unit").
//
// out_root = round(x_N 2^e), where the input D (WIDTH bits, unsigned) is normalised by an even shift into
// m = D / 4^e in [1/4, 1), held in 2N bits (lower bits truncated), and x_N comes out of N steps of
//     x_0 = 1/2, c_0 = x_0^2 = 1/4;   step k: c_k < m ? (x, c) += (2^-(k+1), x 2^-k + 2^-2(k+1))
//                                                    : (x, c) += (-2^-(k+1), -x 2^-k + 2^-2(k+1))
// so c_k = x_k^2 all along, with additions and shifts only, no multiplier. D = 0 gives 0. x_1 is 0 or 1, so
// x takes N + 1 bits and c 2N + 1 (x_N itself is odd and below 2^N).
//
// Stages (each a register; the same in both forms):
//   lzc      leading zero pairs z of D (a priority encoder over WIDTH/2 bit pairs): e = WIDTH/2 - z
//   shift    m = the top 2N bits of D 4^z 2^2N (a barrel shifter by an even amount), c_0, x_0
//   steps    N iterations of the recurrence
//   round    (x_N 2^e + 2^(N-1)) >> N: a barrel shifter and one addition
// PIPELINED = 1: one stage per iteration (constant shifts: x 2^-k is wiring), a new input every cycle,
// latency N + 3 cycles (the `wide` preset's worker). PIPELINED = 0: one iteration unit used N times,
// CYCLES_PER_ITERATION = 2 (the board's: the compare registered in one cycle, the conditional add in the
// next) or 1; it takes an input only when idle (in_ready) and answers N * CYCLES_PER_ITERATION + 3 cycles
// later. The iterative unit keeps x as xk = x_k 2^(N-k) (which is x 2^-k in units of 2^-2N) and the
// step's square sq = 2^(2N-2k-2), so that its shifts are constant too: xk_{k+1} = xk_k / 2 +- sq_k,
// sq_{k+1} = sq_k / 4, and xk_N = x_N.
//
// The one comparison of the recurrence is step_goes_up() below. The tests build a copy of this file with it flipped
// (c > m; rtl/worker/CMakeLists.txt writes the copy into the build tree): the planted fault they must catch
// (sqrt_unit_rtl_test.cpp, worker_rtl_test.cpp, device_rtl_test.cpp).
//
// A tag of TAG_W bits rides along with each input and comes out with its root (the worker's pair data).
module ts_sqrt_unit #(
    parameter int ITERATIONS = 16,           // N, 1..30 as SqrtUnit
    parameter int WIDTH = 96,                // input bits, 2..126
    parameter int PIPELINED = 1,
    parameter int CYCLES_PER_ITERATION = 2,  // iterative form only: 1 or 2
    parameter int TAG_W = 1
) (
    input  logic                       clk,
    input  logic                       rst,
    input  logic                       flush,      // drop every input in flight
    input  logic                       in_valid,
    output logic                       in_ready,   // always 1 when pipelined
    input  logic [WIDTH-1:0]           in_value,
    input  logic [TAG_W-1:0]           in_tag,
    output logic                       out_valid,  // one cycle per input
    output logic [(WIDTH+1)/2:0]       out_root,
    output logic [TAG_W-1:0]           out_tag
);
  localparam int N = ITERATIONS;
  localparam int MW = 2 * N;                   // m and c: 2N fractional bits
  localparam int WE = WIDTH + (WIDTH % 2);     // the input as whole bit pairs
  localparam int PAIRS = WE / 2;
  localparam int ZW = $clog2(PAIRS + 1);       // leading zero pairs, and e
  localparam int RW = PAIRS + 1;               // root bits: x_N 2^e rounded is at most 2^PAIRS

  // The recurrence's comparison: move x up when its square is below the normalised input.
  function automatic logic step_goes_up(input logic [MW:0] c, input logic [MW-1:0] m);
    step_goes_up = c < {1'b0, m};
  endfunction

  // Leading zero bit pairs of v (PAIRS when v is 0): the normalising shift is twice this.
  function automatic logic [ZW-1:0] leading_zero_pairs(input logic [WE-1:0] v);
    leading_zero_pairs = ZW'(PAIRS);
    for (int i = 0; i < PAIRS; i++)
      if (v[2*i+:2] != 2'b00) leading_zero_pairs = ZW'(PAIRS - 1 - i);
  endfunction

  // m: the top 2N bits of v 4^z, below the 2N guard bits (truncating, as the model's register does).
  function automatic logic [MW-1:0] normalised(input logic [WE-1:0] v, input logic [ZW-1:0] z);
    /* verilator lint_off UNUSEDSIGNAL */  // the bits below m are truncated
    logic [WE+MW-1:0] wide;
    /* verilator lint_on UNUSEDSIGNAL */
    wide = {v, {MW{1'b0}}} << (2 * z);
    normalised = wide[WE+MW-1-:MW];
  endfunction

  // round(x 2^e / 2^N): x shifted by e, plus a half, without the N fractional bits.
  function automatic logic [RW-1:0] rounded(input logic [N:0] x, input logic [ZW-1:0] e);
    /* verilator lint_off UNUSEDSIGNAL */  // the fractional bits are rounded away
    logic [N+PAIRS+1:0] scaled;
    /* verilator lint_on UNUSEDSIGNAL */
    scaled = ((N + PAIRS + 2)'(x) << e) + ((N + PAIRS + 2)'(1) << (N - 1));
    rounded = RW'(scaled[N+PAIRS+1:N]);
  endfunction

  // ---- normalisation, first half: the leading zero pairs (both forms) ----------------------------
  logic             lz_valid;
  logic [WE-1:0]    lz_value;
  logic [ZW-1:0]    lz_pairs;
  logic [TAG_W-1:0] lz_tag;
  logic             accept;

  assign accept = in_valid && in_ready;

  always_ff @(posedge clk) begin
    if (rst || flush) begin
      lz_valid <= 1'b0;
      lz_value <= '0;
      lz_pairs <= '0;
      lz_tag <= '0;
    end else begin
      lz_valid <= accept;
      lz_value <= WE'(in_value);
      lz_pairs <= leading_zero_pairs(WE'(in_value));
      lz_tag <= in_tag;
    end
  end

  if (PIPELINED != 0) begin : g_pipelined
    // ---- the shift, then one stage per iteration: stage k turns (c_k, x_k) into (c_k+1, x_k+1) ----
    (* mem2reg *) logic [MW:0]      c_s    [N+1];
    (* mem2reg *) logic [N:0]       x_s    [N+1];
    (* mem2reg *) logic [MW-1:0]    m_s    [N+1];
    (* mem2reg *) logic [ZW-1:0]    e_s    [N+1];
    (* mem2reg *) logic             zero_s [N+1];
    (* mem2reg *) logic             valid_s[N+1];
    (* mem2reg *) logic [TAG_W-1:0] tag_s  [N+1];

    always_ff @(posedge clk) begin  // the shift: m, e, and the start x_0 = 1/2, c_0 = 1/4
      if (rst || flush) begin
        c_s[0] <= '0;
        x_s[0] <= '0;
        m_s[0] <= '0;
        e_s[0] <= '0;
        zero_s[0] <= 1'b0;
        valid_s[0] <= 1'b0;
        tag_s[0] <= '0;
      end else begin
        c_s[0] <= (MW + 1)'(1) << (MW - 2);
        x_s[0] <= (N + 1)'(1) << (N - 1);
        m_s[0] <= normalised(lz_value, lz_pairs);
        e_s[0] <= ZW'(PAIRS) - lz_pairs;
        zero_s[0] <= lz_pairs == ZW'(PAIRS);
        valid_s[0] <= lz_valid;
        tag_s[0] <= lz_tag;
      end
    end

    for (genvar k = 0; k < N; k++) begin : g_step
      // x 2^-k, 2^-2(k+1) and 2^-(k+1) in units of 2^-2N, 2^-2N and 2^-N: wiring and constants.
      logic [MW:0] xk, step_sq;
      logic [N:0] step;
      logic up;
      assign xk = (MW + 1)'(x_s[k]) << (N - k);
      assign step_sq = (MW + 1)'(1) << (MW - 2 * k - 2);
      assign step = (N + 1)'(1) << (N - k - 1);
      assign up = step_goes_up(c_s[k], m_s[k]);
      always_ff @(posedge clk) begin
        if (rst || flush) begin
          c_s[k+1] <= '0;
          x_s[k+1] <= '0;
          m_s[k+1] <= '0;
          e_s[k+1] <= '0;
          zero_s[k+1] <= 1'b0;
          valid_s[k+1] <= 1'b0;
          tag_s[k+1] <= '0;
        end else begin
          c_s[k+1] <= up ? c_s[k] + xk + step_sq : c_s[k] + step_sq - xk;
          x_s[k+1] <= up ? x_s[k] + step : x_s[k] - step;
          m_s[k+1] <= m_s[k];
          e_s[k+1] <= e_s[k];
          zero_s[k+1] <= zero_s[k];
          valid_s[k+1] <= valid_s[k];
          tag_s[k+1] <= tag_s[k];
        end
      end
    end

    assign in_ready = 1'b1;
    always_ff @(posedge clk) begin  // the rounding
      if (rst || flush) begin
        out_valid <= 1'b0;
        out_root <= '0;
        out_tag <= '0;
      end else begin
        out_valid <= valid_s[N];
        out_root <= zero_s[N] ? '0 : rounded(x_s[N], e_s[N]);
        out_tag <= tag_s[N];
      end
    end
  end else begin : g_iterative
    // ---- the shift loads one iteration unit, used N times, CYCLES_PER_ITERATION cycles each --------
    localparam int KW = $clog2(N + 1);
    logic             busy;     // an input is in the unit, from its acceptance to its root
    logic             running;  // the iterations are under way
    logic [MW:0]      c, xk, sq;
    logic [MW-1:0]    m;
    logic [ZW-1:0]    e;
    logic             zero;
    logic [TAG_W-1:0] tag;
    logic [KW-1:0]    k;        // iterations done
    logic             phase;    // with two cycles per iteration: 0 compare, 1 add
    logic             up_q;     // the compare, registered
    logic             up;
    logic             do_step;  // this cycle ends an iteration
    logic             last_step;
    logic             x_valid;  // x_N is ready for rounding
    logic [N:0]       x_n;
    logic [MW:0]      xk_next;

    assign up = CYCLES_PER_ITERATION == 1 ? step_goes_up(c, m) : up_q;
    assign do_step = running && (CYCLES_PER_ITERATION == 1 || phase);
    assign last_step = do_step && k == KW'(N - 1);
    assign xk_next = up ? (xk >> 1) + sq : (xk >> 1) - sq;
    assign in_ready = !busy;

    always_ff @(posedge clk) begin
      if (rst || flush) begin
        busy <= 1'b0;
        running <= 1'b0;
        c <= '0;
        xk <= '0;
        sq <= '0;
        m <= '0;
        e <= '0;
        zero <= 1'b0;
        tag <= '0;
        k <= '0;
        phase <= 1'b0;
        up_q <= 1'b0;
        x_valid <= 1'b0;
        x_n <= '0;
        out_valid <= 1'b0;
        out_root <= '0;
        out_tag <= '0;
      end else begin
        if (accept) busy <= 1'b1;
        if (lz_valid) begin  // the shift: m, e, and x_0 = 1/2 (xk = 2^(2N-1)), c_0 = sq_0 = 1/4
          running <= 1'b1;
          c <= (MW + 1)'(1) << (MW - 2);
          xk <= (MW + 1)'(1) << (MW - 1);
          sq <= (MW + 1)'(1) << (MW - 2);
          m <= normalised(lz_value, lz_pairs);
          e <= ZW'(PAIRS) - lz_pairs;
          zero <= lz_pairs == ZW'(PAIRS);
          tag <= lz_tag;
          k <= '0;
          phase <= 1'b0;
        end else if (running) begin
          phase <= !phase;
          up_q <= step_goes_up(c, m);
          if (do_step) begin
            c <= up ? c + xk + sq : c + sq - xk;
            xk <= xk_next;
            sq <= sq >> 2;
            k <= k + KW'(1);
            phase <= 1'b0;
          end
          if (last_step) running <= 1'b0;
        end
        x_valid <= last_step;
        if (last_step) x_n <= (N + 1)'(xk_next);  // xk_N = x_N
        out_valid <= x_valid;  // the rounding
        if (x_valid) begin
          out_root <= zero ? '0 : rounded(x_n, e);
          out_tag <= tag;
          busy <= 1'b0;
        end
      end
    end
  end
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs sqrt_pipelined, sqrt_iterative,
  // sqrt_pipelined_95, sqrt_iterative_53; rtl/worker/proofs.tsv).
  //
  // The contract, for every input D (SqrtUnit in sqrt_unit.h: D normalised into M, the 2N-bit register, D / 4^e
  // truncated; x_N the odd 2j + 1 with (x_N - 1)^2 < M <= (x_N + 1)^2; the result x_N 2^(e - N) rounded), as
  // integers: D = 0 gives 0; below 4^N (e <= N) the result r is within one unit, (r - 1)^2 <= D <= (r + 1)^2;
  // above (e > N, h = 2^(e - N), r = x_N h) M's truncation adds at most h^2, (r - h)^2 + h^2 <= D < (r + h)^2 + h^2,
  // which (as r + h >= 2^(N - 1) h) gives |r - sqrt(D)| <= h + h / 2^N, inside the bound sqrt_unit_test.cpp
  // checks (RelativeErrorBoundForLargeInputs: 2^(e - N) + 2^(e + 1 - 2N) + 1/2).
  //
  // Proven step by step: after step k (2^(N - k) = g) the recurrence's c is x^2, and sqrt(M) lies in
  // (x - g, x + g], written with c only, (x +- g)^2 = c +- 2 g x + g^2, so that only p_square multiplies; the
  // normalised M, e and zero agree with D, carried beside each input (formal only).
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  localparam int FW = 2 * RW + 4;  // (r + h)^2 + h^2 and 4^N M
  localparam int CW = MW + 3;      // c +- 2 g x + g^2
  // z3 bit-blasts the squares (c = x^2, and r^2 in the contract) for every input in seconds only for small units
  // (N = 4, 15-bit inputs: 3 s; N = 6, 21 bits: 15 s; N = 8, 27 bits: 50 s, each two more bits of x about four
  // times longer): a unit beyond N = 8 or a 16-bit root leaves p_square, p_search (which needs c = x^2 to keep x in
  // range) and p_contract out, and its proof checks the rest, which has no product, for every input.
  localparam bit FSquares = N <= 8 && RW <= 16;

  // e of D: the least e with D < 4^e.
  function automatic logic [ZW-1:0] f_exponent(input logic [WE-1:0] d);
    f_exponent = '0;
    for (int i = 0; i < PAIRS; i++)
      if (d[2*i+:2] != 2'b00) f_exponent = ZW'(i + 1);
  endfunction

  // The contract of a result r of D, with (r +- h)^2 = r^2 +- 2 h r + h^2 (h a power of two) so that r^2 is the only
  // product.
  function automatic logic f_contract(input logic [WE-1:0] d, input logic [RW-1:0] r);
    logic [ZW-1:0] e, s;
    logic [FW-1:0] dw, rw, rr, h2;
    e  = f_exponent(d);
    s  = e - ZW'(N);
    dw = FW'(d);
    rw = FW'(r);
    rr = rw * rw;
    h2 = FW'(1) << {s, 1'b0};
    if (d == '0) begin
      f_contract = r == '0;
    end else if (e <= ZW'(N)) begin
      f_contract = (rw == '0 ? dw <= FW'(1) : rr - (rw << 1) + FW'(1) <= dw) && dw <= rr + (rw << 1) + FW'(1);
    end else begin
      f_contract = rw >= FW'(1) << s && rr - (rw << (s + ZW'(1))) + (h2 << 1) <= dw && dw < rr + (rw << (s + ZW'(1))) + (h2 << 1);
    end
  endfunction

  // The normalisation of D: zero, e, and M, the top 2N bits of D 4^(N - e) (D 4^N shifted right by 2e).
  function automatic logic f_normalised(input logic [WE-1:0] d, input logic [MW-1:0] m, input logic [ZW-1:0] e,
                                        input logic zero);
    logic [WE+MW-1:0] scaled;
    scaled = {d, {MW{1'b0}}} >> {e, 1'b0};
    if (d == '0) begin
      f_normalised = zero;
    end else begin
      f_normalised = !zero && e == f_exponent(d) && m[MW-1-:2] != 2'b00 && WE'(scaled >> MW) == '0 && scaled[MW-1:0] == m;
    end
  endfunction

  // The result of x_N (N fractional bits) and e: 0 if zero, else x_N 2^(e - N) rounded to nearest, ties up.
  function automatic logic f_rounded(input logic [N:0] x, input logic [ZW-1:0] e, input logic zero,
                                     input logic [RW-1:0] r);
    logic [RW+N:0] xw, rs, half;
    xw = (RW + N + 1)'(x);
    if (zero) begin
      f_rounded = r == '0;
    end else if (e >= ZW'(N)) begin
      f_rounded = (RW + N + 1)'(r) == xw << (e - ZW'(N));
    end else begin
      rs   = (RW + N + 1)'(r) << (ZW'(N) - e);             // r 2^(N - e), in x's units
      half = (RW + N + 1)'(1) << (ZW'(N) - e - ZW'(1));    // half a unit of r
      f_rounded = rs <= xw + half && xw + half < rs + (half << 1);
    end
  endfunction

  // After step k (0..N) with g = 2^(N - k): c = x^2, and (x - g)^2 < M <= (x + g)^2 (the left side only if x > g).
  function automatic logic f_square(input logic [MW:0] c, input logic [N:0] x);
    f_square = CW'(c) == CW'(x) * CW'(x);
  endfunction
  function automatic logic f_search(input logic [MW:0] c, input logic [N:0] x, input logic [MW-1:0] m,
                                    input int k);
    logic [CW-1:0] cw, gx2, g2;
    cw  = CW'(c);
    gx2 = CW'(x) << (N - k + 1);
    g2  = CW'(1) << (2 * (N - k));
    f_search = CW'(m) <= cw + gx2 + g2 && (CW'(x) <= CW'(1) << (N - k) || cw + g2 - gx2 < CW'(m));
  endfunction

  if (PIPELINED != 0) begin : g_f_pipelined
    logic [WE-1:0] f_lz_d;  // the input in the lz stage
    always_ff @(posedge clk) f_lz_d <= WE'(in_value);
    (* mem2reg *) logic [WE-1:0] f_d[N+2];  // the input of each stage, and of the result (f_d[N + 1])
    logic [N:0]    f_sq, f_srch;
    logic [N-1:0]  f_carried;
    logic [N:0]    f_x_q;  // x_N, e and zero of the result
    logic [ZW-1:0] f_e_q;
    logic          f_zero_q;
    always_ff @(posedge clk) begin
      f_x_q    <= g_pipelined.x_s[N];
      f_e_q    <= g_pipelined.e_s[N];
      f_zero_q <= g_pipelined.zero_s[N];
    end
    always_ff @(posedge clk) begin
      f_d[0] <= f_lz_d;
      for (int k = 0; k <= N; k++) f_d[k+1] <= f_d[k];
    end
    for (genvar k = 0; k <= N; k++) begin : g_stage
      assign f_sq[k]   = !g_pipelined.valid_s[k] || g_pipelined.zero_s[k]
                         || f_square(g_pipelined.c_s[k], g_pipelined.x_s[k]);
      assign f_srch[k] = !g_pipelined.valid_s[k] || g_pipelined.zero_s[k]
                         || f_search(g_pipelined.c_s[k], g_pipelined.x_s[k], g_pipelined.m_s[k], k);
      if (k < N) begin : g_carry
        // Stage k's M, e and zero a cycle ago.
        logic [MW-1:0] m_q;
        logic [ZW-1:0] e_q;
        logic          zero_q;
        always_ff @(posedge clk) begin
          m_q    <= g_pipelined.m_s[k];
          e_q    <= g_pipelined.e_s[k];
          zero_q <= g_pipelined.zero_s[k];
        end
        assign f_carried[k] = !g_pipelined.valid_s[k+1] || g_pipelined.m_s[k+1] == m_q
                              && g_pipelined.e_s[k+1] == e_q && g_pipelined.zero_s[k+1] == zero_q
                              && g_pipelined.e_s[k+1] <= ZW'(PAIRS);
      end
    end
    always_comb begin
      if (past_valid) begin
        // The leading zero pairs of D: rules out a wrong priority encoder.
        if (lz_valid) p_leading_zeros: assert (lz_value == f_lz_d && lz_pairs == ZW'(PAIRS) - f_exponent(f_lz_d));
        // The shift's M, e and zero are D's: rules out a wrong shift, a dropped bit pair, a wrong exponent.
        if (g_pipelined.valid_s[0]) begin
          p_normalised: assert (f_normalised(f_d[0], g_pipelined.m_s[0], g_pipelined.e_s[0], g_pipelined.zero_s[0]));
        end
        // ... which each step carries unchanged.
        p_carried: assert (&f_carried);
        // c = x^2: rules out a wrong update of c (a shift off by one, a sign).
        if (FSquares) p_square: assert (&f_sq);
        // sqrt(M) in (x - g, x + g]: rules out a flipped comparison, a wrong step.
        if (FSquares) p_search: assert (&f_srch);
        // The contract: rules out a wrong rounding or denormalisation.
        if (out_valid) begin
          p_rounding: assert (f_rounded(f_x_q, f_e_q, f_zero_q, out_root));
          if (FSquares) p_contract: assert (f_contract(f_d[N+1], out_root));
        end
      end
    end
  end else begin : g_f_iterative
    // The unit holds one input from its acceptance to its root: its D, captured at acceptance.
    localparam int FKW = $clog2(N + 1);  // g_iterative's KW
    logic [WE-1:0] f_d;
    always_ff @(posedge clk) if (accept) f_d <= WE'(in_value);
    // x after k steps (xk = x_k 2^(N - k)); after the last, x_n. The state's step count: k, or N with x_n.
    logic [N:0]    f_x;
    logic [FKW-1:0] f_k;
    logic          f_busy_ok, f_step_ok;
    assign f_k = g_iterative.x_valid ? FKW'(N) : g_iterative.k;
    assign f_x = g_iterative.x_valid ? g_iterative.x_n : (N + 1)'(g_iterative.xk >> (FKW'(N) - g_iterative.k));
    // busy is exactly one of: the input in the first stage, the iterations, x_N for rounding.
    assign f_busy_ok = g_iterative.busy == (lz_valid || g_iterative.running || g_iterative.x_valid)
                       && 2'(lz_valid) + 2'(g_iterative.running) + 2'(g_iterative.x_valid) <= 2'd1;
    // While iterating: k < N, the step's square sq = 2^(2N - 2k - 2), xk = x 2^(N - k) with no bits below (unless D
    // is 0, when x runs below 0 and the result is 0 anyway; and only with the squares, which keep x in range), and
    // with two cycles an iteration, the compare registered in phase 0 is c < m.
    assign f_step_ok = !g_iterative.running
                       || g_iterative.k < FKW'(N) && g_iterative.sq == (MW + 1)'(1) << (MW - 2 - 2 * 32'(g_iterative.k))
                          && (!FSquares || g_iterative.zero || g_iterative.xk == (MW + 1)'(f_x) << (FKW'(N) - g_iterative.k))
                          && (CYCLES_PER_ITERATION == 1 ? !g_iterative.phase
                                                        : !g_iterative.phase || g_iterative.up_q == step_goes_up(g_iterative.c, g_iterative.m));
    always_comb begin
      if (past_valid) begin
        // The leading zero pairs of D: rules out a wrong priority encoder.
        if (lz_valid) p_leading_zeros: assert (lz_value == f_d && lz_pairs == ZW'(PAIRS) - f_exponent(f_d));
        // The control: one input at a time, and the iteration's registers consistent: rules out a second input
        // taken while busy, an iteration too many or too few, a compare used from the wrong cycle.
        p_control: assert (f_busy_ok && f_step_ok);
        if (g_iterative.running || g_iterative.x_valid) begin
          // M, e and zero are D's: rules out a wrong shift, a dropped bit pair, a wrong exponent.
          p_normalised: assert (f_normalised(f_d, g_iterative.m, g_iterative.e, g_iterative.zero));
          if (!g_iterative.zero) begin
            // c = x^2: rules out a wrong update of c (a shift off by one, a sign).
            if (FSquares) p_square: assert (f_square(g_iterative.c, f_x));
            // sqrt(M) in (x - g, x + g]: rules out a flipped comparison, a wrong step.
            if (FSquares) p_search: assert (f_search(g_iterative.c, f_x, g_iterative.m, 32'(f_k)));
          end
        end
        if (out_valid) begin
          // r is x_N 2^(e - N) rounded to nearest: rules out a wrong rounding or denormalisation.
          p_rounding: assert (f_rounded(g_iterative.x_n, g_iterative.e, g_iterative.zero, out_root));
          // The contract, for every D.
          if (FSquares) p_contract: assert (f_contract(f_d, out_root));
        end
      end
    end
  end
`endif
endmodule
