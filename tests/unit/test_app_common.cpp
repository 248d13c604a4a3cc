// Shared helpers of the command-line tools: scene reading, result files, output-directory locks,
// plots, CLI wrapper.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "scratch.hpp"

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/point_runner.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "asperity/apps/common/vtk_lines.hpp"
#include "asperity/apps/common/xyz_io.hpp"

namespace asperity::app {
namespace {

using asperity::test_support::invalid_argument_message;

namespace fs = std::filesystem;

// Message of the std::invalid_argument thrown by `f`, or a failure if none is thrown.

SceneReader scene(std::string_view text) {
  return SceneReader::from_string(text, "scene.toml");
}

TEST(SceneReader, ReadsTypedValuesAndDefaults) {
  auto s = scene(R"(
    name = "demo"
    [contact]
    a = 2
    load = 1.5e-3
    steps = 40
    method = "fire"
    verbose = true
    loads = [1, 2.5]
  )");
  EXPECT_EQ(s.string("name", "x"), "demo");
  EXPECT_EQ(s.number("contact.a", 0.0, Range::positive()), 2.0);  // integer accepted
  EXPECT_EQ(s.number("contact.load", 0.0), 1.5e-3);
  EXPECT_EQ(s.integer("contact.steps", 1, Range::at_least(1)), 40);
  EXPECT_EQ(s.string("contact.method", "cg", {"cg", "fire"}), "fire");
  EXPECT_TRUE(s.boolean("contact.verbose", false));
  EXPECT_EQ(s.numbers("contact.loads", {}, Range::positive()), (std::vector<double>{1, 2.5}));
  EXPECT_EQ(s.number("contact.missing", 7.0), 7.0);
  EXPECT_FALSE(s.optional_number("other.missing").has_value());
  // has(): present whatever the value, absent through a missing or non-table parent; not a read.
  EXPECT_TRUE(s.has("contact.a"));
  EXPECT_FALSE(s.has("contact.missing"));
  EXPECT_FALSE(s.has("contact.a.deeper"));
  EXPECT_FALSE(s.has("other.missing"));
  auto only_asked = SceneReader::from_string("[x]\nk = 1\n", "t.toml");
  EXPECT_TRUE(only_asked.has("x.k"));
  EXPECT_THROW(only_asked.reject_unknown(), std::invalid_argument);
  EXPECT_NO_THROW(s.reject_unknown());
}

TEST(SceneReader, RejectsUnknownKeysNamingEach) {
  auto s = scene("[contact]\na = 1\nradius = 2\n[solver]\ntol = 1e-9\n");
  s.number("contact.a", 0.0);
  const std::string msg = invalid_argument_message([&] { s.reject_unknown(); });
  EXPECT_NE(msg.find("scene.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("contact.radius"), std::string::npos) << msg;
  EXPECT_NE(msg.find("solver.tol"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("contact.a"), std::string::npos) << msg;
}

TEST(SceneReader, RangeViolationNamesKeyValueAndRange) {
  auto s = scene("[contact]\na = -3\nnu = 0.7\nn = 0\n");
  EXPECT_NE(invalid_argument_message([&] {
              s.number("contact.a", 1.0, Range::positive());
            }).find("scene.toml: contact.a = -3: allowed: > 0"),
            std::string::npos);
  EXPECT_NE(invalid_argument_message([&] {
              s.number("contact.nu", 0.3, Range::closed(0, 0.5));
            }).find("contact.nu = 0.7: allowed: [0, 0.5]"),
            std::string::npos);
  EXPECT_NE(invalid_argument_message([&] {
              s.integer("contact.n", 1, Range::at_least(1));
            }).find("contact.n = 0: allowed: >= 1"),
            std::string::npos);
}

// A list row (settings::Kind::numbers) read from a scene and from a flag's comma-separated text,
// each value range-checked: the sweep's radii.
TEST(SceneReader, ListRowsReadFromScenesAndFlags) {
  struct Holder {
    std::vector<double> radii{1.0};
  };
  const settings::Table<Holder> table = {settings::numbers<Holder>(
      "sweep.R", [](auto& h) -> auto& { return h.radii; }, Range::positive(), "d", "radii", "--R")};
  Holder h;
  auto s = scene("[sweep]\nR = [40, 535.5]\n");
  s.read(table, h);
  EXPECT_EQ(h.radii, (std::vector<double>{40.0, 535.5}));
  Holder untouched;
  scene("[sweep]\n").read(table, untouched);
  EXPECT_EQ(untouched.radii, std::vector<double>{1.0});  // absent: the default stays
  EXPECT_NE(invalid_argument_message([&] {
              Holder bad;
              scene("[sweep]\nR = [40, -2]\n").read(table, bad);
            }).find("sweep.R"),
            std::string::npos);
  EXPECT_EQ(std::get<std::vector<double>>(parse_setting(table[0], "30,60.5,120")),
            (std::vector<double>{30.0, 60.5, 120.0}));
  EXPECT_THROW(parse_setting(table[0], "30,,60"), std::invalid_argument);
  EXPECT_THROW(parse_setting(table[0], "30,-1"), std::invalid_argument);
}

// summary.json's echo gives a choice named by integers (a sign) as its number, other choices as
// their names.
TEST(SettingFlags, EchoGivesASignAsItsNumber) {
  struct Holder {
    int sign = -1;
    std::string method = "flow";
  };
  const settings::Table<Holder> table = {
      settings::choice<Holder>(
          "lines.slip_sign", [](auto& h) -> auto& { return h.sign; }, {"-1", "1"},
          [](int s) { return std::to_string(s); },
          [](const std::string& s) { return std::stoi(s); }, "sign of the slip"),
      settings::choice<Holder>(
          "solver.method", [](auto& h) -> auto& { return h.method; }, {"lbfgs", "flow"}, "method")};
  Holder h;
  nlohmann::json echo = settings_echo(h, table);
  EXPECT_EQ(echo.at("lines.slip_sign"), nlohmann::json(-1));
  EXPECT_TRUE(echo.at("lines.slip_sign").is_number_integer());
  EXPECT_EQ(echo.at("solver.method"), nlohmann::json("flow"));
  h.sign = 1;
  EXPECT_EQ(settings_echo(h, table).at("lines.slip_sign"), nlohmann::json(1));
}

// A boolean's flag is a switch: alone it is true (the Python layer passes True as a bare flag),
// "=false" or " false" (joined by parse_command_line) false; it never takes a file name after it
// as its value; a value other than true/false is refused by the key. The default shows in the
// help, not as CLI11's default (which a bare flag would take).
TEST(SettingFlags, ABooleanFlagIsASwitch) {
  struct Holder {
    bool xyz = false;
    double tolerance = 1e-5;
  };
  const settings::Table<Holder> table = {
      settings::boolean<Holder>(
          "output.xyz", [](auto& h) -> auto& { return h.xyz; }, "also write XYZ", "--xyz"),
      settings::number<Holder>(
          "solver.tolerance", [](auto& h) -> auto& { return h.tolerance; }, Range::positive(), "",
          "tolerance", "--tolerance")};
  std::vector<std::string> files;
  const auto parse = [&](std::vector<std::string> args) {
    CLI::App cli;
    SettingFlags flags;
    const Holder defaults;
    flags.add(cli, table, {}, "summary key", &defaults);
    files.clear();
    cli.add_option("files", files);
    std::string out;
    cli.add_option("--out", out);
    EXPECT_TRUE(parse_command_line(cli, std::move(args)));
    Holder h;
    flags.apply(table, h);
    return h;
  };
  EXPECT_TRUE(parse({"--xyz"}).xyz);
  EXPECT_TRUE(parse({"--xyz", "--out", "x"}).xyz);
  EXPECT_TRUE(parse({"--xyz", "--tolerance", "1e-6"}).xyz);
  EXPECT_EQ(parse({"--xyz", "--tolerance", "1e-6"}).tolerance, 1e-6);
  // A file after the switch stays a file.
  EXPECT_TRUE(parse({"--xyz", "a.nc", "b.nc"}).xyz);
  EXPECT_EQ(files, (std::vector<std::string>{"a.nc", "b.nc"}));
  EXPECT_TRUE(parse({"--xyz", "true", "a.nc"}).xyz);
  EXPECT_EQ(files, (std::vector<std::string>{"a.nc"}));
  EXPECT_FALSE(parse({"--xyz", "false"}).xyz);
  EXPECT_FALSE(parse({"--xyz=false", "a.nc"}).xyz);
  EXPECT_EQ(files, (std::vector<std::string>{"a.nc"}));
  EXPECT_TRUE(parse({"--xyz=true"}).xyz);
  EXPECT_FALSE(parse({}).xyz);
  {
    CLI::App cli;
    SettingFlags flags;
    flags.add(cli, table);
    EXPECT_THROW(parse_command_line(cli, {"--xyz=yes"}), CLI::ValidationError);
  }
  // Other spellings of a truth value are the switch's, refused by its key, not a stray file.
  for (const char* spelling : {"True", "1", "FALSE"}) {
    CLI::App cli;
    SettingFlags flags;
    flags.add(cli, table);
    try {
      parse_command_line(cli, {"--xyz", spelling});
      ADD_FAILURE() << spelling << " accepted";
    } catch (const CLI::ValidationError& e) {
      EXPECT_NE(std::string(e.what()).find("output.xyz = " + std::string(spelling)),
                std::string::npos)
          << e.what();
    }
  }
  CLI::App cli;
  SettingFlags flags;
  const Holder defaults;
  flags.add(cli, table, {}, "summary key", &defaults);
  const std::string help = cli.help();
  EXPECT_NE(help.find("[=true|false]"), std::string::npos) << help;
  EXPECT_NE(help.find("(the flag alone: true); default false"), std::string::npos) << help;
}

// A number that may be left out (settings::optional_number): a flag gives a value (never NaN,
// which is how the row says "not given"); the echo writes null for it, the Markdown "not given".
TEST(SettingFlags, OptionalNumbersAreGivenOrLeftOut) {
  struct Holder {
    std::optional<double> k1;
    double k2 = 1.0;
  };
  const settings::Table<Holder> table = {
      settings::optional_number<Holder>(
          "k1", [](auto& h) -> auto& { return h.k1; }, Range::positive(), "", "prefactor", "--k1"),
      settings::number<Holder>(
          "k2", [](auto& h) -> auto& { return h.k2; }, Range::positive(), "", "exponent", "--k2")};
  EXPECT_EQ(std::get<double>(parse_setting(table[0], "2.5")), 2.5);
  EXPECT_THROW(parse_setting(table[0], "nan"), std::invalid_argument);
  EXPECT_THROW(parse_setting(table[0], "-1"), std::invalid_argument);
  Holder h;
  const nlohmann::json echo = settings_echo(h, table);
  EXPECT_TRUE(echo.at("k1").is_null());
  EXPECT_EQ(echo.at("k2").get<double>(), 1.0);
  h.k1 = 3.0;
  EXPECT_EQ(settings_echo(h, table).at("k1").get<double>(), 3.0);
  const std::string md = settings_markdown(Holder{}, table);
  EXPECT_NE(md.find("| `k1` | not given | > 0, or not given | `--k1` |"), std::string::npos) << md;
  // Through the flags: left out, the field keeps what it held (7 here); given, it is set. The
  // help shows the defaults' values, none for an optional number not given.
  for (const bool give : {false, true}) {
    CLI::App cli;
    SettingFlags flags;
    const Holder defaults;  // k1 not given, k2 = 1
    flags.add(cli, table, {}, "summary key", &defaults);
    const std::string help = cli.help();
    EXPECT_NE(help.find("--k2 NUMBER=1"), std::string::npos) << help;
    EXPECT_EQ(help.find("--k1 NUMBER="), std::string::npos) << help;
    EXPECT_NE(help.find("summary key k1, allowed: > 0, or not given"), std::string::npos) << help;
    std::vector<std::string> args = {"--k2", "2"};
    if (give) args = {"--k1", "4", "--k2", "2"};
    std::vector<const char*> argv = {"tool"};
    for (const auto& a : args)
      argv.push_back(a.c_str());
    cli.parse(static_cast<int>(argv.size()), argv.data());
    Holder got;
    got.k1 = 7.0;
    flags.apply(table, got);
    ASSERT_TRUE(got.k1.has_value());
    EXPECT_EQ(*got.k1, give ? 4.0 : 7.0);
    EXPECT_EQ(got.k2, 2.0);
  }
}

TEST(SceneReader, TypeErrorsNameKeyAndValue) {
  auto s = scene("[contact]\na = \"abc\"\nn = 1.5\nmethod = \"bfgs\"\n");
  EXPECT_NE(invalid_argument_message([&] {
              s.number("contact.a", 1.0);
            }).find("key 'contact.a': expected a number, got string \"abc\""),
            std::string::npos);
  EXPECT_NE(
      invalid_argument_message([&] { s.integer("contact.n", 1); }).find("expected an integer"),
      std::string::npos);
  EXPECT_NE(invalid_argument_message([&] {
              s.string("contact.method", "cg", {"cg", "fire"});
            }).find("contact.method = \"bfgs\": allowed: one of \"cg\", \"fire\""),
            std::string::npos);
  EXPECT_NE(invalid_argument_message([&] { s.number("contact.a.b", 1.0); }).find("not a table"),
            std::string::npos);
}

TEST(SceneReader, RejectsNonFiniteNumbers) {
  auto s = scene("a = nan\nb = inf\nc = [1.0, -inf]\n");
  EXPECT_NE(invalid_argument_message([&] { s.number("a", 1.0); }).find("a = nan: not a finite"),
            std::string::npos);
  EXPECT_THROW(s.number("b", 1.0), std::invalid_argument);
  EXPECT_NE(invalid_argument_message([&] { s.numbers("c", {}); }).find("c[1] = -inf"),
            std::string::npos);
}

TEST(SceneReader, ParseErrorNamesFileAndLine) {
  const std::string msg =
      invalid_argument_message([] { SceneReader::from_string("a = 1\nb = = 2\n", "bad.toml"); });
  EXPECT_EQ(msg.rfind("bad.toml:2:", 0), 0u) << msg;
  EXPECT_THROW(SceneReader::from_file("/nonexistent/scene.toml"), std::invalid_argument);
}

class FilesTest : public asperity::test_support::ScratchDirTest {
 protected:
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
};

TEST_F(FilesTest, AtomicWriteReplacesContentAndLeavesNoTemporaries) {
  const fs::path p = dir_ / "out.txt";
  write_file_atomic(p, "first version, longer\n");
  write_file_atomic(p, "second\n");
  EXPECT_EQ(slurp(p), "second\n");
  EXPECT_EQ(entries(), 1u);
  EXPECT_THROW(write_file_atomic(dir_ / "missing" / "x.txt", "x"), std::runtime_error);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(FilesTest, WriteJsonIsPrettyWithTrailingNewline) {
  write_json(dir_ / "r.json", {{"a", 1}});
  EXPECT_EQ(slurp(dir_ / "r.json"), "{\n  \"a\": 1\n}\n");
}

TEST_F(FilesTest, EnsureDirectoryRejectsFiles) {
  EXPECT_EQ(ensure_directory(dir_ / "a" / "b"), dir_ / "a" / "b");
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  write_file_atomic(dir_ / "f", "x");
  EXPECT_THROW(ensure_directory(dir_ / "f"), std::runtime_error);
}

// Another process holding a DirectoryLock on `dir` until kill() sends it SIGKILL (no destructor
// runs, as when a run is killed).
class LockHeldByChild {
 public:
  explicit LockHeldByChild(const fs::path& dir) {
    int ready[2];
    if (::pipe(ready) != 0) throw std::runtime_error("pipe failed");
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::close(ready[0]);
      try {
        const DirectoryLock held(dir);
        const char c = 'x';
        if (::write(ready[1], &c, 1) != 1) ::_exit(1);
        ::pause();
      } catch (...) {
      }
      ::_exit(1);
    }
    ::close(ready[1]);
    char c = 0;
    const bool locked = ::read(ready[0], &c, 1) == 1;
    ::close(ready[0]);
    if (!locked) {
      kill();
      throw std::runtime_error("the child did not take the lock");
    }
  }
  ~LockHeldByChild() { kill(); }
  LockHeldByChild(const LockHeldByChild&) = delete;
  LockHeldByChild& operator=(const LockHeldByChild&) = delete;

  pid_t pid() const { return pid_; }
  // True if the child died of the SIGKILL.
  bool kill() {
    if (pid_ <= 0) return false;
    int status = 0;
    const bool killed =
        ::kill(pid_, SIGKILL) == 0 && ::waitpid(pid_, &status, 0) == pid_ && WIFSIGNALED(status);
    pid_ = -1;
    return killed;
  }

 private:
  pid_t pid_ = -1;
};

TEST_F(FilesTest, DirectoryLockAdmitsOneRunAndDiesWithItsHolder) {
  {
    const DirectoryLock first(dir_);
    // A second lock (another open file, as another process would have) is refused, naming the
    // directory and the holder.
    const std::string message = invalid_argument_message([&] { DirectoryLock second(dir_); });
    EXPECT_NE(message.find("another run is writing to " + dir_.string()), std::string::npos)
        << message;
    EXPECT_NE(message.find("(process " + std::to_string(::getpid()) + ")"), std::string::npos)
        << message;
  }
  { const DirectoryLock again(dir_); }  // released with its holder

  // Another process holds it, then is killed: the lock goes with it.
  LockHeldByChild child(dir_);
  const std::string message = invalid_argument_message([&] { DirectoryLock mine(dir_); });
  EXPECT_NE(message.find("(process " + std::to_string(child.pid()) + ")"), std::string::npos)
      << message;
  EXPECT_TRUE(child.kill());
  EXPECT_NO_THROW(DirectoryLock after(dir_)) << "a killed holder left a stale lock";
}

// A sweep locks its directory, then each point folder while it runs: the folders below a
// directory another run holds are refused, those below this process's own locks are not.
TEST_F(FilesTest, DirectoryLockCoversTheFoldersBelowIt) {
  const fs::path point = ensure_directory(dir_ / "points" / "a250_R1700");
  const fs::path other = ensure_directory(dir_ / "points" / "a275_R1700");
  {
    const DirectoryLock sweep(dir_);
    const DirectoryLock first(point);
    const DirectoryLock second(other);
    EXPECT_THROW(DirectoryLock again(point), std::invalid_argument);  // still one run per folder
  }
  {
    // Released: its folders are free again, also to another process.
    const DirectoryLock first(point);
  }

  LockHeldByChild sweep(dir_);
  const std::string message = invalid_argument_message([&] { DirectoryLock mine(point); });
  EXPECT_NE(message.find("another run is writing to " + fs::weakly_canonical(dir_).string() +
                         ", which contains " + point.string()),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("(process " + std::to_string(sweep.pid()) + ")"), std::string::npos)
      << message;
  // The probe of the ancestor leaves it as it was: still held by the child.
  EXPECT_THROW(DirectoryLock still(dir_), std::invalid_argument);
  EXPECT_TRUE(sweep.kill());
  EXPECT_NO_THROW(DirectoryLock after(point)) << "a killed holder still guards its folders";
}

// Over MPI ranks, rank 0 holds the sweep's directory and the other ranks lock its point folders
// (mpi_points.hpp): the run's own directory, held by another of its processes, is not in the way;
// a directory further up that another run holds still is.
TEST_F(FilesTest, DirectoryLockLetsTheRunsOwnDirectoryPass) {
  const fs::path point = ensure_directory(dir_ / "points" / "a250_R1700");
  {
    LockHeldByChild rank0(dir_);
    EXPECT_THROW(DirectoryLock refused(point), std::invalid_argument);
    EXPECT_NO_THROW(DirectoryLock mine(point, dir_));
    // The run's directory itself stays rank 0's.
    EXPECT_THROW(DirectoryLock again(dir_, dir_), std::invalid_argument);
  }
  const fs::path sweep = ensure_directory(dir_ / "sweep");
  const fs::path inner = ensure_directory(sweep / "points" / "a6_R535");
  LockHeldByChild other_run(dir_);
  EXPECT_THROW(DirectoryLock mine(inner, sweep), std::invalid_argument);
}

TEST_F(FilesTest, CsvRoundTripIsBitIdentical) {
  const std::vector<double> values = {0.1,
                                      1.0 / 3.0,
                                      -2.5e-300,
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::max(),
                                      std::nextafter(1.0, 2.0)};
  CsvTable table({"i", "value", "label"});
  for (std::size_t i = 0; i < values.size(); ++i) {
    table.add_row({static_cast<long long>(i), values[i], i % 2 ? "plain" : "with, \"quote\"\n"});
  }
  EXPECT_THROW(table.add_row({1.0}), std::invalid_argument);
  table.write(dir_ / "t.csv");
  EXPECT_EQ(entries(), 1u);

  const CsvTable back = CsvTable::read(dir_ / "t.csv");
  ASSERT_EQ(back.columns(), table.columns());
  ASSERT_EQ(back.rows(), values.size());
  for (std::size_t r = 0; r < values.size(); ++r) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back.number(r, "value")),
              std::bit_cast<std::uint64_t>(values[r]));
    EXPECT_EQ(back.integer(r, "i"), static_cast<long long>(r));
    EXPECT_EQ(back.text(r, "label"), table.text(r, "label"));
  }
  EXPECT_EQ(back.to_string(), table.to_string());
  EXPECT_THROW(back.number(0, "label"), std::invalid_argument);
  EXPECT_THROW(back.number(0, "nope"), std::invalid_argument);
  EXPECT_THROW(CsvTable::parse("a,b\n1\n", "x.csv"), std::invalid_argument);
}

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof magic);
  return in && std::string_view(magic, 8) == "\x89PNG\r\n\x1a\n";
}

