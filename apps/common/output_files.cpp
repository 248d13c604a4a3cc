#include "asperity/apps/common/output_files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace asperity::app {
namespace {

template <class T>
std::string format(T v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

template <class T>
bool parse_whole(std::string_view s, T& v) {
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

std::string csv_field(std::string_view s) {
  if (s.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(s);
  std::string out = "\"";
  for (char c : s)
    out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + '"';
}

std::string cell_text(const CsvTable::Cell& cell) {
  if (const auto* s = std::get_if<std::string>(&cell)) return *s;
  if (const auto* d = std::get_if<double>(&cell)) return format(*d);
  return format(std::get<long long>(cell));
}

}  // namespace

std::filesystem::path ensure_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create directory '" + dir.string() +
                             "': " + (ec ? ec.message() : "exists and is not a directory"));
  }
  return dir;
}

namespace {

// A name ".<target>.<pid>.<counter>.tmp" next to `target`: pid and counter make it unique across
// processes and threads.
std::filesystem::path hidden_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  // append() rather than "." + string: GCC 12 warns falsely (-Wrestrict) on the latter.
  return dir / std::string(".")
                   .append(target.filename().string())
                   .append(".")
                   .append(std::to_string(::getpid()))
                   .append(".")
                   .append(std::to_string(counter++))
                   .append(".tmp");
}

}  // namespace

TemporaryFile::TemporaryFile(const std::filesystem::path& target, Kind kind) : target_(target) {
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
#ifdef O_TMPFILE
  if (kind == Kind::unnamed) fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (fd_ >= 0) {
    // /proc/<pid>, not /proc/self: the path must name this file in child processes too.
    path_ = "/proc/" + std::to_string(::getpid()) + "/fd/" + std::to_string(fd_);
    return;
  }
#endif
  // No O_TMPFILE here (NFS, older overlayfs): a named temporary. O_EXCL guards against leftovers
  // of an earlier, killed process that had the same pid.
  for (;;) {
    path_ = hidden_name(target);
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return;
    }
    if (errno != EEXIST) {
      throw std::runtime_error("cannot write '" + target.string() +
                               "': cannot create a temporary file: " + std::strerror(errno));
    }
  }
}

TemporaryFile::~TemporaryFile() {
  if (fd_ >= 0) {
    ::close(fd_);  // an unnamed file disappears with its last descriptor
  } else if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
}

void TemporaryFile::commit() {
  const auto fail = [this](const std::string& why) {
    throw std::runtime_error("cannot write '" + target_.string() + "': " + why);
  };
  std::filesystem::path named = path_;
  if (fd_ >= 0) {
    // Give the unnamed file a hidden name, then rename that over the target: linkat cannot
    // replace an existing file.
    for (;;) {
      named = hidden_name(target_);
      if (::linkat(AT_FDCWD, path_.c_str(), AT_FDCWD, named.c_str(), AT_SYMLINK_FOLLOW) == 0) {
        break;
      }
      if (errno != EEXIST)
        fail(std::string("cannot name the temporary file: ") + std::strerror(errno));
    }
  }
  std::error_code ec;
  std::filesystem::rename(named, target_, ec);
  if (ec) {
    std::error_code ignored;
    if (fd_ >= 0) std::filesystem::remove(named, ignored);
    fail(ec.message());
  }
  committed_ = true;
}

namespace {

// The pid in a TemporaryFile name ".<target>.<pid>.<counter>.tmp", or -1 for any other name.
long temporary_owner(const std::string& name) {
  constexpr std::string_view suffix = ".tmp";
  if (name.size() < 8 || name.front() != '.' || !name.ends_with(suffix)) return -1;
  const std::string_view stem(name.data(), name.size() - suffix.size());
  const std::size_t counter_dot = stem.rfind('.');
  if (counter_dot == std::string_view::npos || counter_dot == 0) return -1;
  const std::size_t pid_dot = stem.rfind('.', counter_dot - 1);
  if (pid_dot == std::string_view::npos || pid_dot == 0) return -1;
  long pid = 0;
  unsigned long counter = 0;
  if (!parse_whole(stem.substr(pid_dot + 1, counter_dot - pid_dot - 1), pid) ||
      !parse_whole(stem.substr(counter_dot + 1), counter) || pid <= 0) {
    return -1;
  }
  return pid;
}

}  // namespace

