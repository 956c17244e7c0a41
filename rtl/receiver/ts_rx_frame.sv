// ts_rx_frame: the framed wires' stream decoder (v2 and v3): hunts for the magic, checks each header byte as it
// comes, runs the frame CRC, assembles the sphere records and checks each for a bad sphere, applies v3's cut rule,
// and reports every byte it drops. A frame that arrived intact is handed to the receiver (`intact`), which answers
// `admit_drop` (a replay, or content the device refuses) or `admit_copy` (go over its payload again and give each
// sphere record to scene memory). Part of ts_receiver (the composition, docs/rtl.md).
//
// C++ twin: link::FrameStreamDecoder and decode_body (src/tripsitter/link/frame.h/.cpp); the formats in
// docs/link_format.md and ts_link_pkg.sv.
//
// Byte buffer. Every byte is written into a circular buffer of 2^BufAW bytes (block RAM). The model goes back over
// the bytes of a frame that failed (it drops the first byte and hunts for the magic from the second, so a frame
// hidden in a damaged one is still found), so the buffer keeps every byte from the start of the frame being decoded:
// the largest frame the preset can announce plus a quarter more and 512 bytes for the input that arrives while the
// engine goes back over a frame or copies one out. A byte that arrives while it is full is dropped (`full`; the
// receiver counts it in overflow_bytes; the model has no such limit): with SCLK at most clk/8 and the engine taking 2
// clocks per byte this happens only to streams built to make the decoder go back over the largest frame again and
// again.
//
// Engine. One state machine reads the buffer one byte every 2 clocks (address, then data) at `pos_q` and does what
// FrameStreamDecoder does with that byte: while hunting, match the magic (a partial magic waits for more bytes: the
// magics have no repeated letter, so a mismatch restarts the match at most at the byte itself); while expecting a
// frame, check each header byte as it comes (magic, version, frac_bits, reserved, and on v3 the header CRC, then
// count and length, at the offsets the model checks them), then feed payload and trailer through the frame CRC,
// assemble each 24-byte sphere record and check it (radius 0, material above 2, ior 0). On any failure it rewinds
// `pos_q` as the model's read position moves: to the frame's first byte (bad magic: a hunt from there) or its second
// (a header error, a bad CRC: 1 byte dropped, a hunt from the next). On v3 it also applies the cut rule: a 28-byte
// window of the last bytes; whenever a magic starts 27 bytes back, at frame offset 28 or more, a second CRC unit
// checks that candidate header in 24 clocks; if it is intact the frame is dropped as truncated up to it and decoding
// restarts there. What the checks need is registered in the clock before the byte they judge (the offset decoded,
// `at_*_q`; a field's first three bytes compared, `*_hi_*_q`), so only that byte's own comparison is left in the
// clock that decides.
//
// Reports (`rep_*`, one clock each, registered): a run of garbage (the hunt's skipped bytes, when a magic is found
// or the stream ends) or a dropped frame with its bytes: a header error or bad CRC (1 byte), a cut (the bytes before
// the cut), a truncated frame at the end of the stream (all its bytes). The receiver counts them.
//
// Records (`rec_*`, one clock each, registered): every sphere record of a frame whose header passed, first while the
// frame is checked (`rec_copy` low: the receiver checks the preset's ranges), then, once admitted, again while the
// payload is copied out (`rec_copy` high: the receiver writes it to scene memory). `copy_done` follows the last.
// With `Hierarchy`, a v3 frame's header may say content 1: its length then covers 1 to MaxSpheres node records after
// the spheres, which the check pass gives too, marked `rec_node` (the receiver's ts_rx_hierarchy checks them); the
// copy gives the spheres alone.
//
// End of stream: `end_of_stream` is handled when the engine has processed every byte received before it: a partial
// frame is dropped as truncated, a hunt in progress as a garbage run. A second end_of_stream before the first is
// handled moves it to the later position (the engine keeps one).
module ts_rx_frame #(
    parameter int Wire = 3,                  // 2 or 3
    parameter int MaxSpheres = 4096,         // the most a frame may announce; a power of two
    parameter int CntW = 64,                 // width of a report's byte count
    parameter int Hierarchy = 0,             // 1: v3 frames may carry a hierarchy (content 1), 1..MaxSpheres nodes
    // Byte buffer: the largest frame (spheres and as many nodes), a quarter more and 512 bytes (wide: 128 KiB,
    // board-2023: 4 KiB).
    parameter int BufAW = $clog2(((Wire == 3) ? ts_link_pkg::V3HeaderBytes : ts_link_pkg::V2HeaderBytes) * 5 / 4 +
                                 ts_link_pkg::FrameTrailerBytes * 5 / 4 +
                                 30 * MaxSpheres * (Hierarchy != 0 ? 2 : 1) + 512),
    localparam int AW = $clog2(MaxSpheres)
) (
    input  logic            clk,
    input  logic            rst,
    input  logic            byte_valid,
    input  logic [7:0]      byte_data,
    input  logic            end_of_stream,
    output logic            full,          // the buffer is full: byte_valid's byte is dropped
    // Reports of dropped bytes.
    output logic            rep_valid,
    output logic            rep_garbage,   // a run of garbage; else a dropped frame
    output logic [CntW-1:0] rep_bytes,
    // The frame's header, stable from its last header byte until the frame is done with.
    output logic [31:0]     hdr_session,   // v3; 0 on v2
    output logic [31:0]     hdr_sequence,
    output logic [AW:0]     hdr_count,     // at most MaxSpheres once the header passed
    output logic [7:0]      hdr_frac,
    output logic [31:0]     frame_bytes,   // header, payload and trailer
    output logic            in_body,       // the header has passed: records of this frame follow
    output logic            bad_sphere,    // a record of the frame had radius 0, material above 2 or ior 0
    // An intact frame (CRC good), waiting for the receiver's answer.
    output logic            intact,
    input  logic            admit_drop,
    input  logic            admit_copy,
    // Sphere records.
    output logic            rec_valid,
    output logic            rec_copy,
    output logic [31:0]     rec_x,
    output logic [31:0]     rec_y,
    output logic [31:0]     rec_z,
    output logic [31:0]     rec_r,
    output logic [7:0]      rec_material,
    output logic [23:0]     rec_albedo,
    output logic            rec_node,      // Hierarchy: the record is a node's (check pass only; the copy gives
                                           // the spheres alone); its last 8 bytes, first_child to first_sphere:
    output logic [63:0]     rec_links,
    output logic            copy_done,
    output logic            idle           // every byte received processed
);
  // ---- Wire layout (ts_link_pkg, frame.cpp's Layout) ----
  localparam int H = (Wire == 3) ? ts_link_pkg::V3HeaderBytes : ts_link_pkg::V2HeaderBytes;
  localparam int SessionAt = ts_link_pkg::V3SessionAt;  // v3 only
  localparam int SequenceAt = (Wire == 3) ? ts_link_pkg::V3SequenceAt : ts_link_pkg::V2SequenceAt;
  localparam int CountAt = (Wire == 3) ? ts_link_pkg::V3CountAt : ts_link_pkg::V2CountAt;
  localparam int LengthAt = (Wire == 3) ? ts_link_pkg::V3LengthAt : ts_link_pkg::V2LengthAt;
  localparam int HcrcAt = ts_link_pkg::V3HeaderCrcAt;  // v3 only
  localparam int Rec = ts_link_pkg::SphereBytes;
  localparam int MaxFrame = H + Rec * MaxSpheres * (Hierarchy != 0 ? 2 : 1) + ts_link_pkg::FrameTrailerBytes;
  localparam bit Content = Wire == 3 && Hierarchy != 0;  // the header's content byte may say 1
  localparam int OW = $clog2(MaxFrame + 1) + 1;       // frame offsets
  localparam int PW = BufAW + 1;                      // buffer positions: one bit more, so full != empty
  localparam logic [7:0] Version = 8'((Wire == 3) ? ts_link_pkg::V3Version : ts_link_pkg::V2Version);
  localparam logic [31:0] Magic = 32'((Wire == 3) ? ts_link_pkg::V3Magic : ts_link_pkg::V2Magic);
  localparam logic [31:0] Max32 = 32'(MaxSpheres);
  localparam logic [PW-1:0] Depth = {1'b1, {BufAW{1'b0}}};
  // Where each check of inspect_header falls: the count as soon as its 4 bytes are there (v2: its last byte; v3:
  // the header's last, after the header CRC), the length at the header's last byte.
  localparam int CountCheckAt = (Wire == 3) ? H - 1 : CountAt + 3;
  // v3's cut rule: a magic 27 bytes back at frame offset 28 or more.
  localparam int CutWindow = ts_link_pkg::V3HeaderBytes;

  function automatic logic [7:0] magic_byte(input logic [1:0] i);
    case (i)
      2'd0: magic_byte = Magic[31:24];
      2'd1: magic_byte = Magic[23:16];
      2'd2: magic_byte = Magic[15:8];
      default: magic_byte = Magic[7:0];
    endcase
  endfunction

  // ---- Byte buffer ----
  logic [7:0] buffer[1 << BufAW];
  logic [7:0] b;  // the byte at the address presented in the previous clock
  logic [PW-1:0] wr_ptr_q, pos_q, start_q, eos_at_q;
  wire [PW-1:0] held = wr_ptr_q - start_q;  // bytes the engine may still need
  assign full = held == Depth;
  wire take = byte_valid && !full;

  always_ff @(posedge clk) begin
    if (take) buffer[wr_ptr_q[BufAW-1:0]] <= byte_data;
    b <= buffer[pos_q[BufAW-1:0]];
  end

  // ---- Engine state ----
  typedef enum logic [3:0] {
    S_FETCH,    // present pos to the buffer (or wait for a byte, or handle end of stream)
    S_EXEC,     // the byte at pos
    S_CAND,     // v3: checking the CRC of a header candidate inside the frame
    S_VERDICT,  // a whole frame: its CRC
    S_ADMIT,    // an intact frame: waiting for the receiver
    S_CBEGIN,   // copy: from the payload's first byte
    S_CFETCH,   // copy: present a payload byte
    S_CEXEC,    // copy: a payload byte; every 24th completes a record
    S_CEND      // copy: the world is whole
  } state_e;
  state_e state_q;

  logic eos_pending_q;
  logic hunting_q;
  logic [1:0] m_q;                // hunting: bytes of the magic matched so far
  logic [CntW-1:0] skipped_q;     // hunting: bytes consumed by this hunt, the partial magic's included
  logic [OW-1:0] off_q;           // expecting a frame: offset of the byte at pos in the frame
  logic hdr_ok_q;                 // the frame's header has passed
  logic [OW-1:0] fb_q;            // the frame's size once its header passed
  logic [31:0] count_q;           // the count field as it is read
  logic [31:0] count_x24_q;       // count * 24, a clock behind count_q
  logic [23:0] hcrc_car_q;        // v3: the carried header CRC's first 3 bytes (the 4th is the byte at pos)
  logic [31:0] hcrc_calc_q, fcrc_car_q, fcrc_calc_q;
  logic [183:0] srec_q;           // the sphere record's bytes so far (23 at most), first byte in the top bits
  logic [4:0] sbyte_q;            // its bytes so far
  logic [AW:0] left_q;            // copy: records still to give
  logic [215:0] window_q;         // v3: the frame's last 27 bytes before the one at pos, oldest in the top bits
  logic [191:0] cand_sr_q;        // v3: the candidate header's first 24 bytes, shifted into the CRC unit
  logic [31:0] cand_car_q;        // its carried CRC
  logic [4:0] cand_cnt_q;
  logic cand_final_q;             // the candidate ends at the frame's last byte: the verdict follows
  logic [31:0] length_q;          // the length field as it is read
  logic [31:0] session_q;         // v3: the session field as it is read
  logic content_q;                // Content: the frame carries a hierarchy
  logic [AW+1:0] recs_q;          // Content: the frame's records so far (its spheres first, then its nodes)
  // The offset's decodes and the header's comparisons, a clock ahead: off_q changes only in clocks that go to
  // S_FETCH, and S_EXEC always follows S_FETCH, so flags registered from it every clock are current in S_EXEC. The
  // comparisons of a field whose last byte is the one at pos compare its other bytes here and that byte in S_EXEC.
  logic at_zero_q, at_magic_q, at_version_q, at_frac_q, at_reserved_q, at_content_q, at_count_check_q,
        at_header_end_q;
  logic in_payload_q, at_trailer_q, at_last_q, cut_window_q;
  logic count_big_q;              // v3: count > MaxSpheres
  logic count_hi_gt_q, count_hi_eq_q;  // v2: the count's first 3 bytes against MaxSpheres's
  logic len_bad_q;                // v3: length != count * 24
  logic len_hi_bad_q;             // v2: the length's first 3 bytes against count * 24's
  logic hcrc_hi_bad_q;            // v3: the carried header CRC's first 3 bytes against the computed one's
  logic cut_magic_q;              // v3: the window's oldest 4 bytes, 27 back from the byte at pos, are the magic

  // ---- CRC units: the frame's running CRC, and the v3 candidate checker ----
  wire in_frame_exec = state_q == S_EXEC && !hunting_q;
  logic [31:0] crc_run, crc_cand;
  ts_crc32 u_crc_run (
      .clk, .rst,
      .clear(at_zero_q && in_frame_exec),  // at_zero_q lags off_q by a clock outside S_EXEC
      .en(in_frame_exec),
      .data(b),
      .crc(crc_run)
  );
  ts_crc32 u_crc_cand (
      .clk, .rst,
      .clear(cand_cnt_q == 5'd0),
      .en(state_q == S_CAND && cand_cnt_q != 5'd24),
      .data(cand_sr_q[191:184]),
      .crc(crc_cand)
  );

  // ---- The byte at pos, taken apart ----
  wire [191:0] srec_next = {srec_q, b};
  wire [223:0] window_next = {window_q, b};
  // A record's field at byte offset `at` (ts_link_pkg's Sphere*At), in the record that the byte at pos completes.
  localparam int RecTop = 8 * Rec - 1;
  localparam int XAt = RecTop - 8 * ts_link_pkg::SphereXAt;
  localparam int YAt = RecTop - 8 * ts_link_pkg::SphereYAt;
  localparam int ZAt = RecTop - 8 * ts_link_pkg::SphereZAt;
  localparam int RAt = RecTop - 8 * ts_link_pkg::SphereRadiusAt;
  localparam int MaterialAt = RecTop - 8 * ts_link_pkg::SphereMaterialAt;
  localparam int AlbedoAt = RecTop - 8 * ts_link_pkg::SphereAlbedoAt;
  localparam int IorAt = RecTop - 8 * ts_link_pkg::SphereIorAt;
  wire s_bad = srec_next[RAt-:32] == 32'd0 ||                                        // decode_body's bad sphere:
               srec_next[MaterialAt-:8] > 8'(ts_link_pkg::MaterialDielectric) ||     // radius 0, an unknown
               srec_next[IorAt-:16] == 16'd0;                                        // material, ior 0
  wire [31:0] count_next = {count_q[23:0], b};
  wire [31:0] length_next = {length_q[23:0], b};
  // inspect_header's count check: v3 the whole count, v2 {count_q[23:0], b} > MaxSpheres.
  wire count_bad = (Wire == 3) ? count_big_q : count_hi_gt_q || (count_hi_eq_q && b > Max32[7:0]);
  wire length_bad = (Wire == 3) ? len_bad_q : len_hi_bad_q || b != count_x24_q[7:0];
  wire hcrc_bad = hcrc_hi_bad_q || b != hcrc_calc_q[7:0];
  // The frame's size: header, payload (its length: count x 24 without a hierarchy, checked) and trailer.
  wire [OW-1:0] fb_of_header = Content ? OW'(H + 4) + OW'(length_q) : OW'(H + 4) + OW'(count_x24_q);
  // Content 1: the payload is the spheres and 1 to MaxSpheres node records after them: length - count x 24 a
  // multiple of 24 from 24 to 24 MaxSpheres, decided over three clocks (registered below; the length's last byte
  // comes 4 bytes, 8 clocks, before the header's last, which the check waits for): the difference and its borrow;
  // its range, its low 3 bits, and the sum of the base-4 digits of the rest (4 = 1 mod 3, so the sum is the rest
  // mod 3); then that sum mod 3, from a table.
  localparam int NodeBytesW = $clog2(Rec * MaxSpheres) + 1;
  localparam int Digits = (NodeBytesW - 3 + 1) / 2;
  logic [31:0] node_bytes_q;
  logic node_borrow_q, node_range_bad_q, nodes_bad_q;
  logic [4:0] node_digits_q;  // at most 3 x 8 digits
  localparam logic [31:0] MultiplesOf3 = 32'b01001001001001001001001001001001;  // bit i: i mod 3 == 0
  function automatic logic [4:0] digit_sum(input logic [2*Digits-1:0] v);
    digit_sum = '0;
    for (int i = 0; i < Digits; i++) digit_sum += 5'(v[2*i+:2]);
  endfunction
  wire is_node = Content && recs_q >= (AW + 2)'(count_q[AW:0]);
  wire cut_candidate = Wire == 3 && hdr_ok_q && cut_window_q && cut_magic_q;
  wire [OW-1:0] cut_at = off_q - OW'(CutWindow);  // in S_CAND, off is one past the byte that completed the candidate

  wire header_bad =
      (at_version_q && b != Version) ||                                  // bad version
      (at_frac_q && b > 8'(ts_link_pkg::MaxFracBits)) ||                 // bad header: frac_bits
      (at_reserved_q && b != 8'd0 &&                                     // bad header: reserved (v3 with a
       !(Content && at_content_q && b == 8'(ts_link_pkg::ContentHierarchy))) ||  // hierarchy: content 0 or 1)
      (Wire == 3 && at_header_end_q && hcrc_bad) ||                      // bad header CRC
      (at_count_check_q && count_bad) ||                                 // too many spheres
      (at_header_end_q && length_bad);                                   // bad length

  // A header error (the byte at pos fails a check of inspect_header), or a whole frame whose CRC fails.
  wire header_error = state_q == S_EXEC && !hunting_q && !hdr_ok_q && !at_magic_q && header_bad;
  wire crc_error = state_q == S_VERDICT && fcrc_car_q != fcrc_calc_q;

  assign idle = state_q == S_FETCH && pos_q == wr_ptr_q && !eos_pending_q;
  assign in_body = hdr_ok_q;
  assign frame_bytes = 32'(fb_q);
  assign hdr_count = count_q[AW:0];
  assign hdr_session = (Wire == 3) ? session_q : 32'd0;

  always_ff @(posedge clk) begin
    if (rst) begin
      state_q <= S_FETCH;
      wr_ptr_q <= '0;
      pos_q <= '0;
      start_q <= '0;
      eos_pending_q <= 1'b0;
      hunting_q <= 1'b0;
      m_q <= '0;
      skipped_q <= '0;
      off_q <= '0;
      hdr_ok_q <= 1'b0;
      bad_sphere <= 1'b0;
      sbyte_q <= '0;
      cand_cnt_q <= '0;
      rep_valid <= 1'b0;
      intact <= 1'b0;
      rec_valid <= 1'b0;
      copy_done <= 1'b0;
    end else begin
      rep_valid <= 1'b0;
      intact <= 1'b0;
      rec_valid <= 1'b0;
      copy_done <= 1'b0;
      if (take) wr_ptr_q <= wr_ptr_q + 1'b1;
      if (end_of_stream) eos_pending_q <= 1'b1;

      case (state_q)
        S_FETCH: begin
          if (eos_pending_q && pos_q == eos_at_q && !end_of_stream) begin
            // FrameStreamDecoder::end_of_stream, with every byte before it processed: a hunt in progress (its
            // garbage and a partial magic) is one garbage run, a partial frame is truncated with all its bytes.
            eos_pending_q <= 1'b0;
            rep_valid <= hunting_q ? skipped_q != '0 : off_q != '0;
            rep_garbage <= hunting_q;
            rep_bytes <= hunting_q ? skipped_q : CntW'(off_q);
            hunting_q <= 1'b0;
            m_q <= '0;
            skipped_q <= '0;
            off_q <= '0;
            hdr_ok_q <= 1'b0;
            start_q <= pos_q;
          end else if (pos_q != wr_ptr_q) begin
            state_q <= S_EXEC;
          end
        end

        S_EXEC: begin
          pos_q <= pos_q + 1'b1;
          state_q <= S_FETCH;
          if (hunting_q) begin
            // ---- hunting for the magic (FrameStreamDecoder::hunt) ----
            skipped_q <= skipped_q + 1'b1;
            if (b == magic_byte(m_q)) begin
              if (m_q == 2'd3) begin
                // The magic, at `start`: the run of garbage before it is one report, and a frame is expected
                // there. The engine goes back over the 4 magic bytes, so the frame CRC starts at the magic.
                rep_valid <= skipped_q != CntW'(3);
                rep_garbage <= 1'b1;
                rep_bytes <= skipped_q - CntW'(3);
                hunting_q <= 1'b0;
                m_q <= '0;
                off_q <= '0;
                hdr_ok_q <= 1'b0;
                pos_q <= start_q;
              end else begin
                m_q <= m_q + 2'd1;
              end
            end else if (b == magic_byte(2'd0)) begin
              // The partial magic was garbage; this byte may begin the magic.
              m_q <= 2'd1;
              start_q <= pos_q;
            end else begin
              m_q <= '0;
              start_q <= pos_q + 1'b1;
            end
          end else begin
            // ---- expecting a frame: the byte at offset `off` ----
            off_q <= off_q + 1'b1;
            window_q <= window_next[215:0];
            if (!hdr_ok_q) begin
              bad_sphere <= 1'b0;
              sbyte_q <= '0;
              recs_q <= '0;
              if (at_magic_q) begin
                if (b != magic_byte(off_q[1:0])) begin
                  // Bad magic: hunt from the frame's first byte, nothing dropped yet.
                  hunting_q <= 1'b1;
                  skipped_q <= '0;
                  m_q <= '0;
                  pos_q <= start_q;
                end
              end else if (at_header_end_q && !header_bad) begin  // (a header error: below)
                hdr_ok_q <= 1'b1;
                fb_q <= fb_of_header;
              end
            end else begin
              if (in_payload_q) begin
                // Payload: one byte of a sphere record; its last byte checks the sphere and gives the record.
                srec_q <= srec_next[183:0];
                sbyte_q <= (sbyte_q == 5'(Rec - 1)) ? 5'd0 : sbyte_q + 5'd1;
                if (sbyte_q == 5'(Rec - 1)) begin
                  rec_valid <= 1'b1;
                  rec_copy <= 1'b0;
                  rec_node <= is_node;
                  recs_q <= recs_q + 1'b1;
                  if (s_bad && !is_node) bad_sphere <= 1'b1;
                end
              end else begin
                // Trailer: the CRC of header and payload.
                if (at_trailer_q) fcrc_calc_q <= crc_run;
                fcrc_car_q <= {fcrc_car_q[23:0], b};
              end
              if (cut_candidate) begin
                // v3: a magic 27 bytes back; check whether the header it begins is intact.
                state_q <= S_CAND;
                cand_sr_q <= window_next[223:32];
                cand_car_q <= window_next[31:0];
                cand_cnt_q <= '0;
                cand_final_q <= at_last_q;
              end else if (at_last_q) begin
                state_q <= S_VERDICT;
              end
            end
          end
        end

        S_CAND: begin
          if (cand_cnt_q != 5'd24) begin
            cand_cnt_q <= cand_cnt_q + 5'd1;
            cand_sr_q <= {cand_sr_q[183:0], 8'd0};
          end else if (crc_cand == cand_car_q) begin
            // An intact header inside the frame: the frame was cut there. Truncated, with the bytes before it;
            // the frame that header begins is expected at once.
            rep_valid <= 1'b1;
            rep_garbage <= 1'b0;
            rep_bytes <= CntW'(cut_at);
            pos_q <= start_q + PW'(cut_at);
            start_q <= start_q + PW'(cut_at);
            off_q <= '0;
            hdr_ok_q <= 1'b0;
            state_q <= S_FETCH;
          end else begin
            state_q <= cand_final_q ? S_VERDICT : S_FETCH;
          end
        end

        S_VERDICT: begin
          if (crc_error) begin
            state_q <= S_FETCH;  // (below)
          end else begin
            // The frame arrived intact: the receiver's sequence rules and content checks decide.
            intact <= 1'b1;
            state_q <= S_ADMIT;
          end
        end

        S_ADMIT: begin
          if (admit_copy) begin
            state_q <= S_CBEGIN;
          end else if (admit_drop) begin
            start_q <= pos_q;  // the next frame is expected right after this one
            off_q <= '0;
            hdr_ok_q <= 1'b0;
            state_q <= S_FETCH;
          end
        end

        S_CBEGIN: begin
          pos_q <= start_q + PW'(H);
          sbyte_q <= '0;
          left_q <= hdr_count;
          state_q <= (hdr_count == '0) ? S_CEND : S_CFETCH;
        end

        S_CFETCH: state_q <= S_CEXEC;

        S_CEXEC: begin
          pos_q <= pos_q + 1'b1;
          srec_q <= srec_next[183:0];
          state_q <= S_CFETCH;
          if (sbyte_q == 5'(Rec - 1)) begin
            sbyte_q <= '0;
            rec_valid <= 1'b1;
            rec_copy <= 1'b1;
            rec_node <= 1'b0;
            left_q <= left_q - 1'b1;
            if (left_q == (AW + 1)'(1)) state_q <= S_CEND;
          end else begin
            sbyte_q <= sbyte_q + 5'd1;
          end
        end

        S_CEND: begin
          copy_done <= 1'b1;
          pos_q <= start_q + PW'(fb_q);
          start_q <= start_q + PW'(fb_q);
          off_q <= '0;
          hdr_ok_q <= 1'b0;
          state_q <= S_FETCH;
        end

        default: state_q <= S_FETCH;
      endcase
      if (header_error || crc_error) begin
        // A damaged frame: its first byte dropped, a hunt from the next (the model drops one byte and hunts).
        rep_valid <= 1'b1;
        rep_garbage <= 1'b0;
        rep_bytes <= CntW'(1);
        hunting_q <= 1'b1;
        skipped_q <= '0;
        m_q <= '0;
        pos_q <= start_q + 1'b1;
        start_q <= start_q + 1'b1;
      end
    end
  end

  // ---- Datapath registers: no reset (their valid bits above say when they mean anything) ----
  always_ff @(posedge clk) begin
    if (end_of_stream) eos_at_q <= take ? wr_ptr_q + 1'b1 : wr_ptr_q;  // a byte in the same clock comes first
    count_x24_q <= (count_q << 4) + (count_q << 3);
    if (sbyte_q == 5'(Rec - 1)) begin
      // The record that completes with the byte at pos (used only when rec_valid rises with it).
      rec_x <= srec_next[XAt-:32];
      rec_y <= srec_next[YAt-:32];
      rec_z <= srec_next[ZAt-:32];
      rec_r <= srec_next[RAt-:32];
      rec_material <= srec_next[MaterialAt-:8];
      rec_albedo <= srec_next[AlbedoAt-:24];  // fuzz and ior: checked by the CRC (ior also above), not stored
      rec_links <= srec_next[RecTop-8*ts_link_pkg::NodeFirstChildAt-:64];
    end
    if (in_frame_exec && !hdr_ok_q) begin
      // The header's fields as they go by (inspect_header reads them at these offsets).
      if (off_q == OW'(ts_link_pkg::FracBitsAt)) hdr_frac <= b;
      if (off_q == OW'(ts_link_pkg::ContentAt)) content_q <= Content && b == 8'(ts_link_pkg::ContentHierarchy);
      if (off_q >= OW'(SessionAt) && off_q < OW'(SessionAt + 4)) session_q <= {session_q[23:0], b};
      if (off_q >= OW'(SequenceAt) && off_q < OW'(SequenceAt + 4)) hdr_sequence <= {hdr_sequence[23:0], b};
      if (off_q >= OW'(CountAt) && off_q < OW'(CountAt + 4)) count_q <= count_next;
      if (off_q >= OW'(LengthAt) && off_q < OW'(LengthAt + 4)) length_q <= length_next;
      if (Wire == 3 && off_q >= OW'(HcrcAt)) hcrc_car_q <= {hcrc_car_q[15:0], b};
      if (Wire == 3 && off_q == OW'(HcrcAt)) hcrc_calc_q <= crc_run;  // CRC of bytes 0..23
    end
    // The offset's decodes and the header's comparisons (see their declarations).
    at_zero_q <= off_q == '0;
    at_magic_q <= off_q < OW'(4);
    at_version_q <= off_q == OW'(ts_link_pkg::VersionAt);
    at_frac_q <= off_q == OW'(ts_link_pkg::FracBitsAt);
    at_reserved_q <= off_q >= OW'(ts_link_pkg::ReservedAt) && off_q < OW'(ts_link_pkg::ReservedEnd);
    at_content_q <= off_q == OW'(ts_link_pkg::ContentAt);
    at_count_check_q <= off_q == OW'(CountCheckAt);
    at_header_end_q <= off_q == OW'(H - 1);
    in_payload_q <= off_q < fb_q - OW'(4);
    at_trailer_q <= off_q == fb_q - OW'(4);
    at_last_q <= off_q == fb_q - OW'(1);
    cut_window_q <= off_q >= OW'(2 * CutWindow - 1);
    count_big_q <= count_q > Max32;
    count_hi_gt_q <= count_q[23:0] > Max32[31:8];
    count_hi_eq_q <= count_q[23:0] == Max32[31:8];
    len_bad_q <= (Content && content_q) ? nodes_bad_q : length_q != count_x24_q;
    node_bytes_q <= length_q - count_x24_q;
    node_borrow_q <= length_q < count_x24_q;
    node_range_bad_q <= node_borrow_q || node_bytes_q < 32'(Rec) || node_bytes_q > 32'(Rec * MaxSpheres) ||
                        node_bytes_q[2:0] != 3'd0;
    node_digits_q <= digit_sum((2 * Digits)'(node_bytes_q[NodeBytesW-1:3]));
    nodes_bad_q <= node_range_bad_q || !MultiplesOf3[node_digits_q];
    len_hi_bad_q <= length_q[23:0] != count_x24_q[31:8];
    hcrc_hi_bad_q <= hcrc_car_q != hcrc_calc_q[31:8];
    cut_magic_q <= window_q[215:184] == Magic;
  end
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proofs rx_frame_v3, rx_frame_v2). The byte
  // stream is free (any bytes, at any clock, end_of_stream at any time), and so are the receiver's answers
  // (admit_drop, admit_copy); only the reset at the start is assumed. These are the decoder's side of the chain
  // "a frame that fails its CRC or its header check leaves both copies of scene memory unchanged" and the
  // guarantees ts_rx_commit's contract names: a frame is reported intact only once its header passed every check
  // and its CRC matched; then it waits, its header held, with no other frame and no report, until the receiver
  // answers; only an answer to copy starts the copy, which gives exactly its count of records, then copy_done.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  // The header's byte checks as the engine goes over the frame's bytes (docs/link_format.md, "Checks and errors"):
  // the magic, the version, frac_bits at most 30, both reserved bytes 0 (f_fixed_bad: one failed), and on v3 the
  // carried header CRC equal to the CRC of bytes 0..23 (f_hcrc_ok), each from the frame's first byte on.
  logic f_fixed_bad, f_hcrc_ok;
  wire f_hdr_exec = in_frame_exec && !hdr_ok_q;
  wire f_fixed_fails = (off_q < OW'(4) && b != magic_byte(off_q[1:0])) ||
                       (off_q == OW'(ts_link_pkg::VersionAt) && b != Version) ||
                       (off_q == OW'(ts_link_pkg::FracBitsAt) && b > 8'(ts_link_pkg::MaxFracBits)) ||
                       (off_q >= OW'(ts_link_pkg::ReservedAt) && off_q < OW'(ts_link_pkg::ReservedEnd) && b != 8'd0);
  always_ff @(posedge clk) begin
    if (f_hdr_exec) begin
      f_fixed_bad <= (off_q != '0 && f_fixed_bad) || f_fixed_fails;
      if (off_q == '0) f_hcrc_ok <= 1'b0;
      if (off_q == OW'(H - 1)) f_hcrc_ok <= {hcrc_car_q, b} == hcrc_calc_q;
    end
  end
  // The phase of the frame that was reported intact: waiting for the answer (S_ADMIT), or being copied (S_CBEGIN to
  // S_CEND), with the records copied so far.
  wire f_waiting = state_q == S_ADMIT;
  wire f_copying = state_q == S_CBEGIN || state_q == S_CFETCH || state_q == S_CEXEC || state_q == S_CEND;
  logic [AW+1:0] f_copied;
  always_ff @(posedge clk) begin
    if (state_q == S_CBEGIN) f_copied <= '0;
    else if (rec_valid && rec_copy) f_copied <= f_copied + 1'b1;
  end

  always_comb begin
    if (past_valid) begin
      // Invariants that make the induction close (each a property).
      p_state_valid: assert (state_q <= S_CEND && (state_q != S_CAND || Wire == 3));
      if (!hunting_q && off_q != '0 && (state_q == S_FETCH || state_q == S_EXEC)) begin
        p_prefix_checked: assert (!f_fixed_bad && (hdr_ok_q || off_q <= OW'(ts_link_pkg::FracBitsAt)
                                                   || hdr_frac <= 8'(ts_link_pkg::MaxFracBits))
                                  && (hdr_ok_q || off_q <= OW'(CountCheckAt) || count_q <= Max32));
      end
      if (state_q == S_VERDICT || state_q == S_CAND || f_waiting || f_copying) begin
        p_body_states: assert (hdr_ok_q && !hunting_q);
      end
      // In the body the offset lies between the header's end and the frame's; a cut candidate is checked from
      // offset 56 on, ending at the frame's last byte when the verdict follows it.
      if (hdr_ok_q && !hunting_q && (state_q == S_FETCH || state_q == S_EXEC)) begin
        p_body_offset: assert (off_q >= OW'(H) && off_q < fb_q);
      end
      if (state_q == S_CAND) begin
        p_cand_state: assert (cand_cnt_q <= 5'd24 && off_q >= OW'(2 * CutWindow) && off_q <= fb_q
                              && (!cand_final_q || off_q == fb_q) && (cand_final_q || off_q < fb_q));
      end
      if (f_copying && state_q != S_CBEGIN) begin
        p_copy_progress: assert (f_copied + (AW + 2)'(rec_valid && rec_copy) + (AW + 2)'(left_q)
                                 == (AW + 2)'(count_q[AW:0])
                                 && f_copied <= (AW + 2)'(count_q[AW:0]) && left_q <= count_q[AW:0] && sbyte_q < 5'(Rec)
                                 && (state_q != S_CEND || left_q == '0) && (state_q == S_CEND || left_q != '0));
      end
      // The header passed every check: its fixed bytes, its CRC (v3), its count at most MaxSpheres (so hdr_count,
      // count's low bits, is the whole count), its length exactly count x 24, and the frame's size from them.
      // Rules out a header error that is not caught, on any byte stream: the count that would let scene memory
      // be written beyond its capacity, a length believed from a header whose CRC failed.
      if (hdr_ok_q && !hunting_q) begin
        p_header_checked: assert (!f_fixed_bad && (Wire == 2 || f_hcrc_ok) && count_q <= Max32
                                  && length_q == count_q * 32'd24 && count_x24_q == length_q
                                  && 32'(fb_q) == 32'(H + 4) + length_q && hdr_frac <= 8'(ts_link_pkg::MaxFracBits));
      end
      // A verdict is given on the whole frame: every byte of it, its 4 CRC bytes the last, has gone by. Rules out
      // a CRC compared a byte early or late.
      if (state_q == S_VERDICT) p_verdict_at_end: assert (off_q == fb_q);
      // Intact only for a frame whose header passed and whose carried CRC equals the one computed (the verdict's
      // state, its CRCs equal); it then waits for the answer. Rules out an intact report without the checks.
      if (intact) p_intact_checked: assert (f_waiting && hdr_ok_q && fcrc_car_q == fcrc_calc_q);
      // While a frame waits, no other frame and no report; no record of a check pass while it waits or is copied;
      // a copied record only while it is copied, one of its count. Rules out a verdict that could be taken for
      // another frame's, or a record written that is not the frame's.
      if (f_waiting || f_copying) begin
        p_one_waits: assert (!rep_valid && !(rec_valid && !rec_copy) && !(intact && !f_waiting));
      end
      if (rec_valid && rec_copy) p_copy_records: assert (f_copying && f_copied < (AW + 2)'(hdr_count));
      // copy_done after exactly the frame's count of records.
      if (copy_done) p_copy_done_count: assert (f_copied == (AW + 2)'(hdr_count));
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      // A frame is admitted to the copy only on admit_copy while it waits (reported intact). Rules out a copy
      // started by anything but the receiver's answer to this frame.
      if (f_copying && !$past(f_copying)) p_copy_after_admit: assert ($past(f_waiting && admit_copy));
      if (f_waiting && !$past(f_waiting)) p_waits_after_intact: assert (intact);
      // The frame's header and content flags are held from the clock it is reported intact until it is done with
      // (ts_rx_commit and ts_rx_sequence read them then). Rules out a verdict or a commit on another header's fields.
      if ((f_waiting || f_copying) && $past(f_waiting || f_copying)) begin
        p_waits_held: assert (hdr_session == $past(hdr_session) && hdr_sequence == $past(hdr_sequence)
                              && hdr_count == $past(hdr_count) && hdr_frac == $past(hdr_frac)
                              && frame_bytes == $past(frame_bytes) && bad_sphere == $past(bad_sphere) && in_body);
      end
    end
  end
`endif
endmodule