TEST_F(FilesTest, PlotWritesPng) {
  std::vector<double> x, y;
  for (int i = 0; i < 50; ++i) {
    x.push_back(0.1 * (i + 1));
    y.push_back(std::exp(-x.back()));
  }
  y[10] = std::numeric_limits<double>::quiet_NaN();
  PlotOptions options;
  options.title = "it's a test";
  options.xlabel = "x_0";
  options.logy = true;
  options.keep_script = true;
  plot_png(dir_ / "p.png", {{x, y, "exp(-x)"}, {x, x, "", "points"}}, options);
  EXPECT_TRUE(is_png(dir_ / "p.png"));
  EXPECT_TRUE(fs::exists(dir_ / "p.gp"));
  EXPECT_EQ(entries(), 2u);

  EXPECT_THROW(plot_png(dir_ / "q.png", {{x, {1.0}, "bad"}}, {}), std::invalid_argument);
  PlotOptions broken;
  broken.extra_commands = {"this is not gnuplot"};
  EXPECT_THROW(plot_png(dir_ / "q.png", {{x, y, ""}}, broken), std::runtime_error);
  // A gnuplot that does not finish is killed at the timeout, and the figure fails.
  PlotOptions stuck;
  stuck.extra_commands = {"pause 30"};
  stuck.timeout_s = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_THROW(plot_png(dir_ / "r.png", {{x, y, ""}}, stuck), std::runtime_error);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "r.png"));
  EXPECT_EQ(entries(), 2u);
}

