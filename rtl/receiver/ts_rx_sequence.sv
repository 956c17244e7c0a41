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
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs rx_sequence_v3, rx_sequence_v2): the
  // verdict is the table of docs/link_format.md ("Sessions and sequence numbers") for any session and number,
  // hostile ones included, and the rules' state moves only with a world shown. The inputs are free; the verdict
  // properties hold while they have kept the block's contract (f_ok), which ts_rx_frame keeps (a frame's header
  // fields are held while it waits for the verdict, p_waits_held, and no other frame is reported meanwhile,
  // p_one_waits).
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The contract: no check in the clock after a check (while it is compared), session and number held then.
  // f_ok: kept so far, this clock included.
  logic f_in_ok;
  logic [31:0] f_held_session, f_held_number;
  wire f_ok = f_in_ok && !(cmp_q && (check || session != f_held_session || number != f_held_number));
  always_ff @(posedge clk) begin
    if (rst) f_in_ok <= 1'b1;
    else f_in_ok <= f_ok;
    if (check) begin
      f_held_session <= session;
      f_held_number <= number;
    end
  end

  // "One of the last 16 sessions that ended", for one session the solver picks (so for every session), f_s:
  // whether it ended (it was the current session and a world of another session was shown) and how many sessions
  // began since (up to 16: then it is forgotten). The block's current session and last number (seen_q,
  // cur_session_q, last_q) are the table's "current one" and p: p_state_* below hold them to the worlds shown.
  /* verilator lint_off UNDRIVEN */  // a free value of the proof: the solver picks it, once
  (* anyconst *) logic [31:0] f_s;
  /* verilator lint_on UNDRIVEN */
  logic f_s_ended;
  logic [4:0] f_s_since;
  wire f_s_retired = f_s_ended && f_s_since < 5'(ts_link_pkg::RetiredSessions);  // (the package's 16, not Ring)
  wire f_begins = cmp_q && v_new;  // a world shown begins a session (v3: another session's; v2: the first)
  always_ff @(posedge clk) begin
    if (rst) begin
      f_s_ended <= 1'b0;
      f_s_since <= '0;
    end else if (f_begins) begin
      if (f_held_session == f_s) f_s_ended <= 1'b0;
      else if (seen_q && cur_session_q == f_s) f_s_ended <= 1'b1;
      if (seen_q && cur_session_q == f_s) f_s_since <= '0;
      else if (seen_q && f_s_ended && f_s_since != 5'(ts_link_pkg::RetiredSessions)) begin
        f_s_since <= f_s_since + 5'd1;  // another session ends after f_s
      end
    end
  end
  // Where f_s sits in the ring while it is remembered, and whether another valid slot holds it.
  wire [$clog2(Ring)-1:0] f_s_slot = retired_next_q - 4'd1 - f_s_since[3:0];
  logic f_s_elsewhere;
  always_comb begin
    f_s_elsewhere = 1'b0;
    for (int i = 0; i < Ring; i++) begin
      f_s_elsewhere = f_s_elsewhere | (retired_v_q[i] && retired_q[i] == f_s && 4'(i) != f_s_slot);
    end
  end

  // The table, for the frame being compared (cmp_q): its session and number as they were at the check, p = last_q.
  wire f_same = seen_q && f_held_session == cur_session_q;
  wire f_newer = f_held_number > last_q;
  wire [31:0] f_from_one = (f_held_number == 32'd0) ? 32'd0 : f_held_number - 32'd1;  // s - 1 (0 for 0)
  always_comb begin
    if (past_valid && cmp_q && f_ok) begin
      if (Wire == 2) begin
        // v2: every world is shown; a step forward counts the numbers between; the first world begins a session.
        p_verdict_v2: assert (!v_replay && v_new == !seen_q
                              && v_missing == ((seen_q && f_newer) ? f_held_number - last_q - 32'd1 : 32'd0));
      end else if (f_same) begin
        // The current session: shown only if s > p, with s - p - 1 missing; s <= p is a replay. So an older or
        // repeated number is never shown. Rules out wrap-around and equal-number mistakes the tests' numbers miss.
        p_verdict_current: assert (v_replay == !f_newer && !v_new
                                   && (!f_newer || v_missing == f_held_number - last_q - 32'd1));
      end else if (f_held_session == f_s) begin
        // Another session: a replay if it is one of the last 16 that ended, else shown as a new session with
        // s - 1 missing. Rules out showing a world of an ended session, or refusing a restarted host.
        p_verdict_other: assert (v_replay == f_s_retired
                                 && (f_s_retired || (v_new && v_missing == f_from_one)));
      end
    end
    if (past_valid && Wire == 3 && f_in_ok) begin
      // Invariants that make the induction close (each a property): the ring holds f_s, at its place and nowhere
      // else, exactly while it is one of the last 16 ended sessions; the current session is not an ended one.
      p_ring_holds_ended: assert (!f_s_elsewhere
                                  && (retired_v_q[f_s_slot] && retired_q[f_s_slot] == f_s) == f_s_retired);
      p_current_not_ended: assert (!(seen_q && cur_session_q == f_s && f_s_ended)
                                   && f_s_since <= 5'(ts_link_pkg::RetiredSessions)
                                   && (seen_q || (retired_v_q == '0 && !f_s_ended)));
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      // A verdict two clocks after each check and at no other time, as registered. Rules out a verdict without a
      // frame that ts_rx_frame reported intact (a link of the chain in ts_rx_commit).
      p_done_after_check: assert (done == $past(cmp_q) && cmp_q == $past(check));
      if (done) p_verdict_registered: assert (replay == $past(v_replay) && new_session == $past(v_new)
                                              && missing == $past(v_missing));
      // The rules' state moves only with a world shown, to that world's session and number. Rules out a replay
      // that moves p (so that the next world of the session is refused, or an old one let through).
      if ($past(cmp_q && !v_replay)) begin
        if ($past(f_ok)) p_state_shown: assert (seen_q && last_q == $past(f_held_number)
                                                && (Wire == 2 || cur_session_q == $past(f_held_session)));
      end else begin
        p_state_holds: assert (seen_q == $past(seen_q) && last_q == $past(last_q)
                               && (Wire == 2 || cur_session_q == $past(cur_session_q)));
      end
    end
  end
`endif
endmodule
