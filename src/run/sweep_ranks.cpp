// SPDX-License-Identifier: GPL-2.0-or-later
// The ranks of `mbsc sweep` (include/mbsc/run/sweep_ranks.hpp). With MBSC_HAVE_MPI the
// MPI ranks of a launch; MPI is entered only when a launcher started this process, so the
// same binary runs alone without mpirun. A message travels as bytes with its kind as the
// tag: Ask (the count, 8 bytes), Rows (1 byte `end`, then 8 bytes per row), Line (the row,
// 8 bytes; 1 byte `failed`; the text) and Done (1 byte `stopped`).
#include "mbsc/run/sweep_ranks.hpp"

#include <cstdlib>
#include <cstring>
#include <deque>

#ifdef MBSC_HAVE_MPI
#include <mpi.h>
#endif

namespace mbsc::run {

#ifdef MBSC_HAVE_MPI
namespace {

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

class Bytes {
 public:
  void put(const void* data, std::size_t n) {
    const auto* p = static_cast<const char*>(data);
    bytes_.insert(bytes_.end(), p, p + n);
  }
  void put_long(long v) { put(&v, sizeof v); }
  void put_flag(bool v) { bytes_.push_back(v ? 1 : 0); }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& bytes) : bytes_(bytes) {}
  std::size_t left() const { return bytes_.size() - at_; }
  long take_long() {
    long v = 0;
    if (left() >= sizeof v) std::memcpy(&v, bytes_.data() + at_, sizeof v), at_ += sizeof v;
    return v;
  }
  bool take_flag() { return left() >= 1 && bytes_[at_++] != 0; }
  std::string take_rest() {
    std::string s(bytes_.data() + at_, left());
    at_ = bytes_.size();
    return s;
  }

 private:
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

class MpiRanks final : public SweepRanks {
 public:
  MpiRanks() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiRanks() override {
    for (Sending& s : sending_) MPI_Wait(&s.request, MPI_STATUS_IGNORE);
    MPI_Finalize();
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void barrier() override { MPI_Barrier(MPI_COMM_WORLD); }
  long broadcast(long value) override {
    long v = value;
    MPI_Bcast(&v, 1, MPI_LONG, 0, MPI_COMM_WORLD);
    return v;
  }
  long all_min(long value) override {
    long v = value, smallest = value;
    MPI_Allreduce(&v, &smallest, 1, MPI_LONG, MPI_MIN, MPI_COMM_WORLD);
    return smallest;
  }
  void send(const SweepMessage& m) override {
    Bytes b;
    switch (m.kind) {
      case SweepMessage::Kind::Ask: b.put_long(m.count); break;
      case SweepMessage::Kind::Rows:
        b.put_flag(m.end);
        for (long r : m.rows) b.put_long(r);
        break;
      case SweepMessage::Kind::Line:
        b.put_long(m.row);
        b.put_flag(m.failed);
        b.put(m.line.data(), m.line.size());
        break;
      case SweepMessage::Kind::Done: b.put_flag(m.stopped); break;
    }
    // Sent without waiting (a blocking send can wait for the receiver to look); the
    // buffer lives until MPI is done with it.
    sending_.push_back({MPI_REQUEST_NULL, std::move(b.bytes())});
    Sending& last = sending_.back();
    MPI_Isend(last.bytes.data(), static_cast<int>(last.bytes.size()), MPI_BYTE, m.peer, static_cast<int>(m.kind),
              MPI_COMM_WORLD, &last.request);
    forget_sent();
  }
  bool poll(SweepMessage& m) override {
    forget_sent();
    int waiting = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
    if (!waiting) return false;
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::vector<char> bytes(static_cast<std::size_t>(count));
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    m = SweepMessage();
    m.kind = static_cast<SweepMessage::Kind>(status.MPI_TAG);
    m.peer = status.MPI_SOURCE;
    Reader in(bytes);
    switch (m.kind) {
      case SweepMessage::Kind::Ask: m.count = in.take_long(); break;
      case SweepMessage::Kind::Rows:
        m.end = in.take_flag();
        while (in.left() >= sizeof(long)) m.rows.push_back(in.take_long());
        break;
      case SweepMessage::Kind::Line:
        m.row = in.take_long();
        m.failed = in.take_flag();
        m.line = in.take_rest();
        break;
      case SweepMessage::Kind::Done: m.stopped = in.take_flag(); break;
    }
    return true;
  }

 private:
  struct Sending {
    MPI_Request request;
    std::vector<char> bytes;
  };
  /// Drops the sends MPI has finished with, oldest first.
  void forget_sent() {
    while (!sending_.empty()) {
      int finished = 0;
      MPI_Test(&sending_.front().request, &finished, MPI_STATUS_IGNORE);
      if (!finished) return;
      sending_.pop_front();
    }
  }

  int rank_ = 0, size_ = 1;
  std::deque<Sending> sending_;
};

}  // namespace

std::unique_ptr<SweepRanks> sweep_ranks(std::string& why) {
  why.clear();
  if (!launched_by_mpi()) return std::make_unique<SweepRanks>();
  return std::make_unique<MpiRanks>();
}

#else

std::unique_ptr<SweepRanks> sweep_ranks(std::string& why) {
  why.clear();
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* size = std::getenv(name); size != nullptr && std::atoi(size) > 1)
      why = "this mbsc was built without MPI (MBSC_MPI=OFF, or no MPI found when it was built), but an MPI launcher "
            "started several copies of it; run it without mpirun, or build it with Debian's libopenmpi-dev";
  return std::make_unique<SweepRanks>();
}

#endif

}  // namespace mbsc::run