TEST_F(FilesTest, HeatmapWritesPng) {
  const std::vector<double> x = {0, 1, 2, 4}, y = {0, 0.5, 1};
  std::vector<double> v;
  for (double xi : x) {
    for (double yj : y)
      v.push_back(xi * yj);
  }
  PlotOptions options;
  options.title = "map";
  heatmap_png(dir_ / "h.png", x, y, v, options, "energy", std::pair{0.0, 4.0},
              {{{0, 4}, {0, 1}, "path"}});
  EXPECT_TRUE(is_png(dir_ / "h.png"));
  EXPECT_EQ(entries(), 1u);
  EXPECT_THROW(heatmap_png(dir_ / "h.png", x, y, {1.0}, options), std::invalid_argument);
}

int run_with(const std::function<int(int, char**)>& body, std::string& err,
             std::vector<std::string> args = {"/usr/bin/tool"}) {
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  ::testing::internal::CaptureStderr();
  const int status = run_main(static_cast<int>(argv.size()), argv.data(), body);
  err = ::testing::internal::GetCapturedStderr();
  return status;
}

TEST(RunMain, MapsExceptionsToExitStatus) {
  std::string err;
  EXPECT_EQ(run_with([](int, char**) { return 0; }, err), 0);
  EXPECT_EQ(run_with([](int, char**) -> int { throw std::invalid_argument("bad k"); }, err), 2);
  EXPECT_EQ(err, "tool: error: bad k\n");
  EXPECT_EQ(run_with([](int, char**) -> int { throw std::runtime_error("disk full"); }, err), 1);
  EXPECT_EQ(err, "tool: error: disk full\n");
}

