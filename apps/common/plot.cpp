#include "asperity/apps/common/plot.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "asperity/apps/common/output_files.hpp"

extern char** environ;

namespace asperity::app {
namespace {

struct ProcessResult {
  int status;          // exit status, -1 if killed by a signal
  std::string output;  // stdout and stderr interleaved
};

// Runs args, killed (and an error thrown) if it has not finished within `timeout`.
ProcessResult run_process(const std::vector<std::string>& args,
                          std::chrono::milliseconds timeout = std::chrono::minutes(10)) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error("cannot run " + args[0] + ": " + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  std::vector<char*> argv;
  for (const auto& a : args)
    argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // Its own process group: a Ctrl-C at the terminal is for our process, which finishes the
  // figure it is drawing before it stops (a killed gnuplot would fail a finished point).
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  const int err = ::posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (err != 0) {
    ::close(fds[0]);
    throw std::runtime_error("cannot run " + args[0] + ": " + std::strerror(err));
  }
  ProcessResult result{-1, {}};
  char buf[4096];
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool timed_out = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{.fd = fds[0], .events = POLLIN, .revents = 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      result.output.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  // Its whole process group (it was started as the group's leader).
  if (timed_out) ::kill(-pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out) {
    throw std::runtime_error(args[0] + " did not finish in " +
                             std::to_string(std::chrono::duration<double>(timeout).count()) +
                             " s and was killed");
  }
  if (WIFEXITED(status)) result.status = WEXITSTATUS(status);
  return result;
}

// pngcairo draws antialiased text and lines, but some gnuplot builds lack it.
const std::string& png_terminal() {
  static const std::string terminal =
      run_process({ASPERITY_GNUPLOT, "-e", "set terminal"}).output.find("pngcairo") !=
              std::string::npos
          ? "pngcairo"
          : "png";
  return terminal;
}

// gnuplot single-quoted strings have no escapes except '' for a quote.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (char c : s)
    out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string num(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

// append() rather than "[" + string: GCC 12 warns falsely (-Wrestrict) on the latter.
std::string range(const std::pair<double, double>& r) {
  return std::string("[").append(num(r.first)).append(":").append(num(r.second)).append("]");
}

void check(const Series& s) {
  if (s.x.size() != s.y.size()) {
    throw std::invalid_argument("plot series '" + s.title + "': " + std::to_string(s.x.size()) +
                                " x values but " + std::to_string(s.y.size()) + " y values");
  }
}

// A blank line breaks a gnuplot line, so non-finite points become gaps.
std::string data_block(const std::string& name, const Series& s) {
  std::string out = name + " << EOD\n";
  bool gap = true;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const bool finite = std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
    if (finite) out += num(s.x[i]) + " " + num(s.y[i]) + "\n";
    if (!finite && !gap) out += "\n";
    gap = !finite;
  }
  return out + "EOD\n";
}

std::string plot_item(const std::string& data, const std::string& columns, const Series& s) {
  return data + " using " + columns + " with " + s.style + " " +
         (s.title.empty() ? "notitle" : "title " + quote(s.title));
}

std::string axes_setup(const PlotOptions& o) {
  std::string out;
  if (!o.title.empty()) out += "set title " + quote(o.title) + "\n";
  if (!o.xlabel.empty()) out += "set xlabel " + quote(o.xlabel) + "\n";
  if (!o.ylabel.empty()) out += "set ylabel " + quote(o.ylabel) + "\n";
  if (o.logx) out += "set logscale x\n";
  if (o.logy) out += "set logscale y\n";
  if (o.xrange) out += "set xrange " + range(*o.xrange) + "\n";
  if (o.yrange) out += "set yrange " + range(*o.yrange) + "\n";
  return out;
}

void render(const std::filesystem::path& png, const std::string& body, const PlotOptions& o) {
  if (o.width <= 0 || o.height <= 0) {
    throw std::invalid_argument("plot size must be positive, got " + std::to_string(o.width) + "x" +
                                std::to_string(o.height));
  }
  std::string extra;
  for (const auto& c : o.extra_commands)
    extra += c + "\n";
  auto script = [&](const std::filesystem::path& output) {
    return "set terminal " + png_terminal() + " size " + std::to_string(o.width) + "," +
           std::to_string(o.height) + " noenhanced\nset output " + quote(output.string()) + "\n" +
           axes_setup(o) + extra + body;
  };

  std::filesystem::path gp = png;
  gp.replace_extension(".gp");
  TemporaryFile image(png), script_file(gp);
  std::ofstream(script_file.path()) << script(image.path());
  if (!(o.timeout_s > 0.0)) {
    throw std::invalid_argument("plot timeout must be positive, got " +
                                std::to_string(o.timeout_s));
  }
  const ProcessResult result = run_process(
      {ASPERITY_GNUPLOT, script_file.path().string()},
      std::chrono::milliseconds(static_cast<long long>(std::ceil(1000.0 * o.timeout_s))));
  std::error_code ec;
  if (result.status != 0 || std::filesystem::file_size(image.path(), ec) == 0 || ec) {
    throw std::runtime_error("gnuplot failed to draw '" + png.string() + "':\n" + result.output);
  }
  image.commit();
  if (o.keep_script) write_file_atomic(gp, script(png));
}

}  // namespace

void plot_png(const std::filesystem::path& png, const std::vector<Series>& series,
              const PlotOptions& options) {
  if (series.empty()) throw std::invalid_argument("plot '" + png.string() + "': no series");
  std::string data, plot = "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    check(series[k]);
    const std::string name = "$s" + std::to_string(k);
    data += data_block(name, series[k]);
    plot += (k ? ", " : "") + plot_item(name, "1:2", series[k]);
  }
  render(png, data + plot + "\n", options);
}

void heatmap_png(const std::filesystem::path& png, const std::vector<double>& x,
                 const std::vector<double>& y, const std::vector<double>& values,
                 const PlotOptions& options, const std::string& cblabel,
                 std::optional<std::pair<double, double>> cbrange,
                 const std::vector<Series>& overlays) {
  if (x.size() < 2 || y.size() < 2 || values.size() != x.size() * y.size()) {
    throw std::invalid_argument("heatmap '" + png.string() + "': need a grid of at least 2 x 2 " +
                                "with x.size() * y.size() values, got " + std::to_string(x.size()) +
                                " x " + std::to_string(y.size()) + " and " +
                                std::to_string(values.size()) + " values");
  }
  if (!std::is_sorted(x.begin(), x.end(), std::less_equal<>()) ||
      !std::is_sorted(y.begin(), y.end(), std::less_equal<>())) {
    throw std::invalid_argument("heatmap '" + png.string() +
                                "': grid coordinates must be strictly increasing");
  }
  // A picture cannot show more cells than it has pixels, and gnuplot takes seconds per million
  // cells (17 s for a 2048 x 2048 snapshot): larger grids are averaged over blocks (the
  // finite values of each) down to at most kMaxCells per axis.
  constexpr std::size_t kMaxCells = 512;
  const std::size_t bx = (x.size() + kMaxCells - 1) / kMaxCells;
  const std::size_t by = (y.size() + kMaxCells - 1) / kMaxCells;
  const auto block_mean = [](const std::vector<double>& v, std::size_t i, std::size_t bin) {
    double sum = 0.0;
    std::size_t end = std::min(v.size(), (i + 1) * bin), n = 0;
    for (std::size_t a = i * bin; a < end; ++a, ++n)
      sum += v[a];
    return sum / static_cast<double>(n);
  };
  const std::size_t nx = (x.size() + bx - 1) / bx, ny = (y.size() + by - 1) / by;
  // One gnuplot scan per x value; pm3d colours each grid cell by the mean of its corners.
  std::string data = "$map << EOD\n";
  for (std::size_t i = 0; i < nx; ++i) {
    for (std::size_t j = 0; j < ny; ++j) {
      double sum = 0.0;
      std::size_t count = 0;
      for (std::size_t a = i * bx; a < std::min(x.size(), (i + 1) * bx); ++a) {
        for (std::size_t b = j * by; b < std::min(y.size(), (j + 1) * by); ++b) {
          const double v = values[a * y.size() + b];
          if (std::isfinite(v)) {
            sum += v;
            ++count;
          }
        }
      }
      const double v = count > 0 ? sum / static_cast<double>(count) : std::nan("");
      data += num(block_mean(x, i, bx)) + " " + num(block_mean(y, j, by)) + " " + num(v) + "\n";
    }
    data += "\n";
  }
  data += "EOD\n";
  // Overlays sit at a z taken from the data so that they do not widen the autoscaled ranges.
  const auto finite =
      std::find_if(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
  const double z = finite == values.end() ? 0.0 : *finite;
  std::string plot = "splot $map using 1:2:3 with pm3d notitle";
  for (std::size_t k = 0; k < overlays.size(); ++k) {
    check(overlays[k]);
    const std::string name = "$o" + std::to_string(k);
    data += data_block(name, overlays[k]);
    plot += ", " + plot_item(name, "1:2:(" + num(z) + ")", overlays[k]);
  }
  std::string setup =
      "set view map\nset pm3d at b\n"
      "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n";
  if (!cblabel.empty()) setup += "set cblabel " + quote(cblabel) + "\n";
  if (cbrange) setup += "set cbrange " + range(*cbrange) + "\n";
  // Without this gnuplot extends the axes to round tic values, leaving blank bands.
  if (!options.xrange) setup += "set autoscale xfix\n";
  if (!options.yrange) setup += "set autoscale yfix\n";
  // The key opaque over the map, set before the caller's commands so that they can restyle it
  // (a later "set key opaque" would reset a fill colour they chose).
  PlotOptions o = options;
  o.extra_commands.insert(o.extra_commands.begin(), "set key opaque");
  render(png, setup + data + plot + "\n", o);
}

}  // namespace asperity::app
