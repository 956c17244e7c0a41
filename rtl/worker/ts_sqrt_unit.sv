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
    logic [MW:0]      c_s    [N+1];
    logic [N:0]       x_s    [N+1];
    logic [MW-1:0]    m_s    [N+1];
    logic [ZW-1:0]    e_s    [N+1];
    logic             zero_s [N+1];
    logic             valid_s[N+1];
    logic [TAG_W-1:0] tag_s  [N+1];

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
endmodule
