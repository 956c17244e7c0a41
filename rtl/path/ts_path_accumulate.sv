// The path preset's accumulation into frame memory (src/tripsitter/device/path_kernel.h, path_pixel; frame_memory.h):
// a pixel's entry read-modified-written as its samples come in, one operation a cycle, 1 cycle later.
//
// An entry is 64 bits, {epoch 5, count 8, b, g, r 17 bits each} (the sums of the samples' 9-bit channels). An
// operation on a pixel's entry, any of:
//   open:  an entry of another epoch starts again empty in this one (a new world's frames accumulate apart), and
//          `traced` says whether the pixel takes this frame's spp samples (count + spp <= 255; else it has
//          converged and traces nothing);
//   add:   a sample's light (times 2^16) as 9-bit channels, min(511, (light + 64) >> 7), onto the sums;
//   close: count + spp.
// A traced pixel's frame is open + add, add, ..., add + close (spp = 1: all three at once); a converged one's is open.
module ts_path_accumulate #(
    parameter int TAG_W = 1
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             in_valid,
    input  logic             in_open,
    input  logic             in_add,
    input  logic             in_close,
    input  logic [63:0]      in_entry,
    input  logic [4:0]       in_epoch,   // the frame's
    input  logic [7:0]       in_spp,     // 1..255
    input  logic [3*17-1:0]  in_light,   // r, g, b from the low bits, 17 bits each, times 2^16 (at most 1.0)
    input  logic [TAG_W-1:0] in_tag,
    output logic             out_valid,
    output logic             out_traced, // an open's answer
    output logic [63:0]      out_entry,
    output logic [TAG_W-1:0] out_tag
);
  // A sample's channel: its light times 512, rounded, at most 511.
  function automatic logic [8:0] channel(input logic [16:0] light);
    logic [10:0] v;
    v = 11'((18'(light) + 18'd64) >> 7);
    channel = v > 11'd511 ? 9'd511 : 9'(v);
  endfunction

  logic [63:0] opened;
  logic [8:0]  after;  // the count with this frame's samples
  assign opened = in_open && in_entry[63:59] != in_epoch ? {in_epoch, 59'd0} : in_entry;
  assign after = 9'(opened[58:51]) + 9'(in_spp);

  always_ff @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= in_valid;
    out_traced <= after <= 9'd255;
    out_entry[63:59] <= opened[63:59];
    out_entry[58:51] <= in_close ? after[7:0] : opened[58:51];
    for (int k = 0; k < 3; k++)
      out_entry[k*17+:17] <= opened[k*17+:17] + (in_add ? 17'(channel(in_light[k*17+:17])) : 17'd0);
    out_tag <= in_tag;
  end
endmodule
