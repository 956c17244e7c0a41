// ts_rx_hierarchy: the receiver's check of a world's hierarchy of bounding spheres (the v3 wire's content 1,
// docs/link_format.md "The hierarchy"): the node records as a frame brings them, and, once the frame is whole and
// intact, whether they keep the rules, so that a world that breaks one is refused whole. Its C++ model is
// link::hierarchy_error (src/tripsitter/link/frame.h) with the receiver's format check of the bounds
// (DevicePreset::holds_ball, device/receiver.cpp): `ok` is exactly "hierarchy_error finds nothing and every bound
// but the root's fits scene memory's formats".
//
// As each record is written (node_we, node 0 first; at most MaxNodes of them, which the frame's length check
// guarantees, and a record beyond them fails the world):
//   - node 0 carries no bound (x, y, z and radius 0); every other node's bound is above zero and fits the formats
//     (CoordW-bit signed centre, RadiusW-bit radius);
//   - no children means first_child 0, no spheres means first_sphere 0, and a node but the root holds something;
//   - the largest first_child + children and first_sphere + sphere_count are kept, for the ranges below.
// On `check`, in turn, each a walk over the stored records (`done` for a cycle at the end, the answer in `ok`):
//   ranges   every child range inside the nodes written, every sphere range inside the spheres written;
//   clear    the marks below, a node's and a sphere's a cycle;
//   tree     from the root, breadth first, each node reached once (a second time is a cycle or a second parent), none
//            deeper than MaxDepth levels below the root, every node reached: one child a cycle;
//   spheres  every sphere in exactly one node: one sphere a cycle;
//   enclose  every bound but the root's encloses each of its spheres (from the block's own copy of their balls,
//            written as the frame brings them: scene memory is written only once the world is accepted) and each of
//            its children's bounds, in exact integers, as link::encloses:
//            r_outer >= r_inner and |c_inner - c_outer|^2 <= (r_outer - r_inner)^2, the four squares one after
//            another through one 23 x 23-bit multiplier: 9 cycles a sphere, 8 a child.
// A world of 256 spheres in 17 nodes (host::build_hierarchy's) took 2,929 cycles from `check` in
// rx_hierarchy_rtl_test: 29 us at the device's 100 MHz. Part of ts_receiver when it takes hierarchies (Hierarchy).
module ts_rx_hierarchy #(
    parameter int MaxSpheres = 256,  // scene memory's capacity, and the most nodes a frame may carry (a power of two)
    parameter int CoordW = 22,       // scene memory's formats: x, y, z signed, the radius unsigned
    parameter int RadiusW = 21,
    localparam int MaxNodes = MaxSpheres,
    localparam int MaxDepth = ts_link_pkg::MaxHierarchyDepth,
    localparam int NW = $clog2(MaxNodes),
    localparam int SW = $clog2(MaxSpheres)
) (
    input  logic                     clk,
    input  logic                     rst,
    input  logic                     begin_world,  // a frame of content 1 begins: forget the last one's records
    input  logic                     node_we,
    input  logic signed [31:0]       node_x,
    input  logic signed [31:0]       node_y,
    input  logic signed [31:0]       node_z,
    input  logic [31:0]              node_radius,
    input  logic [15:0]              node_first_child,
    input  logic [7:0]               node_children,
    input  logic [7:0]               node_sphere_count,
    input  logic [31:0]              node_first_sphere,
    input  logic                     check,        // the frame is whole and its CRCs good
    output logic                     done,
    output logic                     ok,
    // the frame's spheres in order, as scene memory's formats hold them (a sphere outside them fails the world
    // in the receiver's own checks; here its low bits are kept)
    input  logic                     sphere_we,
    input  logic signed [CoordW-1:0] sphere_x,
    input  logic signed [CoordW-1:0] sphere_y,
    input  logic signed [CoordW-1:0] sphere_z,
    input  logic [RadiusW-1:0]       sphere_r
);
  localparam int DW = $clog2(MaxDepth + 2);  // a depth, 0 .. MaxDepth + 1
  localparam int OpW = CoordW + 1;            // a centre's difference, or a radii's
  localparam int BallW = 3 * CoordW + RadiusW;

  // ---- the records: {ball, first_child, children, first_sphere, sphere_count} -------------------------------------
  // first_child and first_sphere are kept in NW and SW bits: the range checks make that exact for a world that passes
  // them, and a world that fails them is not walked.
  localparam int RecW = BallW + NW + 8 + SW + 8;
  logic [RecW-1:0] records[MaxNodes];
  logic [NW:0]     nodes;      // records written
  logic [NW-1:0]   rd_node;
  logic [RecW-1:0] rd;
  logic [BallW-1:0] rd_ball;
  logic [NW:0]     rd_child_first, rd_child_end;
  logic [SW:0]     rd_sphere_first, rd_sphere_end;
  assign rd = records[rd_node];
  assign rd_ball = rd[RecW-1-:BallW];
  assign rd_child_first = (NW + 1)'(rd[SW+16+:NW]);
  assign rd_child_end = rd_child_first + (NW + 1)'(rd[SW+8+:8]);
  assign rd_sphere_first = (SW + 1)'(rd[8+:SW]);
  assign rd_sphere_end = rd_sphere_first + (SW + 1)'(rd[7:0]);

  // The spheres' balls, read a clock after the address (block RAM).
  logic [BallW-1:0] balls[MaxSpheres];
  logic [SW:0]      spheres;  // written
  always_ff @(posedge clk) begin
    if (begin_world) spheres <= '0;
    else if (sphere_we && spheres != (SW + 1)'(MaxSpheres)) spheres <= spheres + 1'b1;
    if (sphere_we && spheres != (SW + 1)'(MaxSpheres))
      balls[SW'(spheres)] <= {sphere_x, sphere_y, sphere_z, sphere_r};
  end

  // A record's own rules. A 32-bit coordinate fits CoordW bits when its bits from the format's sign bit up are all
  // equal.
  function automatic logic fits_signed(input logic [32-CoordW:0] high);
    fits_signed = high == '0 || high == '1;
  endfunction
  logic record_bad;
  always_comb begin
    record_bad = nodes == (NW + 1)'(MaxNodes);
    if (nodes == '0) begin
      record_bad |= node_x != 0 || node_y != 0 || node_z != 0 || node_radius != 0;
    end else begin
      record_bad |= node_radius == 0 || node_radius[31:RadiusW] != '0;
      record_bad |= !fits_signed(node_x[31:CoordW-1]) || !fits_signed(node_y[31:CoordW-1]) ||
                    !fits_signed(node_z[31:CoordW-1]);
      record_bad |= node_children == 0 && node_sphere_count == 0;
    end
    record_bad |= node_children == 0 && node_first_child != 0;
    record_bad |= node_sphere_count == 0 && node_first_sphere != 0;
  end

  logic        records_bad;
  logic [16:0] child_end_max;   // the largest first_child + children
  logic [32:0] sphere_end_max;  // the largest first_sphere + sphere_count
  always_ff @(posedge clk) begin
    if (begin_world) begin
      nodes <= '0;
      records_bad <= 1'b0;
      child_end_max <= '0;
      sphere_end_max <= '0;
    end else if (node_we) begin
      if (nodes != (NW + 1)'(MaxNodes)) nodes <= nodes + 1'b1;
      records_bad <= records_bad || record_bad;
      if (17'(node_first_child) + 17'(node_children) > child_end_max)
        child_end_max <= 17'(node_first_child) + 17'(node_children);
      if (33'(node_first_sphere) + 33'(node_sphere_count) > sphere_end_max)
        sphere_end_max <= 33'(node_first_sphere) + 33'(node_sphere_count);
    end
  end
  always_ff @(posedge clk) begin
    if (node_we && nodes != (NW + 1)'(MaxNodes)) begin
      records[NW'(nodes)] <= {CoordW'(node_x), CoordW'(node_y), CoordW'(node_z), RadiusW'(node_radius),
                              NW'(node_first_child), node_children, SW'(node_first_sphere), node_sphere_count};
    end
  end

  // ---- the walks ------------------------------------------------------------------------------------------------
  typedef enum logic [3:0] {
    Idle, Start, Clear, TreeLoad, TreeWalk, SpheresLoad, SpheresWalk, EncloseLoad, EncloseItem, EncloseFetch,
    EncloseBall, EncloseSquare, EncloseCompare, Pass, Fail
  } state_t;
  state_t state;

  // The tree's queue, in the order nodes are reached: {depth, node}.
  logic [DW+NW-1:0]  order[MaxNodes];
  logic [NW:0]       head, tail;
  // Whether a node is reached, a sphere owned: LUT RAM, cleared a word a cycle as the check starts.
  localparam int Marks = MaxNodes > MaxSpheres ? MaxNodes : MaxSpheres;
  logic              reached[MaxNodes];
  logic              owned[MaxSpheres];
  logic [$clog2(Marks):0] clear;  // the word being cleared
  logic [SW:0]       marks;      // spheres found in a node
  logic [NW:0]       node;       // the node walked (spheres, enclose)
  logic [NW:0]       child, child_end;
  logic [SW:0]       sphere, sphere_end;
  logic [DW-1:0]     depth;      // of the children walked
  logic [DW+NW-1:0]  popped;
  assign popped = order[NW'(head)];

  // The enclosing bound, the ball inside, and the squares.
  logic signed [CoordW-1:0]  bx, by, bz;
  logic [RadiusW-1:0]        br;
  (* mem2reg *) logic signed [OpW-1:0] op[4];      // dx, dy, dz, then r_outer - r_inner
  logic [2:0]                step;       // the square being formed: 0 .. 3, then its last product's sum
  logic [2*OpW-1:0]          square;
  logic [2*OpW+1:0]          distance2;  // dx^2 + dy^2 + dz^2
  logic [2*OpW-1:0]          room2;      // (r_outer - r_inner)^2

  // The queue's one write: the root as the walk starts, then each child reached.
  logic ranges_ok;  // the records' own rules and ranges, registered: read in Start, a clock after `check`
  always_ff @(posedge clk)
    ranges_ok <= !records_bad && child_end_max <= 17'(nodes) && sphere_end_max <= 33'(spheres);
  always_ff @(posedge clk) begin
    if (state == Start) order[0] <= '0;
    else if (state == TreeWalk) order[NW'(tail)] <= {depth, NW'(child)};
  end
  // The marks' one write each: cleared (the root reached), then set as the walks find them.
  always_ff @(posedge clk) begin
    if (state == Clear) reached[NW'(clear)] <= clear == '0;
    else if (state == TreeWalk && child != child_end) reached[NW'(child)] <= 1'b1;
    if (state == Clear) owned[SW'(clear)] <= 1'b0;
    else if (state == SpheresWalk && sphere != sphere_end) owned[SW'(sphere)] <= 1'b1;
  end

  always_comb begin
    case (state)
      TreeLoad:    rd_node = NW'(popped);
      EncloseItem: rd_node = NW'(child);
      default:     rd_node = NW'(node);
    endcase
  end

  // A ball inside the bound: the differences, and whether the radii already fail it.
  logic signed [CoordW-1:0] in_x, in_y, in_z;
  logic [RadiusW-1:0]       in_r;
  logic                     from_sphere;  // EncloseFetch: the ball is the sphere read
  logic signed [CoordW-1:0] ball_x, ball_y, ball_z;  // the ball, registered
  logic [RadiusW-1:0]       ball_r;
  assign from_sphere = state == EncloseFetch;
  logic [BallW-1:0] sp;  // the ball of `sphere` a clock before
  always_ff @(posedge clk) sp <= balls[SW'(sphere)];
  logic [BallW-1:0] ball;
  assign ball = from_sphere ? sp : rd_ball;
  assign in_x = ball[BallW-1-:CoordW];
  assign in_y = ball[BallW-1-CoordW-:CoordW];
  assign in_z = ball[RadiusW+:CoordW];
  assign in_r = ball[RadiusW-1:0];

  always_ff @(posedge clk) begin
    done <= 1'b0;
    if (rst || begin_world) begin
      state <= Idle;
    end else begin
      case (state)
        Idle: if (check) state <= nodes == '0 ? Pass : Start;
        Start: begin
          if (!ranges_ok) begin
            state <= Fail;
          end else begin
            clear <= '0;
            head <= '0;
            tail <= (NW + 1)'(1);
            state <= Clear;
          end
        end
        Clear: begin
          clear <= clear + 1'b1;
          if (clear == ($clog2(Marks) + 1)'(Marks - 1)) state <= TreeLoad;
        end
        TreeLoad: if (head == tail) begin
          state <= tail == nodes ? SpheresLoad : Fail;
          marks <= '0;
          node <= '0;
        end else begin
          child <= rd_child_first;
          child_end <= rd_child_end;
          depth <= popped[NW+:DW] + 1'b1;
          head <= head + 1'b1;
          state <= TreeWalk;
        end
        TreeWalk: if (child == child_end) begin
          state <= TreeLoad;
        end else if (reached[NW'(child)] || depth > DW'(MaxDepth)) begin
          state <= Fail;
        end else begin
          tail <= tail + 1'b1;
          child <= child + 1'b1;
        end
        SpheresLoad: if (node == nodes) begin
          state <= marks == spheres ? EncloseLoad : Fail;
          node <= (NW + 1)'(1);
        end else begin
          sphere <= rd_sphere_first;
          sphere_end <= rd_sphere_end;
          node <= node + 1'b1;
          state <= SpheresWalk;
        end
        SpheresWalk: if (sphere == sphere_end) begin
          state <= SpheresLoad;
        end else if (owned[SW'(sphere)]) begin
          state <= Fail;
        end else begin
          marks <= marks + 1'b1;
          sphere <= sphere + 1'b1;
        end
        EncloseLoad: if (node == nodes) begin
          state <= Pass;
        end else begin
          {bx, by, bz, br} <= rd_ball;
          sphere <= rd_sphere_first;
          sphere_end <= rd_sphere_end;
          child <= rd_child_first;
          child_end <= rd_child_end;
          node <= node + 1'b1;
          state <= EncloseItem;
        end
        EncloseItem, EncloseFetch: if (state == EncloseItem && sphere != sphere_end) begin
          sphere <= sphere + 1'b1;  // its ball is read now, there in EncloseFetch
          state <= EncloseFetch;
        end else if (state == EncloseItem && child == child_end) begin
          state <= EncloseLoad;
        end else begin
          if (state == EncloseItem) child <= child + 1'b1;
          {ball_x, ball_y, ball_z, ball_r} <= {in_x, in_y, in_z, in_r};
          state <= EncloseBall;
        end
        EncloseBall: begin
          op[0] <= OpW'(ball_x) - OpW'(bx);
          op[1] <= OpW'(ball_y) - OpW'(by);
          op[2] <= OpW'(ball_z) - OpW'(bz);
          op[3] <= OpW'(br) - OpW'(ball_r);
          step <= '0;
          distance2 <= '0;
          state <= ball_r > br ? Fail : EncloseSquare;
        end
        EncloseSquare: begin
          // step k squares op[k] and adds the square of op[k - 1]
          square <= (2 * OpW)'(op[step[1:0]] * op[step[1:0]]);
          if (step != 0 && step != 3'd4) distance2 <= distance2 + (2 * OpW + 2)'(square);
          step <= step + 1'b1;
          if (step == 3'd4) begin
            room2 <= square;
            state <= EncloseCompare;
          end
        end
        EncloseCompare: state <= distance2 <= (2 * OpW + 2)'(room2) ? EncloseItem : Fail;
        Pass, Fail: begin
          done <= 1'b1;
          ok <= state == Pass;
          state <= Idle;
        end
        default: state <= Idle;
      endcase
    end
  end
endmodule
