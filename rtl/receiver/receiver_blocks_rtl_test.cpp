// The receiver's blocks (rtl/receiver/ts_rx_*.sv), each alone against its C++ twin:
//   ts_rx_frame     link::FrameStreamDecoder: the same reports (garbage runs and dropped frames with their bytes),
//                   the same frames (header fields and every sphere record, given twice when copied), in the same
//                   order, for streams of good, damaged, cut and lying frames and garbage on v2 and v3;
//   ts_rx_sequence  link::SequenceRules::check: the same verdict, new session and missing count for every number;
//   ts_rx_v1_word   link::decode_v1_word and device::Receiver's v1 conversion: the same accept or reject, the same
//                   sphere in scene memory, the same partial word at the end of the stream;
//   ts_rx_commit    device::Receiver, with its upstream played by the C++ (FrameStreamDecoder's events and
//                   SequenceRules' verdicts turned into the block's inputs): the same counters after every byte and
//                   the same front copy after every swap.
// The whole receiver from its pins is receiver_rtl_test's. Fixed seeds; every stream is checked to contain what it
// is meant to exercise.
#include <cstdint>
#include <iostream>
#include <memory>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"

#include "Vts_rx_commit_v3.h"
#include "Vts_rx_frame_v2.h"
#include "Vts_rx_frame_v3.h"
#include "Vts_rx_sequence_v2.h"
#include "Vts_rx_sequence_v3.h"
#include "Vts_rx_v1_word_board.h"
#include "Vts_rx_v1_word_wide.h"
#include "test_util.h"

#include <tripsitter/core/crc32.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/wire_v1.h>

