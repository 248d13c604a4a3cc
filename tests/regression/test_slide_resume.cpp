// Regression tier: contact_slide is deterministic, and a run stopped by a signal resumes
// (--resume) to the uninterrupted result, bit for bit (issue 8: nothing lost on interruption;
// determinism).
//
// - Determinism: two runs of the same scene with the same threads (2 FFT threads) write
//   byte-identical trace.csv, NetCDF snapshots with the same frames bit for bit, and
//   summary.json files that differ only in "run" (wall time, provenance).
// - Resume: the default scene with the relaxation paths of every slip (two slip events, the
//   second replayed: its path is read back from paths.nc) runs once to the end (duration T);
//   then a run is
//   sent SIGUSR1 at a random moment in [0.2 T, 0.7 T) and must exit with status 3 having saved
//   checkpoint.cbor and written no results; its resumption (with a checkpoint after every step)
//   gets SIGTERM likewise, and a third SIGINT if it had not finished first (a resumption that
//   finishes before its signal ends the chain: each run prints which signal met it, and at least
//   the first must); the next resumption runs to the end. Its trace.csv must be
//   byte-identical to the uninterrupted run's, its snapshots hold the same frames bit for bit
//   (paths.nc copied up to the checkpoint and appended to), its summary.json the same but for
//   "run", and
//   the checkpoint gone. ASPERITY_KILL_SEED=<n> repeats the moments of a run. The same for the
//   explicit model (--model explicit --slide, a Regime II contact with two slips).
// - Bad resumptions: --resume without a checkpoint, with other settings, or of the other model,
//   exit 2 naming the problem.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <thread>

#include "kill_support.hpp"

namespace {

using namespace asperity::test_support;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const fs::path kWork = WORK_DIR;
const fs::path kLog = kWork / "log.txt";

std::vector<std::string> slide_command(const fs::path& out, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {CONTACT_SLIDE, SCENE, "--out", out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

int run_to_end(const std::vector<std::string>& args) {
  Child run(args, kLog);
  return run.wait();
}

// The same frames, bit for bit: labels, iterations, positions and every field. (Not the same
// bytes: a resumed run copies paths.nc up to its checkpoint and appends, and HDF5 may lay the
// file out differently.)
void expect_same_frames(const fs::path& a, const fs::path& b) {
  const auto x = asperity::app::read_snapshots(a), y = asperity::app::read_snapshots(b);
  ASSERT_EQ(x.size(), y.size()) << a.filename();
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto &f = x[k], &g = y[k];
    EXPECT_TRUE(f.label == g.label && f.iteration == g.iteration && f.Dx == g.Dx && f.Fx == g.Fx &&
                f.energy == g.energy && f.block.origin0 == g.block.origin0 && f.ux == g.ux &&
                f.uy == g.uy && f.sx == g.sx && f.tau_x == g.tau_x && f.tau_y == g.tau_y &&
                f.tau_max == g.tau_max && f.in_contact == g.in_contact)
        << a.filename() << ": frame " << k << " (" << f.label << ")";
  }
}

// The files two runs must agree on byte for byte, the summaries less "run", and the frames of
// the snapshots.
void expect_same_results(const fs::path& a, const fs::path& b) {
  EXPECT_EQ(slurp(a / "trace.csv"), slurp(b / "trace.csv"));
  EXPECT_EQ(without_run(nlohmann::json::parse(slurp(a / "summary.json"))),
            without_run(nlohmann::json::parse(slurp(b / "summary.json"))));
  std::size_t snapshots = 0, paths = 0;
  for (const auto& entry : fs::directory_iterator(a / "snapshots")) {
    const fs::path other = b / "snapshots" / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    expect_same_frames(entry.path(), other);
    ++snapshots;
    if (entry.path().filename() == "paths.nc") paths = asperity::app::read_snapshots(other).size();
  }
  EXPECT_GT(snapshots, 0u);
  std::size_t files_b = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(b / "snapshots"))
    ++files_b;
  EXPECT_EQ(files_b, snapshots);  // no partial or leftover file in the resumed run's folder
  std::printf("%zu snapshot files, %zu path frames\n", snapshots, paths);
}

std::string log_tail() {
  const std::string text = slurp(kLog);
  return text.substr(text.size() > 2000 ? text.size() - 2000 : 0);
}

// The log is shared by every run of the suite (appended to): a run's own lines are those after
// the size it had when the run started.
std::size_t log_size() {
  return fs::exists(kLog) ? static_cast<std::size_t>(fs::file_size(kLog)) : 0;
}
std::string log_since(std::size_t mark) {
  const std::string text = slurp(kLog);
  return mark < text.size() ? text.substr(mark) : std::string();
}

// Runs `args` (with --checkpoint-every 0) until its first checkpoint is on disk, then sends
// `sig`: a run stopped with a checkpoint to resume from, whatever the machine's speed. Returns
// the run's status ("exit 0" if it finished before a checkpoint appeared).
std::string stop_after_first_checkpoint(const std::vector<std::string>& args,
                                        const fs::path& checkpoint, int sig) {
  Child run(args, kLog);
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (!fs::exists(checkpoint) && !run.finished() && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  run.signal(sig);
  return describe_status(run.wait());
}

class SlideResume : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(kWork);
    fs::create_directories(kWork);
  }
};

}  // namespace

