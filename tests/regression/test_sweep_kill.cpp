// Regression tier: a friction_sweep killed with SIGKILL at random points resumes to the same
// table as an uninterrupted run (issue 8, acceptance 2).
//
// The sweep (sweep_kill.toml, with --figures: tables, JSON, PNG and NetCDF files per point) runs
// once to the end (the reference, its duration T), then into a second folder that is killed
// several times at random moments in [0, T/2) of each run, each run resuming the last; a final
// run completes it. After every kill every result file in the folder must be complete (named
// files only appear by rename). Hidden temporaries may be left by a kill (SIGKILL runs no
// clean-up; rare, the window is the write of one file): the next run removes those of dead
// processes, so none remain at the end. The final sweep.csv must be byte-identical to the
// reference, and so must every point's trace.csv and summary.json (less its "run": wall time and
// provenance). The seed of the kill times is printed; ASPERITY_KILL_SEED=<n> repeats a run.
//
// SIGINT (and SIGTERM) stop a sweep cleanly instead: the points in flight save their slides to
// points/<point>/checkpoint.cbor, the sweep exits with status 3, and the same command continues
// those points from their checkpoints to the uninterrupted result, bit for bit.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <thread>

#include "kill_support.hpp"

namespace {

using namespace asperity::test_support;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const fs::path kWork = WORK_DIR;

std::vector<std::string> sweep_command(const fs::path& out, bool figures = true) {
  std::vector<std::string> args = {FRICTION_SWEEP, SCENE, "--out", out.string()};
  if (figures) args.push_back("--figures");
  return args;
}

void expect_complete(const fs::path& dir, const std::string& when) {
  const OutputCheck c = check_outputs(dir);
  for (const auto& b : c.broken)
    ADD_FAILURE() << when << ": incomplete result file " << b;
}

// Every point of `reference` has the same trace.csv and summary.json (less "run") in `other`;
// returns the number of points compared.
std::size_t expect_same_points(const fs::path& reference, const fs::path& other) {
  std::size_t points = 0;
  for (const auto& entry : fs::directory_iterator(reference / "points")) {
    const fs::path same = other / "points" / entry.path().filename();
    EXPECT_EQ(slurp(same / "trace.csv"), slurp(entry.path() / "trace.csv")) << same;
    EXPECT_EQ(without_run(nlohmann::json::parse(slurp(same / "summary.json"))),
              without_run(nlohmann::json::parse(slurp(entry.path() / "summary.json"))))
        << same;
    ++points;
  }
  return points;
}

}  // namespace

TEST(FrictionSweepKill, ResumesToTheUninterruptedTable) {
  fs::remove_all(kWork);
  fs::create_directories(kWork);
  const fs::path reference = kWork / "reference", killed = kWork / "killed";
  const fs::path log = kWork / "log.txt";

  const auto t0 = Clock::now();
  {
    Child run(sweep_command(reference), log);
    ASSERT_EQ(describe_status(run.wait()), "exit 0") << "see " << log;
  }
  const double T = std::chrono::duration<double>(Clock::now() - t0).count();
  expect_complete(reference, "reference");

  unsigned seed = std::random_device{}();
  if (const char* s = std::getenv("ASPERITY_KILL_SEED"))
    seed = static_cast<unsigned>(std::stoul(s));
  std::printf("uninterrupted sweep: %.2f s; kill seed %u (ASPERITY_KILL_SEED to repeat)\n", T,
              seed);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> when(0.0, 0.5 * T);

  constexpr int kKills = 4;
  int kills = 0;
  std::size_t leftovers = 0;
  for (int k = 0; k < kKills; ++k) {
    const double delay = when(gen);
    Child run(sweep_command(killed), log);
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    const bool was_running = run.signal(SIGKILL);
    const int status = run.wait();
    if (was_running) {
      ++kills;
      // Killed, or finished in the moment between the check and the signal.
      EXPECT_TRUE((WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) ||
                  describe_status(status) == "exit 0")
          << describe_status(status);
    } else {
      EXPECT_EQ(describe_status(status), "exit 0") << "see " << log;
    }
    const OutputCheck c = check_outputs(killed);
    leftovers += c.temporaries;
    std::printf("run %d: %s after %.3f s; %zu complete result files, %zu temporaries\n", k + 1,
                was_running ? "killed" : "finished", delay, c.files, c.temporaries);
    for (const auto& b : c.broken)
      ADD_FAILURE() << "after kill " << k + 1 << ": incomplete result file " << b;
  }
  EXPECT_GE(kills, 1) << "no run was still running when killed: T = " << T << " s";

  // Temporaries of a dead process go, those of a live one stay: plant one of each.
  pid_t dead = 0;
  {
    Child quick({"/bin/true"}, log);
    quick.wait();
    dead = quick.pid();
  }
  fs::create_directories(killed);
  const fs::path stale = killed / (".sweep.csv." + std::to_string(dead) + ".0.tmp");
  const fs::path live = killed / (".sweep.csv." + std::to_string(::getpid()) + ".0.tmp");
  std::ofstream(stale) << "partial";
  std::ofstream(live) << "partial";
  {
    Child run(sweep_command(killed), log);
    ASSERT_EQ(describe_status(run.wait()), "exit 0") << "see " << log;
  }
  EXPECT_FALSE(fs::exists(stale)) << "a dead run's temporary was not removed";
  EXPECT_TRUE(fs::exists(live)) << "a live process's temporary was removed";
  fs::remove(live);
  const OutputCheck end = check_outputs(killed);
  EXPECT_TRUE(end.broken.empty());
  EXPECT_EQ(end.temporaries, 0u) << "temporaries left after the resumed run";
  std::printf("%d kills, %zu temporaries seen after kills; %zu result files at the end\n", kills,
              leftovers, end.files);

  EXPECT_EQ(slurp(killed / "sweep.csv"), slurp(reference / "sweep.csv"));
  EXPECT_EQ(expect_same_points(reference, killed), 8u);
  // The sweep's summary differs only in what was reused and in "run".
  EXPECT_EQ(
      without_run(nlohmann::json::parse(slurp(killed / "summary.json")), {"computed", "reused"}),
      without_run(nlohmann::json::parse(slurp(reference / "summary.json")),
                  {"computed", "reused"}));
}

