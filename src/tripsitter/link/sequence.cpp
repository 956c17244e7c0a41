#include <tripsitter/link/sequence.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include <tripsitter/link/frame.h>

namespace tripsitter::link {

Numbering::Numbering(WireVersion wire, std::uint32_t session) : wire_(wire), session_(session) {
  if (wire_ == WireVersion::kV3 && session_ == 0) throw std::invalid_argument("a v3 session is never 0");
}

void Numbering::stamp(std::span<std::uint8_t> world_bytes) {
  if (wire_ == WireVersion::kV1) return;
  if (last_ == UINT32_MAX) {
    session_ = session_ == UINT32_MAX ? 1 : session_ + 1;
    last_ = 0;
  }
  restamp_frame(wire_, world_bytes, session_, ++last_);
}

std::uint32_t random_session() {
  std::random_device device;
  std::uint32_t session = 0;
  while (session == 0) session = device();
  return session;
}

SequenceRules::SequenceRules(WireVersion wire) : wire_(wire) {
  if (wire_ == WireVersion::kV1) throw std::invalid_argument("v1 words carry no sequence number");
}

bool SequenceRules::retired(std::uint32_t session) const {
  return std::find(retired_.begin(), retired_.begin() + static_cast<std::ptrdiff_t>(retired_count_), session) !=
         retired_.begin() + static_cast<std::ptrdiff_t>(retired_count_);
}

SequenceCheck SequenceRules::check(std::uint32_t session, std::uint32_t sequence) {
  SequenceCheck c;
  if (wire_ == WireVersion::kV2) {
    if (session_ && sequence > last_) c.missing = sequence - last_ - 1;
    c.new_session = !session_;
    session_ = 0;
    last_ = sequence;
    return c;
  }
  if (session_ && session == *session_) {
    if (sequence <= last_) {
      c.verdict = SequenceVerdict::kReplay;
      return c;
    }
    c.missing = sequence - last_ - 1;
    last_ = sequence;
    return c;
  }
  if (retired(session)) {
    c.verdict = SequenceVerdict::kReplay;
    c.ended_session = true;
    return c;
  }
  if (session_) {
    retired_[retired_next_] = *session_;
    retired_next_ = (retired_next_ + 1) % kRetiredSessions;
    retired_count_ = std::min(retired_count_ + 1, kRetiredSessions);
  }
  c.new_session = true;
  c.missing = sequence == 0 ? 0 : sequence - 1;  // a host numbers from 1 in each session
  session_ = session;
  last_ = sequence;
  return c;
}

}  // namespace tripsitter::link