TEST_F(SlideResume, SameInputsAndThreadsGiveIdenticalResults) {
  const std::vector<std::string> extra = {"--a", "30", "--threads", "2"};
  ASSERT_EQ(describe_status(run_to_end(slide_command(kWork / "det1", extra))), "exit 0")
      << log_tail();
  ASSERT_EQ(describe_status(run_to_end(slide_command(kWork / "det2", extra))), "exit 0")
      << log_tail();
  expect_same_results(kWork / "det1", kWork / "det2");
}

namespace {

// The resume check of the header for the slide `extra` selects (a model and its scene), in
// kWork/<name>_reference and kWork/<name>_resumed.
void interrupted_runs_resume(const std::string& name, const std::vector<std::string>& extra) {
  const fs::path reference = kWork / (name + "_reference"), resumed = kWork / (name + "_resumed");
  const auto with = [&extra](std::vector<std::string> more) {
    more.insert(more.begin(), extra.begin(), extra.end());
    return more;
  };
  const auto t0 = Clock::now();
  ASSERT_EQ(describe_status(run_to_end(slide_command(reference, extra))), "exit 0") << log_tail();
  const double T = std::chrono::duration<double>(Clock::now() - t0).count();

  unsigned seed = std::random_device{}();
  if (const char* s = std::getenv("ASPERITY_KILL_SEED"))
    seed = static_cast<unsigned>(std::stoul(s));
  std::printf("uninterrupted slide: %.2f s; seed %u (ASPERITY_KILL_SEED to repeat)\n", T, seed);
  std::mt19937 gen(seed);

  const fs::path checkpoint = resumed / "checkpoint.cbor";
  int interrupted = 0;
  bool finished = false;
  // SIGUSR1 first, so that every run tries it (the fresh run is retried until a signal meets
  // it): the signal mpirun forwards to its ranks stops a serial run as well.
  for (const int sig : {SIGUSR1, SIGTERM, SIGINT}) {
    // The first run starts afresh, the second resumes (and checkpoints after every step), so its
    // signal comes sooner.
    const bool first = interrupted == 0;
    const auto args = first ? slide_command(resumed, extra)
                            : slide_command(resumed, with({"--resume", "--checkpoint-every", "0"}));
    // A fresh run that ends before the signal is tried again with a shorter delay.
    for (double fraction = first ? 0.7 : 0.3; fraction > 0.01; fraction *= 0.5) {
      const double delay = std::uniform_real_distribution<double>(0.2, 1.0)(gen) * fraction * T;
      const std::size_t mark = log_size();
      Child run(args, kLog);
      std::this_thread::sleep_for(std::chrono::duration<double>(delay));
      const bool sent = run.signal(sig);
      const std::string status = describe_status(run.wait());
      std::printf("signal %d after %.3f s: %s\n", sig, delay, sent ? status.c_str() : "finished");
      if (status == "exit 0") {
        if (!first) {  // the resumption finished first: one interruption is all this run has
          finished = true;
          break;
        }
        fs::remove_all(resumed);
        continue;
      }
      ASSERT_EQ(status, "exit 3") << log_tail();
      ASSERT_TRUE(fs::exists(checkpoint));
      EXPECT_FALSE(fs::exists(resumed / "trace.csv")) << "an interrupted run wrote results";
      const OutputCheck c = check_outputs(resumed);
      EXPECT_TRUE(c.broken.empty());
      EXPECT_EQ(c.temporaries, 0u);
      EXPECT_NE(log_since(mark).find("--resume"), std::string::npos) << "no resume command printed";
      ++interrupted;
      break;
    }
    if (finished) break;
  }
  ASSERT_GE(interrupted, 1) << "no run was interrupted; see " << kLog;

  if (!finished) {
    const auto t1 = Clock::now();
    ASSERT_EQ(describe_status(run_to_end(slide_command(resumed, with({"--resume"})))), "exit 0")
        << log_tail();
    std::printf("last resumption: %.2f s\n",
                std::chrono::duration<double>(Clock::now() - t1).count());
  }
  EXPECT_FALSE(fs::exists(checkpoint)) << "a finished run leaves its checkpoint";
  expect_same_results(reference, resumed);
}

}  // namespace

