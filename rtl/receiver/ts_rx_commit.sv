// ts_rx_commit: what the receiver does with what the wire's decoder hands it: counts every byte it drops, puts each
// intact frame through the sequence rules, refuses content the device cannot hold, and writes an accepted world
// into scene memory's back copy: begin_write, one write per sphere, commit. Part of ts_receiver (docs/rtl.md).
//
// C++ twin: device::Receiver (src/tripsitter/device/receiver.h/.cpp): admit (the sequence rules' verdict and its
// counters), accept_frame (the fractional bits and the preset's ranges, then the back copy), accept_v1, reject and
// report, and ReceiverStats. The counters are ReceiverStats' fields, counted at the same events (last_error, a
// sentence, is not kept), and two extras: bytes_received (every byte stored) and overflow_bytes (ts_rx_frame's
// buffer was full).
//
// Framed wires (2, 3): the spheres of a frame (ts_rx_frame's records) are checked against the preset's ranges while
// the frame is checked; an intact frame goes to the sequence rules (ts_rx_sequence); a replay is counted and dropped
// (`admit_drop`), a world with a bad sphere, other fractional bits or a sphere outside the preset is rejected
// (`admit_drop`), any other is accepted (`admit_copy`, begin_write): ts_rx_frame goes over its payload again and
// each record is written, then `copy_done` commits it. v1: a word in range is one sphere, written at once and
// numbered by the words accepted; a word out of range, or a partial word at the end of the stream, is rejected.
//
// Scene memory's write side is driven from registers of this block and of the decoders (the records, the v1
// sphere, the header's count and number), so its write port adds no logic but the metal flag's compare.
module ts_rx_commit #(
    parameter int Wire = 3,
    parameter int Frac = 4,
    parameter int XW = 24,
    parameter int YW = 24,
    parameter int ZW = 24,
    parameter int RW = 24,
    parameter int MaxSpheres = 4096,
    parameter int CntW = 64,
    localparam int AW = $clog2(MaxSpheres)
) (
    input  logic            clk,
    input  logic            rst,
    input  logic            byte_valid,
    input  logic            byte_full,      // ts_rx_frame's buffer is full (0 on v1)
    // Framed wires: ts_rx_frame.
    input  logic            rep_valid,
    input  logic            rep_garbage,
    input  logic [CntW-1:0] rep_bytes,
    input  logic [31:0]     hdr_sequence,
    input  logic [AW:0]     hdr_count,      // at most MaxSpheres: ts_rx_frame's header check saw to it
    input  logic [7:0]      hdr_frac,
    input  logic [31:0]     frame_bytes,
    input  logic            in_body,
    input  logic            bad_sphere,
    input  logic            intact,
    output logic            admit_drop,
    output logic            admit_copy,
    input  logic            rec_valid,
    input  logic            rec_copy,
    input  logic [31:0]     rec_x,
    input  logic [31:0]     rec_y,
    input  logic [31:0]     rec_z,
    input  logic [31:0]     rec_r,
    input  logic [7:0]      rec_material,
    input  logic [23:0]     rec_albedo,
    input  logic            copy_done,
    // Framed wires: ts_rx_sequence (its check is `intact`).
    input  logic            seq_done,
    input  logic            seq_replay,
    input  logic            seq_new,
    input  logic [31:0]     seq_missing,
    // v1: ts_rx_v1_word.
    input  logic            word_valid,
    input  logic            word_ok,
    input  logic [XW-1:0]   word_x,
    input  logic [YW-1:0]   word_y,
    input  logic [ZW-1:0]   word_z,
    input  logic [RW-1:0]   word_r,
    input  logic [23:0]     word_albedo,
    input  logic            partial_valid,
    input  logic [2:0]      partial_bytes,
    // Scene memory's write side (ts_scene_memory).
    output logic            sm_begin,
    output logic            sm_we,
    output logic [AW-1:0]   sm_waddr,
    output logic [XW-1:0]   sm_wx,
    output logic [YW-1:0]   sm_wy,
    output logic [ZW-1:0]   sm_wz,
    output logic [RW-1:0]   sm_wr,
    output logic            sm_wmetal,
    output logic [23:0]     sm_walbedo,
    output logic            sm_commit,
    output logic [AW:0]     sm_count,
    output logic [31:0]     sm_sequence,
    input  logic            sm_replaced,    // scene memory: sm_begin overwrote a world never shown
    // ReceiverStats.
    output logic [CntW-1:0] worlds_accepted,
    output logic [CntW-1:0] worlds_replaced,
    output logic [CntW-1:0] frames_rejected,
    output logic [CntW-1:0] garbage_runs,
    output logic [CntW-1:0] bytes_dropped,
    output logic [CntW-1:0] worlds_missing,
    output logic [CntW-1:0] worlds_replayed,
    output logic [CntW-1:0] sessions,
    output logic [CntW-1:0] bytes_received,
    output logic [CntW-1:0] overflow_bytes,
    input  logic            source_idle,    // the decoder has processed every byte received
    output logic            idle
);
  localparam bit V1 = Wire == 1;
  // The preset's ranges (core::FixedFormat::contains), as 64-bit signed bounds.
  localparam logic signed [63:0] XMin = -(64'sd1 <<< (XW - 1));
  localparam logic signed [63:0] XMax = (64'sd1 <<< (XW - 1)) - 64'sd1;
  localparam logic signed [63:0] YMin = -(64'sd1 <<< (YW - 1));
  localparam logic signed [63:0] YMax = (64'sd1 <<< (YW - 1)) - 64'sd1;
  localparam logic signed [63:0] ZMin = -(64'sd1 <<< (ZW - 1));
  localparam logic signed [63:0] ZMax = (64'sd1 <<< (ZW - 1)) - 64'sd1;
  localparam logic signed [63:0] RMax = (64'sd1 <<< RW) - 64'sd1;

  // ---- accept_frame's content checks, as the frame's records go by ----
  wire signed [63:0] sx = {{32{rec_x[31]}}, rec_x};
  wire signed [63:0] sy = {{32{rec_y[31]}}, rec_y};
  wire signed [63:0] sz = {{32{rec_z[31]}}, rec_z};
  wire signed [63:0] sr = {32'd0, rec_r};
  wire outside = sx < XMin || sx > XMax || sy < YMin || sy > YMax || sz < ZMin || sz > ZMax || sr > RMax;
  logic outside_any_q;  // a record of this frame lies outside the preset's formats
  logic content_bad_q;  // the frame's content is refused: a bad sphere, other fractional bits, a sphere outside

  // ---- The events counted: at most one drop report a clock (the decoder's, or a verdict's) ----
  wire v1_reject = V1 && (partial_valid || (word_valid && !word_ok));
  wire verdict = !V1 && seq_done;
  wire verdict_drop = verdict && (seq_replay || content_bad_q);
  wire drop = (!V1 && rep_valid) || v1_reject || verdict_drop;
  wire [CntW-1:0] drop_bytes = V1 ? (partial_valid ? CntW'(partial_bytes) : CntW'(ts_link_pkg::V1WordBytes))
                                  : (rep_valid ? rep_bytes : CntW'(frame_bytes));
  wire drop_garbage = !V1 && rep_valid && rep_garbage;
  wire drop_replay = verdict && seq_replay;
  wire begin_world = V1 ? word_valid && word_ok : verdict && !verdict_drop;  // accept_v1, or accept_frame

  logic v1_write_q;           // v1: the accepted word's write and commit
  logic [31:0] v1_number_q;   // v1: the next accepted word's number (the v1 world's sequence number)

  always_ff @(posedge clk) begin
    if (rst) begin
      sm_begin <= 1'b0;
      admit_drop <= 1'b0;
      admit_copy <= 1'b0;
      v1_write_q <= 1'b0;
      v1_number_q <= 32'd1;
      sm_waddr <= '0;
      worlds_accepted <= '0;
      worlds_replaced <= '0;
      frames_rejected <= '0;
      garbage_runs <= '0;
      bytes_dropped <= '0;
      worlds_missing <= '0;
      worlds_replayed <= '0;
      sessions <= '0;
      bytes_received <= '0;
      overflow_bytes <= '0;
    end else begin
      if (byte_valid && !byte_full) bytes_received <= bytes_received + 1'b1;
      if (byte_valid && byte_full) overflow_bytes <= overflow_bytes + 1'b1;
      if (sm_replaced) worlds_replaced <= worlds_replaced + 1'b1;
      if (drop) begin
        // Receiver::report (garbage or a damaged frame), reject (content), admit (a replay).
        bytes_dropped <= bytes_dropped + drop_bytes;
        if (drop_garbage) garbage_runs <= garbage_runs + 1'b1;
        else if (drop_replay) worlds_replayed <= worlds_replayed + 1'b1;
        else frames_rejected <= frames_rejected + 1'b1;
      end
      if (verdict && !seq_replay) begin
        // Receiver::admit: a world the sequence rules let through, whatever its content.
        worlds_missing <= worlds_missing + CntW'(seq_missing);
        if (seq_new) sessions <= sessions + 1'b1;
      end
      if (sm_commit) worlds_accepted <= worlds_accepted + 1'b1;

      admit_drop <= verdict_drop;
      admit_copy <= verdict && !verdict_drop;
      sm_begin <= begin_world;
      v1_write_q <= V1 && sm_begin;
      if (v1_write_q) v1_number_q <= v1_number_q + 32'd1;
      // The sphere's place in the back copy: 0 from begin_write on, one up per write.
      if (begin_world) sm_waddr <= '0;
      else if (sm_we) sm_waddr <= sm_waddr + 1'b1;
    end
  end

  // Datapath: no reset (in_body clears the content checks before a frame's records).
  always_ff @(posedge clk) begin
    if (!in_body) outside_any_q <= 1'b0;
    else if (rec_valid && !rec_copy && outside) outside_any_q <= 1'b1;
    content_bad_q <= bad_sphere || outside_any_q || hdr_frac != 8'(Frac);
  end

  // Scene memory's write side, from registers.
  assign sm_we = V1 ? v1_write_q : rec_valid && rec_copy;
  assign sm_wx = V1 ? word_x : rec_x[XW-1:0];
  assign sm_wy = V1 ? word_y : rec_y[YW-1:0];
  assign sm_wz = V1 ? word_z : rec_z[ZW-1:0];
  assign sm_wr = V1 ? word_r : rec_r[RW-1:0];
  assign sm_wmetal = !V1 && rec_material == 8'(ts_link_pkg::MaterialMetal);  // a v1 sphere is lambertian
  assign sm_walbedo = V1 ? word_albedo : rec_albedo;
  assign sm_commit = V1 ? v1_write_q : copy_done;
  assign sm_count = V1 ? (AW + 1)'(1) : hdr_count;
  assign sm_sequence = V1 ? v1_number_q : hdr_sequence;

  assign idle = source_idle && !rep_valid && !word_valid && !partial_valid && !intact && !seq_done && !sm_begin &&
                !admit_drop && !admit_copy && !v1_write_q && !copy_done;
endmodule
