// Points over MPI ranks (mpi_points.hpp): rank 0 keeps the queue and the table, every rank runs
// points on its threads. Only the main thread of a rank calls MPI (MPI_THREAD_FUNNELED); the
// point threads talk to it through a mutex. Waits poll (MPI_Iprobe, then a 5 ms sleep) instead
// of blocking in MPI, whose blocking calls spin a core: on a host whose cores all run points, a
// spinning rank 0 would take one from them.
#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/apps/common/mpi_session.hpp"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#ifdef ASPERITY_HAVE_MPI
#include <mpi.h>
#endif

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/point_runner.hpp"

namespace asperity::app {

// ---- bytes ----

ByteWriter& ByteWriter::real(double v) {
  char b[sizeof v];
  std::memcpy(b, &v, sizeof v);
  bytes_.append(b, sizeof b);
  return *this;
}

ByteWriter& ByteWriter::integer(std::int64_t v) {
  char b[sizeof v];
  std::memcpy(b, &v, sizeof v);
  bytes_.append(b, sizeof b);
  return *this;
}

ByteWriter& ByteWriter::text(std::string_view v) {
  integer(static_cast<std::int64_t>(v.size()));
  bytes_.append(v);
  return *this;
}

namespace {
// The type of a cell, before its value.
enum CellType : std::int64_t { kReal = 0, kInteger = 1, kText = 2 };
}  // namespace

ByteWriter& ByteWriter::cell(const CsvTable::Cell& v) {
  if (const auto* d = std::get_if<double>(&v)) return integer(kReal).real(*d);
  if (const auto* i = std::get_if<long long>(&v)) return integer(kInteger).integer(*i);
  return integer(kText).text(std::get<std::string>(v));
}

std::string_view ByteReader::take(std::size_t n) {
  if (bytes_.size() < n) throw std::runtime_error("a row from another rank ends early");
  const std::string_view out = bytes_.substr(0, n);
  bytes_.remove_prefix(n);
  return out;
}

double ByteReader::real() {
  double v = 0.0;
  std::memcpy(&v, take(sizeof v).data(), sizeof v);
  return v;
}

std::int64_t ByteReader::integer() {
  std::int64_t v = 0;
  std::memcpy(&v, take(sizeof v).data(), sizeof v);
  return v;
}

std::string ByteReader::text() {
  const std::int64_t n = integer();
  if (n < 0) throw std::runtime_error("a row from another rank has a negative length");
  return std::string(take(static_cast<std::size_t>(n)));
}

CsvTable::Cell ByteReader::cell() {
  switch (integer()) {
    case kReal:
      return real();
    case kInteger:
      return static_cast<long long>(integer());
    case kText:
      return text();
    default:
      throw std::runtime_error("a row from another rank has a cell of no known type");
  }
}

void ByteReader::finish() const {
  if (!bytes_.empty()) throw std::runtime_error("a row from another rank is longer than read");
}

// ---- ranks ----

#ifdef ASPERITY_HAVE_MPI

namespace {

constexpr auto kPollInterval = std::chrono::milliseconds(5);

// The messages of the points' protocol (tags). A rank other than 0 sends request (a thread is
// free), result (id, row), interrupted, skipped (taken after a stop, not run), error (status,
// message), stopped (a stop was requested here) and done; rank 0 answers a request with task (id)
// or none, sends stop when the run is stopped, and final (exit status) after its report.
namespace msg {
enum Tag : int {
  request = 1,
  task,
  none,
  result,
  interrupted,
  skipped,
  error,
  stopped,
  stop,
  done,
  final_status
};
}  // namespace msg
using msg::Tag;

// Started by an MPI launcher (mpi_session.hpp: the one test of the tools).
bool started_by_launcher() {
  return launcher_ranks() > 0;
}

// The status and message a point's exception ends a run with (run_main's mapping).
std::pair<int, std::string> error_of(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::invalid_argument& e) {
    return {2, e.what()};
  } catch (const std::exception& e) {
    return {1, e.what()};
  } catch (...) {
    return {1, "an exception of unknown type"};
  }
}

std::exception_ptr exception_of(int status, const std::string& message) {
  if (status == 2) return std::make_exception_ptr(std::invalid_argument(message));
  return std::make_exception_ptr(std::runtime_error(message));
}

}  // namespace

struct Ranks::Comm {
  MPI_Comm comm = MPI_COMM_NULL;

