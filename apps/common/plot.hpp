// Figures as PNG files through gnuplot. The data go inline into the gnuplot script, so a kept
// script (PlotOptions::keep_script) reproduces the figure on its own.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace asperity::app {

struct Series {
  std::vector<double> x, y;  // same length; non-finite values leave gaps
  std::string title;         // empty: no legend entry
  // gnuplot style, e.g. "points", "linespoints", "lines lw 2 lc 'red'"
  std::string style = "lines";
};

struct PlotOptions {
  std::string title, xlabel, ylabel;  // plain text: gnuplot enhanced-text markup is off
  bool logx = false, logy = false;    // logarithmic axes
  int width = 900, height = 600;      // image size, pixels
  std::optional<std::pair<double, double>> xrange, yrange;  // axis limits; default autoscale
  std::vector<std::string> extra_commands;  // gnuplot commands issued just before plotting
  bool keep_script = false;  // also write the gnuplot script as <png without extension>.gp
  // gnuplot is killed, and the figure fails, after this long (s): the figures a sweep draws
  // mid-slide (friction_sweep --largest-slip, at every slip of a run of days) must not hang it
  // on a stuck gnuplot; the largest maps take seconds.
  double timeout_s = 600.0;
};

// Line/point plot. Throws std::invalid_argument for empty or mismatched series and
// std::runtime_error with gnuplot's messages if gnuplot fails.
void plot_png(const std::filesystem::path& png, const std::vector<Series>& series,
              const PlotOptions& options);

// Colour map of values[i * y.size() + j] at (x[i], y[j]) on a rectilinear grid (at least 2 x 2,
// coordinates increasing, spacing may be uneven), with optional line overlays such as traced
// paths. Colour range follows the data unless `cbrange` is given.
void heatmap_png(const std::filesystem::path& png, const std::vector<double>& x,
                 const std::vector<double>& y, const std::vector<double>& values,
                 const PlotOptions& options, const std::string& cblabel = "",
                 std::optional<std::pair<double, double>> cbrange = std::nullopt,
                 const std::vector<Series>& overlays = {});

}  // namespace asperity::app
