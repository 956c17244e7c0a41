// ts_scene_memory: the device's scene memory, two copies of the world: the front copy that the workers read
// while a frame is drawn, and the back copy that the receiver writes. They swap during vertical blanking, and
// only when a new world waits, so a frame never mixes two worlds.
//
// C++ model: src/tripsitter/device/scene_memory.h (SceneMemory: valid, sequence, geometry, surfaces) and the
// pending flag, ready line and swap_if_pending of src/tripsitter/device/receiver.h/.cpp.
//
// Per sphere the memory holds what the mirror workers read (device/worker.h, kernel_surface): the geometry in
// the preset's raw fixed-point formats (x, y, z signed, X_W/Y_W/Z_W bits; radius unsigned, R_W bits), the metal
// flag (material code 1) and the albedo, 3 x 8 bits as on the wire (the reflected colour is base * albedo /
// 255 per bounce, so all 8 bits matter). Per copy: valid (a world was ever written), the sphere count and the
// sequence number. Not held: fuzz, ior and the content CRC (SceneMemory::content), which only the path preset
// uses.
//
// Read ports. Every worker reads its own sphere each clock: NREAD ports, each a registered read (data the clock
// after the address) of the front copy. Block RAM has two ports, so the memory is built as ceil(NREAD / 2)
// replicas, each replica two banks (copy 0 and copy 1) of one block RAM group: port A is the write port while
// the bank is the back copy and worker 2i's read port while it is the front copy (its address is muxed by the
// bank's role), port B is worker 2i+1's read port. The receiver's writes go to the back bank of every replica.
// So a pair of workers costs one replica of the two copies. Which bank is the front is one flip-flop; the
// swap changes only that.
//
// Ready line: high while no accepted world waits for the swap and none is being written (the model's ready()
// is !pending; here the receiver also lowers it while it copies an accepted world in, which the model does at
// once).
module ts_scene_memory #(
    parameter int X_W = 24,
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int MAX_SPHERES = 4096,
    parameter int NREAD = 2,
    parameter int AW = $clog2(MAX_SPHERES)  // derived: leave as it is
) (
    input  logic                   clk,
    input  logic                   rst,
    // The receiver's side: begin_write, then writes, then commit.
    input  logic                   begin_write,  // a world starts to overwrite the back copy
    input  logic                   we,
    input  logic [AW-1:0]          waddr,
    input  logic [X_W-1:0]         wx,
    input  logic [Y_W-1:0]         wy,
    input  logic [Z_W-1:0]         wz,
    input  logic [R_W-1:0]         wr,
    input  logic                   wmetal,
    input  logic [23:0]            walbedo,       // r, g, b from the high byte down
    input  logic                   commit,        // the back copy now holds a whole world: it is pending
    input  logic [AW:0]            commit_count,
    input  logic [31:0]            commit_sequence,
    output logic                   replaced,      // combinational: begin_write overwrites a world never shown
    // Vertical blanking.
    input  logic                   vblank_swap,   // one clock: swap the copies if a world is pending
    output logic                   ready,
    output logic                   pending,
    // The front copy.
    output logic                   front_valid,
    output logic [AW:0]            front_count,
    output logic [31:0]            front_sequence,
    input  logic [NREAD*AW-1:0]    rd_addr,
    output logic [NREAD*X_W-1:0]   rd_x,
    output logic [NREAD*Y_W-1:0]   rd_y,
    output logic [NREAD*Z_W-1:0]   rd_z,
    output logic [NREAD*R_W-1:0]   rd_r,
    output logic [NREAD-1:0]       rd_metal,
    output logic [NREAD*24-1:0]    rd_albedo
);
  localparam int SW = X_W + Y_W + Z_W + R_W + 1 + 24;  // one sphere's word
  localparam int DEPTH = 1 << AW;
  localparam int REPLICAS = (NREAD + 1) / 2;

  logic front_sel;    // which bank is the front copy
  logic front_sel_q;  // its value at the last read, to pick the bank the read data came from
  logic writing;
  logic swap;
  logic [1:0] meta_valid;
  logic [AW:0] meta_count[2];
  logic [31:0] meta_sequence[2];

  assign swap = vblank_swap && pending;
  assign replaced = begin_write && pending && !swap;
  assign ready = !pending && !writing;

  always_ff @(posedge clk) begin
    if (rst) begin
      front_sel <= 1'b0;
      front_sel_q <= 1'b0;
      pending <= 1'b0;
      writing <= 1'b0;
      meta_valid <= '0;
      meta_count[0] <= '0;
      meta_count[1] <= '0;
      meta_sequence[0] <= '0;
      meta_sequence[1] <= '0;
    end else begin
      front_sel_q <= front_sel;
      if (swap) front_sel <= ~front_sel;
      if (commit) begin
        // The receiver commits only after begin_write, and a swap needs a pending world, so the back copy
        // cannot change between its begin_write and its commit.
        pending <= 1'b1;
        writing <= 1'b0;
        meta_valid[~front_sel] <= 1'b1;
        meta_count[~front_sel] <= commit_count;
        meta_sequence[~front_sel] <= commit_sequence;
      end else if (begin_write) begin
        // A swap in the same clock moves the pending world to the front first; the write goes to the bank
        // that becomes the back copy.
        pending <= 1'b0;
        writing <= 1'b1;
      end else if (swap) begin
        pending <= 1'b0;
      end
    end
  end

  assign front_valid = meta_valid[front_sel];
  assign front_count = meta_count[front_sel];
  assign front_sequence = meta_sequence[front_sel];

  wire [SW-1:0] wdata = {walbedo, wmetal, wr, wz, wy, wx};

  // rd_word[p]: port p's data, a word of the front copy.
  logic [SW-1:0] rd_word[NREAD];

  for (genvar g = 0; g < REPLICAS; g++) begin : g_replica
    logic [SW-1:0] qa[2];
    /* verilator lint_off UNUSEDSIGNAL */
    logic [SW-1:0] qb[2];  // unused in the last replica when NREAD is odd
    /* verilator lint_on UNUSEDSIGNAL */
    for (genvar b = 0; b < 2; b++) begin : g_bank
      logic [SW-1:0] mem[DEPTH];
      wire is_back = (b == 1) ? ~front_sel : front_sel;  // bank b is the back copy when the front is the other
      // Port A: the receiver's write port while this bank is the back copy, worker 2g's read port otherwise.
      wire [AW-1:0] addr_a = is_back ? waddr : rd_addr[2*g*AW+:AW];
      always_ff @(posedge clk) begin
        if (we && is_back) mem[addr_a] <= wdata;
        qa[b] <= mem[addr_a];
      end
      if (2 * g + 1 < NREAD) begin : g_port_b
        // Port B: worker 2g+1's read port.
        always_ff @(posedge clk) qb[b] <= mem[rd_addr[(2*g+1)*AW+:AW]];
      end else begin : g_no_port_b
        assign qb[b] = '0;
      end
    end
    assign rd_word[2*g] = qa[front_sel_q];
    if (2 * g + 1 < NREAD) begin : g_word_b
      assign rd_word[2*g+1] = qb[front_sel_q];
    end
  end

  for (genvar p = 0; p < NREAD; p++) begin : g_port
    assign rd_x[p*X_W+:X_W] = rd_word[p][0+:X_W];
    assign rd_y[p*Y_W+:Y_W] = rd_word[p][X_W+:Y_W];
    assign rd_z[p*Z_W+:Z_W] = rd_word[p][X_W+Y_W+:Z_W];
    assign rd_r[p*R_W+:R_W] = rd_word[p][X_W+Y_W+Z_W+:R_W];
    assign rd_metal[p] = rd_word[p][X_W+Y_W+Z_W+R_W];
    assign rd_albedo[p*24+:24] = rd_word[p][X_W+Y_W+Z_W+R_W+1+:24];
  end
endmodule
