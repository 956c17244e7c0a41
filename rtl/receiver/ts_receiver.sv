// ts_receiver: the device's receiver. Turns the link's byte stream into checked worlds in the back copy of
// scene memory, and counts what it drops, exactly as the C++ receiver does.
//
// C++ model: src/tripsitter/device/receiver.h/.cpp (Receiver, ReceiverStats), with the wires of
// src/tripsitter/link/: wire_v1.h (the 64-bit word), frame.h/.cpp (v2 and v3 frames and FrameStreamDecoder),
// sequence.h/.cpp (SequenceRules); the formats in docs/link_format.md and ts_link_pkg.sv. WIRE selects the wire
// (1, 2 or 3) and FRAC, X_W, Y_W, Z_W, R_W and MAX_SPHERES the preset's scene memory (device/preset.h: wide is 4,
// 24, 24, 24, 24, 4096; board-2023 is 3, 16, 15, 15, 16, 64).
//
// Blocks, one per piece of the C++ (docs/rtl.md, "The receiver and scene memory"):
//   ts_rx_frame     v2 and v3: the byte buffer, the hunt for the magic, the header's checks, the frame CRC, the
//                   sphere records, v3's cut rule (FrameStreamDecoder, frame.cpp)
//   ts_rx_sequence  v2 and v3: the sequence rules (SequenceRules, sequence.cpp)
//   ts_rx_v1_word   v1: the 64-bit word, rescaled and range-checked (V1StreamDecoder, wire_v1.cpp; accept_v1)
//   ts_rx_commit    the counters, the verdict on an intact frame, and the writes to scene memory (Receiver,
//                   receiver.cpp)
// An accepted frame's spheres are not written while the frame is checked: a damaged frame must never touch the
// world waiting for the swap (the model's back_ changes only when a world is accepted). Its payload is still in
// ts_rx_frame's byte buffer, so the engine goes over it a second time and each sphere is written: 48 clocks per
// sphere (2 per byte), 2 ms for 4096 spheres (whose 98 KB took 79 ms on a 10 MHz link); meanwhile ready is low and
// a vertical blanking swaps nothing (scene memory has no pending world while the back copy is being overwritten),
// so a world whose commit spans a blanking is shown one frame later than the model shows it. A v1 word is one
// sphere, written at once.
//
// Counters: the fields of ReceiverStats (last_error, a sentence, is not kept), counted at the same events.
// Extra: bytes_received (every byte stored), overflow_bytes (ts_rx_frame's buffer was full).
//
// End of stream: `end_of_stream` (the host went away: Receiver::end_of_stream) is handled when every byte received
// before it is processed: a partial frame is dropped as truncated, a hunt in progress as a garbage run, a partial v1
// word as a rejection.
//
// Timing contract: the counters, `ready` (scene memory) and the back copy are final when `idle` is high (every
// received byte processed, nothing being decided or written to scene memory). The test waits for idle before
// comparing.
module ts_receiver #(
    parameter int WIRE = 3,            // 1, 2 or 3
    parameter int FRAC = 4,            // fractional bits of the preset's formats
    parameter int X_W = 24,            // total bits: x, y, z signed, radius unsigned
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int MAX_SPHERES = 4096,  // scene memory capacity; a power of two
    parameter int CNT_W = 64,          // counter width (ReceiverStats holds 64-bit counters)
    parameter int HIERARCHY = 0,       // 1: v3 worlds may carry a hierarchy (DevicePreset::walks_hierarchy)
    parameter int IOR_MIN = 0,         // a dielectric's index of refraction, u4.12 (the path presets': 1024..32768)
    parameter int IOR_MAX = 65535,
    parameter int AW = $clog2(MAX_SPHERES)  // derived: leave as it is
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             byte_valid,
    input  logic [7:0]       byte_data,
    input  logic             end_of_stream,
    // Scene memory's write side (ts_scene_memory).
    output logic             sm_begin,
    output logic             sm_we,
    output logic [AW-1:0]    sm_waddr,
    output logic [X_W-1:0]   sm_wx,
    output logic [Y_W-1:0]   sm_wy,
    output logic [Z_W-1:0]   sm_wz,
    output logic [R_W-1:0]   sm_wr,
    output logic             sm_wmetal,
    output logic [23:0]      sm_walbedo,
    output logic             sm_commit,
    output logic [AW:0]      sm_count,
    output logic [31:0]      sm_sequence,
    input  logic             sm_replaced,  // scene memory: sm_begin overwrote a world never shown
    // ReceiverStats.
    output logic [CNT_W-1:0] worlds_accepted,
    output logic [CNT_W-1:0] worlds_replaced,
    output logic [CNT_W-1:0] frames_rejected,
    output logic [CNT_W-1:0] garbage_runs,
    output logic [CNT_W-1:0] bytes_dropped,
    output logic [CNT_W-1:0] worlds_missing,
    output logic [CNT_W-1:0] worlds_replayed,
    output logic [CNT_W-1:0] sessions,
    output logic [CNT_W-1:0] bytes_received,
    output logic [CNT_W-1:0] overflow_bytes,
    output logic             idle
);
  logic full;
  logic rep_valid, rep_garbage;
  logic [CNT_W-1:0] rep_bytes;
  logic [31:0] hdr_sequence, frame_bytes;
  logic [AW:0] hdr_count;
  logic [7:0] hdr_frac;
  logic in_body, bad_sphere, intact, bad_hierarchy;
  /* verilator lint_off UNUSEDSIGNAL */
  logic admit_drop, admit_copy;  // not read on v1, which has no frames to admit
  /* verilator lint_on UNUSEDSIGNAL */
  logic rec_valid, rec_copy, copy_done;
  logic [31:0] rec_x, rec_y, rec_z, rec_r;
  logic [7:0] rec_material;
  logic [23:0] rec_albedo;
  logic [15:0] rec_ior;
  logic seq_done, seq_replay, seq_new;
  logic [31:0] seq_missing;
  logic word_valid, word_ok, partial_valid;
  logic [X_W-1:0] word_x;
  logic [Y_W-1:0] word_y;
  logic [Z_W-1:0] word_z;
  logic [R_W-1:0] word_r;
  logic [23:0] word_albedo;
  logic [2:0] partial_bytes;
  logic source_idle;

  if (WIRE == 1) begin : g_v1
    ts_rx_v1_word #(
        .Frac(FRAC), .XW(X_W), .YW(Y_W), .ZW(Z_W), .RW(R_W)
    ) u_v1 (
        .clk, .rst, .byte_valid, .byte_data, .end_of_stream,
        .word_valid, .word_ok, .x(word_x), .y(word_y), .z(word_z), .r(word_r), .albedo(word_albedo),
        .partial_valid, .partial_bytes
    );
    assign source_idle = 1'b1;  // a byte is taken in the clock it comes
    assign full = 1'b0;
    assign {rep_valid, rep_garbage, rep_bytes} = '0;
    assign {hdr_sequence, hdr_count, frame_bytes, hdr_frac} = '0;
    assign {in_body, bad_sphere, intact, rec_valid, rec_copy, copy_done, bad_hierarchy} = '0;
    assign {rec_x, rec_y, rec_z, rec_r, rec_material, rec_albedo, rec_ior} = '0;
    assign {seq_done, seq_replay, seq_new, seq_missing} = '0;
  end else begin : g_framed
    logic [31:0] hdr_session;
    logic frame_intact, frame_rec_valid, rec_node;  // the decoder's intact frame and records, nodes among them
    logic [63:0] rec_links;
    ts_rx_frame #(
        .Wire(WIRE), .MaxSpheres(MAX_SPHERES), .CntW(CNT_W), .Hierarchy(HIERARCHY)
    ) u_frame (
        .clk, .rst, .byte_valid, .byte_data, .end_of_stream, .full,
        .rep_valid, .rep_garbage, .rep_bytes,
        .hdr_session, .hdr_sequence, .hdr_count, .hdr_frac, .frame_bytes, .in_body, .bad_sphere,
        .intact(frame_intact), .admit_drop, .admit_copy,
        .rec_valid(frame_rec_valid), .rec_copy, .rec_x, .rec_y, .rec_z, .rec_r, .rec_material, .rec_albedo,
        .rec_node, .rec_links, .copy_done,
        .idle(source_idle)
    );
    // The spheres' records go on to the commit's checks and scene memory, the nodes' only to the hierarchy's check.
    // (Without hierarchies there are no nodes: the record valid goes straight on, no gate on the path to scene
    // memory's write.)
    assign rec_valid = HIERARCHY != 0 ? frame_rec_valid && !rec_node : frame_rec_valid;
    assign rec_ior = rec_links[15:0];  // a sphere record's last field
    if (HIERARCHY != 0) begin : g_hierarchy
      // An intact frame's verdict waits for its hierarchy's check (a frame without one passes it at once): the
      // sequence rules and the commit see `intact` when it is done (the check is done only after `check`, which is
      // the frame's intact), with its answer held until the next frame's.
      logic in_body_q;
      logic check_done, check_ok;
      always_ff @(posedge clk) begin
        in_body_q <= rst ? 1'b0 : in_body;
        if (check_done) bad_hierarchy <= !check_ok;
        intact <= !rst && check_done;
      end
      ts_rx_hierarchy #(
          .MaxSpheres(MAX_SPHERES), .CoordW(X_W), .RadiusW(R_W)
      ) u_hierarchy (
          .clk, .rst, .begin_world(in_body && !in_body_q),
          .node_we(frame_rec_valid && !rec_copy && rec_node),
          .node_x(rec_x), .node_y(rec_y), .node_z(rec_z), .node_radius(rec_r),
          .node_first_child(rec_links[63:48]), .node_children(rec_links[47:40]),
          .node_sphere_count(rec_links[39:32]), .node_first_sphere(rec_links[31:0]),
          .check(frame_intact), .done(check_done), .ok(check_ok),
          .sphere_we(frame_rec_valid && !rec_copy && !rec_node),
          .sphere_x(rec_x[X_W-1:0]), .sphere_y(rec_y[X_W-1:0]), .sphere_z(rec_z[X_W-1:0]), .sphere_r(rec_r[R_W-1:0])
      );
    end else begin : g_flat
      assign intact = frame_intact;
      assign bad_hierarchy = 1'b0;
      logic unused_links;  // a sphere record's ior is all the commit reads of them without a hierarchy
      assign unused_links = ^rec_links[63:16];
    end
    ts_rx_sequence #(
        .Wire(WIRE)
    ) u_sequence (
        .clk, .rst, .check(intact), .session(hdr_session), .number(hdr_sequence),
        .done(seq_done), .replay(seq_replay), .new_session(seq_new), .missing(seq_missing)
    );
    assign {word_valid, word_ok, word_x, word_y, word_z, word_r, word_albedo} = '0;
    assign {partial_valid, partial_bytes} = '0;
  end

  ts_rx_commit #(
      .Wire(WIRE), .Frac(FRAC), .XW(X_W), .YW(Y_W), .ZW(Z_W), .RW(R_W), .MaxSpheres(MAX_SPHERES), .CntW(CNT_W),
      .IorMin(IOR_MIN), .IorMax(IOR_MAX)
  ) u_commit (
      .clk, .rst, .byte_valid, .byte_full(full),
      .rep_valid, .rep_garbage, .rep_bytes,
      .hdr_sequence, .hdr_count, .hdr_frac, .frame_bytes, .in_body, .bad_sphere, .bad_hierarchy,
      .intact, .admit_drop, .admit_copy,
      .rec_valid, .rec_copy, .rec_x, .rec_y, .rec_z, .rec_r, .rec_material, .rec_albedo, .rec_ior, .copy_done,
      .seq_done, .seq_replay, .seq_new, .seq_missing,
      .word_valid, .word_ok, .word_x, .word_y, .word_z, .word_r, .word_albedo, .partial_valid, .partial_bytes,
      .sm_begin, .sm_we, .sm_waddr, .sm_wx, .sm_wy, .sm_wz, .sm_wr, .sm_wmetal, .sm_walbedo,
      .sm_commit, .sm_count, .sm_sequence, .sm_replaced,
      .worlds_accepted, .worlds_replaced, .frames_rejected, .garbage_runs, .bytes_dropped,
      .worlds_missing, .worlds_replayed, .sessions, .bytes_received, .overflow_bytes,
      .source_idle, .idle
  );
endmodule
