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
  (* mem2reg *) logic [SW-1:0] rd_word[NREAD];

  for (genvar g = 0; g < REPLICAS; g++) begin : g_replica
    (* mem2reg *) logic [SW-1:0] qa[2];
    /* verilator lint_off UNUSEDSIGNAL */
    (* mem2reg *) logic [SW-1:0] qb[2];  // unused in the last replica when NREAD is odd
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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs scene_memory, scene_memory_odd). Every
  // input is free. The properties that need the receiver to keep the write protocol hold while it has kept it
  // (f_proto_ok, below), which ts_rx_commit guarantees (its p_sm_protocol); nothing is assumed but the reset.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The write protocol: begin_write opens a world when none is open, writes and the commit come only while one is
  // open (from the clock after its begin_write), and the commit closes it. f_proto_ok falls for good at a breach.
  // f_back_complete / f_front_complete: the back / front copy holds a whole world, committed after its last
  // begin_write and not written since. f_unshown: an accepted world (begun, or committed) no swap has shown yet.
  // (One bit per role rather than a bit per bank with a variable index: z3 4.8 was far slower on that.)
  // f_waiting: a committed world waits for the swap (not shown, not overwritten); f_swap: the specification's swap,
  // in a clock of vertical blanking while a world waits. (The bank bits follow the block's own swap, front_sel's.)
  logic f_open, f_proto_ok, f_back_complete, f_front_complete, f_unshown, f_waiting;
  wire f_swap = vblank_swap && f_waiting;
  always_ff @(posedge clk) begin
    if (rst) begin
      f_open <= 1'b0;
      f_proto_ok <= 1'b1;
      f_back_complete <= 1'b0;
      f_front_complete <= 1'b0;
      f_unshown <= 1'b0;
      f_waiting <= 1'b0;
    end else begin
      if ((begin_write && (f_open || commit)) || ((we || commit) && !f_open)) f_proto_ok <= 1'b0;
      if (begin_write) f_open <= 1'b1;
      else if (commit) f_open <= 1'b0;
      if (swap) f_front_complete <= f_back_complete;
      if (commit) f_back_complete <= 1'b1;
      else if (begin_write || (we && !swap)) f_back_complete <= 1'b0;
      else if (swap) f_back_complete <= f_front_complete;
      if (begin_write || commit) f_unshown <= 1'b1;
      else if (f_swap) f_unshown <= 1'b0;
      if (commit) f_waiting <= 1'b1;
      else if (begin_write || vblank_swap) f_waiting <= 1'b0;
    end
  end

  // The first word and the last of both banks (all of them in the proof's instance; a ghost copy per address, as
  // z3 4.8 is erratic, seconds to minutes, with a solver-chosen (* anyconst *) address into the memories): the word
  // last written into the bank while it was the back copy (f_known: one was written since the reset; the memory
  // itself has no reset), and a read of that address from the front copy: what it must return the next clock, on
  // port A (0) and port B (1) of the first replica and on the last port.
  for (genvar i = 0; i < 2; i++) begin : f_addr
    localparam int a = (i == 0) ? 0 : DEPTH - 1;
    logic [SW-1:0] f_word0, f_word1;
    logic f_known0, f_known1;
    logic [2:0] f_read_q;
    logic [SW-1:0] f_expect_q;
    always_ff @(posedge clk) begin
      if (rst) begin
        f_known0 <= 1'b0;
        f_known1 <= 1'b0;
      end else if (we && waddr == AW'(a)) begin
        if (front_sel) begin
          f_known0 <= 1'b1;
          f_word0 <= wdata;
        end else begin
          f_known1 <= 1'b1;
          f_word1 <= wdata;
        end
      end
      f_read_q[0] <= !rst && (front_sel ? f_known1 : f_known0) && rd_addr[0+:AW] == AW'(a);
      f_read_q[1] <= !rst && (front_sel ? f_known1 : f_known0) && rd_addr[(NREAD > 1 ? AW : 0)+:AW] == AW'(a);
      f_read_q[2] <= !rst && (front_sel ? f_known1 : f_known0) && rd_addr[(NREAD-1)*AW+:AW] == AW'(a);
      f_expect_q <= front_sel ? f_word1 : f_word0;
    end
  end
  wire [SW-1:0] f_first_word0 = f_addr[0].f_word0, f_first_word1 = f_addr[0].f_word1;
  wire [SW-1:0] f_last_word0 = f_addr[1].f_word0, f_last_word1 = f_addr[1].f_word1;
  always_comb begin
    if (past_valid) begin
      // Invariant that makes the induction close: both banks of the first and the last replica hold the ghost
      // words (the receiver's writes go to every replica).
      p_mem_words: assert ((!f_addr[0].f_known0 || (g_replica[0].g_bank[0].mem[0] == f_first_word0
                                                   && g_replica[REPLICAS-1].g_bank[0].mem[0] == f_first_word0))
                           && (!f_addr[0].f_known1 || (g_replica[0].g_bank[1].mem[0] == f_first_word1
                                                      && g_replica[REPLICAS-1].g_bank[1].mem[0] == f_first_word1))
                           && (!f_addr[1].f_known0
                               || (g_replica[0].g_bank[0].mem[DEPTH-1] == f_last_word0
                                   && g_replica[REPLICAS-1].g_bank[0].mem[DEPTH-1] == f_last_word0))
                           && (!f_addr[1].f_known1
                               || (g_replica[0].g_bank[1].mem[DEPTH-1] == f_last_word1
                                   && g_replica[REPLICAS-1].g_bank[1].mem[DEPTH-1] == f_last_word1)));
      // Every read port returns the front copy's word as last written while that bank was the back copy: the
      // receiver's writes never reach the copy on screen, and a read in the clock of a swap comes from the copy
      // that was the front when the address was given. Rules out a write into the front copy, or data from the
      // wrong bank (the read multiplexer a clock off).
      p_read_front: assert ((!f_addr[0].f_read_q[0] || rd_word[0] == f_addr[0].f_expect_q)
                            && (!f_addr[0].f_read_q[1] || rd_word[NREAD > 1 ? 1 : 0] == f_addr[0].f_expect_q)
                            && (!f_addr[0].f_read_q[2] || rd_word[NREAD-1] == f_addr[0].f_expect_q)
                            && (!f_addr[1].f_read_q[0] || rd_word[0] == f_addr[1].f_expect_q)
                            && (!f_addr[1].f_read_q[1]
                                || rd_word[NREAD > 1 ? 1 : 0] == f_addr[1].f_expect_q)
                            && (!f_addr[1].f_read_q[2] || rd_word[NREAD-1] == f_addr[1].f_expect_q));
    end
  end

  always_comb begin
    if (past_valid) begin
      // Invariants that make the induction close (each a property): the world waiting for the swap and the world
      // shown are whole; a world is being written exactly while one is open; pending is the waiting world.
      if (f_proto_ok) begin
        p_pending_complete: assert (!pending || f_back_complete);
        p_front_complete: assert (!front_valid || f_front_complete);
        p_writing_open: assert (writing == f_open);
        p_pending_closed: assert (!(pending && writing));
        p_pending_waiting: assert (pending == f_waiting);
        // The ready line (docs/link_format.md, "Transfers, the ready line and link time", "Device to host"): high
        // exactly when no accepted world waits to be shown, including one being written in. Rules out a credit
        // while an accepted world waits, and a ready line left low after the swap that showed it.
        p_ready_rule: assert (ready == !f_unshown);
        // worlds_replaced's event: a begin_write that overwrites a committed world no swap has shown, and only
        // that. Rules out counting a world the swap in the same clock shows, or missing one overwritten.
        p_replaced_rule: assert (replaced == (begin_write && f_waiting && !vblank_swap));
      end
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      if (front_sel != $past(front_sel)) begin
        // The shown copy changes only in vertical blanking: the front bank changes only in a clock of
        // vblank_swap. Rules out a swap outside blanking (a torn frame).
        p_swap_only_in_vblank: assert ($past(vblank_swap));
        // ... and only to a whole, accepted world waiting for it: the bank that becomes the front was committed
        // after its last begin_write and not written since. Rules out showing a world half copied in, or swapping
        // back to the world shown before.
        if ($past(f_proto_ok)) p_swap_shows_complete: assert ($past(f_waiting && f_back_complete));
      end else begin
        // ... and a waiting world is shown at the first vertical blanking. Rules out a blanking that swaps nothing.
        if ($past(f_proto_ok)) p_swap_at_first_vblank: assert (!$past(f_swap));
        // The front copy's count, number and valid bit change only with a swap. Rules out a commit's count or
        // number landing in the copy on screen.
        p_front_meta_holds: assert (front_valid == $past(front_valid) && front_count == $past(front_count)
                                    && front_sequence == $past(front_sequence));
      end
      // The ready line rises only at a swap and falls only when the receiver begins (or commits) a world.
      if (ready && !$past(ready) && $past(f_proto_ok)) p_ready_rises_at_swap: assert ($past(f_swap));
      if (!ready && $past(ready)) p_ready_falls_on_accept: assert ($past(begin_write || commit));
    end
  end
`endif
endmodule
