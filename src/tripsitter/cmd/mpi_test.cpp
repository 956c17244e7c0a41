// render under Open MPI's mpirun on loopback (docs/mpi.md): the same bytes on 1, 2 and 4 ranks as without
// mpirun, one message for bad input, and a job that loses a rank fails without writing its output.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "command_test_util.h"

namespace {

namespace fs = std::filesystem;

const std::string kMpiexec = TRIPSITTER_MPIEXEC;  // empty in builds without MPI

using tripsitter::cmd::test::Result;
using tripsitter::cmd::test::slurp;

std::size_t count(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

// "r2_", 1, ".png" is "r2_1.png" (appended: GCC 12 warns falsely on "literal" + std::to_string(n)).
std::string numbered(std::string prefix, int n, const std::string& suffix) {
  prefix += std::to_string(n);
  prefix += suffix;
  return prefix;
}

class Mpi : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = tripsitter::cmd::test::scratch_dir("tripsitter_mpi_"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs `command` (shell words) with stdout and stderr kept apart from the files the test looks at.
  Result shell(const std::string& command) const {
    return tripsitter::cmd::test::run_shell(command + " </dev/null", dir_ / "log");
  }

  // tripsitter without mpirun.
  Result run(const std::string& args) const { return shell(std::string(TRIPSITTER_BIN) + " " + args); }

  // tripsitter on `ranks` ranks of one mpirun job on this machine. Open MPI refuses root without the two
  // variables (CI may run as root); --oversubscribe lets 4 ranks run on 2 cores.
  Result mpirun(int ranks, const std::string& args, const std::string& env = "") const {
    return shell("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + env + " " + kMpiexec + " -np " +
                 std::to_string(ranks) + " --oversubscribe " + TRIPSITTER_BIN + " " + args);
  }

  // The files the job left, log aside.
  std::vector<std::string> outputs() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename() != "log") names.push_back(entry.path().filename().string());
    return names;
  }

  fs::path dir_;
};

class MpiJob : public Mpi {
 protected:
  void SetUp() override {
    if (kMpiexec.empty()) GTEST_SKIP() << "built without MPI (not found, or TRIPSITTER_WITH_MPI=OFF): no MPI mode to test";
    Mpi::SetUp();
  }
};

// A small path-traced still: 37 rows, so no rank count used here divides them evenly.
const std::string kStill = "render --scene field --mode path --width 48 --height 37 --spp 4 --depth 8 --seed 7 --quiet";
const std::string kAnimation = kStill + " --frames 4 --orbit 90";

