// ts_path_pixels: one path unit's pixels of a line (the artix path preset): each column's frame-memory entry, its
// samples summed into it as they end, and the entry final when the last one has. C++ model: path_pixel's entry
// (src/tripsitter/device/path_kernel.h, frame_memory.h) and the schedule's pixel port (artix::serve_pixel_port,
// DeviceUnits::pixel_port, src/tripsitter/device/artix_units.h); docs/rtl.md, "Path tracing blocks".
//
// The unit's columns are u, u + N, ...; column c's entry is at c >> K (K = floor(log2 N): the unit's columns are
// N >= 2^K apart, so no two share an address, and no divider is needed). Three banks, one row each, change roles at
// every line window's first cycle (`start`): the row being loaded (the next window's: its entries from frame memory
// as the camera gives its pixels), the row being worked (this window's), the row worked in the last window (read
// for the display and for frame memory while its line is shown).
//
// Load: an entry of another epoch starts empty in this one (a new world's frames accumulate apart); the column takes
// this frame's spp samples if its count + spp <= 255 (`ld_takes`, the same cycle), else it has converged and traces
// nothing. A bank word is {left 5, entry 64}: the samples still to end (spp, or 0 for a converged column), and the
// entry {epoch 5, count 8, b, g, r 17 bits each}.
//
// The port: one sample a cycle. A light out of the bounce stage goes in the cycle it comes (`lit_valid`, its light
// as min(511, (light + 64) >> 7) per channel); a cut path's end (no light) waits in a queue for a cycle with no light,
// in the order cut (the queue's front, or a cut that finds the port free in its own cycle). A sample taken in cycle
// T reads its column's word (the bank's registered read), adds its channels, one to the count and -1 to left in
// T + 1, and the word is written at the end of T + 1 (ts_artix_pkg::PixelLatency = 2: a sample taken in the window's
// cycle 3198 is its last to count); the sample after it on the same column takes the written word from a register,
// as the bank gives the old one in that cycle. Nothing is taken in the window's last cycle (`flush`), and the queue
// is emptied then. A column is final when left is 0 (`rd_final`). A column not final when its window closed (late)
// holds neither its old entry nor a new one: the model keeps a late pixel's entry as it was, so only final columns
// are to be written back to frame memory.
module ts_path_pixels #(
    parameter int N = ts_artix_pkg::Units,
    localparam int K = $clog2(N + 1) - 1,
    localparam int DEPTH = ((ts_artix_pkg::LineWidth - 1) >> K) + 1,
    localparam int AW = $clog2(DEPTH),
    localparam int WordW = 5 + 64
) (
    input  logic            clk,
    input  logic            rst,
    input  logic            start,
    input  logic            flush,
    // The epoch and samples per pixel (1..31) of the frame of the row being loaded.
    input  logic [4:0]      epoch,
    input  logic [4:0]      spp,
    // The next row's pixel: its column and its entry from frame memory.
    input  logic            ld_we,
    input  logic [9:0]      ld_col,
    input  logic [63:0]     ld_entry,
    output logic            ld_takes,
    // A sample's end: a light out of the bounce stage (r, g, b from the low bits, 18 bits each, times 2^16), or a
    // cut path (no light).
    input  logic            lit_valid,
    input  logic [9:0]      lit_col,
    input  logic [3*18-1:0] lit_light,
    input  logic            cut_valid,
    input  logic [9:0]      cut_col,
    // The last window's row: a column's entry and whether it is final, the cycle after it is asked.
    input  logic [9:0]      rd_col,
    output logic            rd_final,
    output logic [63:0]     rd_entry,
    output logic            overflow   // sticky: the cuts' queue overflowed
);
  // ---- the banks' roles: work k, load k + 1, last k + 2 (mod 3) ---------------------------------------------------
  function automatic logic [1:0] next_bank(input logic [1:0] b);
    next_bank = b == 2'd2 ? 2'd0 : b + 2'd1;
  endfunction
  logic [1:0] work_q;
  wire  [1:0] work = start ? next_bank(work_q) : work_q;
  wire  [1:0] load = next_bank(work);
  wire  [1:0] last = next_bank(load);
  always_ff @(posedge clk) begin
    if (rst) work_q <= 2'd0;
    else work_q <= work;
  end

  // ---- load ----------------------------------------------------------------------------------------------------
  wire [63:0] opened = ld_entry[63:59] != epoch ? {epoch, 59'd0} : ld_entry;
  wire [8:0]  after = 9'(opened[58:51]) + 9'(spp);
  assign ld_takes = after <= 9'd255;
  wire [WordW-1:0] ld_word = {ld_takes ? spp : 5'd0, opened};

  // ---- the port: a light in its cycle, else the first cut ----------------------------------------------------
  logic       q_empty;
  logic [9:0] q_front;
  wire        take_cut = !lit_valid && (!q_empty || cut_valid);
  ts_artix_fifo #(.W(10), .DEPTH(32)) cuts (
      .clk, .rst, .clear(flush),
      .push(cut_valid && !flush && (lit_valid || !q_empty)), .push_data(cut_col),
      .pop(!q_empty && !lit_valid && !flush), .front(q_front), .empty(q_empty), .overflow
  );
  wire       op_valid = !flush && (lit_valid || take_cut);
  wire [9:0] op_col = lit_valid ? lit_col : q_empty ? cut_col : q_front;

  function automatic logic [8:0] channel(input logic [17:0] light);
    logic [11:0] v;
    v = 12'((19'(light) + 19'd64) >> 7);
    channel = v > 12'd511 ? 9'd511 : 9'(v);
  endfunction

  // Stage 1: the word read; its sum written at the end of the cycle.
  logic          s1_valid;
  logic [1:0]    s1_bank;
  logic [AW-1:0] s1_addr;
  logic [26:0]   s1_ch;
  always_ff @(posedge clk) begin
    if (rst) s1_valid <= 1'b0;
    else s1_valid <= op_valid;
    s1_bank <= work;
    s1_addr <= AW'(op_col >> K);
    for (int k = 0; k < 3; k++) s1_ch[k*9+:9] <= lit_valid ? channel(lit_light[k*18+:18]) : 9'd0;
  end

  logic [3*WordW-1:0] bank_q;  // each bank's registered read, bank b's at [b WordW +: WordW]
  logic               wr_valid_q;
  logic [1:0]         wr_bank_q;
  logic [AW-1:0]      wr_addr_q;
  logic [WordW-1:0]   wr_word_q;
  wire  [WordW-1:0]   old_word = wr_valid_q && wr_bank_q == s1_bank && wr_addr_q == s1_addr
                                 ? wr_word_q : bank_q[s1_bank*WordW+:WordW];
  logic [WordW-1:0]   new_word;
  always_comb begin
    new_word[68:64] = old_word[68:64] - 5'd1;
    new_word[63:59] = old_word[63:59];
    new_word[58:51] = old_word[58:51] + 8'd1;
    for (int k = 0; k < 3; k++) new_word[k*17+:17] = old_word[k*17+:17] + 17'(s1_ch[k*9+:9]);
  end
  always_ff @(posedge clk) begin
    if (rst) wr_valid_q <= 1'b0;
    else wr_valid_q <= s1_valid;
    wr_bank_q <= s1_bank;
    wr_addr_q <= s1_addr;
    wr_word_q <= new_word;
  end

  // ---- the banks (one block RAM each) --------------------------------------------------------------------------
  wire [AW-1:0] ld_addr = AW'(ld_col >> K);
  wire [AW-1:0] op_addr = AW'(op_col >> K);
  wire [AW-1:0] rd_addr = AW'(rd_col >> K);
  for (genvar b = 0; b < 3; b++) begin : g_bank
    (* ram_style = "block" *) logic [WordW-1:0] mem [DEPTH];
    wire sum_we = s1_valid && s1_bank == 2'(b);
    always_ff @(posedge clk) begin
      if (sum_we) mem[s1_addr] <= new_word;
      else if (ld_we && load == 2'(b)) mem[ld_addr] <= ld_word;
      bank_q[b*WordW+:WordW] <= mem[work == 2'(b) ? op_addr : rd_addr];
    end
  end

  logic [1:0] last_q;
  always_ff @(posedge clk) last_q <= last;
  wire [WordW-1:0] read_word = bank_q[last_q*WordW+:WordW];
  assign rd_final = read_word[68:64] == 5'd0;
  assign rd_entry = read_word[63:0];
endmodule