TEST(RunMain, CommandLineParsing) {
  auto body = [](int argc, char** argv) {
    CLI::App cli{"test tool"};
    double load = 0;
    cli.add_option("--load", load, "Normal load");
    if (!parse_command_line(cli, argc, argv)) return 0;
    return load == 2.0 ? 0 : 3;
  };
  std::string err;
  EXPECT_EQ(run_with(body, err, {"tool", "--load", "2"}), 0);
  EXPECT_EQ(run_with(body, err, {"tool", "--bogus"}), 2);
  EXPECT_EQ(err.rfind("tool: error: ", 0), 0u) << err;
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(run_with(body, err, {"tool", "--help"}), 0);
  EXPECT_NE(::testing::internal::GetCapturedStdout().find("--load"), std::string::npos);
}

TEST(Provenance, HasVersionAndDate) {
  const auto j = provenance_json();
  const std::string version = j.at("version").get<std::string>();
  EXPECT_FALSE(version.empty());
  EXPECT_FALSE(j.at("commit").get<std::string>().empty());
  EXPECT_EQ(j.at("date_utc").get<std::string>().size(), 20u);  // 2024-01-31T12:00:00Z
  EXPECT_EQ(provenance_string().rfind("asperity " + version, 0), 0u);
}

TEST(Provenance, CommitIsTheBuildsNotTheConfigures) {
  // The commit is found at build time: after a commit the next build carries the new hash (it
  // was fixed at configure time and labelled results and checkpoints of later code with an old
  // commit). This test runs right after the build of the checkout it was built from, so the
  // hash is HEAD's, "+dirty.<hash of the diff>" exactly when tracked files differ from HEAD.
  const std::string commit = git_commit();
  // Output and exit status of a shell command.
  const auto shell = [](const std::string& command, std::string& out) {
    FILE* p = ::popen(command.c_str(), "r");
    if (!p) return -1;
    char buf[256];
    out.clear();
    while (std::fgets(buf, sizeof buf, p))
      out += buf;
    return ::pclose(p);
  };
  const std::string git = std::string("git -C '") + ASPERITY_SOURCE_DIR + "' ";
  std::string hash, diff;
  if (shell(git + "rev-parse --short HEAD 2>/dev/null", hash) != 0 || hash.empty())
    GTEST_SKIP() << "not a git checkout: " << commit;
  hash.erase(hash.find_last_not_of('\n') + 1);
  const bool dirty = shell(git + "diff --quiet HEAD", diff) != 0;
  EXPECT_EQ(commit.rfind(hash, 0), 0u) << commit << " against HEAD " << hash;
  EXPECT_EQ(commit.find("+dirty.") != std::string::npos, dirty) << commit;
  EXPECT_NE(provenance_token().find(hash), std::string::npos);
}