namespace tripsitter::rtl {
namespace {

using link::WireVersion;

constexpr std::uint32_t kMaxSpheres = 64;  // the blocks' MaxSpheres (rtl/receiver/CMakeLists.txt)

// The low `bits` bits of a port as a two's complement number.
std::int64_t sx(std::uint64_t v, int bits) { return static_cast<std::int64_t>(sign_extend(v, bits)); }

// A Verilated model with a fresh context, reset for a few clocks (random initial state: the reset must make the
// rest irrelevant).
template <class M>
struct Model {
  Model() : ctx(std::make_unique<VerilatedContext>()) {
    ctx->randReset(2);
    top = std::make_unique<M>(ctx.get());
    top->rst = 1;
    for (int i = 0; i < 3; ++i) rising_edge(*top);
    top->rst = 0;
  }
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
  ~Model() { top->final(); }
  M& operator*() { return *top; }
  M* operator->() { return top.get(); }
  const M* operator->() const { return top.get(); }
  std::unique_ptr<VerilatedContext> ctx;
  std::unique_ptr<M> top;
};

// ---- Streams of frames: good ones, damaged ones, and garbage ----

// A world in board-2023's formats, now and then with a sphere the link's decoder refuses (radius 0, material 3,
// ior 0), other fractional bits, or a sphere outside the formats (the commit's refusals).
link::World random_world(Rng& rng, std::uint32_t sequence, std::uint32_t session) {
  link::World w;
  w.session = session;
  w.sequence = sequence;
  w.frac_bits = rng.percent(8) ? 5 : 3;
  const auto n = static_cast<int>(rng.between(rng.percent(8) ? 0 : 1, 6));
  for (int i = 0; i < n; ++i) {
    link::WireSphere s;
    s.x = static_cast<std::int32_t>(rng.between(-32768, 32767));
    s.y = static_cast<std::int32_t>(rng.between(-16384, 16383));
    s.z = static_cast<std::int32_t>(rng.between(-16384, 16383));
    s.radius = static_cast<std::uint32_t>(rng.between(1, 65535));
    s.material = static_cast<std::uint8_t>(rng.below(3));
    s.albedo = {rng.byte(), rng.byte(), rng.byte()};
    s.fuzz = static_cast<std::uint16_t>(rng.below(65536));
    s.ior = static_cast<std::uint16_t>(rng.between(1, 65535));
    w.spheres.push_back(s);
  }
  if (!w.spheres.empty() && rng.percent(6)) w.spheres.back().x = 40000;  // outside board-2023's 16 bits
  return w;
}


// A stream of `pieces` pieces: good frames (numbered as a host would, with restarts and replays), frames with a flipped
// bit, dropped or inserted bytes, cut short, with a header inside (v3's cut rule), with a lying count or length or a
// bad sphere, and runs of garbage.
Bytes random_stream(Rng& rng, WireVersion wire, int pieces, std::uint32_t first_session = 7) {
  const bool v3 = wire == WireVersion::kV3;
  const std::size_t header = link::frame_header_bytes(wire);
  Bytes out;
  std::vector<Bytes> sent;
  std::uint32_t session = first_session, sequence = 0;
  for (int p = 0; p < pieces; ++p) {
    if (rng.percent(5)) {
      session += 1 + static_cast<std::uint32_t>(rng.below(3));  // a host restart (v3: maybe an earlier session)
      sequence = 0;
    }
    sequence += rng.percent(10) ? 1 + static_cast<std::uint32_t>(rng.below(4)) : 1;
    link::World w = random_world(rng, sequence, session);
    Bytes f = link::encode_frame(wire, w);
    if (rng.percent(4) && !w.spheres.empty()) {
      f[header + 12 + 3] = 0;  // a sphere's radius 0 (its low byte; the high bytes are random) ...
      f[header + 12 + 2] = 0;
      f[header + 12 + 1] = 0;
      f[header + 12] = 0;
      fix_crcs(wire, f);  // ... in a frame that arrived intact: decode_body's bad sphere
    }
    sent.push_back(f);
    switch (rng.below(12)) {
      case 0:  // a flipped bit anywhere
        f[rng.below(f.size())] ^= static_cast<std::uint8_t>(1u << rng.below(8));
        break;
      case 1:  // a dropped byte
        f.erase(f.begin() + static_cast<std::ptrdiff_t>(rng.below(f.size())));
        break;
      case 2:  // an inserted byte
        f.insert(f.begin() + static_cast<std::ptrdiff_t>(rng.below(f.size())), rng.byte());
        break;
      case 3:  // cut short
        f.resize(rng.below(f.size()));
        break;
      case 4: {  // a count above MaxSpheres or a length that lies, with good CRCs
        const std::size_t count_at = v3 ? 16 : 12;
        if (rng.percent(50)) {
          put_be32(f, count_at, kMaxSpheres + 1 + static_cast<std::uint32_t>(rng.below(3)));
        } else {
          put_be32(f, count_at + 4, static_cast<std::uint32_t>(rng.below(200)));
        }
        fix_crcs(wire, f);
        break;
      }
      case 5:  // a replay of an earlier frame
        f = sent[rng.below(sent.size())];
        break;
      case 6: {  // a frame cut by the start of another: a header inside its payload
        Bytes next = link::encode_frame(wire, random_world(rng, ++sequence, session));
        // Now and then right after the header: the earliest offset at which v3's cut rule looks (28).
        f.resize(rng.percent(30) ? header : std::max<std::size_t>(header + 1, rng.below(f.size())));
        f.insert(f.end(), next.begin(), next.end());
        break;
      }
      case 7:  // garbage, now and then with a stray magic in it
        f.clear();
        for (auto n = rng.between(1, 40); n > 0; --n) f.push_back(rng.byte());
        if (rng.percent(50)) {
          const auto& magic = v3 ? link::kV3Magic : link::kV2Magic;
          f.insert(f.begin() + static_cast<std::ptrdiff_t>(rng.below(f.size())), magic.begin(),
                   magic.begin() + static_cast<std::ptrdiff_t>(rng.between(1, 4)));
        }
        break;
      default:  // a good frame
        break;
    }
    out.insert(out.end(), f.begin(), f.end());
  }
  return out;
}

// ---- ts_rx_frame against link::FrameStreamDecoder ----

struct Record {
  std::uint32_t x = 0, y = 0, z = 0, r = 0;
  std::uint8_t material = 0;
  std::uint32_t albedo = 0;
  bool operator==(const Record&) const = default;
};

Record record_of(const link::WireSphere& s) {
  return Record{static_cast<std::uint32_t>(s.x), static_cast<std::uint32_t>(s.y), static_cast<std::uint32_t>(s.z),
                s.radius,                        s.material,
                (std::uint32_t{s.albedo[0]} << 16) | (std::uint32_t{s.albedo[1]} << 8) | s.albedo[2]};
}

// What the decoder did with a piece of the stream.
struct Event {
  enum Kind { kGarbage, kDropped, kIntact } kind = kGarbage;
  std::uint64_t bytes = 0;
  bool bad_sphere = false;  // kIntact: decode_body refused a sphere (the C++ reports it as an error)
  std::uint32_t session = 0, sequence = 0;
  int frac = 0;
  std::vector<Record> records;  // kIntact and not bad_sphere
  bool operator==(const Event&) const = default;
};

std::string describe(const Event& e) {
  std::ostringstream out;
  const char* kinds[] = {"garbage", "dropped", "intact"};
  out << kinds[e.kind] << " " << e.bytes << " bytes";
  if (e.kind == Event::kIntact) {
    out << (e.bad_sphere ? " (bad sphere)" : "") << ", session " << e.session << ", number " << e.sequence
        << ", frac " << e.frac << ", " << e.records.size() << " records";
  }
  return out.str();
}

std::vector<Event> model_events(WireVersion wire, std::span<const std::uint8_t> stream) {
  std::vector<Event> events;
  link::FrameStreamDecoder decoder(
      wire, kMaxSpheres,
      {.on_frame =
           [&](link::World&& w) {
             Event e{Event::kIntact, link::frame_bytes(wire, w.spheres.size()), false, w.session, w.sequence,
                     w.frac_bits, {}};
             for (const auto& s : w.spheres) e.records.push_back(record_of(s));
             events.push_back(e);
           },
       .on_error =
           [&](const link::FrameFailure& f, std::size_t bytes) {
             Event e;
             e.bytes = bytes;
             if (f.intact) {
               e.kind = Event::kIntact;
               e.bad_sphere = true;
               e.session = f.intact->session;
               e.sequence = f.intact->sequence;
             } else {
               e.kind = f.error == link::FrameError::kBadMagic ? Event::kGarbage : Event::kDropped;
             }
             events.push_back(e);
           }});
  decoder.push(stream);
  decoder.end_of_stream();
  return events;
}

// Feeds the stream to ts_rx_frame a byte every few clocks and plays the receiver: every intact frame is answered,
// alternately, by a copy (whose records must repeat the first pass's) and by a drop.
template <class M>
std::vector<Event> rtl_events(std::span<const std::uint8_t> stream, Rng& rng, std::string& error) {
  Model<M> m;
  std::vector<Event> events;
  std::vector<Record> pass1, pass2;
  bool copying = false, copy_next = true;
  int answer_in = -1;  // clocks until the answer to an intact frame
  std::size_t next = 0;
  int gap = 0;
  bool eos_sent = false;
  const auto rec = [&] {
    return Record{m->rec_x, m->rec_y, m->rec_z, m->rec_r, m->rec_material, m->rec_albedo};
  };
  for (long clock = 0; clock < 40'000'000; ++clock) {
    m->byte_valid = 0;
    m->end_of_stream = 0;
    m->admit_copy = 0;
    m->admit_drop = 0;
    if (next < stream.size() && gap-- <= 0) {
      m->byte_valid = 1;
      m->byte_data = stream[next++];
      gap = static_cast<int>(rng.between(1, 5));
      if (m->full) {
        error = "the byte buffer was full";
        return events;
      }
    } else if (next == stream.size() && !eos_sent) {
      m->end_of_stream = 1;
      eos_sent = true;
    }
    if (answer_in == 0) {
      (copy_next ? m->admit_copy : m->admit_drop) = 1;
      copying = copy_next;
      copy_next = !copy_next;
    }
    --answer_in;
    rising_edge(*m);
    if (!m->in_body && !copying) pass1.clear();
    if (m->rep_valid) {
      Event e;
      e.kind = m->rep_garbage ? Event::kGarbage : Event::kDropped;
      e.bytes = m->rep_bytes;
      events.push_back(e);
    }
    if (m->rec_valid) (m->rec_copy ? pass2 : pass1).push_back(rec());
    if (m->intact) {
      Event e{Event::kIntact, m->frame_bytes, m->bad_sphere != 0, m->hdr_session, m->hdr_sequence, m->hdr_frac, {}};
      if (e.bad_sphere) {
        e.frac = 0;  // the C++ reports a bad sphere as an error, without the frame's fractional bits
      } else {
        e.records = pass1;
      }
      if (static_cast<std::size_t>(m->hdr_count) != pass1.size()) error = "the header's count is not the records given";
      events.push_back(e);
      answer_in = static_cast<int>(rng.between(0, 3));
    }
    if (m->copy_done) {
      if (!copying || pass2 != pass1) error = "the copy's records differ from the check's";
      copying = false;
      pass2.clear();
      pass1.clear();
    }
    if (!error.empty()) return events;
    if (eos_sent && m->idle && !m->rep_valid && answer_in < 0 && !copying) return events;
  }
  error = "ts_rx_frame did not finish the stream";
  return events;
}

template <class M>
void frame_decoder(WireVersion wire, std::uint64_t seed, int streams) {
  Rng rng(seed);
  std::size_t intact = 0, copied_records = 0, bad = 0, garbage = 0, dropped = 0;
  for (int s = 0; s < streams; ++s) {
    const Bytes stream = random_stream(rng, wire, 40);
    const std::vector<Event> expected = model_events(wire, stream);
    std::string error;
    const std::vector<Event> got = rtl_events<M>(stream, rng, error);
    ASSERT_TRUE(error.empty()) << "stream " << s << ": " << error;
    for (std::size_t i = 0; i < std::max(expected.size(), got.size()); ++i) {
      ASSERT_TRUE(i < expected.size() && i < got.size() && expected[i] == got[i])
          << "stream " << s << ", event " << i << ": model "
          << (i < expected.size() ? describe(expected[i]) : "(none)") << ", RTL "
          << (i < got.size() ? describe(got[i]) : "(none)");
    }
    for (const Event& e : expected) {
      intact += e.kind == Event::kIntact;
      copied_records += e.records.size();
      bad += e.bad_sphere;
      garbage += e.kind == Event::kGarbage;
      dropped += e.kind == Event::kDropped;
    }
  }
  // The streams exercised what they are for.
  EXPECT_GT(intact, 100u);
  EXPECT_GT(copied_records, 200u);
  EXPECT_GT(bad, 2u);
  EXPECT_GT(garbage, 20u);
  EXPECT_GT(dropped, 40u);
}

TEST(RtlRxFrame, V2MatchesFrameStreamDecoder) { frame_decoder<Vts_rx_frame_v2>(WireVersion::kV2, 1201, 12); }
TEST(RtlRxFrame, V3MatchesFrameStreamDecoder) { frame_decoder<Vts_rx_frame_v3>(WireVersion::kV3, 1301, 12); }

// ---- ts_rx_sequence against link::SequenceRules ----

template <class M>
void sequence_rules(WireVersion wire, std::uint64_t seed, int checks) {
  Model<M> m;
  link::SequenceRules rules(wire);
  Rng rng(seed);
  std::vector<std::uint32_t> sessions{1};
  std::uint32_t session = 1, number = 0;
  std::size_t replays = 0, ended = 0, fresh = 0, missing = 0;
  for (int i = 0; i < checks; ++i) {
    // A host's numbers, with lost worlds, replays, restarts (new sessions) and worlds of sessions that have ended.
    const auto r = rng.below(100);
    std::uint32_t s = session, n = number + 1;
    if (r < 10) {
      n = number + 2 + static_cast<std::uint32_t>(rng.below(5));
    } else if (r < 20) {
      n = static_cast<std::uint32_t>(rng.below(std::uint64_t{number} + 1));
    } else if (r < 27) {
      session = s = static_cast<std::uint32_t>(rng.word());
      sessions.push_back(s);
      n = static_cast<std::uint32_t>(rng.below(4));
    } else if (r < 35) {
      s = sessions[sessions.size() - 1 - rng.below(std::min<std::size_t>(sessions.size(), 20))];
      n = static_cast<std::uint32_t>(rng.below(100));
    } else if (r < 37) {
      n = rng.percent(50) ? 0 : 0xFFFF'FFFFu;
    }
    if (s == session) number = std::max(number, n);
    const link::SequenceCheck c = rules.check(s, n);
    m->session = s;
    m->number = n;
    m->check = 1;
    rising_edge(*m);
    m->check = 0;
    int wait = 0;
    while (!m->done && wait++ < 4) rising_edge(*m);
    ASSERT_TRUE(m->done) << "check " << i << ": no verdict";
    const bool replay = c.verdict == link::SequenceVerdict::kReplay;
    ASSERT_EQ(m->replay != 0, replay) << "check " << i << ": session " << s << ", number " << n;
    ASSERT_EQ(m->new_session != 0, c.new_session) << "check " << i << ": session " << s << ", number " << n;
    ASSERT_EQ(std::uint64_t{m->missing}, c.missing) << "check " << i << ": session " << s << ", number " << n;
    ASSERT_EQ(wait, 1) << "the verdict comes two clocks after the check";
    rising_edge(*m);
    replays += replay;
    ended += c.ended_session;
    fresh += c.new_session;
    missing += c.missing > 0;
  }
  EXPECT_GT(missing, 50u);
  if (wire == WireVersion::kV2) {
    EXPECT_EQ(fresh, 1u);  // v2 has no sessions: only the first world begins one
  } else {
    EXPECT_GT(fresh, 10u);
    EXPECT_GT(replays, 100u);
    EXPECT_GT(ended, 20u);
  }
}

TEST(RtlRxSequence, V2MatchesSequenceRules) { sequence_rules<Vts_rx_sequence_v2>(WireVersion::kV2, 1401, 3000); }
TEST(RtlRxSequence, V3MatchesSequenceRules) { sequence_rules<Vts_rx_sequence_v3>(WireVersion::kV3, 1402, 3000); }

// ---- ts_rx_v1_word against decode_v1_word and device::Receiver's v1 conversion ----

struct V1Case {
  device::DevicePreset preset;
  int xw, yw, zw, rw;
};

template <class M>
void v1_words(const V1Case& cfg, std::uint64_t seed, int words) {
  Model<M> m;
  device::Receiver model(cfg.preset, WireVersion::kV1);
  Rng rng(seed);
  std::size_t accepted = 0, rejected = 0, partials = 0;
  std::uint64_t bytes_seen = 0;
  for (int i = 0; i < words; ++i) {
    // Random words with radii the preset takes most of the time, and now and then a partial word ended.
    std::uint64_t word = rng.word();
    if (rng.percent(75)) word = (word & ~(std::uint64_t{63} << 12)) | (rng.below(12) << 12);
    const bool partial = rng.percent(10);
    const int n = partial ? static_cast<int>(rng.between(1, 7)) : 8;
    const device::ReceiverStats before = model.stats();
    for (int k = 0; k < n; ++k) {
      const auto byte = static_cast<std::uint8_t>(word >> (56 - 8 * k));
      model.receive(std::span(&byte, 1));
      m->byte_valid = 1;
      m->byte_data = byte;
      m->end_of_stream = partial && k == n - 1 && rng.percent(50);  // the end in the clock of the last byte
      rising_edge(*m);
      const bool eos_now = m->end_of_stream != 0;
      m->byte_valid = 0;
      m->end_of_stream = 0;
      if (partial && k == n - 1 && !eos_now) {
        m->end_of_stream = 1;
        rising_edge(*m);
        m->end_of_stream = 0;
      }
      ASSERT_EQ(m->word_valid != 0, k == 7 && !partial) << "word " << i << ", byte " << k;
    }
    bytes_seen += static_cast<std::uint64_t>(n);
    if (partial) {
      model.end_of_stream();
      ASSERT_TRUE(m->partial_valid) << "word " << i;
      ASSERT_EQ(int{m->partial_bytes}, n) << "word " << i;
      ASSERT_EQ(model.stats().bytes_dropped - before.bytes_dropped, static_cast<std::uint64_t>(n));
      ++partials;
      continue;
    }
    ASSERT_FALSE(m->partial_valid);
    const bool ok = model.stats().worlds_accepted > before.worlds_accepted;
    ASSERT_EQ(m->word_ok != 0, ok) << "word " << i << ": " << std::hex << word;
    if (!ok) {
      ++rejected;
      continue;
    }
    ++accepted;
    device::SceneMemory front;
    ASSERT_TRUE(model.swap_if_pending(front));
    const auto& g = front.geometry.at(0);
    EXPECT_EQ(sx(m->x, cfg.xw), g.center.x) << "word " << i;
    EXPECT_EQ(sx(m->y, cfg.yw), g.center.y) << "word " << i;
    EXPECT_EQ(sx(m->z, cfg.zw), g.center.z) << "word " << i;
    EXPECT_EQ(static_cast<std::int64_t>(m->r), g.radius) << "word " << i;
    const auto& a = front.surfaces.at(0).albedo;
    EXPECT_EQ(m->albedo, (std::uint32_t{a[0]} << 16) | (std::uint32_t{a[1]} << 8) | a[2]) << "word " << i;
    // The RTL decodes what decode_v1_word decodes: its radius field is the model's radius_log2.
    EXPECT_EQ(std::int64_t{1} << (link::decode_v1_word(word).radius_log2 + cfg.preset.frac_bits()), g.radius);
  }
  EXPECT_GT(accepted, static_cast<std::size_t>(words) / 3);
  EXPECT_GT(rejected, static_cast<std::size_t>(words) / 10);
  EXPECT_GT(partials, static_cast<std::size_t>(words) / 20);
  EXPECT_GT(bytes_seen, 0u);
}

TEST(RtlRxV1Word, WideMatchesTheReceiversConversion) {
  v1_words<Vts_rx_v1_word_wide>({device::wide_preset(), 24, 24, 24, 24}, 1501, 2000);
}
TEST(RtlRxV1Word, BoardMatchesTheReceiversConversion) {
  v1_words<Vts_rx_v1_word_board>({device::board_2023_preset(), 16, 15, 15, 16}, 1502, 2000);
}

// ---- ts_rx_commit against device::Receiver ----

// Drives ts_rx_commit (v3, board-2023) as ts_rx_frame and ts_rx_sequence would, with their C++ twins deciding what
// they say, and keeps the scene memory it writes.
class CommitRig {
 public:
  CommitRig() : rules_(WireVersion::kV3) {
    // Every input quiet (the model starts with random values on its inputs too).
    m_->byte_valid = m_->byte_full = m_->rep_valid = m_->rep_garbage = 0;
    m_->rep_bytes = 0;
    m_->hdr_sequence = m_->frame_bytes = 0;
    m_->hdr_count = m_->hdr_frac = m_->in_body = m_->bad_sphere = m_->bad_hierarchy = m_->intact = 0;
    m_->rec_valid = m_->rec_copy = m_->copy_done = m_->seq_done = m_->seq_replay = m_->seq_new = 0;
    m_->seq_missing = 0;
    m_->word_valid = m_->word_ok = m_->partial_valid = m_->partial_bytes = 0;
    m_->word_x = m_->word_y = m_->word_z = m_->word_r = m_->word_albedo = 0;
    m_->sm_replaced = 0;
    m_->source_idle = 1;
    clock();
    if (stats().frames_rejected + stats().bytes_dropped + stats().worlds_accepted != 0)
      throw std::logic_error("ts_rx_commit counted something before any input");
  }

