// par::Comm (common/comm.hpp) on an MPI communicator (issue 26), in the MPI part of core
// (asperity::fft_mpi) beside the FFTW-MPI engine, so that the serial toolkit does not link MPI.
// The communicator is used as given (not duplicated); the caller keeps it valid and calls every
// operation on every rank together.
#pragma once

#include <mpi.h>

#include "asperity/core/common/comm.hpp"

namespace asperity::par {

class MpiComm final : public Comm {
 public:
  explicit MpiComm(MPI_Comm comm);

  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  [[nodiscard]] MPI_Comm handle() const { return comm_; }

  [[nodiscard]] double sum(double local) const override;
  [[nodiscard]] double max(double local) const override;
  [[nodiscard]] long long sum(long long local) const override;
  [[nodiscard]] bool any(bool local) const override;
  [[nodiscard]] std::vector<long long> all_gather(long long local) const override;
  [[nodiscard]] std::vector<double> gather(std::span<const double> local,
                                           bool to_all = false) const override;
  void exchange(std::span<const double> send, std::span<const int> send_counts,
                std::span<double> recv, std::span<const int> recv_counts) const override;

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

}  // namespace asperity::par