std::size_t remove_stale_temporaries(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return 0;
  std::size_t removed = 0;
  // skip_permission_denied: a folder we cannot read holds no temporaries of ours.
  for (auto it = std::filesystem::recursive_directory_iterator(
           dir, std::filesystem::directory_options::skip_permission_denied, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const long pid = temporary_owner(it->path().filename().string());
    if (pid <= 0 || pid == ::getpid()) continue;
    // kill(pid, 0) probes without sending: ESRCH means no such process (EPERM: alive).
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code remove_ec;
    if (std::filesystem::remove(it->path(), remove_ec)) ++removed;
  }
  return removed;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  TemporaryFile tmp(path);
  std::ofstream out(tmp.path(), std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
  tmp.commit();
}

void write_json(const std::filesystem::path& path, const nlohmann::json& value) {
  write_file_atomic(path, value.dump(2) + "\n");
}

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("CSV table needs at least one column");
}

void CsvTable::add_row(std::vector<Cell> row) {
  if (row.size() != columns_.size()) {
    throw std::invalid_argument("CSV row has " + std::to_string(row.size()) +
                                " fields, table has " + std::to_string(columns_.size()) +
                                " columns");
  }
  rows_.push_back(std::move(row));
}

std::size_t CsvTable::column_index(std::string_view name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  if (it == columns_.end()) {
    throw std::invalid_argument("CSV table has no column '" + std::string(name) + "'");
  }
  return static_cast<std::size_t>(it - columns_.begin());
}

double CsvTable::number(std::size_t row, std::string_view column) const {
  const Cell& c = cell(row, column_index(column));
  if (const auto* d = std::get_if<double>(&c)) return *d;
  if (const auto* i = std::get_if<long long>(&c)) return static_cast<double>(*i);
  double v = 0;
  if (!parse_whole(std::get<std::string>(c), v)) {
    throw std::invalid_argument("CSV column '" + std::string(column) + "', row " +
                                std::to_string(row) + ": '" + std::get<std::string>(c) +
                                "' is not a number");
  }
  return v;
}

long long CsvTable::integer(std::size_t row, std::string_view column) const {
  const Cell& c = cell(row, column_index(column));
  if (const auto* i = std::get_if<long long>(&c)) return *i;
  long long v = 0;
  if (const auto* s = std::get_if<std::string>(&c); s && parse_whole(*s, v)) return v;
  throw std::invalid_argument("CSV column '" + std::string(column) + "', row " +
                              std::to_string(row) + ": '" + cell_text(c) + "' is not an integer");
}

std::string CsvTable::text(std::size_t row, std::string_view column) const {
  return cell_text(cell(row, column_index(column)));
}

std::string CsvTable::to_string() const {
  std::string out;
  auto append_line = [&out](const auto& fields, auto to_text) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (i) out += ',';
      out += csv_field(to_text(fields[i]));
    }
    out += '\n';
  };
  append_line(columns_, [](const std::string& s) { return s; });
  for (const auto& row : rows_)
    append_line(row, cell_text);
  return out;
}

CsvTable CsvTable::parse(std::string_view text, const std::string& source_name) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::size_t> record_lines;
  std::vector<std::string> record;
  std::string field;
  std::size_t line = 1, record_line = 1;
  bool in_quotes = false;
  auto end_record = [&] {
    record.push_back(std::move(field));
    field.clear();
    records.push_back(std::move(record));
    record.clear();
    record_lines.push_back(record_line);
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        line += c == '\n';
        field += c;
      }
    } else if (c == '"') {
      in_quotes = true;
    } else if (c == ',') {
      record.push_back(std::move(field));
      field.clear();
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_record();
      record_line = ++line;
    } else {
      field += c;
    }
  }
  if (in_quotes) {
    throw std::invalid_argument(source_name + ":" + std::to_string(record_line) +
                                ": unterminated quoted field");
  }
  if (!field.empty() || !record.empty()) end_record();
  if (records.empty()) throw std::invalid_argument(source_name + ": empty CSV, no header line");

  CsvTable table(std::move(records.front()));
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].size() != table.columns_.size()) {
      throw std::invalid_argument(source_name + ":" + std::to_string(record_lines[r]) +
                                  ": expected " + std::to_string(table.columns_.size()) +
                                  " fields, got " + std::to_string(records[r].size()));
    }
    table.rows_.emplace_back(std::make_move_iterator(records[r].begin()),
                             std::make_move_iterator(records[r].end()));
  }
  return table;
}

