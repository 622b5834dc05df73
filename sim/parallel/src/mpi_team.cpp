// The MPI job as a Team (built with TOCD_WITH_MPI). MPI starts only when a launcher started
// this process, so the same binary still runs alone, without mpirun.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <mpi.h>

#include "tocd/sim/parallel/team.hpp"

namespace tocd::sim::parallel {
namespace {

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string("MPI ") + what + ": " +
                           std::string(text, static_cast<std::size_t>(len)));
}

class MpiTeam final : public Team {
 public:
  MpiTeam() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    // Errors come back as codes (and become exceptions) instead of killing the job
    // silently, so the message names what failed before the job is aborted.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  }
  int rank() const noexcept override { return rank_; }
  int size() const noexcept override { return size_; }
  void sum(std::span<std::int64_t> words) override {
    // MPI counts are int: large tallies go in pieces of at most 2^30 words.
    constexpr std::size_t kPiece = std::size_t{1} << 30;
    for (std::size_t at = 0; at < words.size(); at += kPiece) {
      const auto n = static_cast<int>(std::min(kPiece, words.size() - at));
      check(MPI_Allreduce(MPI_IN_PLACE, words.data() + at, n, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD),
            "sum of tallies");
    }
  }
  void broadcast(std::vector<std::int64_t>& words, int root) override {
    std::int64_t n = static_cast<std::int64_t>(words.size());
    check(MPI_Bcast(&n, 1, MPI_INT64_T, root, MPI_COMM_WORLD), "broadcast size");
    words.resize(static_cast<std::size_t>(n));
    check(MPI_Bcast(words.data(), static_cast<int>(n), MPI_INT64_T, root, MPI_COMM_WORLD), "broadcast");
  }
  void send(int to, int tag, std::span<const std::int64_t> words) override {
    check(MPI_Send(words.data(), static_cast<int>(words.size()), MPI_INT64_T, to, tag, MPI_COMM_WORLD),
          "send");
  }
  Message receive(int from, int tag) override {
    MPI_Status status;
    // Probe, then receive exactly the probed message (matched probe: safe with two threads).
    MPI_Message handle;
    check(MPI_Mprobe(from < 0 ? MPI_ANY_SOURCE : from, tag < 0 ? MPI_ANY_TAG : tag, MPI_COMM_WORLD, &handle,
                     &status),
          "probe");
    int count = 0;
    MPI_Get_count(&status, MPI_INT64_T, &count);
    Message m{status.MPI_SOURCE, status.MPI_TAG, std::vector<std::int64_t>(static_cast<std::size_t>(count))};
    check(MPI_Mrecv(m.words.data(), count, MPI_INT64_T, &handle, &status), "receive");
    return m;
  }
  void abort(int status) noexcept override { MPI_Abort(MPI_COMM_WORLD, status); }

 private:
  int rank_ = 0, size_ = 1;
};

bool started_by_launcher() {
  // Open MPI's mpirun, PMIx launchers (srun --mpi=pmix) and PMI-1/2 launchers set these.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

bool started_here = false;

}  // namespace

Team& world() {
  static Team* team = nullptr;
  if (team) return *team;
  if (!started_by_launcher()) return *(team = &solo());
  int provided = 0;
  // The study's dispatcher thread on rank 0 receives while the rank's own worker sends.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided);
  started_here = true;
  if (provided < MPI_THREAD_MULTIPLE) {
    std::fputs("tocdlab: error: this MPI library does not support MPI_THREAD_MULTIPLE\n", stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  static MpiTeam mpi;
  return *(team = &mpi);
}

void finish_world() noexcept {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (started_here && !finalized) MPI_Finalize();
}

bool built_with_mpi() noexcept {
  return true;
}

}  // namespace tocd::sim::parallel