  void byte() {
    m_->byte_valid = 1;
    clock();
    m_->byte_valid = 0;
  }
  void report(bool garbage, std::uint64_t bytes) {
    m_->rep_valid = 1;
    m_->rep_garbage = garbage;
    m_->rep_bytes = bytes;
    clock();
    m_->rep_valid = 0;
  }
  // An intact frame: its records while it is checked, the verdict, then (if admitted) the copy.
  void frame(std::uint32_t session, std::uint32_t sequence, int frac, std::uint64_t bytes, bool bad,
             const std::vector<link::WireSphere>& spheres, std::string& error) {
    m_->hdr_sequence = sequence;
    m_->hdr_count = static_cast<CData>(spheres.size());
    m_->hdr_frac = static_cast<CData>(frac);
    m_->frame_bytes = static_cast<IData>(bytes);
    m_->in_body = 1;
    m_->bad_sphere = bad;
    clock();
    for (const auto& s : spheres) give(s, false);
    clock(3);
    m_->intact = 1;
    clock();
    m_->intact = 0;
    const link::SequenceCheck c = rules_.check(session, sequence);
    clock();
    m_->seq_done = 1;
    m_->seq_replay = c.verdict == link::SequenceVerdict::kReplay;
    m_->seq_new = c.new_session;
    m_->seq_missing = static_cast<IData>(c.missing);
    clock();
    m_->seq_done = 0;
    bool copy = false, drop = false;
    for (int i = 0; i < 3 && !copy && !drop; ++i) {
      copy = m_->admit_copy != 0;
      drop = m_->admit_drop != 0;
      if (!copy && !drop) clock();
    }
    if (copy == drop) {
      error = "no single answer to an intact frame";
      return;
    }
    if (copy) {
      writes_.clear();
      for (const auto& s : spheres) give(s, true);
      m_->copy_done = 1;
      clock();
      m_->copy_done = 0;
    }
    m_->in_body = 0;
    m_->bad_sphere = 0;
    clock(2);
    if (!m_->idle) error = "not idle after a frame";
  }
  // Vertical blanking: a committed world becomes the front copy.
  void swap() {
    if (pending_) front_ = back_;
    pending_ = false;
  }

