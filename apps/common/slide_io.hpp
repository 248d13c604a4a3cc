// Scene files and result files of the sliding tools (contact_slide, friction_sweep).
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "interface/lfm.hpp"
#include "slide/slider.hpp"

namespace asperity::app {

struct SlideScene {
  interface::ContactScene contact;
  slide::SlideOptions options;
};

// Reads a scene (data/scenes/default.toml documents every key); unknown keys, wrong types and
// out-of-range values throw std::invalid_argument naming the file, key, value and range.
SlideScene read_slide_scene(const std::string& path);

// summary.json contents: parameters, results, cost and accuracy (tolerances, steps, grid).
nlohmann::json slide_summary(const SlideScene& scene, const slide::SlideResult& result);

// Writes trace.csv, summary.json, the figures and the NetCDF snapshots into dir.
// Returns the list of files written (figures first).
std::vector<std::filesystem::path> write_slide_outputs(const std::filesystem::path& dir,
                                                       const SlideScene& scene,
                                                       const slide::SlideResult& result);

}  // namespace asperity::app