TEST(Progress, PrintsALineEveryStepInLogs) {
  std::ostringstream out;
  {
    Progress progress("relax", 200, out, false, 25);
    for (int i = 0; i < 200; ++i)
      progress.advance();
  }
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 5) << text;  // 0, 25, 50, 75, 100 %
  EXPECT_NE(text.find("relax: 200/200 (100%)"), std::string::npos) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos);
}

// A row for another rank (mpi_points.hpp) reads back bit for bit: NaN with its sign and
// payload, -0.0, infinities, subnormals, the integer limits, strings of any bytes, each cell
// with its type; a row that ends early or goes on is refused.
TEST(ByteWriter, RowsReadBackBitForBit) {
  const double payload_nan = std::bit_cast<double>(std::uint64_t{0xfff8000000000123});
  const std::vector<double> reals = {payload_nan,
                                     -0.0,
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     std::numeric_limits<double>::denorm_min(),
                                     1.0 / 3.0};
  const std::string text("a,b \"c\"\n\0d", 10);
  ByteWriter w;
  for (double v : reals)
    w.real(v);
  w.integer(std::numeric_limits<std::int64_t>::min())
      .integer(std::numeric_limits<std::int64_t>::max());
  w.text(text).text("");
  w.cell(CsvTable::Cell{0.1}).cell(CsvTable::Cell{-7LL}).cell(CsvTable::Cell{std::string("x,y")});

  ByteReader r(w.bytes());
  for (double v : reals)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(r.real()), std::bit_cast<std::uint64_t>(v));
  EXPECT_EQ(r.integer(), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(r.integer(), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(r.text(), text);
  EXPECT_EQ(r.text(), "");
  EXPECT_EQ(r.cell(), CsvTable::Cell{0.1});
  EXPECT_EQ(r.cell(), CsvTable::Cell{-7LL});
  EXPECT_EQ(r.cell(), CsvTable::Cell{std::string("x,y")});
  EXPECT_NO_THROW(r.finish());

  const std::string& bytes = w.bytes();
  ByteReader short_row(std::string_view(bytes).substr(0, 12));
  short_row.real();
  EXPECT_THROW(short_row.real(), std::runtime_error);
  ByteReader long_row(bytes);
  long_row.real();
  EXPECT_THROW(long_row.finish(), std::runtime_error);
}

// One process (no MPI launcher, or a build without MPI): Ranks::run_points is the serial pool,
// each row recorded once, by rank 0, and the interrupted points counted.
TEST(Ranks, OneProcessRunsThePointsAsThePool) {
  std::vector<std::string> args = {"/usr/bin/tool"};
  std::vector<char*> argv = {args[0].data(), nullptr};
  int argc = 1;
  char** argv_p = argv.data();
  Ranks ranks(argc, argv_p);
  EXPECT_FALSE(ranks.distributed());
  EXPECT_TRUE(ranks.leader());
  EXPECT_EQ(ranks.hardware_threads(), static_cast<int>(std::thread::hardware_concurrency()));
  ranks.start("anything");
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < 40; ++i)
    ids.push_back(39 - i);
  std::vector<std::atomic<int>> recorded(40);
  std::atomic<bool> stop{false};
  const std::size_t interrupted = ranks.run_points(
      ids, 3,
      [](std::size_t id) -> std::optional<std::string> {
        if (id % 10 == 0) return std::nullopt;  // interrupted: no row
        return ByteWriter().integer(static_cast<std::int64_t>(id) * 2).bytes();
      },
      [&](std::size_t id, std::string_view row, int rank) {
        EXPECT_EQ(rank, 0);
        EXPECT_EQ(ByteReader(row).integer(), static_cast<std::int64_t>(id) * 2);
        ++recorded[id];
      },
      stop);
  EXPECT_EQ(interrupted, 4u);
  for (std::size_t id = 0; id < 40; ++id)
    EXPECT_EQ(recorded[id].load(), id % 10 == 0 ? 0 : 1) << id;
  EXPECT_EQ(ranks.phase(), Ranks::Phase::done);
  EXPECT_EQ(ranks.finish(3), 3);
}

}  // namespace
}  // namespace asperity::app

