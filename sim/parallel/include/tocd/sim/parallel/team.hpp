#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace tocd::sim::parallel {

/// The processes that share one computation: one process alone, or the ranks of an MPI job.
/// Every collective (sum, broadcast) must be called by every member in the same order.
/// Thread contract: a member's collectives are called from one thread; send / receive may
/// be called from two threads at once (the study's dispatcher and its worker) where the
/// implementation says so (MPI: started with MPI_THREAD_MULTIPLE).
class Team {
 public:
  virtual ~Team() = default;
  virtual int rank() const noexcept = 0;
  virtual int size() const noexcept = 0;

  /// Element-wise sum of `words` over every member; every member gets the total. Integer
  /// addition is exact, so the total does not depend on the order in which the members are
  /// combined: this is what keeps Monte Carlo tallies identical for any number of ranks.
  virtual void sum(std::span<std::int64_t> words) = 0;
  /// Copies `words` of member `root` to every member (resized on the receivers).
  virtual void broadcast(std::vector<std::int64_t>& words, int root) = 0;

  /// A message between two members: `tag` says what it is, the payload is 64-bit words.
  struct Message {
    int source = 0;
    int tag = 0;
    std::vector<std::int64_t> words;
  };
  virtual void send(int to, int tag, std::span<const std::int64_t> words) = 0;
  /// Blocks until a message with `tag` from `from` arrives (from < 0: from anyone; tag < 0:
  /// any tag) and returns it.
  virtual Message receive(int from, int tag) = 0;

  /// Ends the whole job at once with `status` (a failed member must not leave the others
  /// waiting in a collective). For a team of one, returns and lets the caller exit.
  virtual void abort(int status) noexcept = 0;
};

/// A team of one process: sums and broadcasts change nothing; messages go to itself.
Team& solo();

/// The team of this process's MPI job when the program was started by an MPI launcher
/// (mpirun, mpiexec, srun) and built with TOCD_WITH_MPI; otherwise solo(). Starts MPI on
/// first use; finish_world() ends it.
Team& world();
/// Ends MPI if world() started it (call once, before returning from main).
void finish_world() noexcept;
/// True when this build has MPI (TOCD_WITH_MPI).
bool built_with_mpi() noexcept;

}  // namespace tocd::sim::parallel