CsvTable CsvTable::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot open CSV file '" + path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path.string());
}

namespace {

// The directories this process holds a DirectoryLock on. A sweep locks its directory and then
// each point folder below it; flock makes no exception for the same process (a second open file
// is a second holder), so the probe of the ancestors must skip the ones locked here.
std::mutex& held_mutex() {
  static std::mutex m;
  return m;
}
std::multiset<std::filesystem::path>& held_here() {
  static std::multiset<std::filesystem::path> held;
  return held;
}

// The pid the holder wrote into its lock file, or "" if there is none.
std::string lock_holder(int fd) {
  char buf[32] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return {};
  std::string holder(buf, static_cast<std::size_t>(n));
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' '))
    holder.pop_back();
  return holder;
}

[[noreturn]] void refuse(const std::filesystem::path& locked, const std::filesystem::path& dir,
                         const std::string& holder) {
  throw std::invalid_argument(
      "another run is writing to " + locked.string() +
      (locked == dir ? std::string() : ", which contains " + dir.string()) +
      (holder.empty() ? std::string() : " (process " + holder + ")") +
      "; wait for it to end or stop it (SIGINT: it checkpoints), or choose another --out");
}

}  // namespace

namespace {
std::filesystem::path canonical_or_absolute(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::weakly_canonical(dir, ec);
  return ec ? std::filesystem::absolute(dir) : p;
}
}  // namespace

DirectoryLock::DirectoryLock(const std::filesystem::path& dir,
                             const std::filesystem::path& run_dir) {
  dir_ = canonical_or_absolute(dir);
  const std::filesystem::path held_by_run =
      run_dir.empty() ? std::filesystem::path() : canonical_or_absolute(run_dir);
  const std::lock_guard held_lock(held_mutex());
  // A directory inside one another run holds is written by that run too (a sweep's point
  // folders), so an ancestor's lock refuses this one. Probed with a shared lock, dropped at once.
  for (std::filesystem::path p = dir_.parent_path();; p = p.parent_path()) {
    if (!held_here().contains(p) && p != held_by_run) {
      const std::filesystem::path file = p / kFileName;
      if (const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC); fd >= 0) {
        const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
        const std::string holder = held ? lock_holder(fd) : std::string();
        ::close(fd);  // releases the probe
        if (held) refuse(p, dir, holder);
      }
    }
    if (p == p.parent_path()) break;
  }
  const std::filesystem::path path = dir / kFileName;
  // O_CLOEXEC: a child (gnuplot) must not inherit the lock and hold it past our exit.
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error("cannot open the lock file " + path.string() + ": " +
                             std::strerror(errno));
  }
  // Another run's probe of its ancestors holds this lock shared for a moment; a few retries
  // keep that moment from refusing a run.
  int err = 0;
  for (int attempt = 0; attempt < 4; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    err = ::flock(fd_, LOCK_EX | LOCK_NB) == 0 ? 0 : errno;
    if (err != EWOULDBLOCK) break;
  }
  if (err != 0) {
    const std::string holder = lock_holder(fd_);
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) refuse(dir, dir, holder);
    throw std::runtime_error("cannot lock " + path.string() + ": " + std::strerror(err));
  }
  held_here().insert(dir_);
  const std::string pid = std::to_string(::getpid()) + "\n";
  // Informational only (the lock is the flock): a failed write leaves the message without it.
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  const std::lock_guard held_lock(held_mutex());
  held_here().erase(held_here().find(dir_));
  ::close(fd_);  // releases the lock
}

}  // namespace asperity::app
