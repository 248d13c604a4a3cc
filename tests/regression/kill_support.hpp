// Helpers of the interruption tests (test_sweep_kill.cpp, test_slide_resume.cpp): start a tool,
// signal it, wait for it, and check that every result file in a folder is complete.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/apps/common/snapshot_io.hpp"

extern char** environ;

namespace asperity::test_support {

namespace fs = std::filesystem;

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A child process with stdout and stderr appended to `log`.
class Child {
 public:
  Child(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<char*> argv;
    for (const auto& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    const int err = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (err != 0) throw std::runtime_error("cannot start " + args[0]);
  }
  ~Child() {
    if (!reaped_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  // True if the process has ended (and reaps it).
  bool finished() {
    if (reaped_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      reaped_ = true;
      status_ = status;
    }
    return reaped_;
  }
  // Waits for the end; returns the raw wait status.
  int wait() {
    if (!reaped_) {
      ::waitpid(pid_, &status_, 0);
      reaped_ = true;
    }
    return status_;
  }
  // Sends `signal` if the process still runs; returns whether it did.
  bool signal(int sig) {
    if (finished()) return false;
    ::kill(pid_, sig);
    return true;
  }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool reaped_ = false;
};

inline std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exit " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

// What check_outputs found.
struct OutputCheck {
  std::size_t files = 0;            // complete result files
  std::size_t temporaries = 0;      // hidden ".<name>.<pid>.<n>.tmp" files (TemporaryFile)
  std::vector<std::string> broken;  // result files that are not complete, with the reason
};

// Every result file below `dir` must be complete: CSV tables parse with whole rows and end with a
// line break, JSON parses, NetCDF snapshots read back, PNG images end with their IEND chunk.
inline OutputCheck check_outputs(const fs::path& dir) {
  OutputCheck out;
  if (!fs::exists(dir)) return out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const fs::path& p = entry.path();
    const std::string name = p.filename().string();
    if (name.starts_with(".") && name.ends_with(".tmp")) {
      ++out.temporaries;
      continue;
    }
    const std::string ext = p.extension().string();
    try {
      if (ext == ".csv") {
        const std::string text = slurp(p);
        if (text.empty() || text.back() != '\n') throw std::runtime_error("no final line break");
        (void)app::CsvTable::parse(text, p.string());
      } else if (ext == ".json") {
        const auto json = nlohmann::json::parse(slurp(p));
        if (json.is_discarded()) throw std::runtime_error("not JSON");
      } else if (ext == ".cbor") {
        (void)app::read_checkpoint(p);
      } else if (ext == ".nc") {
        if (app::read_snapshots(p).empty()) throw std::runtime_error("no frames");
      } else if (ext == ".png") {
        static constexpr std::array<unsigned char, 12> iend = {0,   0,   0,    0,    'I',  'E',
                                                               'N', 'D', 0xAE, 0x42, 0x60, 0x82};
        const std::string bytes = slurp(p);
        if (bytes.size() < 20 ||
            !std::equal(iend.begin(), iend.end(),
                        reinterpret_cast<const unsigned char*>(bytes.data()) + bytes.size() - 12)) {
          throw std::runtime_error("no IEND chunk at the end");
        }
      } else {
        continue;  // not a result file of the tools
      }
      ++out.files;
    } catch (const std::exception& e) {
      out.broken.push_back(p.string() + ": " + e.what());
    }
  }
  return out;
}

// The JSON without the "run" object (wall times, provenance) and the `also` keys.
inline nlohmann::json without_run(nlohmann::json j, const std::vector<std::string>& also = {}) {
  j.erase("run");
  for (const auto& key : also)
    j.erase(key);
  return j;
}

}  // namespace asperity::test_support
