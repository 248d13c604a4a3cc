// The points of a sweep (friction_sweep) or a scan (peierls_scan) handed to the processes of an
// MPI job (issue 26, part 3): `mpirun -np N tool ...` runs each point on one rank with the serial
// code, so every point's numbers, and the table, are those of the serial tool, bit for bit. One
// contact is not distributed here (that is the FFTW-MPI engine's part, core/fft).
//
// The roles. Rank 0 does what the serial tool does before and after its points: it locks the
// output directory, reads what an earlier run left, plans, writes the table as rows come in, and
// writes the summary and the figures. Every rank, rank 0 too, runs points on its own threads
// (the tool's `jobs`), each thread asking rank 0 for the next point when it is free: a queue in
// the tool's order, so that points of unequal cost balance. A point writes its own folder as in
// a serial run (the ranks share the file system), and its row goes to rank 0 as bytes
// (ByteWriter). Only rank 0 writes to standard output.
//
// Without an MPI launcher, or in a build without MPI (ASPERITY_MPI=OFF), there is one process,
// MPI is not started (a singleton MPI_Init costs 0.4 s and a daemon), and a tool runs exactly as
// it always did, its points on its threads.
//
// Errors. A rank's error before the points (bad input, a locked directory, another scene on
// another host) ends every rank with that error's status; rank 0 prints its message once. A
// point's exception stops the handing out, the points in flight on every rank finish and are
// recorded, and rank 0 ends with the message (as the serial tool). Every rank exits with rank
// 0's status, after rank 0 has written everything. Anything else (a rank that dies, an MPI
// error) aborts the whole job: no rank waits for ever.
//
// Stopping. mpirun answers SIGINT and SIGTERM by killing the ranks a second later, too soon for a
// checkpoint (the last timed one stands); SIGUSR1, which it forwards to every rank, stops a sweep
// over ranks as SIGINT stops a serial one: no new points, the points in flight checkpoint, exit
// status 3 (`kill -USR1 <pid of mpirun>`). A rank that is stopped alone stops all.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "asperity/apps/common/output_files.hpp"

namespace asperity::app {

// A result as bytes for another rank: numbers bit for bit (NaN and its payload, -0.0), strings
// with their length (any bytes), table cells with their type.
class ByteWriter {
 public:
  ByteWriter& real(double v);
  ByteWriter& integer(std::int64_t v);
  ByteWriter& text(std::string_view v);
  ByteWriter& cell(const CsvTable::Cell& v);
  [[nodiscard]] const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

// Reads what a ByteWriter wrote, in the same order; throws std::runtime_error if the bytes end
// early or (finish()) go on.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  double real();
  std::int64_t integer();
  std::string text();
  CsvTable::Cell cell();
  void finish() const;

 private:
  std::string_view take(std::size_t n);
  std::string_view bytes_;
};

// The processes of a run.
class Ranks {
 public:
  // Starts MPI (threads: funnelled, only this thread calls it) if the build has MPI and an MPI
  // launcher started this process (mpirun, mpiexec, srun: OMPI_COMM_WORLD_SIZE, PMI_SIZE or
  // PMIX_RANK in the environment); otherwise, and under `mpirun -np 1`, one process. Over
  // ranks, the ranks other than 0 send their standard output to /dev/null, and SIGUSR1 stops
  // the run (install_stop_handler).
  Ranks(int& argc, char**& argv);
  ~Ranks();
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] bool distributed() const { return size_ > 1; }
  [[nodiscard]] bool leader() const { return rank_ == 0; }
  // The ranks on this host (MPI_COMM_TYPE_SHARED); 1 for one process.
  [[nodiscard]] int ranks_on_host() const { return ranks_on_host_; }
  // Hardware threads for this rank's points: std::thread::hardware_concurrency() (0 if unknown)
  // for one process, as the serial tools use it; over ranks, the host's shared among its ranks,
  // and no more than the cores the rank is bound to (at least 1).
  [[nodiscard]] int hardware_threads() const;

