// A dislocation line (tracking::Line, MODEL.md section 7) as the JSON record of track_loops'
// lines.json: one description for the tool and the Python package (python/), whose find_lines()
// returns the same records. Likewise the census of a frame's lines (tracking::census), the
// columns of friction_sweep's slips.csv and the "census" of Python's find_lines().
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"

namespace asperity::app {

// A number, or null where it is not finite (the aspect ratio of a line along x).
nlohmann::json finite_or_null(double v);

// Line `l` of frame `f` under its id (track_loops: the persistent id of the tracker), with the
// location class of its centroid (tracking::location_class with `centre_fraction`).
nlohmann::json line_json(const tracking::Line& l, int id, const tracking::FrameLines& f,
                         double centre_fraction);

// The census as named values in their order (counts as integers, the rest as doubles, NaN where
// there is no loop); the names are the struct's fields.
std::vector<std::pair<std::string, nlohmann::json>> census_fields(const tracking::LineCensus& c);

}  // namespace asperity::app