  device::ReceiverStats stats() const {
    device::ReceiverStats s;
    s.worlds_accepted = m_->worlds_accepted;
    s.worlds_replaced = m_->worlds_replaced;
    s.frames_rejected = m_->frames_rejected;
    s.garbage_runs = m_->garbage_runs;
    s.bytes_dropped = m_->bytes_dropped;
    s.worlds_missing = m_->worlds_missing;
    s.worlds_replayed = m_->worlds_replayed;
    s.sessions = m_->sessions;
    return s;
  }
  std::uint64_t bytes_received() const { return m_->bytes_received; }

  struct Sphere {
    std::int64_t x = 0, y = 0, z = 0, r = 0;
    bool metal = false;
    std::uint32_t albedo = 0;
    bool operator==(const Sphere&) const = default;
  };
  struct Copy {
    bool valid = false;
    std::uint32_t sequence = 0;
    std::vector<Sphere> spheres;
  };
  const Copy& front() const { return front_; }

 private:
  void give(const link::WireSphere& s, bool copy) {
    m_->rec_valid = 1;
    m_->rec_copy = copy;
    m_->rec_x = static_cast<IData>(s.x);
    m_->rec_y = static_cast<IData>(s.y);
    m_->rec_z = static_cast<IData>(s.z);
    m_->rec_r = s.radius;
    m_->rec_material = s.material;
    m_->rec_albedo = (std::uint32_t{s.albedo[0]} << 16) | (std::uint32_t{s.albedo[1]} << 8) | s.albedo[2];
    m_->rec_ior = s.ior;
    clock();
    m_->rec_valid = 0;
  }
  // Clocks, keeping what scene memory would: the writes, the commit, the pending world and `replaced`.
  void clock(int n = 1) {
    for (int i = 0; i < n; ++i) {
      m_->eval();
      m_->sm_replaced = m_->sm_begin && pending_;
      if (m_->sm_begin) pending_ = false;
      if (m_->sm_we) {
        if (m_->sm_waddr >= writes_.size()) writes_.resize(m_->sm_waddr + 1u);
        writes_[m_->sm_waddr] = Sphere{sx(m_->sm_wx, 16), sx(m_->sm_wy, 15), sx(m_->sm_wz, 15), static_cast<std::int64_t>(m_->sm_wr),
                                       m_->sm_wmetal != 0, m_->sm_walbedo};
      }
      if (m_->sm_commit) {
        back_.valid = true;
        back_.sequence = m_->sm_sequence;
        back_.spheres.assign(writes_.begin(), writes_.begin() + std::min<std::size_t>(m_->sm_count, writes_.size()));
        back_.spheres.resize(m_->sm_count);
        pending_ = true;
      }
      rising_edge(*m_);
    }
  }