TEST_F(SlideResume, InterruptedRunsResumeToTheUninterruptedResult) {
  interrupted_runs_resume("lfm", {});
}

// The explicit model (a Regime II contact with two slips, a = 12 d, R = 125 d, 1 s): its states
// live on blocks that follow the tip and grow, and carry the tip height and the load loop's
// secant slope; the resumed slide must still repeat the uninterrupted one exactly.
TEST_F(SlideResume, InterruptedExplicitRunsResumeToTheUninterruptedResult) {
  interrupted_runs_resume(
      "explicit", {"--model", "explicit", "--slide", "--a", "12", "--R", "125", "--threads", "1"});
}

TEST_F(SlideResume, BadResumptionsExitTwoNamingTheProblem) {
  const fs::path dir = kWork / "bad";
  fs::remove_all(dir);
  std::size_t mark = log_size();
  EXPECT_EQ(describe_status(run_to_end(slide_command(dir, {"--resume"}))), "exit 2");
  EXPECT_NE(log_since(mark).find("no checkpoint"), std::string::npos) << log_tail();

  // A checkpoint of the default settings, then a resumption with another tolerance.
  {
    const std::string status = stop_after_first_checkpoint(
        slide_command(dir, {"--checkpoint-every", "0"}), dir / "checkpoint.cbor", SIGTERM);
    // Only a run that finished before its first checkpoint is a reason to skip; a crash or
    // another exit is a failure.
    if (status == "exit 0") GTEST_SKIP() << "the run ended before its first checkpoint";
    ASSERT_EQ(status, "exit 3") << log_tail();
  }
  mark = log_size();
  EXPECT_EQ(describe_status(run_to_end(slide_command(dir, {"--resume", "--tolerance", "1e-7"}))),
            "exit 2");
  EXPECT_NE(log_since(mark).find("tolerance=1e-07"), std::string::npos) << log_tail();

  // A damaged checkpoint.
  const std::string bytes = slurp(dir / "checkpoint.cbor");
  std::ofstream(dir / "checkpoint.cbor", std::ios::binary | std::ios::trunc)
      << bytes.substr(0, bytes.size() / 2);
  mark = log_size();
  EXPECT_EQ(describe_status(run_to_end(slide_command(dir, {"--resume"}))), "exit 2");
  EXPECT_NE(log_since(mark).find("not a contact_slide checkpoint"), std::string::npos)
      << log_tail();
}

TEST_F(SlideResume, AnExplicitCheckpointDoesNotResumeTheLfm) {
  const fs::path dir = kWork / "bad_model";
  fs::remove_all(dir);
  const std::vector<std::string> expl = {"--model", "explicit", "--slide",   "--a", "12",
                                         "--R",     "125",      "--threads", "1"};
  {
    std::vector<std::string> args = expl;
    args.insert(args.end(), {"--checkpoint-every", "0"});
    const std::string status =
        stop_after_first_checkpoint(slide_command(dir, args), dir / "checkpoint.cbor", SIGTERM);
    if (status == "exit 0") GTEST_SKIP() << "the run ended before its first checkpoint";
    ASSERT_EQ(status, "exit 3") << log_tail();
  }
  const std::size_t mark = log_size();
  EXPECT_EQ(describe_status(run_to_end(
                slide_command(dir, {"--a", "12", "--R", "125", "--threads", "1", "--resume"}))),
            "exit 2");
  EXPECT_NE(log_since(mark).find("model=explicit"), std::string::npos) << log_tail();
}