// The point runner (point_runner.hpp): every point once over several threads; a point that
// throws stops the others from starting new points and its exception comes out; a point that
// sets `stop` likewise ends the run.
TEST(PointRunner, RunsEveryPointOnceAndStopsOnFailure) {
  std::vector<std::atomic<int>> runs(50);
  std::atomic<bool> stop{false};
  asperity::app::run_points(
      runs.size(), 3, [&](std::size_t i) { ++runs[i]; }, stop);
  for (const auto& r : runs)
    EXPECT_EQ(r.load(), 1);
  EXPECT_FALSE(stop);

  // The points after the failing one wait (up to 10 s) until the failure has set `stop`:
  // without that, under load the other thread could run all 996 trivial points before the
  // thread of point 3 got to throw, and the test would measure the scheduler.
  std::atomic<int> started{0};
  EXPECT_THROW(asperity::app::run_points(
                   1000, 2,
                   [&](std::size_t i) {
                     ++started;
                     if (i == 3) throw std::runtime_error("point 3 failed");
                     for (int k = 0; i > 3 && !stop && k < 10000; ++k)
                       std::this_thread::sleep_for(std::chrono::milliseconds(1));
                   },
                   stop),
               std::runtime_error);
  EXPECT_TRUE(stop);
  EXPECT_LT(started.load(), 10);  // points 0-3, and at most one more per thread

  stop = false;
  started = 0;
  asperity::app::run_points(
      1000, 1,
      [&](std::size_t i) {
        ++started;
        if (i == 9) stop = true;
      },
      stop);
  EXPECT_EQ(started.load(), 10);
}