  // The end of the set-up, on every rank (nothing on one process). `agreement`: what every rank
  // must have read alike (the settings fingerprint and the number of points): a rank that differs
  // from rank 0 is an error (status 2: another scene or build on another host). Returns when every
  // rank got here; if a rank failed before (its exception reached run_main_over_ranks) or
  // returned early, the others end with its status (RanksEnded).
  void start(const std::string& agreement);

  // Runs the points `ids` (rank 0's list, handed out in this order; the other ranks pass any
  // list, unused) on `jobs` threads of every rank: run(id) computes a point on the rank that
  // took it and returns its row as bytes (ByteWriter), or nothing if it was interrupted (a
  // stop); record(id, row, rank) is called on rank 0 only, for every row of every rank, with the
  // rank that computed it (from several threads: it must lock). The handing out ends when every
  // point is taken, `stop` is set on rank 0 (by record: its table could not be written), a stop is
  // requested on any rank (stop_requested(), propagated to all), or a point threw. Then the points
  // in flight finish; the first exception a point let out, on any rank, is rethrown on rank 0 (its
  // rank named); on the other ranks the call returns. Returns the points that returned no row
  // (interrupted), over every rank, on rank 0. One process: app::run_points (point_runner.hpp).
  std::size_t run_points(const std::vector<std::size_t>& ids, int jobs,
                         const std::function<std::optional<std::string>(std::size_t)>& run,
                         const std::function<void(std::size_t, std::string_view, int)>& record,
                         std::atomic<bool>& stop);

  // Used by run_main_over_ranks: where the run is; the tool's name in messages.
  enum class Phase { setup, points, done };
  [[nodiscard]] const std::string& program() const { return program_; }
  [[nodiscard]] Phase phase() const { return phase_; }
  // A rank that ends before start(): its status (0: an early return, as after --help) and its
  // message (printed by rank 0 if this is the first rank that failed); returns the status every
  // rank ends with.
  int end_before_start(int status, const std::string& lines);
  // After the points: rank 0 sends its exit status to every rank, the others wait for it and
  // return it.
  int finish(int status);
  // Ends every rank at once (MPI_Abort), after `lines` are printed.
  [[noreturn]] void abort(int status, const std::string& lines);

 private:
  struct Comm;  // this run's communicator (a duplicate of MPI_COMM_WORLD)

  // The set-up's collective: each rank's status (-1: go on); if one is not -1, rank 0 prints the
  // lines of the first failed rank (of the first that ended early if none failed) and every
  // rank returns its status. Then, if every rank goes on, rank 0's `agreement` against each
  // rank's (status 2 if one differs); -1: go on.
  int agree(int status, const std::string& lines, const std::string& agreement);
  std::size_t lead_points(const std::vector<std::size_t>& ids, int jobs,
                          const std::function<std::optional<std::string>(std::size_t)>& run,
                          const std::function<void(std::size_t, std::string_view, int)>& record,
                          std::atomic<bool>& stop);
  void follow_points(int jobs, const std::function<std::optional<std::string>(std::size_t)>& run);

  std::string program_;  // for messages: the tool's name
  int rank_ = 0, size_ = 1, ranks_on_host_ = 1;
  Phase phase_ = Phase::setup;
  std::unique_ptr<Comm> comm_;  // null: MPI not started
};

// Ends the ranks of a run whose set-up failed on some rank: the status every rank exits with.
struct RanksEnded {
  int status = 0;
};

// run_main (cli.hpp) for a tool whose points may run over ranks: body(argc, argv, ranks). One
// process: run_main's behaviour exactly. Over ranks: an error before Ranks::start() ends every
// rank (its message printed once, by rank 0); after the points, rank 0's exit status is every
// rank's; an error between start() and the end of the points aborts the job.
int run_main_over_ranks(int argc, char** argv, const std::function<int(int, char**, Ranks&)>& body);

}  // namespace asperity::app
