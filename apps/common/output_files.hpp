// Result files. Everything is written to a temporary file next to the target and renamed over it,
// so a killed run leaves either the old file or the complete new one, never a truncated one.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace asperity::app {

// Creates the directory and its parents if needed; throws std::runtime_error if that fails or
// the path exists and is not a directory. Returns `dir`.
std::filesystem::path ensure_directory(const std::filesystem::path& dir);

// A new empty file in the directory of `target`, removed on destruction unless commit() has
// renamed it onto `target`. Same directory, so the rename is atomic.
//
// Kind::unnamed, where the file system allows (Linux O_TMPFILE: ext4, xfs, btrfs, tmpfs): the
// file has no name until commit(); path() is /proc/<pid>/fd/<n>, which this process and its
// children (gnuplot) open like any path, and a process killed by SIGKILL leaves nothing behind.
// Otherwise, and for Kind::named (for writers that resolve the path they are given, as HDF5
// does), a hidden ".<name>.<pid>.<counter>.tmp" next to the target, which a kill can leave
// behind (see remove_stale_temporaries). commit() of an unnamed file passes through such a name
// for the moment between two system calls (linkat cannot replace an existing file).
class TemporaryFile {
 public:
  enum class Kind { unnamed, named };
  explicit TemporaryFile(const std::filesystem::path& target, Kind kind = Kind::unnamed);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  void commit();

 private:
  std::filesystem::path target_, path_;
  int fd_ = -1;  // the unnamed file (O_TMPFILE), or -1 for a named temporary
  bool committed_ = false;
};

// Removes, anywhere below `dir`, the temporaries of TemporaryFile that processes no longer running
// left behind: SIGKILL runs no destructor, so a run killed between creating a temporary and
// renaming it leaves one. Temporaries of live processes (this host's pids) are kept; on a
// directory shared between hosts the pid cannot tell, so concurrent runs on several hosts must
// not share an output directory. Returns the number removed; a missing `dir` removes nothing.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

// An exclusive lock on an output directory for as long as the object lives, so that two runs
// cannot write one directory at once: their checkpoints, tables and point folders would
// interleave (two friction_sweep runs of one point once ran side by side for 7 minutes). An
// advisory flock on `<dir>/.asperity.lock`, which the kernel releases when the process ends,
// however it ends, so a killed run leaves no stale lock; the file itself stays (removing it
// would let a third run lock a file that a second one has just opened). The holder writes its
// pid into it, for the message. A directory inside one that another run holds is refused too
// (that run writes below its directory: a sweep's point folders, which the sweep also locks one
// by one while it runs them); directories this process locked itself are not in the way.
// `run_dir`, if given, is a directory that this run holds through another of its processes (the
// sweep's directory, which rank 0 of a sweep over MPI ranks holds while the other ranks lock its
// point folders, mpi_points.hpp): its lock is not in the way either.
// Throws std::invalid_argument (exit status 2: a command-line problem) naming the locked
// directory and the holder's pid if another run holds the lock, and std::runtime_error if the
// lock file cannot be opened.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::filesystem::path& dir,
                         const std::filesystem::path& run_dir = {});
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

  static constexpr const char* kFileName = ".asperity.lock";

 private:
  std::filesystem::path dir_;  // canonical, for this process's list of held directories
  int fd_ = -1;
};

// Throws std::runtime_error naming `path` on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Pretty-printed with a 2-space indent and a trailing newline.
void write_json(const std::filesystem::path& path, const nlohmann::json& value);

// Comma-separated table with a header line. Doubles are written in shortest round-trip form, so
// reading a written table back gives bit-identical values. Fields containing commas, quotes or
// line breaks are quoted as in RFC 4180.
class CsvTable {
 public:
  using Cell = std::variant<double, long long, std::string>;

  explicit CsvTable(std::vector<std::string> columns);

  // Parsed tables hold every field as a string; the typed accessors below convert.
  static CsvTable parse(std::string_view text, const std::string& source_name);
  static CsvTable read(const std::filesystem::path& path);

  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows() const { return rows_.size(); }
  // Throws std::invalid_argument if the row length differs from the number of columns.
  void add_row(std::vector<Cell> row);

  std::size_t column_index(std::string_view name) const;  // throws if absent
  const Cell& cell(std::size_t row, std::size_t column) const { return rows_.at(row).at(column); }
  double number(std::size_t row, std::string_view column) const;
  long long integer(std::size_t row, std::string_view column) const;
  std::string text(std::size_t row, std::string_view column) const;

  std::string to_string() const;
  void write(const std::filesystem::path& path) const { write_file_atomic(path, to_string()); }

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<Cell>> rows_;
};

}  // namespace asperity::app
