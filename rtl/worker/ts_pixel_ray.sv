// ts_pixel_ray: the camera ray of the pixel in column col (0..639) and row (0..479), (col - 320, row - 240, 320),
// as the C++ model's core::device_ray (core/screen.h) gives it: two subtractions, combinational. The x and y
// components come out DW bits wide, signed; with DW = 10 the top bit of x is dropped (-320..319 fit 10 bits). The
// z component is the constant 320, which each user holds as a localparam.
module ts_pixel_ray #(
    parameter int DW = 22
) (
    input  logic [9:0]           col,
    input  logic [8:0]           row,
    output logic signed [DW-1:0] dx,
    output logic signed [DW-1:0] dy
);
  /* verilator lint_off UNUSEDSIGNAL */  // with DW = 10 the direction drops x's top bit (see above)
  logic signed [10:0] x;  // -320..319
  /* verilator lint_on UNUSEDSIGNAL */
  logic signed [9:0] y;   // -240..239
  assign x = $signed({1'b0, col}) - 11'sd320;
  assign y = $signed({1'b0, row}) - 10'sd240;
  assign dx = DW'(x);
  assign dy = DW'(y);
endmodule
