// The frame memory part's model (frame_dram.h) against timings worked out by hand from the part's rules, and the
// frame's traffic through it.
#include <tripsitter/device/frame_dram.h>

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::device::dram {
namespace {

constexpr std::int64_t kRow1Bank0 = std::int64_t{1024} * 8 * 2;  // word 8192: bank 0's next row

TEST(FrameDram, AReadFromIdleActivatesItsRow) {
  Controller m;
  // ACTIVATE at 0, READ at tRCD = 5, data from 5 + CL = 10 for 4 clocks.
  EXPECT_EQ(m.issue(Op::kRead, 0), 14);
  EXPECT_EQ(m.counts().activates, 1);
  // The next burst of the open row: READ at 5 + tCCD, its data right behind the first's.
  EXPECT_EQ(m.issue(Op::kRead, 16), 18);
  EXPECT_EQ(m.counts().activates, 1);
}

TEST(FrameDram, TheBusTurnsAroundBetweenReadsAndWrites) {
  Controller m;
  ASSERT_EQ(m.issue(Op::kRead, 0), 14);  // READ at 5
  // WRITE no sooner than READ + CL + tCCD + 2 - CWL = 11: its data at 16..20, two clocks after the read's.
  EXPECT_EQ(m.issue(Op::kWrite, 16), 20);
  // READ no sooner than the write's last data + tWTR: 11 + CWL + 4 + 4 = 24.
  EXPECT_EQ(m.issue(Op::kRead, 32), 33);
  EXPECT_EQ(m.counts().turnarounds, 2);
}

TEST(FrameDram, AnotherRowOfTheBankWaitsForPrechargeAndActivate) {
  Controller m;
  ASSERT_EQ(m.issue(Op::kRead, 0), 14);  // ACTIVATE at 0, READ at 5
  // PRECHARGE at tRAS = 12 (READ + tRTP = 9 is sooner), ACTIVATE at tRC = 17, READ at 22.
  EXPECT_EQ(m.issue(Op::kRead, kRow1Bank0), 31);
  EXPECT_EQ(m.counts().precharges, 1);
  EXPECT_EQ(m.counts().activates, 2);
}

TEST(FrameDram, OtherBanksOpenWithoutClosingTheFirst) {
  Controller m;
  ASSERT_EQ(m.issue(Op::kRead, 0), 14);
  // Bank 1 (word 1024), in order: ACTIVATE in the command slot after bank 0's READ (6; tRRD ended at 4), READ
  // tRCD later at 11.
  EXPECT_EQ(m.issue(Op::kRead, 2048), 20);
  EXPECT_EQ(m.counts().precharges, 0);
}

TEST(FrameDram, RefreshComesEveryRefiAndBlocksForRfc) {
  Controller m;
  const Timing t = m.timing();
  // A request after the first refresh is due: REFRESH at tREFI, then ACTIVATE tRFC later.
  EXPECT_EQ(m.issue(Op::kRead, 0, t.refi), t.refi + t.rfc + t.rcd + t.cl + t.burst);
  EXPECT_EQ(m.counts().refreshes, 1);
  // Open banks are closed first: with bank 0 open, the next refresh precharges it.
  EXPECT_EQ(m.issue(Op::kRead, 0, 2 * t.refi), 2 * t.refi + t.rp + t.rfc + t.rcd + t.cl + t.burst);
  EXPECT_EQ(m.counts().refreshes, 2);
  EXPECT_EQ(m.counts().precharges, 1);
}

TEST(FrameDram, RefusesAnAddressThatIsNotABurstOfThePart) {
  Controller m;
  EXPECT_THROW(m.issue(Op::kRead, 8), std::invalid_argument);
  EXPECT_THROW(m.issue(Op::kRead, -16), std::invalid_argument);
  EXPECT_THROW(m.issue(Op::kWrite, m.geometry().bytes()), std::invalid_argument);
  EXPECT_EQ(m.counts().reads + m.counts().writes, 0);
}

// A line period's requests: the reads of line i + 2 and the writes of line i - 1 in runs of 32 bursts, reads first;
// near the frame's edges one side or none.
TEST(FrameDram, ALinePeriodReadsTwoLinesAheadAndWritesOneBehind) {
  const std::vector<Request> both = line_requests(1);
  ASSERT_EQ(both.size(), 640u);
  EXPECT_EQ(both[0], (Request{Op::kRead, 3 * 5120}));
  EXPECT_EQ(both[31], (Request{Op::kRead, 3 * 5120 + 31 * 16}));
  EXPECT_EQ(both[32], (Request{Op::kWrite, 0}));
  EXPECT_EQ(both[64], (Request{Op::kRead, 3 * 5120 + 32 * 16}));
  EXPECT_EQ(both.back(), (Request{Op::kWrite, 319 * 16}));
  EXPECT_EQ(line_requests(0).size(), 320u);  // line 2's reads
  EXPECT_EQ(line_requests(480).size(), 320u);  // line 479's writes
  EXPECT_EQ(line_requests(480)[0], (Request{Op::kWrite, 479 * 5120}));
  EXPECT_TRUE(line_requests(500).empty());
  EXPECT_EQ(line_requests(523)[0], (Request{Op::kRead, 0}));  // the next frame's first line, two periods ahead
  const std::vector<Request> ones = line_requests(1, 64, 1);
  EXPECT_EQ(ones[1].op, Op::kWrite);
  EXPECT_THROW(line_requests(1, 64, 0), std::invalid_argument);
}

// Every entry read and written once a frame: 480 lines of 640 64-bit entries, 10,240 bytes a line period, a quarter
// of what the pins carry in it; the in-order controller takes well under the line's time on the worst line.
TEST(FrameDram, AFramesEntriesFitTheLinesWithRoomToSpare) {
  const LineTraffic f = frame_traffic(64, 32, 2);
  EXPECT_EQ(f.bytes_per_line, 10240);
  EXPECT_EQ(f.line_clocks, 10399);  // 32 us at 3,077 ps
  EXPECT_EQ(f.peak_bytes_per_line, 4 * 10399);
  EXPECT_NEAR(f.demand(), 0.246, 0.001);
  EXPECT_EQ(f.counts.reads, 2 * 480 * 320);
  EXPECT_EQ(f.counts.writes, 2 * 480 * 320);
  EXPECT_GE(f.worst_clocks, 640 * 4);  // the data clocks alone
  EXPECT_LT(f.busy(), 0.8);
  // Refresh keeps its pace over the two frames' 1,050 line periods (but for those due after the last request, which
  // the controller has not yet issued: the last line period's).
  EXPECT_NEAR(static_cast<double>(f.counts.refreshes), 1050.0 * 10399 / 2535, 5.0);
}

// Turning the bus around every burst costs: runs of one burst take longer than runs of 32.
TEST(FrameDram, ShortRunsCostTurnarounds) {
  const LineTraffic one = frame_traffic(64, 1, 1);
  const LineTraffic runs = frame_traffic(64, 32, 1);
  EXPECT_GT(one.counts.turnarounds, 10 * runs.counts.turnarounds);
  EXPECT_GT(one.worst_clocks, runs.worst_clocks);
  EXPECT_THROW(frame_traffic(48), std::invalid_argument);
  EXPECT_THROW(frame_traffic(64, 0), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::device::dram