namespace {

// A 2 x 3 block at lattice origin (5, -1) with the explicit model's u_z.
asperity::slide::Snapshot xyz_frame() {
  asperity::slide::Snapshot s;
  s.label = "slip_001_after";
  s.Dx = 1.25;
  s.block.shape = {2, 3};
  s.block.origin0 = 5;
  s.block.origin1 = -1;
  const std::size_t n = 6;
  for (auto* f : {&s.ux, &s.uy, &s.sx, &s.sy, &s.tau_x, &s.tau_y, &s.tau_max, &s.pressure, &s.uz})
    f->assign(n, 0.0);
  s.in_contact.assign(n, 1);
  s.ux[4] = 0.1;    // site (1, 1): X = 6, Y = 0
  s.uz[4] = -0.03;  // the explicit model's normal displacement: the height of the site
  s.sx[4] = -1.6;   // registry index -2
  s.sy[4] = 0.4;    // 0
  return s;
}

}  // namespace

// The explicit model's frames carry u_z: it is the z of the positions and a column of its own,
// and the registry index is round(s) (halves away from zero, as the slider counts slips).
TEST(ExtendedXyz, ExplicitHeightRegistryAndHeader) {
  const std::string text = asperity::app::extended_xyz_frame(
      xyz_frame(), {{"model", "explicit"}, {"bad key", 1}}, false);
  std::istringstream in(text);
  std::string count, comment, line;
  std::getline(in, count);
  std::getline(in, comment);
  EXPECT_EQ(count, "6");
  EXPECT_NE(comment.find("Lattice=\"2 0 0 0 3 0 0 0 1\""), std::string::npos) << comment;
  EXPECT_NE(comment.find(":pressure:R:1:uz:R:1:in_contact:I:1:registry_x:I:1"), std::string::npos)
      << comment;
  EXPECT_NE(comment.find("label=\"slip_001_after\""), std::string::npos) << comment;
  EXPECT_NE(comment.find("model=\"explicit\""), std::string::npos) << comment;
  EXPECT_EQ(comment.find("bad key"), std::string::npos) << "a key the format cannot carry";
  for (int k = 0; k <= 4; ++k)
    std::getline(in, line);
  EXPECT_EQ(line, "X 6.1 0 -0.03 0.1 0 -1.6 0.4 0 0 0 0 -0.03 1 -2 0");
}

