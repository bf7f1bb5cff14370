// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The processes one `mbsc sweep` runs on (docs/sweep.md): this process alone (the
/// default), or the ranks of an MPI launch (`mpirun -n 64 mbsc sweep ...`, a Slurm job).
/// Under MPI rank 0 hands out rows in order to the ranks that ask for them, runs rows
/// itself, and writes the table; the other ranks send it their finished lines. Only the
/// main thread of a process calls these.
#include <memory>
#include <string>
#include <vector>

namespace mbsc::run {

/// One message between rank 0 and another rank.
struct SweepMessage {
  enum class Kind {
    Ask,   ///< to rank 0: `count` more rows wanted
    Rows,  ///< from rank 0, the answer to every Ask: `rows` to run (maybe none for now); `end`: no more will come
    Line,  ///< to rank 0: row `row` finished, its table line `line`, `failed` unless its status is ok
    Done,  ///< to rank 0: this rank sent all its lines; `stopped` when its budget ran out first
  };
  Kind kind = Kind::Ask;
  int peer = 0;  ///< the rank sent to, or the rank a polled message came from
  long count = 0;
  std::vector<long> rows;
  bool end = false;
  long row = 0;
  std::string line;
  bool failed = false;
  bool stopped = false;
};

class SweepRanks {
 public:
  virtual ~SweepRanks() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Returns once every rank has called it.
  virtual void barrier() {}
  /// Rank 0's value, on every rank.
  virtual long broadcast(long value) { return value; }
  /// The smallest of every rank's value, on every rank.
  virtual long all_min(long value) { return value; }
  /// Sends `message` to rank `message.peer`.
  virtual void send(const SweepMessage& message) { (void)message; }
  /// A message sent to this rank, if one is waiting (false when none is).
  virtual bool poll(SweepMessage& message) {
    (void)message;
    return false;
  }
};

/// The ranks of this process: MPI's when mbsc was built with MPI (MBSC_MPI) and an MPI
/// launcher started it (its environment says so: OMPI_COMM_WORLD_SIZE, PMI_SIZE or
/// PMIX_RANK), else this process alone. MPI is initialized here and finalized when the
/// object goes. `why` names a launch that this process cannot join (empty otherwise).
std::unique_ptr<SweepRanks> sweep_ranks(std::string& why);

}  // namespace mbsc::run
