// Following dislocation lines through a sequence of snapshots (MODEL.md sections 5 and 7); see
// tracker.hpp.
#include "tracker.hpp"

#include <algorithm>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/connected_components.hpp>
#include <cmath>
#include <cstdlib>

namespace asperity::tracking {

const settings::Table<TrackOptions>& TrackOptions::settings() {
  using R = settings::Range;
  using O = TrackOptions;
  static const settings::Table<O> table = {
      settings::number<O>(
          "min_overlap", [](auto& o) -> auto& { return o.min_overlap; }, R::open_closed(0.0, 1.0),
          "",
          "overlap coefficient of slipped regions that links lines of "
          "consecutive frames",
          "--min-overlap"),
      settings::number<O>(
          "max_centroid_distance", [](auto& o) -> auto& { return o.max_centroid_distance; },
          R::non_negative(), "d",
          "centroids closer than this link lines of consecutive frames even without overlap",
          "--max-centroid-distance"),
      settings::number<O>(
          "max_motion", [](auto& o) -> auto& { return o.max_motion; }, R::non_negative(), "d",
          "largest motion of a line between frames", "--max-motion"),
      settings::number<O>(
          "arrest_area", [](auto& o) -> auto& { return o.arrest_area; }, R::non_negative(), "d^2",
          "a change of slipped area below this between frames is an arrest", "--arrest-area"),
      settings::number<O>(
          "centre_fraction", [](auto& o) -> auto& { return o.centre_fraction; },
          R::closed(0.0, 1.0), "",
          "nucleation and annihilation within this fraction of the contact "
          "radius of its centre are classed centre",
          "--centre-fraction"),
  };
  return table;
}

void TrackOptions::validate() const {
  settings::validate(*this, settings());
}

std::string to_string(EventType type) {
  switch (type) {
    case EventType::nucleation:
      return "nucleation";
    case EventType::growth:
      return "growth";
    case EventType::retreat:
      return "retreat";
    case EventType::arrest:
      return "arrest";
    case EventType::annihilation:
      return "annihilation";
    case EventType::merge:
      return "merge";
    case EventType::split:
      return "split";
    case EventType::reconnection:
      return "reconnection";
  }
  return "unknown";
}

Tracker::Tracker(TrackOptions options) : options_(options) {
  options_.validate();
}

namespace {

using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS>;

// |A n B| of two sorted key lists.
std::size_t intersection_size(const std::vector<std::int64_t>& a,
                              const std::vector<std::int64_t>& b) {
  std::size_t count = 0;
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (*i < *j) {
      ++i;
    } else if (*j < *i) {
      ++j;
    } else {
      ++count;
      ++i;
      ++j;
    }
  }
  return count;
}

// The shift (a multiple of the cell's sides) that brings `p` nearest `ref`: zero outside a
// periodic cell.
Point image_shift(Point p, Point ref, const FrameLines& frame) {
  if (!frame.periodic) return {};
  return {image_offset(ref.x - p.x, frame.cell.x), image_offset(ref.y - p.y, frame.cell.y)};
}

Point mean_point(const std::vector<Point>& points) {
  Point m;
  for (const Point& p : points) {
    m.x += p.x;
    m.y += p.y;
  }
  if (!points.empty()) {
    m.x /= static_cast<double>(points.size());
    m.y /= static_cast<double>(points.size());
  }
  return m;
}

}  // namespace

