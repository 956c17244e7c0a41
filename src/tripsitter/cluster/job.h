// The MPI job this process is one rank of (docs/mpi.md). MPI stays in this folder: the rest of TripSitter
// is built with or without it, and only the command's MPI mode uses cluster/.
#pragma once

namespace tripsitter::cluster {

// MPI initialised for the Job's lifetime, in MPI_COMM_WORLD. Only the thread that made the Job calls MPI
// (MPI_THREAD_FUNNELED); other threads may compute. At most one Job per process, ever.
class Job {
 public:
  // Throws std::runtime_error when MPI cannot give funnelled threads.
  Job();
  // MPI_Finalize, which waits for every rank: destroy a Job only where every rank does.
  ~Job();
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  // Collective: every rank says whether it failed; all learn the lowest rank that did, or -1 if none did.
  int first_failed_rank(bool failed) const;

  // Stops every rank of the job at once (MPI_Abort); mpirun exits non-zero. For failures past the point
  // where ranks can agree, when the other ranks may be waiting for this one.
  [[noreturn]] void abort(int exit_code) const;

  // Test only: when the environment variable TRIPSITTER_MPI_TEST_KILL_RANK names this rank, the process
  // kills itself with SIGKILL here, as a rank that crashes or is killed mid-job would die. The shared
  // renders call it once a rank has done its first piece of work.
  void test_kill_point() const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool test_kill_ = false;
};

}  // namespace tripsitter::cluster
