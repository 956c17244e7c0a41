// ts_rx_sequence: the receiver's sequence rules, which turn the session and number of every frame that arrived
// intact into "show" or "replay" and a count of the worlds the link lost. Part of ts_receiver (docs/rtl.md).
//
// C++ twin: link::SequenceRules::check (src/tripsitter/link/sequence.h/.cpp; docs/link_format.md, "Sessions and
// sequence numbers"). v3: a world of the current session is shown if its number is above the last one's and counts
// the numbers between as missing; at or below it, it is a replay. A world of another session that has not ended
// starts that session: it is shown, the numbers below its own count as missing, and the session it replaces joins
// the ring of RetiredSessions ended ones (valid bits, compared in parallel). A world of an ended session is a
// replay. v2: every world is shown; a number above the last counts the numbers between as missing.
//
// Timing: `check` for one clock with `session` and `number` held until `done`, which rises two clocks later with
// the verdict (`replay`, `new_session`, `missing`); the rules' state moves on with it (not on a replay). The first
// clock registers the comparisons (the current session, the ring, the step from the last number), the second
// decides from them, so neither is deeper than a 32-bit compare.
module ts_rx_sequence #(
    parameter int Wire = 3  // 2 or 3
) (
    input  logic        clk,
    input  logic        rst,
    input  logic        check,
    input  logic [31:0] session,      // v3; ignored on v2
    input  logic [31:0] number,
    output logic        done,
    output logic        replay,       // never shown
    output logic        new_session,  // the world begins a host session not seen before (v2: the first world)
    output logic [31:0] missing       // numbers skipped before this world
);
  localparam int Ring = ts_link_pkg::RetiredSessions;

  // The rules' state.
  logic seen_q;                       // a world was shown: cur_session_q and last_q hold
  logic [31:0] cur_session_q, last_q;
  logic [31:0] retired_q[Ring];
  logic [Ring-1:0] retired_v_q;
  logic [$clog2(Ring)-1:0] retired_next_q;

  // The first clock: the comparisons.
  logic cmp_q;                        // the comparisons below are of the frame being checked
  logic same_q;                       // v3: a world of the current session
  logic retired_hit_q;                // v3: a world of an ended session
  logic newer_q;                      // its number is above the last one's
  logic [31:0] step_q;                // number - last - 1: the numbers skipped in this session
  logic [31:0] from_one_q;            // number - 1 (0 for 0): the numbers skipped in a new session

  logic retired_hit;
  always_comb begin
    retired_hit = 1'b0;
    for (int i = 0; i < Ring; i++) retired_hit = retired_hit | (retired_v_q[i] && retired_q[i] == session);
  end

  // The second clock: the verdict from the comparisons.
  logic v_replay, v_new, v_retire;
  logic [31:0] v_missing;
  always_comb begin
    v_replay = 1'b0;
    v_new = 1'b0;
    v_retire = 1'b0;
    v_missing = 32'd0;
    if (Wire == 2) begin
      // No session: every world is shown; only a step forward counts numbers as missing.
      v_new = !seen_q;
      if (seen_q && newer_q) v_missing = step_q;
    end else if (same_q) begin
      v_replay = !newer_q;
      if (newer_q) v_missing = step_q;
    end else if (retired_hit_q) begin
      v_replay = 1'b1;  // a world of a session that has ended
    end else begin
      v_new = 1'b1;     // a host that started or reconnected; its numbers below this one were lost
      v_retire = seen_q;
      v_missing = from_one_q;
    end
  end

  always_ff @(posedge clk) begin
    if (rst) begin
      seen_q <= 1'b0;
      retired_v_q <= '0;
      retired_next_q <= '0;
      cmp_q <= 1'b0;
      done <= 1'b0;
    end else begin
      cmp_q <= check;
      done <= cmp_q;
      if (cmp_q && !v_replay) begin
        seen_q <= 1'b1;
        if (v_retire) begin
          retired_v_q[retired_next_q] <= 1'b1;
          retired_next_q <= retired_next_q + 1'b1;
        end
      end
    end
  end

  // Datapath: no reset (seen_q and the valid bits say when these hold).
  always_ff @(posedge clk) begin
    same_q <= seen_q && session == cur_session_q;
    retired_hit_q <= retired_hit;
    newer_q <= number > last_q;
    step_q <= number + ~last_q;  // number - last - 1
    from_one_q <= (number == 32'd0) ? 32'd0 : number - 32'd1;
    replay <= v_replay;
    new_session <= v_new;
    missing <= v_missing;
    if (cmp_q && !v_replay) begin
      if (Wire == 3) cur_session_q <= session;
      last_q <= number;
      if (v_retire) retired_q[retired_next_q] <= cur_session_q;
    end
  end
endmodule
