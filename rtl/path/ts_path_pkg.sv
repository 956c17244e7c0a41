// What the path preset's blocks (rtl/path/) share: the model's rounding (approx::round_shift), and the random
// streams' step (PathRng::next).
package ts_path_pkg;
  // x >> s, rounded to nearest with ties away from zero (symmetric in sign), s >= 1.
  function automatic logic signed [63:0] round_shift(input logic signed [63:0] x, input int s);
    logic signed [63:0] half;
    half = 64'sd1 <<< (s - 1);
    if (x >= 0) round_shift = (x + half) >>> s;
    else round_shift = -((-x + half) >>> s);
  endfunction

  // One xorshift32 step, shifts 13, 17, 5.
  function automatic logic [31:0] xorshift32(input logic [31:0] s);
    logic [31:0] x;
    x = s ^ (s << 13);
    x = x ^ (x >> 17);
    xorshift32 = x ^ (x << 5);
  endfunction
endpackage
