// The processes a computation is spread over (issue 26): the reductions and the few collective
// moves of data that the minimisers and the slide make once the sites of a contact are
// distributed over ranks. core does not depend on MPI: this is the interface and its serial
// implementation (one process: every operation is the identity or a copy); fft/mpi_comm.hpp
// implements it on an MPI communicator. Every process of a Comm calls each operation together
// and in the same order (collective), as MPI's own collectives require.
#pragma once

#include <algorithm>
#include <cassert>
#include <span>
#include <vector>

namespace asperity::par {

class Comm {
 public:
  virtual ~Comm() = default;

  [[nodiscard]] virtual int rank() const { return 0; }
  [[nodiscard]] virtual int size() const { return 1; }
  [[nodiscard]] bool root() const { return rank() == 0; }
  [[nodiscard]] bool distributed() const { return size() > 1; }

  // Sum and largest value over the processes. The sum adds the processes' values in rank order
  // (so the result differs from a serial sum of the same terms by round-off only); a NaN on any
  // process makes max() NaN (as detail::max_abs of the minimisers promises serially).
  [[nodiscard]] virtual double sum(double local) const { return local; }
  [[nodiscard]] virtual double max(double local) const { return local; }
  [[nodiscard]] virtual long long sum(long long local) const { return local; }
  // Whether any process says yes: for decisions every process must take together (a checkpoint
  // that is due by one process's clock, a stop request, an early stop of a relaxation).
  [[nodiscard]] virtual bool any(bool local) const { return local; }
  // Every process's value, in rank order.
  [[nodiscard]] virtual std::vector<long long> all_gather(long long local) const { return {local}; }

  // The processes' `local` values concatenated in rank order, on the root (the others get an
  // empty vector), or on every process with to_all.
  [[nodiscard]] virtual std::vector<double> gather(std::span<const double> local,
                                                   bool to_all = false) const {
    (void)to_all;
    return {local.begin(), local.end()};
  }

  // The sum of every process's `partials`, added one by one in rank order and, within a
  // process, in their order: the same bits as a serial sum of the same partials in that order.
  // With partials per row of a block whose rows are spread over the processes in rank order, a
  // sum that does not depend on how many processes hold the rows (the minimisers' dot products
  // and the slide's forces and energies, issue 26).
  [[nodiscard]] double ordered_sum(std::span<const double> partials) const {
    double s = 0.0;
    if (!distributed()) {
      for (double v : partials)
        s += v;
      return s;
    }
    for (double v : gather(partials, true))
      s += v;
    return s;
  }

  // Personalised exchange: send holds, in rank order, send_counts[r] values for process r;
  // recv receives recv_counts[r] values from process r, in rank order.
  virtual void exchange(std::span<const double> send, std::span<const int> send_counts,
                        std::span<double> recv, std::span<const int> recv_counts) const {
    assert(send_counts.size() == 1 && recv_counts.size() == 1 && send_counts[0] == recv_counts[0]);
    (void)recv_counts;
    std::copy_n(send.begin(), send_counts[0], recv.begin());
  }
};

// The one process of a computation that is not distributed.
inline const Comm& serial() {
  static const Comm comm;
  return comm;
}

}  // namespace asperity::par
