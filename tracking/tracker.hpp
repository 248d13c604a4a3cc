// Following dislocation lines through a sequence of snapshots (MODEL.md sections 5 and 7).
//
// Lines of consecutive frames are linked when they have the same |b| and either their slipped
// regions overlap (overlap coefficient |A n B| / min(|A|, |B|) >= min_overlap, for lines whose
// bounding boxes, grown by max_motion, meet) or their centroids are within
// max_centroid_distance (in a periodic cell by minimum image: lines are unwrapped from their
// first crossing, so a loop gliding across the cell's side jumps by a side). Of these candidates
// each line keeps its best (nearest bounding box, then nearest centroid) on the other side. The
// links form a bipartite graph (Boost.Graph); each connected component is one story: 0 -> 1
// nucleation, 1 -> 0 annihilation, 1 -> 1 the same line (same persistent id), n -> 1 merge, 1 -> n
// split, n -> m reconnection. Merged, split and reconnected lines get new ids. A line that keeps
// its id is classified each interval by the change of its slipped area: growth (slip spreads),
// retreat, or arrest (change below arrest_area); an event is recorded when that state changes.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "lines.hpp"

namespace asperity::tracking {

struct TrackOptions {
  // Overlap coefficient of slipped regions that links two lines of consecutive frames (0..1].
  double min_overlap = 0.3;
  // Centroids closer than this link two lines even without overlap (d): a small loop can move
  // off its own slipped region between frames.
  double max_centroid_distance = 3.0;
  // Largest distance a line moves between frames (d): overlapping regions link only lines whose
  // bounding boxes are closer than this (several lines can share one slipped domain).
  double max_motion = 20.0;
  // A change of slipped area below this between frames is an arrest (d^2).
  double arrest_area = 2.0;
  // Nucleation and annihilation within this fraction of the contact radius of the centre are
  // classed "centre" (see location_class).
  double centre_fraction = 0.5;

  // Each setting described once (core/common/settings.hpp): keys min_overlap,
  // max_centroid_distance, max_motion, arrest_area, centre_fraction; track_loops lifts them
  // under "track.".
  static const settings::Table<TrackOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated setting
};

enum class EventType {
  nucleation,
  growth,
  retreat,
  arrest,
  annihilation,
  merge,
  split,
  reconnection
};
std::string to_string(EventType type);

struct Event {
  int frame = 0;  // index of the frame (in the order given to Tracker::add) where it is seen
  EventType type = EventType::nucleation;
  std::vector<int> before;           // ids in the previous frame
  std::vector<int> after;            // ids in this frame
  Point where;                       // mean centroid of the lines concerned (d)
  std::string location;              // nucleation and annihilation: location_class(); else empty
  double slipped_area_change = 0.0;  // sum over `after` minus sum over `before` (d^2)
};

class Tracker {
 public:
  explicit Tracker(TrackOptions options = {});

  // Adds the next frame: returns the persistent id of each of its lines (same order) and
  // records the events between the previous frame and this one.
  std::vector<int> add(const FrameLines& frame);

  const std::vector<Event>& events() const { return events_; }
  int frames() const { return frames_; }

 private:
  struct Kept {  // what is needed of the previous frame's lines
    int id = 0;
    int burgers = 0;
    Point centroid;
    double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
    int region = -1;
    double slipped_area = 0.0;
  };
  enum class Motion { unknown, growth, retreat, arrest };

  TrackOptions options_;
  int frames_ = 0;
  int next_id_ = 0;
  std::vector<Kept> previous_;
  std::vector<std::vector<std::int64_t>> previous_regions_;
  FrameLines previous_frame_geometry_;  // contact centre and radius for annihilation sites
  std::map<int, Motion> motion_;
  std::vector<Event> events_;
};

}  // namespace asperity::tracking
