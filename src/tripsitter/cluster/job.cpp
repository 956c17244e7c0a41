#include <tripsitter/cluster/job.h>

#include <mpi.h>

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace tripsitter::cluster {

Job::Job() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error("MPI does not support funnelled threads (MPI_THREAD_FUNNELED)");
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  const char* kill_rank = std::getenv("TRIPSITTER_MPI_TEST_KILL_RANK");
  test_kill_ = kill_rank != nullptr && std::string(kill_rank) == std::to_string(rank_);
}

Job::~Job() { MPI_Finalize(); }

int Job::first_failed_rank(bool failed) const {
  const int mine = failed ? rank_ : size_;
  int lowest = size_;
  MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return lowest < size_ ? lowest : -1;
}

void Job::abort(int exit_code) const {
  MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::_Exit(exit_code);  // MPI_Abort does not return; this only tells the compiler so
}

void Job::test_kill_point() const {
  if (test_kill_) std::raise(SIGKILL);
}

}  // namespace tripsitter::cluster
