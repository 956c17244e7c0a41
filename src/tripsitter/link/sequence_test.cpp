// The host's numbering and the receiver's sequence rules (link/sequence.h, docs/link_format.md "Sessions and
// sequence numbers").
#include <tripsitter/link/sequence.h>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>

namespace tripsitter::link {
namespace {

struct Step {
  std::uint32_t session, sequence;
  SequenceVerdict verdict;
  std::uint64_t missing;
  bool new_session;
};

void run(WireVersion wire, const std::vector<Step>& steps) {
  SequenceRules rules(wire);
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    const SequenceCheck c = rules.check(s.session, s.sequence);
    EXPECT_EQ(c.verdict, s.verdict) << "step " << i;
    EXPECT_EQ(c.missing, s.missing) << "step " << i;
    EXPECT_EQ(c.new_session, s.new_session) << "step " << i;
  }
}

constexpr auto kShow = SequenceVerdict::kShow;
constexpr auto kReplay = SequenceVerdict::kReplay;

TEST(SequenceRules, V3ShowsOnlyNewerWorldsOfTheSessionAndCountsTheGaps) {
  run(WireVersion::kV3, {{7, 1, kShow, 0, true},
                         {7, 2, kShow, 0, false},
                         {7, 5, kShow, 2, false},   // 3 and 4 were lost
                         {7, 5, kReplay, 0, false}, // a repeat
                         {7, 4, kReplay, 0, false}, // an older one, late
                         {7, 6, kShow, 0, false}});
}

TEST(SequenceRules, V3TakesARestartedHostFromItsFirstWorldAndRefusesTheOldSession) {
  run(WireVersion::kV3, {{7, 1, kShow, 0, true},
                         {7, 2, kShow, 0, false},
                         {9, 1, kShow, 0, true},    // the host restarted with another session
                         {7, 3, kReplay, 0, false}, // the old session has ended: even a newer number is old
                         {9, 3, kShow, 1, false},
                         {11, 4, kShow, 3, true}}); // a session whose first three worlds were lost
}

TEST(SequenceRules, V3RemembersTheLastSixteenSessions) {
  SequenceRules rules(WireVersion::kV3);
  for (std::uint32_t session = 1; session <= SequenceRules::kRetiredSessions + 2; ++session)
    EXPECT_EQ(rules.check(session, 1).verdict, kShow);
  // Sessions 1..17 have ended; 16 are remembered, so the oldest, 1, has been forgotten.
  EXPECT_EQ(rules.check(2, 9).verdict, kReplay);
  EXPECT_EQ(rules.check(SequenceRules::kRetiredSessions, 9).verdict, kReplay);
  EXPECT_EQ(rules.check(1, 9).verdict, kShow);
}

TEST(SequenceRules, V2ShowsEverythingAndCountsOnlyForwardGaps) {
  run(WireVersion::kV2, {{0, 5, kShow, 0, true},
                         {0, 5, kShow, 0, false},
                         {0, 1, kShow, 0, false},  // a host numbering from 1 again
                         {0, 4, kShow, 2, false}});
}

TEST(Numbering, NumbersEachStampedWorldAndMovesToTheNextSessionBeforeWrapping) {
  World w;
  std::vector<std::uint8_t> bytes = encode_frame(WireVersion::kV3, w);
  Numbering n(WireVersion::kV3, 5);
  EXPECT_EQ(n.last_sequence(), 0u);
  n.stamp(bytes);
  n.stamp(bytes);
  auto back = decode_frame(WireVersion::kV3, bytes, 1);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value().session, 5u);
  EXPECT_EQ(back.value().sequence, 2u);
  EXPECT_THROW(Numbering(WireVersion::kV3, 0), std::invalid_argument);
  EXPECT_NE(random_session(), 0u);
}

TEST(Numbering, LeavesV1WordsAlone) {
  std::vector<std::uint8_t> word = {1, 2, 3, 4, 5, 6, 7, 8};
  Numbering n(WireVersion::kV1, 0);
  n.stamp(word);
  EXPECT_EQ(word, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

}  // namespace
}  // namespace tripsitter::link
