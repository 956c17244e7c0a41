// ts_receiver: the device's receiver. Turns the link's byte stream into checked worlds in the back copy of
// scene memory, and counts what it drops, exactly as the C++ receiver does.
//
// C++ model: src/tripsitter/device/receiver.h/.cpp (Receiver, ReceiverStats), with the wires of
// src/tripsitter/link/: wire_v1.h (the 64-bit word), frame.h/.cpp (v2 and v3 frames and FrameStreamDecoder),
// sequence.h/.cpp (SequenceRules); the formats in docs/link_format.md. WIRE selects the wire (1, 2 or 3) and
// FRAC, X_W, Y_W, Z_W, R_W and MAX_SPHERES the preset's scene memory (device/preset.h: wide is 4, 24, 24, 24,
// 24, 4096; board-2023 is 3, 16, 15, 15, 16, 64).
//
// Structure.
//   Byte buffer. Every byte from the SPI slave is written into a circular buffer of 2^BUF_AW bytes (block RAM).
//   The C++ decoder goes back over the bytes of a frame that failed (it drops the first byte and hunts for the
//   magic from the second, so a frame hidden in a damaged one is still found), so the hardware keeps every
//   byte from the start of the frame being decoded: the buffer holds the largest frame the preset can announce
//   plus a quarter more and 512 bytes for the input that arrives while the engine goes back over a frame or
//   copies one into scene memory. A byte that arrives while the buffer is full is dropped and counted in
//   `overflow_bytes` (the model has no such limit): with SCLK at most clk/8 and the engine taking 2 clocks per
//   byte this happens only to streams built to make the decoder go back over the largest frame again and again.
//   Engine. One state machine reads the buffer one byte every 2 clocks (address, then data) at `pos` and does
//   what FrameStreamDecoder does with that byte: while hunting, match the magic (a partial magic waits for more
//   bytes: the magics have no repeated letter, so a mismatch restarts the match at most at the byte itself);
//   while expecting a frame, check each header byte as it comes (magic, version, frac_bits, reserved, and on
//   v3 the header CRC, then count and length, at the offsets the model checks them), then feed payload and
//   trailer through the frame CRC, assemble each 24-byte sphere record and check it (radius 0, material
//   above 2, ior 0, and the preset's ranges). On any failure it rewinds `pos` as the model's read position
//   moves: to the frame's first byte (bad magic: a hunt from there) or its second (a header error, a bad CRC:
//   1 byte dropped, a hunt from the next). On v3 it also applies the cut rule: a 28-byte window of the last
//   bytes; whenever a magic starts 27 bytes back, at frame offset 28 or more, a second CRC unit checks that
//   candidate header in 24 clocks; if it is intact the frame is dropped as truncated up to it and decoding
//   restarts there.
//   Verdict. With the frame CRC good: the sequence rules (SequenceRules: current session and last number, 16
//   ended sessions in a ring with valid bits, compared in parallel), then the content (a bad sphere, other
//   fractional bits, a coordinate outside the preset) decides between reject and accept.
//   Commit. Spheres are not written while the frame is checked: a damaged frame must never touch the world
//   waiting for the swap (the model's back_ changes only when a world is accepted). An accepted frame's payload
//   is still in the byte buffer, so the engine goes over it a second time and writes each sphere into the back
//   copy: begin_write, one write per sphere, commit. That takes 48 clocks per sphere (2 per byte), 2 ms for 4096
//   spheres (whose 98 KB took 79 ms on a 10 MHz link); meanwhile ready is low and a vertical blanking swaps
//   nothing (scene memory has no pending world while the back copy is being overwritten), so a world whose
//   commit spans a blanking is shown one frame later than the model shows it. A v1 word is one sphere, written
//   at once.
//
// Counters: the fields of ReceiverStats (last_error, a sentence, is not kept), counted at the same events.
// Extra: bytes_received (every byte stored), overflow_bytes (see above).
//
// End of stream: `end_of_stream` (the host went away: Receiver::end_of_stream) is handled when the engine has
// processed every byte received before it: a partial frame is dropped as truncated, a hunt in progress as a
// garbage run, a partial v1 word as a rejection. A second end_of_stream before the first is handled moves it
// to the later position (the engine keeps one).
//
// Timing contract: the counters, `ready` (scene memory) and the back copy are final when `idle` is high (every
// received byte processed, nothing being written to scene memory). The test waits for idle before comparing.
module ts_receiver #(
    parameter int WIRE = 3,            // 1, 2 or 3
    parameter int FRAC = 4,            // fractional bits of the preset's formats
    parameter int X_W = 24,            // total bits: x, y, z signed, radius unsigned
    parameter int Y_W = 24,
    parameter int Z_W = 24,
    parameter int R_W = 24,
    parameter int MAX_SPHERES = 4096,  // scene memory capacity; a power of two
    parameter int CNT_W = 64,          // counter width (ReceiverStats holds 64-bit counters)
    parameter int AW = $clog2(MAX_SPHERES),  // derived: leave as it is
    // Byte buffer: the largest frame, a quarter more and 512 bytes (wide: 128 KiB, board-2023: 4 KiB).
    parameter int BUF_AW = (WIRE == 1) ? 4 : $clog2(((WIRE == 3) ? 32 : 24) * 5 / 4 + 30 * MAX_SPHERES + 512)
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
  // ---- Wire layout (frame.cpp, Layout) ----
  localparam int H = (WIRE == 3) ? 28 : 20;          // header bytes
  localparam int SESSION_AT = 8;                     // v3 only
  localparam int SEQUENCE_AT = (WIRE == 3) ? 12 : 8;
  localparam int COUNT_AT = (WIRE == 3) ? 16 : 12;
  localparam int LENGTH_AT = (WIRE == 3) ? 20 : 16;
  localparam int HCRC_AT = 24;                       // v3 only
  localparam int MAX_FRAME = H + 24 * MAX_SPHERES + 4;
  localparam int OW = $clog2(MAX_FRAME + 1) + 1;     // frame offsets
  localparam int PW = BUF_AW + 1;                    // buffer positions: one bit more, so full != empty
  localparam logic [7:0] VERSION = (WIRE == 3) ? 8'd3 : 8'd2;
  localparam logic [7:0] MAGIC3 = (WIRE == 3) ? 8'h33 : 8'h32;  // "TSW3" / "TSW2"
  localparam logic [31:0] MAGIC = {8'h54, 8'h53, 8'h57, MAGIC3};
  localparam logic [31:0] MAX32 = 32'(MAX_SPHERES);
  localparam logic [PW-1:0] DEPTH = {1'b1, {BUF_AW{1'b0}}};
  // The preset's ranges (core::FixedFormat::contains), as 64-bit signed bounds.
  localparam logic signed [63:0] X_MIN = -(64'sd1 <<< (X_W - 1));
  localparam logic signed [63:0] X_MAX = (64'sd1 <<< (X_W - 1)) - 64'sd1;
  localparam logic signed [63:0] Y_MIN = -(64'sd1 <<< (Y_W - 1));
  localparam logic signed [63:0] Y_MAX = (64'sd1 <<< (Y_W - 1)) - 64'sd1;
  localparam logic signed [63:0] Z_MIN = -(64'sd1 <<< (Z_W - 1));
  localparam logic signed [63:0] Z_MAX = (64'sd1 <<< (Z_W - 1)) - 64'sd1;
  localparam logic signed [63:0] R_MAX = (64'sd1 <<< R_W) - 64'sd1;

  function automatic logic [7:0] magic_byte(input logic [1:0] i);
    case (i)
      2'd0: magic_byte = MAGIC[31:24];
      2'd1: magic_byte = MAGIC[23:16];
      2'd2: magic_byte = MAGIC[15:8];
      default: magic_byte = MAGIC[7:0];
    endcase
  endfunction

  // ---- Byte buffer ----
  logic [7:0] buffer[1 << BUF_AW];
  logic [7:0] b;  // the byte at the address presented in the previous clock
  logic [PW-1:0] wr_ptr, pos, start, eos_at;
  wire [PW-1:0] held = wr_ptr - start;  // bytes the engine may still need
  wire full = held == DEPTH;
  wire take = byte_valid && !full;

  always_ff @(posedge clk) begin
    if (take) buffer[wr_ptr[BUF_AW-1:0]] <= byte_data;
    b <= buffer[pos[BUF_AW-1:0]];
  end

  // ---- Engine state ----
  typedef enum logic [3:0] {
    S_FETCH,    // present pos to the buffer (or wait for a byte, or handle end of stream)
    S_EXEC,     // the byte at pos
    S_CAND,     // v3: checking the CRC of a header candidate inside the frame
    S_VERDICT,  // a whole frame: CRC, sequence rules, content
    S_CBEGIN,   // commit: begin_write
    S_CFETCH,   // commit: present a payload byte
    S_CEXEC,    // commit: a payload byte; every 24th writes a sphere
    S_CEND,     // commit: the world is whole
    S_V1C       // v1: write the word's sphere and commit
  } state_t;
  state_t state;

  logic eos_pending;
  logic hunting;
  logic [1:0] m;              // hunting: bytes of the magic matched so far
  logic [CNT_W-1:0] gcount;   // hunting: bytes skipped so far (the run's garbage)
  logic [OW-1:0] off;         // expecting a frame: offset of the byte at pos in the frame
  logic hdr_ok;               // the frame's header has passed
  logic [OW-1:0] fb;          // the frame's size once its header passed
  logic [7:0] frac;
  logic [31:0] session, seq_no, count, length;
  logic [23:0] hcrc_car;      // v3: the carried header CRC's first 3 bytes (the 4th is the byte at pos)
  logic [31:0] hcrc_calc, fcrc_car, fcrc_calc;
  logic [183:0] srec;         // the sphere record's bytes so far (23 at most), first byte in the top bits
  logic [4:0] sbyte;          // its bytes so far
  logic [AW:0] sidx;          // commit: the sphere being written
  logic bad_any;              // a sphere of the frame is bad or outside the preset
  logic [215:0] window;       // v3: the frame's last 27 bytes before the one at pos, oldest in the top bits
  logic [191:0] cand_sr;      // v3: the candidate header's first 24 bytes, shifted into the CRC unit
  logic [31:0] cand_car;      // its carried CRC
  logic [4:0] cand_cnt;
  logic cand_final;           // the candidate ends at the frame's last byte: the verdict follows
  logic [63:0] v1_word;
  logic [2:0] v1_filled;
  logic [31:0] v1_words;      // v1 words accepted: the v1 world's sequence number
  // SequenceRules.
  logic seq_valid;
  logic [31:0] cur_session, last_seq;
  logic [31:0] retired[16];
  logic [15:0] retired_v;
  logic [3:0] retired_next;

  // ---- CRC units: the frame's running CRC, and the v3 candidate checker ----
  wire in_frame_exec = state == S_EXEC && !hunting;
  logic [31:0] crc_run, crc_cand;
  ts_crc32 u_crc_run (
      .clk, .rst,
      .clear(off == '0),
      .en(in_frame_exec),
      .data(b),
      .crc(crc_run)
  );
  ts_crc32 u_crc_cand (
      .clk, .rst,
      .clear(cand_cnt == 5'd0),
      .en(state == S_CAND && cand_cnt != 5'd24),
      .data(cand_sr[191:184]),
      .crc(crc_cand)
  );

  // ---- The byte at pos, taken apart ----
  wire [191:0] srec_next = {srec, b};
  wire [223:0] window_next = {window, b};
  wire [31:0] s_x = srec_next[191:160];
  wire [31:0] s_y = srec_next[159:128];
  wire [31:0] s_z = srec_next[127:96];
  wire [31:0] s_r = srec_next[95:64];
  wire [7:0] s_material = srec_next[63:56];
  wire [23:0] s_albedo = srec_next[55:32];
  wire [15:0] s_ior = srec_next[15:0];  // srec_next[31:16] is fuzz: checked by the CRC, not stored
  wire s_bad = s_r == 32'd0 || s_material > 8'd2 || s_ior == 16'd0;  // decode_body's bad sphere
  wire s_out = $signed({{32{s_x[31]}}, s_x}) < X_MIN || $signed({{32{s_x[31]}}, s_x}) > X_MAX ||
               $signed({{32{s_y[31]}}, s_y}) < Y_MIN || $signed({{32{s_y[31]}}, s_y}) > Y_MAX ||
               $signed({{32{s_z[31]}}, s_z}) < Z_MIN || $signed({{32{s_z[31]}}, s_z}) > Z_MAX ||
               $signed({32'd0, s_r}) > R_MAX;
  wire [31:0] count_next = {count[23:0], b};
  wire [31:0] length_next = {length[23:0], b};
  wire [31:0] hcrc_next = {hcrc_car, b};
  // inspect_header checks the count as soon as its 4 bytes are there (v2: at offset 15, its last byte; v3: at
  // 27, after the header CRC) and the length at the header's last byte (v2: its own last byte).
  wire [31:0] count_checked = (WIRE == 3) ? count : count_next;
  wire [31:0] length_checked = (WIRE == 3) ? length : length_next;
  wire [31:0] count_times_24 = (count << 4) + (count << 3);  // count is whole at the header's last byte
  wire [OW-1:0] fb_of_count = OW'(H + 4) + OW'(count_times_24);
  wire cut_candidate = WIRE == 3 && hdr_ok && off >= OW'(55) && window_next[223:192] == MAGIC;
  wire [OW-1:0] cut_at = off - OW'(28);  // in S_CAND, off is one past the byte that completed the candidate

  // ---- The sequence rules for the frame in S_VERDICT (SequenceRules::check) ----
  logic retired_hit;
  always_comb begin
    retired_hit = 1'b0;
    for (int i = 0; i < 16; i++) retired_hit = retired_hit | (retired_v[i] && retired[i] == session);
  end
  logic a_replay, a_new, a_retire;
  logic [31:0] a_missing;
  always_comb begin
    a_replay = 1'b0;
    a_new = 1'b0;
    a_retire = 1'b0;
    a_missing = 32'd0;
    if (WIRE == 2) begin
      // No session: every world is shown; only a step forward counts numbers as missing.
      a_new = !seq_valid;
      if (seq_valid && seq_no > last_seq) a_missing = seq_no - last_seq - 32'd1;
    end else if (seq_valid && session == cur_session) begin
      a_replay = seq_no <= last_seq;
      if (!a_replay) a_missing = seq_no - last_seq - 32'd1;
    end else if (retired_hit) begin
      a_replay = 1'b1;  // a world of a session that has ended
    end else begin
      a_new = 1'b1;     // a host that started or reconnected; its numbers below this one were lost
      a_retire = seq_valid;
      a_missing = (seq_no == 32'd0) ? 32'd0 : seq_no - 32'd1;
    end
  end
  wire content_bad = bad_any || frac != 8'(FRAC);

  // ---- v1: the word in v1_word_next, checked as accept_v1 does ----
  wire [63:0] v1_word_next = {v1_word[55:0], b};
  // Fields of a word (wire_v1.cpp): x s16.3 at 63..48, y s15.3 at 47..33, z s15.3 at 32..18, r at 17..12.
  localparam int V1_UP = (FRAC >= 3) ? FRAC - 3 : 0;    // v1's 3 fractional bits to FRAC: shift left,
  localparam int V1_DOWN = (FRAC < 3) ? 3 - FRAC : 0;    // or right, rounding
  localparam logic signed [63:0] V1_HALF = (FRAC < 3) ? (64'sd1 <<< (V1_DOWN - 1)) : 64'sd0;
  function automatic logic signed [63:0] v1_rescale(input logic signed [63:0] raw);
    // core::rescale_raw from 3 fractional bits to FRAC: a shift left, or round to nearest, ties away from zero.
    logic signed [63:0] mag;
    mag = raw < 0 ? -raw : raw;
    mag = (mag + V1_HALF) >>> V1_DOWN;
    v1_rescale = (FRAC >= 3) ? raw <<< V1_UP : (raw < 0 ? -mag : mag);
  endfunction
  wire signed [63:0] v1_x = v1_rescale({{48{v1_word_next[63]}}, v1_word_next[63:48]});
  wire signed [63:0] v1_y = v1_rescale({{49{v1_word_next[47]}}, v1_word_next[47:33]});
  wire signed [63:0] v1_z = v1_rescale({{49{v1_word_next[32]}}, v1_word_next[32:18]});
  wire [6:0] v1_shift = {1'b0, v1_word_next[17:12]} + 7'(FRAC);  // the radius is 2^(r + FRAC) raw
  wire v1_ok = v1_shift < 7'(R_W) && v1_x >= X_MIN && v1_x <= X_MAX && v1_y >= Y_MIN && v1_y <= Y_MAX &&
               v1_z >= Z_MIN && v1_z <= Z_MAX;
  // The accepted word's sphere, from the registered word.
  /* verilator lint_off UNUSEDSIGNAL */
  // Only the preset's low bits are stored: the range check made the rest copies of the sign.
  wire signed [63:0] v1q_x = v1_rescale({{48{v1_word[63]}}, v1_word[63:48]});
  wire signed [63:0] v1q_y = v1_rescale({{49{v1_word[47]}}, v1_word[47:33]});
  wire signed [63:0] v1q_z = v1_rescale({{49{v1_word[32]}}, v1_word[32:18]});
  /* verilator lint_on UNUSEDSIGNAL */
  wire [6:0] v1q_shift = {1'b0, v1_word[17:12]} + 7'(FRAC);
  wire [R_W-1:0] v1q_r = R_W'(1) << v1q_shift;
  // RGB444 colour to 8-bit albedo: each nibble times 17 (0xF -> 0xFF).
  wire [23:0] v1q_albedo = {v1_word[11:8], v1_word[11:8], v1_word[7:4], v1_word[7:4], v1_word[3:0], v1_word[3:0]};

  assign idle = state == S_FETCH && pos == wr_ptr && !eos_pending && !sm_begin && !sm_we && !sm_commit;

  // ---- The engine ----
  always_ff @(posedge clk) begin
    if (rst) begin
      state <= S_FETCH;
      wr_ptr <= '0;
      pos <= '0;
      start <= '0;
      eos_at <= '0;
      eos_pending <= 1'b0;
      hunting <= 1'b0;
      m <= '0;
      gcount <= '0;
      off <= '0;
      hdr_ok <= 1'b0;
      fb <= '0;
      frac <= '0;
      session <= '0;
      seq_no <= '0;
      count <= '0;
      length <= '0;
      hcrc_car <= '0;
      hcrc_calc <= '0;
      fcrc_car <= '0;
      fcrc_calc <= '0;
      srec <= '0;
      sbyte <= '0;
      sidx <= '0;
      bad_any <= 1'b0;
      window <= '0;
      cand_sr <= '0;
      cand_car <= '0;
      cand_cnt <= '0;
      cand_final <= 1'b0;
      v1_word <= '0;
      v1_filled <= '0;
      v1_words <= '0;
      seq_valid <= 1'b0;
      cur_session <= '0;
      last_seq <= '0;
      for (int i = 0; i < 16; i++) retired[i] <= '0;
      retired_v <= '0;
      retired_next <= '0;
      sm_begin <= 1'b0;
      sm_we <= 1'b0;
      sm_waddr <= '0;
      sm_wx <= '0;
      sm_wy <= '0;
      sm_wz <= '0;
      sm_wr <= '0;
      sm_wmetal <= 1'b0;
      sm_walbedo <= '0;
      sm_commit <= 1'b0;
      sm_count <= '0;
      sm_sequence <= '0;
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
      sm_begin <= 1'b0;
      sm_we <= 1'b0;
      sm_commit <= 1'b0;
      if (take) begin
        wr_ptr <= wr_ptr + 1'b1;
        bytes_received <= bytes_received + 1'b1;
      end
      if (byte_valid && full) overflow_bytes <= overflow_bytes + 1'b1;
      if (end_of_stream) begin
        eos_pending <= 1'b1;
        eos_at <= take ? wr_ptr + 1'b1 : wr_ptr;  // a byte in the same clock comes before the end
      end
      if (sm_replaced) worlds_replaced <= worlds_replaced + 1'b1;

      case (state)
        S_FETCH: begin
          if (eos_pending && pos == eos_at && !end_of_stream) begin
            // Receiver::end_of_stream, with every byte before it processed.
            eos_pending <= 1'b0;
            if (WIRE == 1) begin
              if (v1_filled != 3'd0) begin
                frames_rejected <= frames_rejected + 1'b1;
                bytes_dropped <= bytes_dropped + CNT_W'(v1_filled);
              end
              v1_filled <= '0;
            end else if (hunting) begin
              // A hunt in progress: its garbage and a partial magic are one garbage run.
              if (gcount + CNT_W'(m) != '0) begin
                garbage_runs <= garbage_runs + 1'b1;
                bytes_dropped <= bytes_dropped + gcount + CNT_W'(m);
              end
            end else if (off != '0) begin
              // A partial frame: truncated, with all its bytes.
              frames_rejected <= frames_rejected + 1'b1;
              bytes_dropped <= bytes_dropped + CNT_W'(off);
            end
            hunting <= 1'b0;
            m <= '0;
            gcount <= '0;
            off <= '0;
            hdr_ok <= 1'b0;
            start <= pos;
          end else if (pos != wr_ptr) begin
            state <= S_EXEC;
          end
        end

        S_EXEC: begin
          pos <= pos + 1'b1;
          state <= S_FETCH;
          if (WIRE == 1) begin
            // ---- v1: every 8 bytes from the start of the stream are one word ----
            v1_word <= v1_word_next;
            start <= pos + 1'b1;
            v1_filled <= v1_filled + 3'd1;  // wraps to 0 after the eighth byte
            if (v1_filled == 3'd7) begin
              if (v1_ok) begin
                sm_begin <= 1'b1;
                state <= S_V1C;
              end else begin
                frames_rejected <= frames_rejected + 1'b1;
                bytes_dropped <= bytes_dropped + CNT_W'(8);
              end
            end
          end else if (hunting) begin
            // ---- hunting for the magic (FrameStreamDecoder::hunt) ----
            if (b == magic_byte(m)) begin
              if (m == 2'd3) begin
                // The magic, at `start`: the run of garbage before it is one report, and a frame is expected
                // there. The engine goes back over the 4 magic bytes, so the frame CRC starts at the magic.
                if (gcount != '0) begin
                  garbage_runs <= garbage_runs + 1'b1;
                  bytes_dropped <= bytes_dropped + gcount;
                end
                hunting <= 1'b0;
                gcount <= '0;
                m <= '0;
                off <= '0;
                hdr_ok <= 1'b0;
                pos <= start;
              end else begin
                m <= m + 2'd1;
              end
            end else if (b == magic_byte(2'd0)) begin
              // The partial magic was garbage; this byte may begin the magic.
              gcount <= gcount + CNT_W'(m);
              m <= 2'd1;
              start <= pos;
            end else begin
              gcount <= gcount + CNT_W'(m) + 1'b1;
              m <= '0;
              start <= pos + 1'b1;
            end
          end else begin
            // ---- expecting a frame: the byte at offset `off` ----
            off <= off + 1'b1;
            window <= window_next[215:0];
            if (!hdr_ok) begin
              bad_any <= 1'b0;
              sbyte <= '0;
              if (off < OW'(4)) begin
                if (b != magic_byte(off[1:0])) begin
                  // Bad magic: hunt from the frame's first byte, nothing dropped yet.
                  hunting <= 1'b1;
                  gcount <= '0;
                  m <= '0;
                  pos <= start;
                end
              end else begin
                if (off == OW'(5)) frac <= b;
                if (WIRE == 3 && off >= OW'(SESSION_AT) && off < OW'(SESSION_AT + 4)) session <= {session[23:0], b};
                if (off >= OW'(SEQUENCE_AT) && off < OW'(SEQUENCE_AT + 4)) seq_no <= {seq_no[23:0], b};
                if (off >= OW'(COUNT_AT) && off < OW'(COUNT_AT + 4)) count <= count_next;
                if (off >= OW'(LENGTH_AT) && off < OW'(LENGTH_AT + 4)) length <= length_next;
                if (WIRE == 3 && off >= OW'(HCRC_AT)) hcrc_car <= hcrc_next[23:0];
                if (WIRE == 3 && off == OW'(HCRC_AT)) hcrc_calc <= crc_run;  // CRC of bytes 0..23
                if ((off == OW'(4) && b != VERSION) ||                          // bad version
                    (off == OW'(5) && b > 8'd30) ||                             // bad header: frac_bits
                    ((off == OW'(6) || off == OW'(7)) && b != 8'd0) ||          // bad header: reserved
                    (WIRE == 3 && off == OW'(H - 1) && hcrc_next != hcrc_calc) ||  // bad header CRC
                    (off == OW'((WIRE == 3) ? H - 1 : COUNT_AT + 3) && count_checked > MAX32) ||  // too many
                    (off == OW'(H - 1) && length_checked != count_times_24)) begin  // bad length
                  // A header error: 1 byte dropped, a hunt from the next.
                  frames_rejected <= frames_rejected + 1'b1;
                  bytes_dropped <= bytes_dropped + 1'b1;
                  hunting <= 1'b1;
                  gcount <= '0;
                  m <= '0;
                  pos <= start + 1'b1;
                  start <= start + 1'b1;
                end else if (off == OW'(H - 1)) begin
                  hdr_ok <= 1'b1;
                  fb <= fb_of_count;
                end
              end
            end else begin
              if (off < fb - OW'(4)) begin
                // Payload: one byte of a sphere record; its last byte checks the sphere.
                srec <= srec_next[183:0];
                sbyte <= (sbyte == 5'd23) ? 5'd0 : sbyte + 5'd1;
                if (sbyte == 5'd23 && (s_bad || s_out)) bad_any <= 1'b1;
              end else begin
                // Trailer: the CRC of header and payload.
                if (off == fb - OW'(4)) fcrc_calc <= crc_run;
                fcrc_car <= {fcrc_car[23:0], b};
              end
              if (cut_candidate) begin
                // v3: a magic 27 bytes back; check whether the header it begins is intact.
                state <= S_CAND;
                cand_sr <= window_next[223:32];
                cand_car <= window_next[31:0];
                cand_cnt <= '0;
                cand_final <= off == fb - OW'(1);
              end else if (off == fb - OW'(1)) begin
                state <= S_VERDICT;
              end
            end
          end
        end

        S_CAND: begin
          if (cand_cnt != 5'd24) begin
            cand_cnt <= cand_cnt + 5'd1;
            cand_sr <= {cand_sr[183:0], 8'd0};
          end else if (crc_cand == cand_car) begin
            // An intact header inside the frame: the frame was cut there. Truncated, with the bytes before it;
            // the frame that header begins is expected at once.
            frames_rejected <= frames_rejected + 1'b1;
            bytes_dropped <= bytes_dropped + CNT_W'(cut_at);
            pos <= start + PW'(cut_at);
            start <= start + PW'(cut_at);
            off <= '0;
            hdr_ok <= 1'b0;
            state <= S_FETCH;
          end else begin
            state <= cand_final ? S_VERDICT : S_FETCH;
          end
        end

        S_VERDICT: begin
          state <= S_FETCH;
          if (fcrc_car != fcrc_calc) begin
            // Bad CRC: 1 byte dropped, a hunt from the frame's second byte.
            frames_rejected <= frames_rejected + 1'b1;
            bytes_dropped <= bytes_dropped + 1'b1;
            hunting <= 1'b1;
            gcount <= '0;
            m <= '0;
            pos <= start + 1'b1;
            start <= start + 1'b1;
          end else begin
            // The frame arrived intact: the sequence rules see it first (Receiver::admit).
            if (a_replay) begin
              worlds_replayed <= worlds_replayed + 1'b1;
              bytes_dropped <= bytes_dropped + CNT_W'(fb);
            end else begin
              seq_valid <= 1'b1;
              if (WIRE == 3) cur_session <= session;
              last_seq <= seq_no;
              if (a_retire) begin
                retired[retired_next] <= cur_session;
                retired_v[retired_next] <= 1'b1;
                retired_next <= retired_next + 4'd1;
              end
              worlds_missing <= worlds_missing + CNT_W'(a_missing);
              if (a_new) sessions <= sessions + 1'b1;
              if (content_bad) begin
                // A bad sphere, other fractional bits, or a sphere outside the preset: all of it dropped.
                frames_rejected <= frames_rejected + 1'b1;
                bytes_dropped <= bytes_dropped + CNT_W'(fb);
              end else begin
                sm_begin <= 1'b1;
                state <= S_CBEGIN;
              end
            end
            if (a_replay || content_bad) begin
              start <= pos;  // the next frame is expected right after this one
              off <= '0;
              hdr_ok <= 1'b0;
            end
          end
        end

        S_CBEGIN: begin
          pos <= start + PW'(H);
          sbyte <= '0;
          sidx <= '0;
          state <= (count == 32'd0) ? S_CEND : S_CFETCH;
        end

        S_CFETCH: state <= S_CEXEC;

        S_CEXEC: begin
          pos <= pos + 1'b1;
          srec <= srec_next[183:0];
          state <= S_CFETCH;
          if (sbyte == 5'd23) begin
            sbyte <= '0;
            sm_we <= 1'b1;
            sm_waddr <= sidx[AW-1:0];
            sm_wx <= s_x[X_W-1:0];
            sm_wy <= s_y[Y_W-1:0];
            sm_wz <= s_z[Z_W-1:0];
            sm_wr <= s_r[R_W-1:0];
            sm_wmetal <= s_material == 8'd1;
            sm_walbedo <= s_albedo;
            sidx <= sidx + 1'b1;
            if (32'(sidx) + 32'd1 == count) state <= S_CEND;
          end else begin
            sbyte <= sbyte + 5'd1;
          end
        end

        S_CEND: begin
          sm_commit <= 1'b1;
          sm_count <= count[AW:0];
          sm_sequence <= seq_no;
          worlds_accepted <= worlds_accepted + 1'b1;
          pos <= start + PW'(fb);
          start <= start + PW'(fb);
          off <= '0;
          hdr_ok <= 1'b0;
          state <= S_FETCH;
        end

        S_V1C: begin
          // accept_v1: one lambertian sphere, the colour's nibbles as albedo, numbered by the words accepted.
          sm_we <= 1'b1;
          sm_waddr <= '0;
          sm_wx <= v1q_x[X_W-1:0];
          sm_wy <= v1q_y[Y_W-1:0];
          sm_wz <= v1q_z[Z_W-1:0];
          sm_wr <= v1q_r;
          sm_wmetal <= 1'b0;
          sm_walbedo <= v1q_albedo;
          sm_commit <= 1'b1;
          sm_count <= (AW + 1)'(1);
          sm_sequence <= v1_words + 32'd1;
          v1_words <= v1_words + 32'd1;
          worlds_accepted <= worlds_accepted + 1'b1;
          state <= S_FETCH;
        end

        default: state <= S_FETCH;
      endcase
    end
  end
endmodule
