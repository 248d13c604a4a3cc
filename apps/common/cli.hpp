// Pieces shared by the command-line tools: provenance records, progress reports and the
// error-handling wrapper around main().
//
// Every tool's main() follows this pattern:
//
//   int main(int argc, char** argv) {
//     return asperity::app::run_main(argc, argv, [](int argc, char** argv) {
//       CLI::App cli{"What the tool does"};
//       std::string scene;
//       cli.add_option("scene", scene, "Scene file")->required();
//       if (!asperity::app::parse_command_line(cli, argc, argv)) return 0;  // --help was shown
//       ...                                                               // do the work
//       return 0;
//     });
//   }
//
// CLI11 prints help only through the CLI::App that was parsed, so --help is handled inside
// parse_command_line(); a malformed command line propagates as CLI::ParseError and run_main()
// reports it like any other bad input.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace CLI {
class App;
}

namespace asperity::app {

// The commit the program was built from, found at build time (cmake/GitCommit.cmake): the short
// hash, with "+dirty.<hash of the diff>" if tracked files differed from it; "unknown" outside a
// git checkout.
const char* git_commit();
// "asperity <version> (commit <git_commit()>)".
std::string provenance_string();
// The same without spaces, for settings fingerprints ("asperity_0.1.0_(commit_abc1234)"):
// results of another build are not reused or resumed.
std::string provenance_token();

// Program, version, commit, UTC date-time (ISO 8601), hostname and hardware threads: stored with
// every result so that it can be traced back to the code and machine that produced it.
nlohmann::json provenance_json();

// The type name of a boolean setting's flag (SettingFlags): a switch, "--xyz" alone is true,
// "--xyz=false" false; parse_command_line() also takes "--xyz true|false" for it, as such a flag
// took them before it was a switch, without letting it swallow a following file name.
inline constexpr const char* kBooleanFlagType = "[=true|false]";

// Parses the command line. Returns false if CLI11 printed help or version text (the tool should
// then exit with status 0); throws CLI::ParseError for a malformed command line.
bool parse_command_line(CLI::App& app, int argc, char** argv);
// The same for arguments in order, without the program's name.
bool parse_command_line(CLI::App& app, std::vector<std::string> args);

// Runs `body` and returns its exit status. Exceptions become "program: error: message" on stderr
// and exit status 2 for bad input (std::invalid_argument, CLI::ParseError) or 1 for failures
// at run time (any other std::exception).
int run_main(int argc, char** argv, const std::function<int(int, char**)>& body);

// What run_main makes of an exception: its exit status (2 for bad input: CLI::ParseError,
// std::invalid_argument; 1 for any other std::exception) and the lines it prints on stderr,
// "program: error: message" (and the usage hint of a malformed command line). An exception that
// is no std::exception is rethrown.
int describe_error(const std::string& program, const std::exception_ptr& error, std::string& lines);

// Exit status of a run stopped by SIGINT, SIGTERM or SIGUSR1 after saving what it had (0: done,
// 1: failed, 2: bad input).
constexpr int kInterrupted = 3;

// Installs handlers for SIGINT, SIGTERM and SIGUSR1 that only set a flag (async-signal-safe):
// long runs poll stop_requested() between steps (slides also inside relaxations), save their
// state and return kInterrupted. SIGUSR1 is the signal that stops a run under mpirun, which
// forwards it to every rank (SIGINT and SIGTERM it answers by killing the ranks a second later;
// mpi_points.hpp); a serial run stops on it too, so that one signal serves both (without a
// handler its default action ended a serial sweep at once, after its last timed checkpoint).
void install_stop_handlers();
// The same handler for one more signal.
void install_stop_handler(int signal);
// Sets the flag as a signal would: another rank of the run was stopped (mpi_points.hpp).
void request_stop();
bool stop_requested();

// The command line as typed, quoted for a POSIX shell, with `extra` appended unless an argument
// equals it already (e.g. "--resume"; empty: nothing appended).
std::string command_line(int argc, char** argv, const std::string& extra = "");

// One-line progress report for long loops. On a terminal the line is rewritten in place; in a
// log file a line is printed each time another `percent_step` percent is done, so logs stay short.
// advance() may be called from several threads. The destructor prints the final state.
class Progress {
 public:
  Progress(std::string label, std::size_t total, int percent_step = 10);  // reports to stderr
  Progress(std::string label, std::size_t total, std::ostream& out, bool interactive,
           int percent_step = 10);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::size_t steps = 1);

 private:
  void print();  // caller holds mutex_

  std::string label_;
  std::size_t total_;
  std::ostream& out_;
  bool interactive_;
  int percent_step_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  std::size_t done_ = 0;
  int shown_percent_ = -1;  // last percentage printed; -1 before the first report
};

}  // namespace asperity::app
