// ts_path_walk: the hierarchy walker of a path preset's sphere unit: it issues the slots of a bounced ray's passes,
// one level of the world's hierarchy of bounding spheres a pass, and keeps each walk's next level from the bounds
// the sphere unit reports entered. C++ model: artix::walk_closest_hit (src/tripsitter/device/artix_units.h) for the
// slots and levels, artix::unit_finish_cycles for the cycles a pass holds the issue port (DeviceUnits::walk_lead);
// docs/device.md, "Path tracing on the artix datapath", and docs/rtl.md, "Path tracing blocks".
//
// A walk is one bounced ray's search, named by an id (0 .. IDS - 1) while it is in flight; the unit around it keeps
// the ray, merges its passes' hits and starts its passes. A pass (`start`, when `ready`) is the walk's first
// (`start_root`: node 0, whose record the unit holds in `root_*`) or its next level (the nodes whose bounds its last
// pass entered). Its slots, in the model's order: on the first pass of a ray that went into the sphere it leaves
// (`start_into`), a far pair of that sphere (`start_from`); then for each node of the level its spheres (the
// sphere the ray leaves a slot without a pair) and its children's bounds; slots without a pair up to MinPass.
//
// Cycles (cycle c the `start`, the model's cycle the port takes the pass): a slot comes out the cycle after the
// model issues it (the cycle the unit reads its sphere or bound from scene memory, so that its fields reach the
// sphere unit SceneReadCycles after its issue). The first pass issues from c, its first slot out in c + 1; a later
// level reads its first node from the walk's head register in c (WalkLead, one cycle), issues from c + 1, its
// first slot out in c + 2; either issues a slot every cycle to its end and `ready` is high again in the cycle after
// its last issue: the port is held WalkLead (later levels) + max(slots, MinPass) cycles, as the model counts.
// A level's other nodes come from its list (a registered read, then the node memory's registered read): they are
// read ahead into a queue of four node records, so that a node of a single slot follows another without a gap.
//
// The sphere unit reports each bound slot's entered in slot order (`entered_valid`, ts_artix_sphere_unit with PATH
// = 1) and each pass's result in pass order (`result_valid`): an entered bound's node is appended to its walk's
// next level; with a pass's result come its walk's id (`result_id`) and whether the walk has another level
// (`result_more`: a bound of the pass was entered). The lists: two banks a walk, one read by the pass being issued
// while the sphere unit's reports for it fill the other, MaxSpheres nodes each (a level never holds more); the
// first node of each walk's next level is also kept in a head register, read in the pass's first cycle.
//
// Queues (ts_artix_fifo): passes in flight, 16 (a pass holds the port at least MinPass cycles and is in flight for
// at most 2 + HitLatency + 1 cycles after its last slot: 15); bound slots in flight, 64 (queued as they come out,
// at most one a cycle, each until its report 40 cycles later); the node records read ahead, 4 (a read is asked only
// with room for it: at most three are on their way or queued). `overflow` (sticky) would say one of them overflowed,
// or that a report or a result came with nothing in flight. Issue decisions start from flip-flops: beside each
// count, whether it is above 0 and above 1 (a record's flags are taken as it arrives), 5 LUT levels at most.
module ts_path_walk #(
    parameter int IDS = 32,  // walks in flight, a power of two
    localparam int IdW = $clog2(IDS),
    localparam int AW = ts_artix_pkg::SphereAW,  // a sphere's or a node's index
    localparam int CntW = AW + 1
) (
    input  logic            clk,
    input  logic            rst,
    // Node 0's record, the root of the world shown.
    input  logic [AW-1:0]   root_first_sphere,
    input  logic [7:0]      root_spheres,
    input  logic [AW-1:0]   root_first_child,
    input  logic [7:0]      root_children,
    // The hierarchy's node records (a registered read: the record of node_addr in the next cycle).
    output logic [AW-1:0]   node_addr,
    input  logic [AW-1:0]   node_first_sphere,
    input  logic [7:0]      node_spheres,
    input  logic [AW-1:0]   node_first_child,
    input  logic [7:0]      node_children,
    // A pass.
    input  logic            start,       // only when ready
    input  logic            start_root,
    input  logic [IdW-1:0]  start_id,
    input  logic [AW-1:0]   start_from,  // the sphere the ray leaves
    input  logic            start_into,  // the ray went into it (the first pass's far pair)
    output logic            ready,
    // Its slots, the cycle after their issue.
    output logic            slot_valid,
    output logic            slot_first,
    output logic            slot_end,
    output logic            slot_pair,   // a sphere's pair: slot_index is the sphere
    output logic            slot_far,    // with slot_pair: the far pair of the sphere the ray is in
    output logic            slot_bound,  // a bound: slot_index is the node
    output logic [AW-1:0]   slot_index,
    // The sphere unit's reports and results, in order.
    input  logic            entered_valid,
    input  logic            entered,
    input  logic            result_valid,
    output logic [IdW-1:0]  result_id,
    output logic            result_more,
    output logic            overflow
);
  localparam int MinPass = ts_artix_pkg::MinPass;
  localparam int RecW = 2 * AW + 16;  // a node record: {first_sphere, spheres, first_child, children}

  if ((1 << IdW) != IDS || IDS < 2) begin : g_bad_ids
    $error("ts_path_walk: IDS must be a power of two, at least 2");
  end

  // ---- Each walk: its next level's count and first node, and the bank its next pass reads ---------------------
  (* mem2reg *) logic [CntW-1:0] count_q [IDS];
  (* mem2reg *) logic [AW-1:0]   head_q [IDS];
  logic [IDS-1:0]                bank_q;

  // ---- The generator: the node it issues from, and the pass's state --------------------------------------------
  // Beside each count, whether it is above 0 and above 1, so that the issue decision starts from flip-flops.
  logic            active_q;   // a pass is issuing (or, a later level, in its lead cycle)
  logic            far_q;      // the far pair is still to issue
  logic [AW-1:0]   from_q;
  logic [AW-1:0]   s_q, c_q;   // the node's next sphere and next child
  logic [7:0]      sl_q, cl_q; // its spheres and children left
  logic            sl_nz_q, sl_many_q, cl_nz_q, cl_many_q;
  logic [CntW-1:0] nodes_q;    // the level's nodes not yet taken by the generator
  logic            nodes_nz_q, nodes_many_q;
  logic [1:0]      issued_q;   // slots issued, up to MinPass
  logic [IdW-1:0]  id_q;
  logic            wbank_q;    // the bank this pass's entered bounds go to

  // ---- The level list: read ahead into the record queue -------------------------------------------------------
  logic [AW-1:0]   list [2 * IDS * (1 << AW)];
  logic [CntW-1:0] rd_left_q;  // list entries still to read
  logic [AW-1:0]   rd_pos_q;
  logic            rd_bank_q;
  logic            lr_q;       // a list entry was read last cycle: list_q is the next node to read
  logic [AW-1:0]   list_q;
  logic            nr_q;       // a node was read last cycle: its record is at the node inputs
  logic            rec_empty, rec_overflow;
  logic [RecW+3:0] rec_front;  // a record and its flags
  logic [2:0]      rec_count_q;  // records in the queue

  // ---- What this cycle issues -----------------------------------------------------------------------------------
  // A node record, {first_sphere, spheres, first_child, children}, with its flags {spheres > 0, spheres > 1,
  // children > 0, children > 1}.
  function automatic logic [3:0] flags_of(input logic [7:0] sl, input logic [7:0] cl);
    flags_of = {sl != 8'd0, sl > 8'd1, cl != 8'd0, cl > 8'd1};
  endfunction
  wire start_list = start && !start_root;
  wire [CntW-1:0] start_count = count_q[start_id];  // a later level's nodes
  wire root_now = start && start_root;
  wire [RecW-1:0] arriving = {node_first_sphere, node_spheres, node_first_child, node_children};
  wire [RecW-1:0] root_rec = {root_first_sphere, root_spheres, root_first_child, root_children};
  // The generator takes the next node when its node has nothing left (the far pair counts as something).
  wire need = active_q && !sl_nz_q && !cl_nz_q && !far_q && nodes_nz_q;
  wire have = !rec_empty || nr_q;
  wire take = need && have;
  wire [RecW+3:0] rec = !rec_empty ? rec_front : {arriving, flags_of(node_spheres, node_children)};
  // The node and flags the slot is issued from.
  logic [AW-1:0]  e_s, e_c, e_from;
  logic [7:0]     e_sl, e_cl;
  logic           e_sl_nz, e_sl_many, e_cl_nz, e_cl_many, e_far, e_nodes_nz, issuing_pass;
  logic [CntW-1:0] e_nodes;
  logic [1:0]     e_issued;
  always_comb begin
    {e_s, e_sl, e_c, e_cl} = {s_q, sl_q, c_q, cl_q};
    {e_sl_nz, e_sl_many, e_cl_nz, e_cl_many} = {sl_nz_q, sl_many_q, cl_nz_q, cl_many_q};
    e_far = far_q;
    e_from = from_q;
    e_nodes = nodes_q;
    e_nodes_nz = nodes_nz_q;
    e_issued = issued_q;
    issuing_pass = active_q;
    if (root_now) begin
      {e_s, e_sl, e_c, e_cl} = root_rec;
      {e_sl_nz, e_sl_many, e_cl_nz, e_cl_many} = flags_of(root_spheres, root_children);
      e_far = start_into;
      e_from = start_from;
      e_nodes = '0;
      e_nodes_nz = 1'b0;
      e_issued = '0;
      issuing_pass = 1'b1;
    end else if (take) begin
      {e_s, e_sl, e_c, e_cl, e_sl_nz, e_sl_many, e_cl_nz, e_cl_many} = rec;
      e_nodes = nodes_q - CntW'(1);
      e_nodes_nz = nodes_many_q;
    end
  end
  // The slot: the far pair, a sphere, a bound, or a pad when the level has no more.
  wire more_real = e_far || e_sl_nz || e_cl_nz;
  wire pad = !more_real && !e_nodes_nz && e_issued < 2'(MinPass);
  wire issue = issuing_pass && !start_list && (more_real || pad);
  wire is_far = e_far;
  wire is_sphere = !e_far && e_sl_nz;
  wire is_bound = !e_far && !e_sl_nz && e_cl_nz;
  // After it: what the node still has, and whether the pass has another slot.
  wire sl_nz_after = is_sphere ? e_sl_many : e_sl_nz;
  wire cl_nz_after = is_bound ? e_cl_many : e_cl_nz;
  wire real_after = sl_nz_after || cl_nz_after || e_nodes_nz;
  wire [1:0] issued_after = e_issued == 2'(MinPass) ? e_issued : e_issued + 2'd1;
  wire last = issue && !real_after && issued_after == 2'(MinPass);
  wire [7:0] sl_after = is_sphere ? e_sl - 8'd1 : e_sl;
  wire [7:0] cl_after = is_bound ? e_cl - 8'd1 : e_cl;

  // ---- The generator's registers, and the slot out ----------------------------------------------------------------
  always_ff @(posedge clk) begin
    if (rst) begin
      active_q   <= 1'b0;
      slot_valid <= 1'b0;
    end else begin
      slot_valid <= issue;
      if (start) active_q <= 1'b1;
      if (last) active_q <= 1'b0;
    end
    if (start) begin
      id_q    <= start_id;
      wbank_q <= !bank_q[start_id];
    end
    if (start_list) begin
      far_q        <= 1'b0;
      from_q       <= start_from;
      {sl_q, cl_q} <= '0;
      {sl_nz_q, sl_many_q, cl_nz_q, cl_many_q} <= '0;
      nodes_q      <= start_count;
      nodes_nz_q   <= 1'b1;  // a later level has a node at least
      nodes_many_q <= start_count > CntW'(1);
      issued_q     <= '0;
    end else if (issuing_pass) begin
      far_q        <= e_far && !issue;
      from_q       <= e_from;
      s_q          <= is_sphere ? e_s + AW'(1) : e_s;
      c_q          <= is_bound ? e_c + AW'(1) : e_c;
      sl_q         <= sl_after;
      cl_q         <= cl_after;
      sl_nz_q      <= sl_after != 8'd0;
      sl_many_q    <= sl_after > 8'd1;
      cl_nz_q      <= cl_after != 8'd0;
      cl_many_q    <= cl_after > 8'd1;
      nodes_q      <= e_nodes;
      nodes_nz_q   <= e_nodes_nz;
      nodes_many_q <= e_nodes > CntW'(1);
      issued_q     <= issue ? issued_after : e_issued;
    end
    slot_first <= issue && e_issued == 2'd0;
    slot_end   <= last;
    slot_pair  <= is_far || (is_sphere && e_s != e_from);
    slot_far   <= is_far;
    slot_bound <= is_bound;
    slot_index <= is_far ? e_from : is_sphere ? e_s : e_c;
  end
  assign ready = !active_q;

  // ---- Reading the level ahead -----------------------------------------------------------------------------------
  // In the cycle a list pass starts, its first node is read from the head register and its second from the list;
  // after that a list read is asked with room in the queue for every record on its way (the read's, the node
  // read's, and those queued: at most three, so the queue of four never fills).
  wire [2:0] on_way = rec_count_q + 3'(lr_q) + 3'(nr_q);
  wire list_next = active_q && rd_left_q != 0 && on_way < 3'd3;
  wire list_read = (start_list && start_count > CntW'(1)) || list_next;
  wire [IdW+AW:0] list_raddr = start_list ? {start_id, bank_q[start_id], AW'(1)} : {id_q, rd_bank_q, rd_pos_q};
  always_ff @(posedge clk) begin
    if (rst) begin
      rd_left_q <= '0;
      lr_q      <= 1'b0;
      nr_q      <= 1'b0;
    end else begin
      if (start_list) rd_left_q <= start_count > CntW'(1) ? start_count - CntW'(2) : '0;
      else if (list_next) rd_left_q <= rd_left_q - CntW'(1);
      lr_q <= list_read;
      nr_q <= start_list || lr_q;
    end
    if (start_list) begin
      rd_pos_q  <= AW'(2);
      rd_bank_q <= bank_q[start_id];
    end else if (list_next) begin
      rd_pos_q <= rd_pos_q + AW'(1);
    end
    if (list_read) list_q <= list[list_raddr];
  end
  assign node_addr = start_list ? head_q[start_id] : list_q;

  // Records that arrive while the generator takes from the queue, or needs none, are queued.
  wire rec_push = nr_q && !(take && rec_empty);
  wire rec_pop = take && !rec_empty;
  ts_artix_fifo #(.W(RecW + 4), .DEPTH(4)) records (
      .clk, .rst, .clear(1'b0), .push(rec_push), .push_data({arriving, flags_of(node_spheres, node_children)}),
      .pop(rec_pop),
      .front(rec_front), .empty(rec_empty), .overflow(rec_overflow)
  );
  always_ff @(posedge clk) begin
    if (rst) rec_count_q <= '0;
    else rec_count_q <= rec_count_q + 3'(rec_push) - 3'(rec_pop);
  end

  // ---- The reports: each entered bound appended to its walk's next level ------------------------------------------
  // A bound slot is queued as it comes out (its report is 39 cycles away): its walk and bank are the pass's, which
  // a pass starting in that cycle has not yet replaced.
  logic            bound_empty, bound_overflow;
  logic [IdW:0]    bound_walk;   // {id, bank}
  logic [AW-1:0]   bound_node;
  ts_artix_fifo #(.W(IdW + 1 + AW), .DEPTH(64)) bounds (
      .clk, .rst, .clear(1'b0), .push(slot_valid && slot_bound), .push_data({id_q, wbank_q, slot_index}),
      .pop(entered_valid), .front({bound_walk, bound_node}), .empty(bound_empty), .overflow(bound_overflow)
  );
  wire [IdW-1:0] rep_id = bound_walk[IdW:1];
  wire rep_add = entered_valid && entered;
  always_ff @(posedge clk) begin
    if (rep_add) list[{bound_walk, count_q[rep_id][AW-1:0]}] <= bound_node;
  end
  always_ff @(posedge clk) begin
    for (int i = 0; i < IDS; i++) begin
      if (start && start_id == IdW'(i)) begin
        count_q[i] <= '0;
        bank_q[i]  <= !bank_q[i];
      end else if (rep_add && rep_id == IdW'(i)) begin
        count_q[i] <= count_q[i] + CntW'(1);
        if (count_q[i] == '0) head_q[i] <= bound_node;
      end
    end
    if (rst) bank_q <= '0;
  end

  // ---- The results: each pass's walk and whether it has another level ---------------------------------------------
  logic pass_empty, pass_overflow;
  ts_artix_fifo #(.W(IdW), .DEPTH(16)) passes (
      .clk, .rst, .clear(1'b0), .push(start), .push_data(start_id), .pop(result_valid),
      .front(result_id), .empty(pass_empty), .overflow(pass_overflow)
  );
  // The pass's last bound may be reported in the cycle of its result.
  assign result_more = count_q[result_id] != '0 || (rep_add && rep_id == result_id);

  always_ff @(posedge clk) begin
    if (rst) overflow <= 1'b0;
    else if (rec_overflow || bound_overflow || pass_overflow || (result_valid && pass_empty)
             || (entered_valid && bound_empty))
      overflow <= 1'b1;
  end
endmodule
