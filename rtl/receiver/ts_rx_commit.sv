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
// (`admit_drop`), a world with a bad sphere, other fractional bits, a sphere outside the preset (its formats, and
// a dielectric's index of refraction its range) or (a receiver that takes hierarchies) a hierarchy that breaks its
// rules is rejected (`admit_drop`), any other is accepted (`admit_copy`, begin_write): ts_rx_frame goes over its
// payload again and each record is written, then `copy_done` commits it. v1: a word in range is one sphere, written
// at once and numbered by the words accepted; a word out of range, or a partial word at the end of the stream, is
// rejected.
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
    // The indices of refraction a dielectric may have, u4.12 (the path presets: kPathIorMin..kPathIorMax of
    // device/path_kernel.h); the wire's own rule, above 0, is ts_rx_frame's bad sphere.
    parameter int IorMin = 0,
    parameter int IorMax = 65535,
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
    input  logic            bad_hierarchy,  // the frame's hierarchy breaks its rules (ts_rx_hierarchy), with intact
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
    input  logic [15:0]     rec_ior,
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
  logic ior_outside;  // a dielectric's index of refraction outside IorMin..IorMax
  if (IorMin > 0 || IorMax < 65535) begin : g_ior
    assign ior_outside = rec_material == 8'(ts_link_pkg::MaterialDielectric) &&
                         (rec_ior < 16'(IorMin) || rec_ior > 16'(IorMax));
  end else begin : g_any_ior
    assign ior_outside = 1'b0;
    logic unused_ior;  // every index the wire allows is taken
    assign unused_ior = ^rec_ior;
  end
  wire outside = sx < XMin || sx > XMax || sy < YMin || sy > YMax || sz < ZMin || sz > ZMax || sr > RMax ||
                 ior_outside;
  logic outside_any_q;  // a record of this frame lies outside the preset's formats
  logic content_bad_q;  // the frame's content is refused: a bad sphere, other fractional bits, a sphere outside,
                        // a hierarchy that breaks its rules

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
    content_bad_q <= bad_sphere || outside_any_q || hdr_frac != 8'(Frac) || bad_hierarchy;
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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs rx_commit_v3, rx_commit_v1). The inputs
  // (the decoders' outputs) are free; the properties hold while the inputs have kept the contract below
  // (f_src_ok_now: so far, this clock included), which ts_rx_frame, ts_rx_sequence and ts_rx_v1_word guarantee
  // (their properties named with each clause). Nothing is assumed but the reset at the start.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // ---- The contract of the framed wires' decoders (ts_rx_frame, ts_rx_sequence) ----
  // One frame at a time: `intact`, then the verdict (seq_done) two clocks later (ts_rx_sequence's
  // p_done_after_check), then, if admitted for copy, its records with rec_copy and copy_done after exactly
  // hdr_count of them (ts_rx_frame's p_copy_after_admit, p_copy_records, p_copy_done_count); no report and no
  // record of the check pass (rec_copy low) while a frame waits or is copied (p_one_waits); the frame's header and
  // content flags (bad_hierarchy among them: ts_receiver holds it) held from intact until the frame is done with
  // (p_waits_held), its count within the capacity (p_header_checked); no header passed (in_body) in the clock after
  // a reset (hdr_ok_q is reset).
  logic f_src_ok, f_rst_q;
  logic [1:0] f_wait;     // clocks since intact while the verdict is pending (1, 2), 0: none pending
  logic f_copy;           // admitted for copy: records and copy_done may come
  logic [AW+1:0] f_copied;  // records copied so far
  logic [AW:0] f_count;
  logic [31:0] f_sequence, f_frame_bytes;
  logic [7:0] f_frac;
  logic f_bad_sphere, f_bad_hierarchy;
  wire f_busy = f_wait != 2'd0 || f_copy;
  wire f_rec_copy = rec_valid && rec_copy;
  // v1 (ts_rx_v1_word): a word (word_valid) or a partial word (partial_valid) at most one a clock, and a word
  // never in the two clocks after another (its 8 bytes take 8 clocks at least: ts_rx_v1_word's p_word_spacing).
  logic [1:0] f_v1_recent;  // a word in the last clock (bit 0) or the one before (bit 1)
  wire f_v1_ok = !(word_valid && (partial_valid || f_v1_recent != 2'b00));
  wire f_src_ok_now = f_src_ok && (V1 ? f_v1_ok : !(
      (intact && (f_busy || admit_copy)) ||
      (seq_done != (f_wait == 2'd2)) ||
      (f_rec_copy && (!f_copy || f_copied >= (AW + 2)'(hdr_count))) ||
      (copy_done && (!f_copy || f_copied != (AW + 2)'(hdr_count))) ||
      (rec_valid && !rec_copy && f_busy) ||
      (rep_valid && seq_done) ||
      (intact && hdr_count > (AW + 1)'(MaxSpheres)) ||
      (f_rst_q && in_body) ||  // the decoder's header state is reset with it
      (f_busy && (hdr_count != f_count || hdr_sequence != f_sequence || frame_bytes != f_frame_bytes ||
                  hdr_frac != f_frac || bad_sphere != f_bad_sphere || bad_hierarchy != f_bad_hierarchy ||
                  !in_body))));
  always_ff @(posedge clk) begin
    f_rst_q <= rst;
    f_v1_recent <= rst ? 2'b00 : {f_v1_recent[0], word_valid};
    if (rst) begin
      f_src_ok <= 1'b1;
      f_wait <= '0;
      f_copy <= 1'b0;
    end else begin
      f_src_ok <= f_src_ok_now;
      if (intact) f_wait <= 2'd1;
      else if (f_wait == 2'd2) f_wait <= 2'd0;
      else if (f_wait != 2'd0) f_wait <= f_wait + 2'd1;
      if (admit_copy) f_copy <= 1'b1;
      else if (copy_done) f_copy <= 1'b0;
    end
    if (admit_copy) f_copied <= '0;
    else if (f_rec_copy) f_copied <= f_copied + 1'b1;
    if (intact) begin
      f_count <= hdr_count;
      f_sequence <= hdr_sequence;
      f_frame_bytes <= frame_bytes;
      f_frac <= hdr_frac;
      f_bad_sphere <= bad_sphere;
      f_bad_hierarchy <= bad_hierarchy;
    end
  end

  // ---- The specification of accept_frame's content check: the frame's fractional bits are the preset's, no record
  // has a bad sphere, and every record of the check pass fits the preset's formats (x, y, z signed in XW, YW, ZW
  // bits: the bits above the format all copies of its sign bit; the radius unsigned in RW bits) and a dielectric's
  // index of refraction its range ----
  function automatic logic f_fits_signed(input logic [31:0] v, input int w);
    f_fits_signed = (v >> (w - 1)) == 32'd0 || (~v >> (w - 1)) == 32'd0;
  endfunction
  logic f_ior_fits;  // in IorMin..IorMax (every 16-bit index when the range is all of them)
  if (IorMin > 0 || IorMax < 65535) begin : g_f_ior
    assign f_ior_fits = {16'd0, rec_ior} - 32'(IorMin) <= 32'(IorMax - IorMin);
  end else begin : g_f_any_ior
    assign f_ior_fits = 1'b1;
  end
  wire f_rec_fits = f_fits_signed(rec_x, XW) && f_fits_signed(rec_y, YW) && f_fits_signed(rec_z, ZW)
                    && (rec_r >> RW) == 32'd0
                    && (rec_material != 8'(ts_link_pkg::MaterialDielectric) || f_ior_fits);
  logic f_outside;  // a record of this frame's check pass does not fit
  always_ff @(posedge clk) begin
    if (!in_body) f_outside <= 1'b0;
    else if (rec_valid && !rec_copy && !f_rec_fits) f_outside <= 1'b1;
  end
  wire f_accept = !seq_replay && !bad_sphere && !f_outside && hdr_frac == 8'(Frac) && !bad_hierarchy;

  // ---- Scene memory's side: the world open (begin_write seen, commit not yet) and its writes so far ----
  logic f_open;
  logic [AW+1:0] f_writes;
  always_ff @(posedge clk) begin
    if (rst) f_open <= 1'b0;
    else if (sm_begin) f_open <= 1'b1;
    else if (sm_commit) f_open <= 1'b0;
    if (sm_begin) f_writes <= '0;
    else if (sm_we) f_writes <= f_writes + 1'b1;
  end

  always_comb begin
    if (past_valid && !V1 && f_src_ok_now) begin
      // Invariants that make the induction close (each a property): the admission, the scene memory write and the
      // content check are in step with the frame's phase.
      p_phase: assert (!(f_wait != 2'd0 && f_copy) && (f_wait != 2'd1 || !(admit_copy || admit_drop))
                       && sm_begin == admit_copy && f_copy == f_open && (!f_copy || f_copied == f_writes)
                       && (!(admit_copy || admit_drop) || (f_wait == 2'd0 && !f_copy))
                       && (!f_busy || f_count <= (AW + 1)'(MaxSpheres)));
      p_outside_tracks: assert (!in_body || outside_any_q == f_outside);
    end
    if (past_valid && V1 && f_src_ok_now) begin
      // v1: a word's begin_write the clock after it, its write and commit the clock after that.
      p_v1_phase: assert (f_open == v1_write_q && (!sm_begin || f_v1_recent[0]) && (!v1_write_q || f_v1_recent[1]));
    end
    if (past_valid && f_src_ok_now) begin
      // Scene memory's write protocol (ts_scene_memory's f_proto_ok): begin_write when no world is open, writes and
      // the commit only while one is open, from the clock after its begin_write. Rules out a write into a world
      // already committed (waiting for the swap) or a commit of a world never begun.
      p_sm_protocol: assert (!(sm_begin && (f_open || sm_commit)) && !((sm_we || sm_commit) && !f_open));
      // Scene memory is never written beyond its capacity, nor twice at one place in a world: each write's
      // address is the number of writes since begin_write, below the world's count, itself at most MaxSpheres.
      // Rules out an address that wraps (sphere MaxSpheres over sphere 0) or a count the header check let by.
      if (sm_we) p_write_in_capacity: assert (sm_waddr == f_writes[AW-1:0] && f_writes < (AW + 2)'(sm_count)
                                              && sm_count <= (AW + 1)'(MaxSpheres));
      if (f_open) p_waddr_counts: assert (sm_waddr == f_writes[AW-1:0]);
      // A commit is of a whole world: as many writes as its count. Rules out a world shown with spheres missing.
      if (sm_commit) p_commit_whole: assert (f_writes + (AW + 2)'(sm_we) == (AW + 2)'(sm_count));
    end
  end

  // What the clock after this one must show (each counter grown by this clock's event; the verdict's answer), when
  // this clock keeps the contract and has no reset.
  logic f_next_checked;
  logic f_exp_admit_copy, f_exp_admit_drop;
  logic [CntW-1:0] f_exp_received, f_exp_overflow, f_exp_replaced, f_exp_accepted, f_exp_garbage, f_exp_replayed;
  logic [CntW-1:0] f_exp_rejected, f_exp_dropped, f_exp_missing, f_exp_sessions;
  wire f_verdict_drop = seq_done && !f_accept;
  always_ff @(posedge clk) begin
    f_next_checked <= !rst && f_src_ok_now;
    f_exp_admit_copy <= seq_done && f_accept;
    f_exp_admit_drop <= f_verdict_drop;
    f_exp_received <= bytes_received + CntW'(byte_valid && !byte_full);
    f_exp_overflow <= overflow_bytes + CntW'(byte_valid && byte_full);
    f_exp_replaced <= worlds_replaced + CntW'(sm_replaced);
    f_exp_accepted <= worlds_accepted + CntW'(sm_commit);
    f_exp_garbage <= garbage_runs + CntW'(rep_valid && rep_garbage);
    f_exp_replayed <= worlds_replayed + CntW'(seq_done && seq_replay);
    f_exp_rejected <= frames_rejected + (V1 ? CntW'(partial_valid || (word_valid && !word_ok))
                                            : CntW'((rep_valid && !rep_garbage) || (f_verdict_drop && !seq_replay)));
    f_exp_dropped <= bytes_dropped + (V1 ? (partial_valid ? CntW'(partial_bytes)
                                                          : (word_valid && !word_ok) ? CntW'(8) : CntW'(0))
                                         : (rep_valid ? rep_bytes : f_verdict_drop ? CntW'(frame_bytes) : CntW'(0)));
    f_exp_missing <= worlds_missing + ((seq_done && !seq_replay) ? CntW'(seq_missing) : CntW'(0));
    f_exp_sessions <= sessions + CntW'(seq_done && !seq_replay && seq_new);
  end

  always_comb begin
    if (past_valid && f_next_checked) begin
      // The verdict: a frame is copied to scene memory (admit_copy, begin_write) only when the sequence rules show
      // it and its content fits the device (fractional bits, no bad sphere, every record in the preset's formats);
      // any other verdict drops it. A link of the chain "a frame that fails its CRC or its header check leaves both
      // copies of scene memory unchanged": scene memory is written only between begin_write and commit
      // (p_sm_protocol here, ts_scene_memory's p_mem_words and p_read_front), begin_write only on an accepted
      // verdict (here), a verdict only two clocks after `intact` (ts_rx_sequence's p_done_after_check), and
      // `intact` only for a frame whose header checks and CRC passed (ts_rx_frame's p_intact_checked,
      // p_header_checked). Rules out a replay, or a world outside the formats, reaching the back copy.
      if (!V1) begin
        p_admit_accepted: assert (admit_copy == f_exp_admit_copy && admit_drop == f_exp_admit_drop
                                  && sm_begin == f_exp_admit_copy);
      end
      // Every counter only grows, by exactly what the clock's one event adds (1, or a report's or a frame's bytes):
      // never otherwise, never backwards (docs/link_format.md, "What the receiver counts"). With CntW bits that is
      // growth until 2^CntW; the receiver's 64-bit counters would need more than 2^32 clocks of the largest step
      // (a frame's 32-bit size) to wrap. Rules out an event counted twice, in the wrong counter, or not at all.
      p_bytes_received_grows: assert (bytes_received == f_exp_received);
      p_overflow_bytes_grows: assert (overflow_bytes == f_exp_overflow);
      p_worlds_replaced_grows: assert (worlds_replaced == f_exp_replaced);
      p_worlds_accepted_grows: assert (worlds_accepted == f_exp_accepted);
      p_frames_rejected_grows: assert (frames_rejected == f_exp_rejected);
      p_bytes_dropped_grows: assert (bytes_dropped == f_exp_dropped);
      if (!V1) begin
        p_garbage_runs_grows: assert (garbage_runs == f_exp_garbage);
        p_worlds_replayed_grows: assert (worlds_replayed == f_exp_replayed);
        p_worlds_missing_grows: assert (worlds_missing == f_exp_missing);
        p_sessions_grows: assert (sessions == f_exp_sessions);
      end
    end
  end
`endif
endmodule