  void send(int to, Tag tag, std::string_view bytes = {}) const {
    MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, comm);
  }
  struct Message {
    int source = 0;
    int tag = 0;
    std::string bytes;
  };
  // The next message from `from` (MPI_ANY_SOURCE: anyone), if one has come.
  std::optional<Message> poll(int from) const {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(from, MPI_ANY_TAG, comm, &flag, &status);
    if (!flag) return std::nullopt;
    int n = 0;
    MPI_Get_count(&status, MPI_BYTE, &n);
    Message m{status.MPI_SOURCE, status.MPI_TAG, std::string(static_cast<std::size_t>(n), '\0')};
    MPI_Recv(m.bytes.data(), n, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, comm,
             MPI_STATUS_IGNORE);
    return m;
  }
  // Waits (polling) for the next message from `from`.
  Message wait(int from) const {
    for (;;) {
      if (auto m = poll(from)) return std::move(*m);
      std::this_thread::sleep_for(kPollInterval);
    }
  }
};

#else

struct Ranks::Comm {};

#endif

Ranks::Ranks(int& argc, char**& argv) {
  program_ = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "asperity";
#ifdef ASPERITY_HAVE_MPI
  if (!started_by_launcher()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  comm_ = std::make_unique<Comm>();
  MPI_Comm_dup(MPI_COMM_WORLD, &comm_->comm);
  MPI_Comm_rank(comm_->comm, &rank_);
  MPI_Comm_size(comm_->comm, &size_);
  if (provided < MPI_THREAD_FUNNELED) {
    abort(1, program_ +
                 ": error: the MPI library offers no thread support (MPI_THREAD_FUNNELED), "
                 "which the points' threads need\n");
  }
  MPI_Comm host = MPI_COMM_NULL;
  MPI_Comm_split_type(comm_->comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &host);
  MPI_Comm_size(host, &ranks_on_host_);
  MPI_Comm_free(&host);
  if (distributed()) {
    // Rank 0 prints what the serial tool prints (--help, --list-angles, the report) once.
    if (rank_ != 0 && std::freopen("/dev/null", "w", stdout) == nullptr) {
      std::fprintf(stderr, "%s: rank %d: cannot silence standard output\n", program_.c_str(),
                   rank_);
    }
    install_stop_handler(SIGUSR1);
  }
#endif
}

Ranks::~Ranks() {
#ifdef ASPERITY_HAVE_MPI
  if (comm_) {
    MPI_Comm_free(&comm_->comm);
    MPI_Finalize();
  }
#endif
}

int Ranks::hardware_threads() const {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  if (!distributed()) return hardware;
  int share = std::max(1, hardware / ranks_on_host_);
  // A rank that mpirun bound to fewer cores (Open MPI binds each of up to 2 ranks to one core)
  // runs no more threads than it has cores.
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  if (sched_getaffinity(0, sizeof cpus, &cpus) == 0) share = std::min(share, CPU_COUNT(&cpus));
  return std::max(1, share);
}

#ifdef ASPERITY_HAVE_MPI

int Ranks::agree(int status, const std::string& lines, const std::string& agreement) {
  std::vector<int> all(static_cast<std::size_t>(size_));
  MPI_Allgather(&status, 1, MPI_INT, all.data(), 1, MPI_INT, comm_->comm);
  // The first rank that failed, else the first that ended early (its status 0).
  auto ended = std::find_if(all.begin(), all.end(), [](int s) { return s > 0; });
  if (ended == all.end())
    ended = std::find_if(all.begin(), all.end(), [](int s) { return s >= 0; });
  if (ended != all.end()) {
    const int first = static_cast<int>(ended - all.begin());
    std::string message = lines;
    if (first != 0) {
      if (rank_ == first) comm_->send(0, msg::error, lines);
      if (rank_ == 0) message = comm_->wait(first).bytes;
    }
    if (rank_ == 0) std::cerr << message << std::flush;
    return *ended;
  }
  // Every rank got to start(): did each read what rank 0 read?
  std::int64_t n = static_cast<std::int64_t>(agreement.size());
  MPI_Bcast(&n, 1, MPI_INT64_T, 0, comm_->comm);
  std::string leader(static_cast<std::size_t>(n), '\0');
  if (rank_ == 0) leader = agreement;
  MPI_Bcast(leader.data(), static_cast<int>(n), MPI_BYTE, 0, comm_->comm);
  const int differs = leader != agreement ? 1 : 0;
  std::vector<int> each(static_cast<std::size_t>(size_));
  MPI_Allgather(&differs, 1, MPI_INT, each.data(), 1, MPI_INT, comm_->comm);
  const auto other = std::find(each.begin(), each.end(), 1);
  if (other == each.end()) return -1;
  if (rank_ == 0) {
    std::cerr << program_ << ": error: rank " << (other - each.begin())
              << " read other settings or points than rank 0 (another scene file or build on "
                 "its host?): every rank must run the same build on the same files\n"
              << std::flush;
  }
  return 2;
}

void Ranks::start(const std::string& agreement) {
  if (!distributed()) {
    phase_ = Phase::points;
    return;
  }
  const int end = agree(-1, "", agreement);
  if (end >= 0) throw RanksEnded{end};
  phase_ = Phase::points;
}

int Ranks::end_before_start(int status, const std::string& lines) {
  if (!distributed()) return status;
  return agree(status, lines, "");
}

int Ranks::finish(int status) {
  if (!distributed()) return status;
  if (leader()) {
    const std::string bytes = ByteWriter().integer(status).bytes();
    for (int r = 1; r < size_; ++r)
      comm_->send(r, msg::final_status, bytes);
    return status;
  }
  // A stop that rank 0 sent after this rank was done is left over: read and dropped.
  for (;;) {
    const auto m = comm_->wait(0);
    if (m.tag == msg::final_status) return static_cast<int>(ByteReader(m.bytes).integer());
  }
}

void Ranks::abort(int status, const std::string& lines) {
  std::cerr << lines << std::flush;
  if (comm_) MPI_Abort(MPI_COMM_WORLD, status);
  std::_Exit(status);  // MPI_Abort does not return
}

std::size_t Ranks::lead_points(
    const std::vector<std::size_t>& ids, int jobs,
    const std::function<std::optional<std::string>(std::size_t)>& run,
    const std::function<void(std::size_t, std::string_view, int)>& record,
    std::atomic<bool>& stop) {
  std::mutex queue_mutex;
  std::size_t next = 0;
  std::exception_ptr failure;  // the first point's exception, on any rank
  std::atomic<std::size_t> interrupted{0};
  const auto fail = [&](std::exception_ptr e) {
    const std::lock_guard lock(queue_mutex);
    if (!failure) failure = std::move(e);
  };
  // The next point to run, here or on another rank; none once every point is out, the sweep is
  // stopped or a point failed.
  const auto take = [&]() -> std::optional<std::size_t> {
    const std::lock_guard lock(queue_mutex);
    if (failure || stop || stop_requested() || next >= ids.size()) return std::nullopt;
    return ids[next++];
  };
  {
    std::vector<std::jthread> pool;
    for (int j = 0; j < std::max(jobs, 1); ++j) {
      pool.emplace_back([&] {
        while (const auto id = take()) {
          try {
            if (const auto row = run(*id)) {
              record(*id, *row, 0);
            } else {
              ++interrupted;
            }
          } catch (...) {
            fail(std::current_exception());
          }
        }
      });
    }
    int working = size_ - 1;  // ranks not yet done
    bool stop_sent = false;
    while (working > 0) {
      bool heard = false;
      while (auto m = comm_->poll(MPI_ANY_SOURCE)) {
        heard = true;
        try {
          ByteReader in(m->bytes);
          switch (m->tag) {
            case msg::request:
              if (const auto id = take()) {
                comm_->send(m->source, msg::task,
                            ByteWriter().integer(static_cast<std::int64_t>(*id)).bytes());
              } else {
                comm_->send(m->source, msg::none);
              }
              break;
            case msg::result: {
              const auto id = static_cast<std::size_t>(in.integer());
              const std::string row = in.text();
              in.finish();
              record(id, row, m->source);
              break;
            }
            case msg::interrupted:
              ++interrupted;
              break;
            case msg::error: {
              const int status = static_cast<int>(in.integer());
              fail(
                  exception_of(status, in.text() + " (on rank " + std::to_string(m->source) + ")"));
              break;
            }
            case msg::stopped:
              request_stop();  // sent on to every rank below
              break;
            case msg::done:
              --working;
              break;
            default:  // msg::skipped: the point stays for the next run
              break;
          }
        } catch (...) {
          fail(std::current_exception());
        }
      }
      if (stop_requested() && !stop_sent) {
        for (int r = 1; r < size_; ++r)
          comm_->send(r, msg::stop);
        stop_sent = true;
      }
      if (!heard) std::this_thread::sleep_for(kPollInterval);
    }
  }  // joins this rank's threads
  phase_ = Phase::done;
  if (failure) std::rethrow_exception(failure);
  return interrupted;
}

void Ranks::follow_points(int jobs,
                          const std::function<std::optional<std::string>(std::size_t)>& run) {
  struct Outcome {
    Tag tag;
    std::string bytes;
  };
  std::mutex mutex;
  std::condition_variable has_task, has_outcome;
  std::deque<std::size_t> tasks;
  std::deque<Outcome> outcomes;
  bool closing = false;
  const int threads = std::max(jobs, 1);
  {
    std::vector<std::jthread> pool;
    for (int j = 0; j < threads; ++j) {
      pool.emplace_back([&] {
        for (;;) {
          std::size_t id = 0;
          {
            std::unique_lock lock(mutex);
            has_task.wait(lock, [&] { return !tasks.empty() || closing; });
            if (tasks.empty()) return;
            id = tasks.front();
            tasks.pop_front();
          }
          Outcome o{msg::skipped, {}};
          if (!stop_requested()) {
            try {
              if (const auto row = run(id)) {
                o = {msg::result,
                     ByteWriter().integer(static_cast<std::int64_t>(id)).text(*row).bytes()};
              } else {
                o = {msg::interrupted, {}};
              }
            } catch (...) {
              const auto [status, message] = error_of(std::current_exception());
              o = {msg::error, ByteWriter().integer(status).text(message).bytes()};
            }
          }
          {
            const std::lock_guard lock(mutex);
            outcomes.push_back(std::move(o));
          }
          has_outcome.notify_one();
        }
      });
    }
    int requested = 0, busy = 0;  // requests not answered; points given to the threads
    bool no_more = false, told_stop = false;
    for (;;) {
      while (!no_more && !stop_requested() && busy + requested < threads) {
        comm_->send(0, msg::request);
        ++requested;
      }
      while (auto m = comm_->poll(0)) {
        if (m->tag == msg::task) {
          --requested;
          ++busy;
          {
            const std::lock_guard lock(mutex);
            tasks.push_back(static_cast<std::size_t>(ByteReader(m->bytes).integer()));
          }
          has_task.notify_one();
        } else if (m->tag == msg::none) {
          --requested;
          no_more = true;
        } else if (m->tag == msg::stop) {
          request_stop();
        }
      }
      std::deque<Outcome> out;
      {
        const std::lock_guard lock(mutex);
        out.swap(outcomes);
      }
      for (const Outcome& o : out) {
        comm_->send(0, o.tag, o.bytes);
        --busy;
      }
      if (stop_requested() && !told_stop) {
        comm_->send(0, msg::stopped);
        told_stop = true;
      }
      if ((no_more || stop_requested()) && requested == 0 && busy == 0) break;
      std::unique_lock lock(mutex);
      has_outcome.wait_for(lock, kPollInterval, [&] { return !outcomes.empty(); });
    }
    {
      const std::lock_guard lock(mutex);
      closing = true;
    }
    has_task.notify_all();
  }  // joins
  comm_->send(0, msg::done);
  phase_ = Phase::done;
}

#else

void Ranks::start(const std::string&) {
  phase_ = Phase::points;
}

int Ranks::end_before_start(int status, const std::string&) {
  return status;
}

int Ranks::finish(int status) {
  return status;
}

void Ranks::abort(int status, const std::string& lines) {
  std::cerr << lines << std::flush;
  std::_Exit(status);
}

#endif

std::size_t Ranks::run_points(const std::vector<std::size_t>& ids, int jobs,
                              const std::function<std::optional<std::string>(std::size_t)>& run,
                              const std::function<void(std::size_t, std::string_view, int)>& record,
                              std::atomic<bool>& stop) {
#ifdef ASPERITY_HAVE_MPI
  if (distributed()) {
    if (leader()) return lead_points(ids, jobs, run, record, stop);
    follow_points(jobs, run);
    return 0;
  }
#endif
  // One process: the serial pool, each row recorded by the thread that made it.
  std::atomic<std::size_t> interrupted{0};
  app::run_points(
      ids.size(), jobs,
      [&](std::size_t i) {
        if (const auto row = run(ids[i])) {
          record(ids[i], *row, 0);
        } else {
          ++interrupted;
        }
      },
      stop);
  phase_ = Phase::done;
  return interrupted;
}

int run_main_over_ranks(int argc, char** argv,
                        const std::function<int(int, char**, Ranks&)>& body) {
  Ranks ranks(argc, argv);
  if (!ranks.distributed()) {
    return run_main(argc, argv, [&](int argc_, char** argv_) { return body(argc_, argv_, ranks); });
  }
  // Messages of ranks other than 0 name their rank.
  const std::string program =
      ranks.leader() ? ranks.program()
                     : ranks.program() + " (rank " + std::to_string(ranks.rank()) + ")";
  int status = 0;
  std::string lines;
  bool failed = false;
  try {
    status = body(argc, argv, ranks);
  } catch (const RanksEnded& e) {
    return e.status;  // start() found a rank ended: printed, agreed
  } catch (const std::exception&) {
    failed = true;
    status = describe_error(program, std::current_exception(), lines);
  }
  switch (ranks.phase()) {
    case Ranks::Phase::setup:
      return ranks.end_before_start(status, lines);
    case Ranks::Phase::points:
      ranks.abort(failed ? status : 1,
                  failed ? lines : program + ": error: ended while the points were running\n");
    case Ranks::Phase::done:
      break;
  }
  if (failed && !ranks.leader()) ranks.abort(status, lines);
  if (failed) std::cerr << lines << std::flush;
  return ranks.finish(ranks.leader() ? status : 0);
}

}  // namespace asperity::app