  Model<Vts_rx_commit_v3> m_;
  link::SequenceRules rules_;
  std::vector<Sphere> writes_;
  Copy back_, front_;
  bool pending_ = false;
};

std::string stats_difference(const device::ReceiverStats& a, const device::ReceiverStats& b) {
  std::ostringstream out;
  const auto field = [&](const char* name, std::uint64_t x, std::uint64_t y) {
    if (x != y && out.tellp() == 0) out << name << ": model " << x << ", RTL " << y;
  };
  field("worlds_accepted", a.worlds_accepted, b.worlds_accepted);
  field("worlds_replaced", a.worlds_replaced, b.worlds_replaced);
  field("frames_rejected", a.frames_rejected, b.frames_rejected);
  field("garbage_runs", a.garbage_runs, b.garbage_runs);
  field("bytes_dropped", a.bytes_dropped, b.bytes_dropped);
  field("worlds_missing", a.worlds_missing, b.worlds_missing);
  field("worlds_replayed", a.worlds_replayed, b.worlds_replayed);
  field("sessions", a.sessions, b.sessions);
  return out.str();
}

TEST(RtlRxCommit, MatchesTheReceiver) {
  const device::DevicePreset preset = device::board_2023_preset();
  Rng rng(1601);
  device::Receiver model(preset, WireVersion::kV3);
  CommitRig rig;
  std::string error;
  // The C++ decoder's events, in the order they come, for the rig to replay after each byte.
  struct Pending {
    bool frame = false, garbage = false, bad = false;
    std::uint64_t bytes = 0;
    link::World world;
  };
  std::vector<Pending> queue;
  link::FrameStreamDecoder decoder(
      WireVersion::kV3, preset.max_spheres,
      {.on_frame =
           [&](link::World&& w) {
             queue.push_back({true, false, false, link::frame_bytes(WireVersion::kV3, w.spheres.size()), w});
           },
       .on_error =
           [&](const link::FrameFailure& f, std::size_t bytes) {
             Pending p;
             p.bytes = bytes;
             if (f.intact) {
               p.frame = p.bad = true;
               p.world.session = f.intact->session;
               p.world.sequence = f.intact->sequence;
               p.world.frac_bits = 3;
             } else {
               p.garbage = f.error == link::FrameError::kBadMagic;
             }
             queue.push_back(p);
           }});
  std::size_t swaps = 0;
  std::uint64_t total_bytes = 0;
  for (int s = 0; s < 12; ++s) {
    // Each stream a host of new sessions (the same sessions again would be refused as ended).
    const Bytes stream = random_stream(rng, WireVersion::kV3, 40, 1000 * static_cast<std::uint32_t>(s + 1));
    for (std::size_t i = 0; i <= stream.size(); ++i) {
      if (i < stream.size()) {
        const std::span<const std::uint8_t> one(&stream[i], 1);
        model.receive(one);
        decoder.push(one);
        rig.byte();
      } else {
        model.end_of_stream();
        decoder.end_of_stream();
      }
      for (const Pending& p : queue) {
        if (!p.frame) {
          rig.report(p.garbage, p.bytes);
        } else {
          rig.frame(p.world.session, p.world.sequence, p.world.frac_bits, p.bytes, p.bad, p.world.spheres, error);
          ASSERT_TRUE(error.empty()) << "stream " << s << ", byte " << i << ": " << error;
        }
      }
      queue.clear();
      const std::string diff = stats_difference(model.stats(), rig.stats());
      ASSERT_TRUE(diff.empty()) << "stream " << s << ", byte " << i << ": " << diff;
      // A vertical blanking now and then (not after every world, so that worlds replace waiting ones).
      if (rng.below(1000) < 3) {
        device::SceneMemory front;
        const bool swapped = model.swap_if_pending(front);
        rig.swap();
        swaps += swapped;
        if (!swapped) continue;
        const CommitRig::Copy& f = rig.front();
        ASSERT_EQ(f.sequence, front.sequence);
        ASSERT_EQ(f.spheres.size(), front.geometry.size());
        for (std::size_t k = 0; k < f.spheres.size(); ++k) {
          const auto& g = front.geometry[k];
          const auto& w = front.surfaces[k];
          const CommitRig::Sphere want{g.center.x, g.center.y, g.center.z, g.radius,
                                       w.material == link::kMaterialMetal,
                                       (std::uint32_t{w.albedo[0]} << 16) | (std::uint32_t{w.albedo[1]} << 8) |
                                           w.albedo[2]};
          const CommitRig::Sphere& got = f.spheres[k];
          ASSERT_TRUE(got == want) << "stream " << s << ", front sphere " << k << ": model " << want.x << " "
                                   << want.y << " " << want.z << " " << want.r << " " << want.metal << " "
                                   << want.albedo << ", RTL " << got.x << " " << got.y << " " << got.z << " "
                                   << got.r << " " << got.metal << " " << got.albedo;
        }
      }
    }
    total_bytes += stream.size();
    ASSERT_EQ(rig.bytes_received(), total_bytes);
  }
  const device::ReceiverStats& st = model.stats();
  std::cout << "commit: " << st.worlds_accepted << " accepted, " << st.worlds_replaced << " replaced, "
            << st.frames_rejected << " rejected, " << st.worlds_replayed << " replayed, " << st.garbage_runs
            << " garbage runs, " << st.sessions << " sessions, " << st.worlds_missing << " missing, " << swaps
            << " swaps\n";
  EXPECT_GT(st.worlds_accepted, 60u);
  EXPECT_GT(st.worlds_replaced, 20u);
  EXPECT_GT(st.worlds_replayed, 10u);
  EXPECT_GT(st.worlds_missing, 10u);
  EXPECT_GT(st.sessions, 5u);
  EXPECT_GT(st.garbage_runs, 10u);
  EXPECT_GT(st.frames_rejected, 60u);
  EXPECT_GT(swaps, 10u);
}

}  // namespace
}  // namespace tripsitter::rtl
