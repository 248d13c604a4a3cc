#include "asperity/apps/common/cli.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <thread>

namespace asperity::app {

std::string provenance_string() {
  return std::string("asperity ") + ASPERITY_VERSION + " (commit " + git_commit() + ")";
}

std::string provenance_token() {
  std::string token = provenance_string();
  for (char& ch : token)
    if (ch == ' ') ch = '_';
  return token;
}

nlohmann::json provenance_json() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
  // gethostname need not terminate a truncated name; the last byte stays zero.
  char host[256] = {};
  const bool have_host = ::gethostname(host, sizeof host - 1) == 0;
  return {{"program", "asperity"},
          {"version", ASPERITY_VERSION},
          {"commit", git_commit()},
          {"date_utc", date},
          {"hostname", have_host ? host : "unknown"},
          {"hardware_threads", std::thread::hardware_concurrency()}};
}

bool parse_command_line(CLI::App& app, int argc, char** argv) {
  // The program's name in --help, as CLI11's own parse(argc, argv) sets it.
  if (app.get_name().empty() && argc > 0) app.name(argv[0]);
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i)
    args.emplace_back(argv[i]);
  return parse_command_line(app, std::move(args));
}

bool parse_command_line(CLI::App& app, std::vector<std::string> args) {
  // "--xyz true" for a boolean setting's switch: "--xyz=true" (kBooleanFlagType).
  std::vector<std::string> switches;
  for (const CLI::Option* option : app.get_options()) {
    if (option->get_type_name() != kBooleanFlagType) continue;
    for (const std::string& name : option->get_lnames())
      switches.push_back("--" + name);
  }
  std::vector<std::string> merged;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const bool is_switch = std::find(switches.begin(), switches.end(), args[i]) != switches.end();
    // Any spelling of a truth value is joined, so that the switch's check refuses the ones it
    // does not take ("True", "1") by its key rather than as a stray file name.
    std::string next = is_switch && i + 1 < args.size() ? args[i + 1] : std::string();
    std::transform(next.begin(), next.end(), next.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (next == "true" || next == "false" || next == "1" || next == "0") {
      merged.push_back(args[i] + "=" + args[i + 1]);
      ++i;
    } else {
      merged.push_back(args[i]);
    }
  }
  std::reverse(merged.begin(), merged.end());  // CLI11 takes a vector last argument first
  try {
    app.parse(merged);
    return true;
  } catch (const CLI::Success& e) {
    app.exit(e);
    return false;
  }
}

int describe_error(const std::string& program, const std::exception_ptr& error,
                   std::string& lines) {
  try {
    std::rethrow_exception(error);
  } catch (const CLI::ParseError& e) {
    lines = program + ": error: " + e.what() + "\n" + program + ": run with --help for usage\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    lines = program + ": error: " + e.what() + "\n";
    return 2;
  } catch (const std::exception& e) {
    lines = program + ": error: " + e.what() + "\n";
    return 1;
  }
}

int run_main(int argc, char** argv, const std::function<int(int, char**)>& body) {
  const std::string program =
      argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "asperity";
  try {
    return body(argc, argv);
  } catch (const std::exception&) {
    std::string lines;
    const int status = describe_error(program, std::current_exception(), lines);
    std::cerr << lines;
    return status;
  }
}

Progress::Progress(std::string label, std::size_t total, int percent_step)
    : Progress(std::move(label), total, std::cerr, ::isatty(STDERR_FILENO) == 1, percent_step) {}

Progress::Progress(std::string label, std::size_t total, std::ostream& out, bool interactive,
                   int percent_step)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      interactive_(interactive),
      percent_step_(percent_step) {
  if (percent_step < 1 || percent_step > 100) {
    throw std::invalid_argument("progress step must be in [1, 100] percent, got " +
                                std::to_string(percent_step));
  }
}

Progress::~Progress() {
  const std::lock_guard lock(mutex_);
  print();
  if (interactive_) out_ << '\n' << std::flush;
}

void Progress::advance(std::size_t steps) {
  const std::lock_guard lock(mutex_);
  done_ = std::min(done_ + steps, total_);
  const int percent = total_ == 0 ? 100 : static_cast<int>(100 * done_ / total_);
  const bool due =
      interactive_ ? percent != shown_percent_
                   : shown_percent_ < 0 || percent / percent_step_ > shown_percent_ / percent_step_;
  if (due) print();
}

void Progress::print() {
  const int percent = total_ == 0 ? 100 : static_cast<int>(100 * done_ / total_);
  if (!interactive_ && percent == shown_percent_) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char elapsed[32];
  std::snprintf(elapsed, sizeof elapsed, "%.1f s", seconds);
  if (interactive_) out_ << '\r';
  out_ << label_ << ": " << done_ << "/" << total_ << " (" << percent << "%), " << elapsed;
  out_ << (interactive_ ? "" : "\n") << std::flush;
  shown_percent_ = percent;
}

namespace {
// Set by the signal handler, read between steps and inside relaxations. Lock-free, so that setting
// it is async-signal-safe.
std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_stop_signal(int) {
  g_stop.store(true);
}
}  // namespace

void install_stop_handler(int signal) {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  // System calls in flight (file writes) just go on; a second signal, while the run finishes
  // what is in flight, ends it at once (the default action).
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(signal, &action, nullptr);
}

void install_stop_handlers() {
  install_stop_handler(SIGINT);
  install_stop_handler(SIGTERM);
  install_stop_handler(SIGUSR1);
}

void request_stop() {
  g_stop.store(true);
}

bool stop_requested() {
  return g_stop.load();
}

std::string command_line(int argc, char** argv, const std::string& extra) {
  std::string out;
  bool has_extra = extra.empty();
  for (int i = 0; i < argc; ++i) {
    std::string arg = argv[i];
    has_extra = has_extra || arg == extra;
    if (arg.empty() || arg.find_first_of(" \t'\"$`\\*?;&|()<>") != std::string::npos) {
      std::string quoted = "'";
      for (char c : arg)
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      arg = quoted + "'";
    }
    out += (i ? " " : "") + arg;
  }
  return has_extra ? out : out + " " + extra;
}

}  // namespace asperity::app
