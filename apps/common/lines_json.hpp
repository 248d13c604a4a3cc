// A dislocation line (tracking::Line, MODEL.md section 7) as the JSON record of track_loops'
// lines.json: one description for the tool and the Python package (python/), whose find_lines()
// returns the same records.
#pragma once

#include <nlohmann/json.hpp>

#include "asperity/tracking/lines.hpp"

namespace asperity::app {

// A number, or null where it is not finite (the aspect ratio of a line along x).
nlohmann::json finite_or_null(double v);

// Line `l` of frame `f` under its id (track_loops: the persistent id of the tracker), with the
// location class of its centroid (tracking::location_class with `centre_fraction`).
nlohmann::json line_json(const tracking::Line& l, int id, const tracking::FrameLines& f,
                         double centre_fraction);

}  // namespace asperity::app