TEST_F(MpiJob, AStillIsTheSameBytesOnOneTwoAndFourRanksAsWithoutMpirun) {
  const Result plain = run(kStill + " --out " + path("plain.png"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const std::string expected = slurp(path("plain.png"));
  ASSERT_FALSE(expected.empty());
  for (const int ranks : {1, 2, 4}) {
    for (const int threads : {1, 2}) {
      const std::string out = path(numbered(numbered("r", ranks, "_t"), threads, ".png"));
      const Result r = mpirun(ranks, kStill + " --threads " + std::to_string(threads) + " --out " + out);
      ASSERT_EQ(r.exit_code, 0) << ranks << " ranks\n" << r.err;
      EXPECT_EQ(slurp(out), expected) << ranks << " ranks, " << threads << " threads";
      EXPECT_EQ(count(r.err, "wrote "), 1u) << "rank 0 alone writes\n" << r.err;
    }
  }
}

TEST_F(MpiJob, AnAnimationIsTheSameBytesOnOneTwoAndFourRanksAsWithoutMpirun) {
  const Result plain = run(kAnimation + " --out " + path("plain_%d.png"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  for (const int ranks : {1, 2, 4}) {
    const std::string pattern = numbered("r", ranks, "_%d.png");
    const Result r = mpirun(ranks, kAnimation + " --out " + path(pattern));
    ASSERT_EQ(r.exit_code, 0) << ranks << " ranks\n" << r.err;
    const std::string on = ranks == 1 ? "wrote 4 frames on 1 MPI rank" : "wrote 4 frames on " + std::to_string(ranks) + " MPI ranks";
    EXPECT_NE(r.err.find(on), std::string::npos) << r.err;
    for (int frame = 0; frame < 4; ++frame) {
      const std::string expected = slurp(path(numbered("plain_", frame, ".png")));
      ASSERT_FALSE(expected.empty());
      EXPECT_EQ(slurp(path(numbered(numbered("r", ranks, "_"), frame, ".png"))), expected)
          << ranks << " ranks, frame " << frame;
    }
  }
}

// The feature buffers travel with the rows: the EXR (beauty and layers), the AOV pictures and the denoised
// picture, which needs them, are the same bytes on two ranks as without mpirun.
TEST_F(MpiJob, FeatureBuffersAndTheDenoisedStillAreTheSameBytesOnTwoRanks) {
  fs::create_directories(path("plain"));
  fs::create_directories(path("ranks"));
  const std::string args = kStill + " --threads 1 --denoise";
  const Result plain = run(args + " --out " + path("plain/still.exr") + " --aov " + path("plain"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const Result r = mpirun(2, args + " --out " + path("ranks/still.exr") + " --aov " + path("ranks"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"still.exr", "albedo.png", "normal.png", "depth.png"}) {
    const std::string expected = slurp(path(std::string("plain/") + name));
    ASSERT_FALSE(expected.empty()) << name;
    EXPECT_EQ(slurp(path(std::string("ranks/") + name)), expected) << name;
  }
}

TEST_F(MpiJob, AKilledRankFailsTheJobAndNothingIsWritten) {
  const Result r = mpirun(2, kStill + " --out " + path("still.png"), "TRIPSITTER_MPI_TEST_KILL_RANK=1");
  EXPECT_NE(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("mpirun stopped rank 0 before the job finished"), std::string::npos) << r.err;
  EXPECT_TRUE(outputs().empty()) << "left " << outputs().front();
}

TEST_F(MpiJob, AKilledRankStopsAnAnimationAtItsFirstFrame) {
  // Rank 1 dies with frame 1 rendered and not sent: frame 0 may be written, whole; nothing from frame 1 on.
  const Result r = mpirun(2, kAnimation + " --out " + path("f_%d.png"), "TRIPSITTER_MPI_TEST_KILL_RANK=1");
  EXPECT_NE(r.exit_code, 0) << r.err;
  for (const std::string& name : outputs()) EXPECT_EQ(name, "f_0.png");
}

TEST_F(MpiJob, BadInputStopsEveryRankWithOneMessageAndExitTwo) {
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"render --mode path --scene nosuchscene --out " + path("x.png"), "nosuchscene"},
      {"render --mode path --spp 4 --out " + path("no/such/dir/x.png"), "does not exist"},
      {"render --mode path --frames 2 --out " + path("x.png"), "%d"},
      {"render --mode path --frobnicate", "frobnicate"},
      {"render --mode hw --out " + path("x.png"), "only --mode path shares its work"},
  };
  for (const auto& c : cases) {
    const Result r = mpirun(2, c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(count(r.err, c.message), 1u) << c.args << "\n" << r.err;
    EXPECT_TRUE(outputs().empty()) << c.args;
  }
}

// Without mpirun's variables nothing changes; with them, a build without MPI refuses rather than letting
// every rank write the same file. Runs in every build.
TEST_F(Mpi, HelpTellsWhatMpirunDoesInThisBuild) {
  const Result help = run("render --help");
  ASSERT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("mpirun"), std::string::npos) << help.out;
  EXPECT_EQ(help.out.find("this build has none") == std::string::npos, !kMpiexec.empty()) << help.out;
}

TEST_F(Mpi, ABuildWithoutMpiRefusesToRunOnSeveralRanks) {
  if (!kMpiexec.empty()) GTEST_SKIP() << "this build has MPI";
  const Result r = shell("OMPI_COMM_WORLD_RANK=0 OMPI_COMM_WORLD_SIZE=2 " + std::string(TRIPSITTER_BIN) +
                         " render --mode path --quiet --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("built without MPI"), std::string::npos) << r.err;
  EXPECT_TRUE(outputs().empty());
}

}  // namespace