std::vector<int> Tracker::add(const FrameLines& frame) {
  const int frame_index = frames_++;
  const double site_area = frame.d * frame.d;
  std::vector<Kept> now(frame.lines.size());
  for (std::size_t k = 0; k < frame.lines.size(); ++k) {
    const Line& l = frame.lines[k];
    Kept& c = now[k];
    c.burgers = l.burgers;
    c.centroid = l.centroid;
    c.x_min = l.x_min;
    c.x_max = l.x_max;
    c.y_min = l.y_min;
    c.y_max = l.y_max;
    c.region = l.slipped_region;
    c.slipped_area = l.slipped_region >= 0
                         ? static_cast<double>(
                               frame.regions[static_cast<std::size_t>(l.slipped_region)].size()) *
                               site_area
                         : 0.0;
  }

  // Links between previous lines (vertices 0..m-1) and current ones (m..m+n-1). Overlaps are
  // computed once per pair of regions: lines often share a slipped domain.
  const std::size_t m = previous_.size(), n = now.size();
  Graph g(m + n);
  std::map<std::pair<int, int>, double> overlap_cache;
  const auto overlap = [&](int ra, int rb) {
    if (ra < 0 || rb < 0) return 0.0;
    const auto key = std::make_pair(ra, rb);
    if (const auto it = overlap_cache.find(key); it != overlap_cache.end()) return it->second;
    const auto& A = previous_regions_[static_cast<std::size_t>(ra)];
    const auto& B = frame.regions[static_cast<std::size_t>(rb)];
    const std::size_t smaller = std::min(A.size(), B.size());
    const double o =
        smaller == 0 ? 0.0
                     : static_cast<double>(intersection_size(A, B)) / static_cast<double>(smaller);
    overlap_cache[key] = o;
    return o;
  };
  // Candidates, ranked by the gap between their bounding boxes, then by centroid distance.
  struct Candidate {
    std::size_t i, j;
    double gap, distance;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < m; ++i) {
    const Kept& a = previous_[i];
    for (std::size_t j = 0; j < n; ++j) {
      const Kept& b = now[j];
      if (std::abs(a.burgers) != std::abs(b.burgers)) continue;
      // By minimum image in a periodic cell (FrameLines::cell): b's image nearest a.
      const Point s = image_shift(b.centroid, a.centroid, frame);
      const double distance =
          std::hypot(a.centroid.x - b.centroid.x - s.x, a.centroid.y - b.centroid.y - s.y);
      const double gap_x = std::max({0.0, a.x_min - b.x_max - s.x, b.x_min + s.x - a.x_max});
      const double gap_y = std::max({0.0, a.y_min - b.y_max - s.y, b.y_min + s.y - a.y_max});
      const double gap = std::hypot(gap_x, gap_y);
      const bool linked =
          distance <= options_.max_centroid_distance ||
          (gap <= options_.max_motion && overlap(a.region, b.region) >= options_.min_overlap);
      if (linked) candidates.push_back({i, j, gap, distance});
    }
  }
  // Each line keeps only its best candidate on the other side (and is kept by those that chose
  // it): lines that share one slipped domain, such as pieces of a core cut by the jagged contact
  // edge, would otherwise all link to each other.
  const auto better = [](const Candidate& x, const Candidate& y) {
    return x.gap < y.gap || (x.gap == y.gap && x.distance < y.distance);
  };
  std::vector<const Candidate*> best_of_old(m, nullptr), best_of_new(n, nullptr);
  for (const Candidate& c : candidates) {
    if (!best_of_old[c.i] || better(c, *best_of_old[c.i])) best_of_old[c.i] = &c;
    if (!best_of_new[c.j] || better(c, *best_of_new[c.j])) best_of_new[c.j] = &c;
  }
  for (const Candidate* c : best_of_old) {
    if (c) boost::add_edge(c->i, m + c->j, g);
  }
  for (const Candidate* c : best_of_new) {
    if (c) boost::add_edge(c->i, m + c->j, g);
  }
  std::vector<std::size_t> component(m + n);
  const std::size_t components = m + n == 0 ? 0 : boost::connected_components(g, component.data());
  std::vector<std::vector<std::size_t>> olds(components), news(components);
  for (std::size_t v = 0; v < m; ++v)
    olds[component[v]].push_back(v);
  for (std::size_t v = 0; v < n; ++v)
    news[component[m + v]].push_back(v);

  std::vector<int> ids(n, -1);
  std::vector<Event> found;
  for (std::size_t c = 0; c < components; ++c) {
    const auto& O = olds[c];
    const auto& N = news[c];
    Event e;
    e.frame = frame_index;
    std::vector<Point> where;
    double area_before = 0.0, area_after = 0.0;
    // The centroids' images nearest the first one (a periodic cell), for their mean.
    const auto near_first = [&](Point p) {
      if (where.empty()) return p;
      const Point s = image_shift(p, where.front(), frame);
      return Point{p.x + s.x, p.y + s.y};
    };
    for (const std::size_t i : O) {
      e.before.push_back(previous_[i].id);
      where.push_back(near_first(previous_[i].centroid));
      area_before += previous_[i].slipped_area;
    }
    for (const std::size_t j : N) {
      where.push_back(near_first(now[j].centroid));
      area_after += now[j].slipped_area;
    }
    e.where = mean_point(where);
    e.slipped_area_change = area_after - area_before;
    if (O.size() == 1 && N.size() == 1) {
      const int id = previous_[O.front()].id;
      ids[N.front()] = id;
      Motion state = Motion::arrest;
      if (e.slipped_area_change > options_.arrest_area) state = Motion::growth;
      if (e.slipped_area_change < -options_.arrest_area) state = Motion::retreat;
      Motion& last = motion_[id];
      if (state != last) {
        e.type = state == Motion::growth    ? EventType::growth
                 : state == Motion::retreat ? EventType::retreat
                                            : EventType::arrest;
        e.after = {id};
        found.push_back(e);
      }
      last = state;
      continue;
    }
    for (const std::size_t j : N) {
      ids[j] = next_id_++;
      e.after.push_back(ids[j]);
    }
    if (frame_index == 0) continue;  // lines already present when the sequence starts
    if (O.empty()) {
      // Each new line is its own nucleation (a component without old lines has one new line).
      e.type = EventType::nucleation;
      e.location = location_class(frame, e.where, options_.centre_fraction);
    } else if (N.empty()) {
      e.type = EventType::annihilation;
      e.location = location_class(previous_frame_geometry_, e.where, options_.centre_fraction);
    } else if (N.size() == 1) {
      e.type = EventType::merge;
    } else if (O.size() == 1) {
      e.type = EventType::split;
    } else {
      e.type = EventType::reconnection;
    }
    for (const int id : e.before)
      motion_.erase(id);
    found.push_back(e);
  }
  std::sort(found.begin(), found.end(), [](const Event& a, const Event& b) {
    const int ia = a.after.empty() ? (a.before.empty() ? 0 : a.before.front()) : a.after.front();
    const int ib = b.after.empty() ? (b.before.empty() ? 0 : b.before.front()) : b.after.front();
    return ia < ib;
  });
  events_.insert(events_.end(), found.begin(), found.end());

  for (std::size_t j = 0; j < n; ++j)
    now[j].id = ids[j];
  previous_ = std::move(now);
  previous_regions_ = frame.regions;
  previous_frame_geometry_.d = frame.d;
  previous_frame_geometry_.periodic = frame.periodic;
  previous_frame_geometry_.contact_centre = frame.contact_centre;
  previous_frame_geometry_.contact_radius = frame.contact_radius;
  return ids;
}

}  // namespace asperity::tracking