// Without --figures: the points' figures and snapshots (gnuplot, NetCDF) take most of a run with
// them, written after the slide, and a stop there leaves no slide in flight to save; without,
// the run is slides nearly all the time.
TEST(FrictionSweepKill, SigintSavesThePointsInFlightAndTheNextRunContinuesThem) {
  const fs::path reference = kWork / "reference_tables", stopped = kWork / "sigint";
  const fs::path log = kWork / "sigint_log.txt";
  fs::create_directories(kWork);
  fs::remove_all(stopped);
  fs::remove(log);
  double T = 0.0;
  {
    fs::remove_all(reference);
    const auto t0 = Clock::now();
    Child run(sweep_command(reference, false), log);
    ASSERT_EQ(describe_status(run.wait()), "exit 0") << "see " << log;
    T = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  // Stop it while points are in flight (two run at once over the whole sweep).
  unsigned seed = std::random_device{}();
  if (const char* s = std::getenv("ASPERITY_KILL_SEED"))
    seed = static_cast<unsigned>(std::stoul(s));
  std::mt19937 gen(seed);
  const double delay = std::uniform_real_distribution<double>(0.2 * T, 0.6 * T)(gen);
  std::size_t checkpoints = 0;
  {
    Child run(sweep_command(stopped, false), log);
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    ASSERT_TRUE(run.signal(SIGINT)) << "the sweep ended before " << delay << " s of " << T;
    ASSERT_EQ(describe_status(run.wait()), "exit 3") << "see " << log;
  }
  for (const auto& entry : fs::recursive_directory_iterator(stopped))
    checkpoints += entry.path().filename() == "checkpoint.cbor" ? 1 : 0;
  expect_complete(stopped, "after SIGINT");  // checkpoints included: they must decode
  EXPECT_GE(checkpoints, 1u) << "no point in flight saved its slide";
  std::printf("SIGINT after %.3f s of %.2f s (seed %u): exit 3, %zu checkpoint(s)\n", delay, T,
              seed, checkpoints);
  {
    Child run(sweep_command(stopped, false), log);
    ASSERT_EQ(describe_status(run.wait()), "exit 0") << "see " << log;
  }
  EXPECT_NE(slurp(log).find("from its checkpoint"), std::string::npos)
      << "the second run did not continue from a checkpoint; see " << log;
  for (const auto& entry : fs::recursive_directory_iterator(stopped))
    EXPECT_NE(entry.path().filename(), "checkpoint.cbor") << "left after the sweep finished";
  EXPECT_EQ(slurp(stopped / "sweep.csv"), slurp(reference / "sweep.csv"));
  EXPECT_EQ(expect_same_points(reference, stopped), 8u);
}
