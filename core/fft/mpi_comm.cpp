// par::MpiComm: see mpi_comm.hpp.
#include "asperity/core/fft/mpi_comm.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace asperity::par {

namespace {

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Counts and their prefix sums as MPI wants them (int).
std::vector<int> displacements(std::span<const int> counts) {
  std::vector<int> d(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r)
    d[r] = d[r - 1] + counts[r - 1];
  return d;
}

}  // namespace

MpiComm::MpiComm(MPI_Comm comm) : comm_(comm) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) throw std::invalid_argument("par::MpiComm: MPI is not initialised");
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

double MpiComm::sum(double local) const {
  // Gathered and added in rank order on every rank, so that every rank gets the same bits
  // whatever reduction tree MPI_Allreduce would choose (its order is not specified, and ranks
  // that disagree in the last bit take different decisions).
  std::vector<double> all(static_cast<std::size_t>(size_));
  check(MPI_Allgather(&local, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, comm_), "Allgather");
  double s = 0.0;
  for (double v : all)
    s += v;
  return s;
}

double MpiComm::max(double local) const {
  // MPI_MAX on doubles compares with <, which loses a NaN; the NaN travels as a flag.
  double in[2] = {std::isnan(local) ? -std::numeric_limits<double>::infinity() : local,
                  std::isnan(local) ? 1.0 : 0.0};
  double out[2] = {0.0, 0.0};
  check(MPI_Allreduce(in, out, 2, MPI_DOUBLE, MPI_MAX, comm_), "Allreduce");
  return out[1] > 0.0 ? std::numeric_limits<double>::quiet_NaN() : out[0];
}

long long MpiComm::sum(long long local) const {
  long long out = 0;
  check(MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_SUM, comm_), "Allreduce");
  return out;
}

bool MpiComm::any(bool local) const {
  int in = local ? 1 : 0, out = 0;
  check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, comm_), "Allreduce");
  return out != 0;
}

std::vector<long long> MpiComm::all_gather(long long local) const {
  std::vector<long long> all(static_cast<std::size_t>(size_));
  check(MPI_Allgather(&local, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, comm_), "Allgather");
  return all;
}

std::vector<double> MpiComm::gather(std::span<const double> local, bool to_all) const {
  if (local.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("par::MpiComm::gather: more values per rank than MPI counts hold");
  const int count = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size_));
  check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_), "Allgather");
  const std::vector<int> at = displacements(counts);
  const long long total = std::accumulate(counts.begin(), counts.end(), 0LL);
  if (total > std::numeric_limits<int>::max())
    throw std::length_error("par::MpiComm::gather: more values than MPI counts hold");
  std::vector<double> out;
  if (to_all) {
    out.resize(static_cast<std::size_t>(total));
    check(MPI_Allgatherv(local.data(), count, MPI_DOUBLE, out.data(), counts.data(), at.data(),
                         MPI_DOUBLE, comm_),
          "Allgatherv");
  } else {
    if (rank_ == 0) out.resize(static_cast<std::size_t>(total));
    check(MPI_Gatherv(local.data(), count, MPI_DOUBLE, out.data(), counts.data(), at.data(),
                      MPI_DOUBLE, 0, comm_),
          "Gatherv");
  }
  return out;
}

void MpiComm::exchange(std::span<const double> send, std::span<const int> send_counts,
                       std::span<double> recv, std::span<const int> recv_counts) const {
  if (send_counts.size() != static_cast<std::size_t>(size_) ||
      recv_counts.size() != static_cast<std::size_t>(size_))
    throw std::invalid_argument("par::MpiComm::exchange: one count per rank wanted");
  const std::vector<int> sd = displacements(send_counts), rd = displacements(recv_counts);
  check(MPI_Alltoallv(send.data(), send_counts.data(), sd.data(), MPI_DOUBLE, recv.data(),
                      recv_counts.data(), rd.data(), MPI_DOUBLE, comm_),
        "Alltoallv");
}

}  // namespace asperity::par