TEST(ExtendedXyz, RefusesAFieldOfTheWrongSize) {
  asperity::slide::Snapshot s = xyz_frame();
  s.tau_x.pop_back();
  EXPECT_THROW((void)asperity::app::extended_xyz_frame(s, nullptr, true), std::invalid_argument);
}

// A loop is closed by its first point again, whose angle is the closing segment's; the counts
// of the legacy format agree with the points.
TEST(VtkLines, LoopClosedAndCounted) {
  asperity::app::VtkLinesFrame f{
      .frame = 3, .iteration = 40, .Dx = 0.5, .title = "t\nx", .lines = {}};
  f.lines.push_back({.id = 7,
                     .kind = 0,
                     .closed = true,
                     .burgers_x = -1.0,
                     .length = 3.0,
                     .points = {{0, 0}, {1, 0}, {0, 1}},
                     .angle_deg = {0.0, 45.0, 90.0}});
  f.lines.push_back({.id = 9,
                     .kind = 1,
                     .closed = false,
                     .burgers_x = -1.0,
                     .length = 1.0,
                     .points = {{2, 2}, {2, 3}},
                     .angle_deg = {80.0}});
  const std::string text = asperity::app::vtk_lines_text(f);
  EXPECT_NE(text.find("\nt x\n"), std::string::npos) << "one title line";
  EXPECT_NE(text.find("POINTS 6 double\n"), std::string::npos) << text;
  EXPECT_NE(text.find("LINES 2 8\n4 0 1 2 3\n2 4 5\n"), std::string::npos) << text;
  EXPECT_NE(text.find("SCALARS character int 1\nLOOKUP_TABLE default\n0\n1\n2\n2\n2\n2\n"),
            std::string::npos)
      << text;
  f.lines[1].angle_deg.push_back(10.0);  // an open line has one segment fewer than points
  EXPECT_THROW((void)asperity::app::vtk_lines_text(f), std::invalid_argument);
}
