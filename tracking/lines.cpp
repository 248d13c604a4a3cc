// Dislocation lines in one snapshot (MODEL.md section 7); see lines.hpp.
#include "lines.hpp"

#include <algorithm>
#include <array>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/connected_components.hpp>
#include <boost/pending/disjoint_sets.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "asperity/core/common/validate.hpp"

namespace asperity::tracking {

void FieldView::validate() const {
  const int min_n = periodic ? 3 : 2;
  if (block.shape.n0 < min_n || block.shape.n1 < min_n) {
    reject("FieldView.block.shape",
           std::to_string(block.shape.n0) + " x " + std::to_string(block.shape.n1),
           periodic ? "at least 3 x 3 for a periodic cell" : "at least 2 x 2");
  }
  require_positive("FieldView.d", d);
  const std::size_t n = block.shape.count();
  const auto check_size = [n](const char* name, std::size_t size, bool may_be_empty) {
    if (size != n && !(may_be_empty && size == 0)) {
      reject(std::string("FieldView.") + name, std::to_string(size) + " values",
             "one per block site (" + std::to_string(n) + ")" + (may_be_empty ? " or none" : ""));
    }
  };
  check_size("sx", sx.size(), false);
  check_size("tau_x", tau_x.size(), false);
  check_size("tau_max", tau_max.size(), false);
  check_size("in_contact", in_contact.size(), true);
  // Out of registry the registry and the stress along the tip's first axis need both components.
  check_size("sy", sy.size(), tip.aligned());
  check_size("tau_y", tau_y.size(), tip.aligned());
  if (!tip.aligned() &&
      !(std::isfinite(tip.angle) && std::isfinite(tip.mismatch) && tip.mismatch > -1.0)) {
    reject("FieldView.tip",
           std::to_string(tip.angle) + " degrees, mismatch " + std::to_string(tip.mismatch),
           "finite, mismatch > -1");
  }
}

FieldView view_of(const slide::Snapshot& snapshot, bool periodic) {
  return FieldView{.block = snapshot.block,
                   .d = 1.0,
                   .periodic = periodic,
                   .sx = snapshot.sx,
                   .tau_x = snapshot.tau_x,
                   .tau_max = snapshot.tau_max,
                   .in_contact = snapshot.in_contact,
                   .sy = snapshot.sy,
                   .tau_y = snapshot.tau_y,
                   .tip = snapshot.tip};
}

std::string to_string(LineKind kind) {
  switch (kind) {
    case LineKind::loop:
      return "loop";
    case LineKind::open:
      return "open";
    case LineKind::wrapping:
      return "wrapping";
  }
  return "unknown";
}

const settings::Table<DetectOptions>& DetectOptions::settings() {
  using R = settings::Range;
  using O = DetectOptions;
  static const settings::Table<O> table = {
      settings::number<O>(
          "min_length", [](auto& o) -> auto& { return o.min_length; }, R::non_negative(), "d",
          "lines shorter than this are dropped", "--min-length"),
      settings::number<O>(
          "join_distance", [](auto& o) -> auto& { return o.join_distance; }, R::non_negative(), "d",
          "open lines are joined end to start across gaps up to this long at the contact's "
          "jagged edge: the pieces of one core running along it (0: never; not in a periodic "
          "cell, which has no edge)",
          "--join-distance"),
      // A sign: a choice of two names rather than an integer range that would admit 0.
      settings::choice<O>(
          "slip_sign", [](auto& o) -> auto& { return o.slip_sign; }, {"-1", "1"},
          [](int sign) { return std::to_string(sign); },
          [](const std::string& name) { return name == "1" ? 1 : -1; },
          "registry-index change of a slipping site: -1 sliding along +x, 1 along -x",
          "--slip-sign"),
      settings::integer<O>(
          "tangent_half_window", [](auto& o) -> auto& { return o.tangent_half_window; },
          R::closed(0, 16), "",
          "a segment's tangent is the chord over this many segments either side (marching "
          "squares zigzag at the grid scale)",
          "--tangent-half-window"),
      settings::number<O>(
          "screw_angle_deg", [](auto& o) -> auto& { return o.screw_angle_deg; }, R::open(0.0, 90.0),
          "degrees",
          "a piece of line at an angle to b below this counts as screw, "
          "otherwise edge",
          "--screw-angle-deg"),
  };
  return table;
}

void DetectOptions::validate() const {
  settings::validate(*this, settings());
}

std::string location_class(const FrameLines& frame, Point p, double centre_fraction) {
  if (frame.periodic) return "cell";
  const double dx = p.x - frame.contact_centre.x, dy = p.y - frame.contact_centre.y;
  if (std::hypot(dx, dy) < centre_fraction * frame.contact_radius) return "centre";
  if (std::abs(dy) > std::abs(dx)) return "side";
  return dx > 0.0 ? "front" : "back";
}

namespace {

// A marching-squares segment remembers the crossing it starts from when oriented with the
// positive stress (the higher registry index, see sense()) on its left.
struct Segment {
  std::size_t from = 0;
};
using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS,
                                    boost::no_property, Segment>;

constexpr std::int32_t kNoCrossing = -1;
constexpr std::int32_t kRegistryCrossing = -2;  // tau_x changes sign, but s_x is near 0 mod d

// A core crossing on the grid edge from site p to site q (q = p + one step along `axis`).
struct Crossing {
  std::size_t p = 0, q = 0;
  int axis = 0;        // 0: edge along x, 1: along y
  Point at;            // position (d), before unwrapping
  int cells_seen = 0;  // cells of the processed region that contain this crossing
  long seam = 0;       // registry winding subtracted from q's phase: the edge wraps the cell
};

// A traced line before the pieces of one core are joined across the contact's edge.
struct Piece {
  Line line;
  std::vector<std::size_t> slipped;            // a site on the slipped side of each crossing
  std::array<bool, 2> edge_end{false, false};  // open lines: first and last point on the edge
};

class Tracer {
 public:
  Tracer(const FieldView& f, const DetectOptions& o) : f_(f), o_(o), frame_(f.tip, f.d) {
    n0_ = f.block.shape.n0;
    n1_ = f.block.shape.n1;
  }

  FrameLines run();

 private:
  std::size_t site(int i0, int i1) const { return f_.block.shape.index(i0, i1); }
  // Neighbour along an axis, wrapping in a periodic cell; false at the block's side otherwise.
  bool step(int i0, int i1, int axis, int& j0, int& j1) const {
    j0 = i0 + (axis == 0 ? 1 : 0);
    j1 = i1 + (axis == 1 ? 1 : 0);
    if (j0 == n0_ || j1 == n1_) {
      if (!f_.periodic) return false;
      j0 %= n0_;
      j1 %= n1_;
    }
    return true;
  }
  std::size_t edge_id(std::size_t p, int axis) const {
    return 2 * p + static_cast<std::size_t>(axis);
  }
  // s_x / d - X / d: its rounding is the registry index. Out of registry rho_1 - X / d, rho_1
  // the registry coordinate along the tip's first axis (tip_lattice.hpp): constant over a patch
  // in registry with the tip, it steps by one across a misfit dislocation.
  double phase(std::size_t s) const {
    const auto i0 = static_cast<int>(s / static_cast<std::size_t>(n1_));
    if (!frame_.aligned()) return rho1_[s] - static_cast<double>(f_.block.origin0 + i0);
    return f_.sx[s] / f_.d - static_cast<double>(f_.block.origin0 + i0);
  }
  void measure_windings();

  void find_crossings();
  void march(Graph& g);
  void build_line(const std::vector<std::size_t>& nodes, const Graph& g, Line& line,
                  std::vector<std::size_t>& order) const;
  void measure(Line& line, std::vector<std::size_t>& order) const;
  void sense(Line& line, const std::vector<std::size_t>& order, const Graph& g,
             std::vector<std::size_t>& slipped_sites) const;
  std::vector<Piece> join(std::vector<Piece> pieces) const;

  const FieldView& f_;
  const DetectOptions& o_;
  interface::TipFrame frame_;
  std::vector<double> rho1_;  // out of registry: rho_1 per site (tip spacings)
  int n0_ = 0, n1_ = 0;
  std::vector<std::uint8_t> valid_;
  std::vector<double> t_;                // tau_x / tau_max on valid sites
  std::vector<std::int32_t> edge_node_;  // per grid edge: crossing index or kNo/kRegistry
  std::vector<Crossing> crossings_;
  std::size_t registry_crossings_ = 0;
  // Registry winding of a periodic cell per axis: the phase of the site across the side minus
  // that of the site before it, away from cores (an integer; 0 unless the registry is frustrated)
  std::array<long, 2> winding_{0, 0};
};

// A Peierls cell is frustrated (MODEL.md 6): its rigid body is shifted by
// w = d (m_x X + m_y Y)/L, so the registry offset s_x - X = u - w is periodic only up to the
// integers m_x, m_y: crossing a side of the cell the phase jumps by them although u is
// continuous there. Such a jump is no core. The winding is the median jump along each side
// (cores cross a side at a few sites only); unfrustrated cells have winding 0.
void Tracer::measure_windings() {
  winding_ = {0, 0};
  if (!f_.periodic) return;
  std::vector<double> jumps;
  for (int axis = 0; axis < 2; ++axis) {
    jumps.clear();
    const int along = axis == 0 ? n1_ : n0_;
    for (int k = 0; k < along; ++k) {
      const std::size_t p = axis == 0 ? site(n0_ - 1, k) : site(k, n1_ - 1);
      const std::size_t q = axis == 0 ? site(0, k) : site(k, 0);
      if (valid_[p] && valid_[q]) jumps.push_back(phase(q) - phase(p));
    }
    if (jumps.empty()) continue;
    const auto mid = jumps.begin() + static_cast<std::ptrdiff_t>(jumps.size() / 2);
    std::nth_element(jumps.begin(), mid, jumps.end());
    winding_[static_cast<std::size_t>(axis)] = std::lround(*mid);
  }
}

void Tracer::find_crossings() {
  const std::size_t n = f_.block.shape.count();
  valid_.assign(n, 0);
  t_.assign(n, 0.0);
  if (!frame_.aligned()) rho1_.assign(n, 0.0);
  for (std::size_t s = 0; s < n; ++s) {
    const bool contact = f_.in_contact.empty() || f_.in_contact[s] != 0;
    if (!(contact && f_.tau_max[s] > 0.0 && std::isfinite(f_.tau_x[s]) && std::isfinite(f_.sx[s])))
      continue;
    if (frame_.aligned()) {
      valid_[s] = 1;
      t_[s] = f_.tau_x[s] / f_.tau_max[s];
      continue;
    }
    // Out of registry: the stress along the tip's first axis, the force conjugate to rho_1.
    if (!std::isfinite(f_.tau_y[s]) || !std::isfinite(f_.sy[s])) continue;
    double rho2 = 0.0, tau1 = 0.0, tau2 = 0.0;
    frame_.registry(f_.sx[s], f_.sy[s], rho1_[s], rho2);
    frame_.to_tip(f_.tau_x[s], f_.tau_y[s], tau1, tau2);
    valid_[s] = 1;
    t_[s] = tau1 / f_.tau_max[s];
  }
  measure_windings();
  edge_node_.assign(2 * n, kNoCrossing);
  constexpr double two_pi = 2.0 * std::numbers::pi;
  for (int i0 = 0; i0 < n0_; ++i0) {
    for (int i1 = 0; i1 < n1_; ++i1) {
      const std::size_t p = site(i0, i1);
      if (!valid_[p]) continue;
      for (int axis = 0; axis < 2; ++axis) {
        int j0 = 0, j1 = 0;
        if (!step(i0, i1, axis, j0, j1)) continue;
        const std::size_t q = site(j0, j1);
        if (!valid_[q] || (t_[p] >= 0.0) == (t_[q] >= 0.0)) continue;
        // The branch at the zero: on a core s_x passes d/2 (mod d), where cos(2 pi s_x / d) < 0,
        // and the registry index n = round(s_x / d - X / d) changes. Between sites closer than
        // d/2 in phase, cos interpolated like the stress decides (robust to noise at the core);
        // across larger jumps (cores narrower than d) interpolation cannot, and the index does.
        const bool wraps = j0 < i0 || j1 < i1;
        const long seam = wraps ? winding_[static_cast<std::size_t>(axis)] : 0;
        const double pp = phase(p), pq = phase(q) - static_cast<double>(seam);
        const bool jump = std::abs(pq - pp) > 0.5;
        double frac = t_[p] / (t_[p] - t_[q]);
        bool core = false;
        if (jump) {
          core = std::lround(pp) != std::lround(pq);
          // The phase, not the stress, is nearly linear across such a jump.
          const double half = std::floor(std::min(pp, pq) + 0.5) + 0.5;
          frac = std::clamp((half - pp) / (pq - pp), 0.0, 1.0);
        } else {
          const double cp = std::cos(two_pi * pp), cq = std::cos(two_pi * pq);
          core = cp + frac * (cq - cp) < 0.0;
        }
        if (!core) {
          edge_node_[edge_id(p, axis)] = kRegistryCrossing;
          ++registry_crossings_;
          continue;
        }
        Crossing c;
        c.p = p;
        c.q = q;
        c.axis = axis;
        c.seam = seam;
        c.at = Point{(f_.block.origin0 + i0 + (axis == 0 ? frac : 0.0)) * f_.d,
                     (f_.block.origin1 + i1 + (axis == 1 ? frac : 0.0)) * f_.d};
        edge_node_[edge_id(p, axis)] = static_cast<std::int32_t>(crossings_.size());
        crossings_.push_back(c);
      }
    }
  }
}

void Tracer::march(Graph& g) {
  // Cell (i0, i1) has corners c0 = (i0, i1), c1 = (i0+1, i1), c2 = (i0+1, i1+1), c3 = (i0, i1+1)
  // and edges e0 = c0-c1, e1 = c1-c2, e2 = c3-c2, e3 = c0-c3; edge k lies between corners k and
  // k+1 (mod 4).
  for (int i0 = 0; i0 < n0_; ++i0) {
    for (int i1 = 0; i1 < n1_; ++i1) {
      int a0 = 0, a1 = 0, b0 = 0, b1 = 0;
      if (!step(i0, i1, 0, a0, a1) || !step(i0, i1, 1, b0, b1)) continue;
      const std::size_t c0 = site(i0, i1), c1 = site(a0, a1), c3 = site(b0, b1);
      const std::size_t c2 = site(a0, b1);
      if (!valid_[c0] || !valid_[c1] || !valid_[c2] || !valid_[c3]) continue;
      const std::array<std::int32_t, 4> e = {edge_node_[edge_id(c0, 0)], edge_node_[edge_id(c1, 1)],
                                             edge_node_[edge_id(c3, 0)],
                                             edge_node_[edge_id(c0, 1)]};
      std::array<int, 4> crossed{};
      int count = 0;
      for (int k = 0; k < 4; ++k) {
        if (e[static_cast<std::size_t>(k)] != kNoCrossing)
          crossed[static_cast<std::size_t>(count++)] = k;
      }
      if (count == 0) continue;
      for (int k = 0; k < count; ++k) {
        const std::int32_t node = e[static_cast<std::size_t>(crossed[static_cast<std::size_t>(k)])];
        if (node >= 0) ++crossings_[static_cast<std::size_t>(node)].cells_seen;
      }
      const std::array<bool, 4> positive = {t_[c0] >= 0.0, t_[c1] >= 0.0, t_[c2] >= 0.0,
                                            t_[c3] >= 0.0};
      const auto add = [&](int ka, int kb) {
        const std::int32_t na = e[static_cast<std::size_t>(ka)],
                           nb = e[static_cast<std::size_t>(kb)];
        if (na < 0 || nb < 0) return;
        // Corners run counter-clockwise and corner k+1 follows edge k: if it is positive, the
        // positive corners lie counter-clockwise from edge ka, and the segment has them on its
        // left when run from kb to ka.
        const bool from_b = positive[static_cast<std::size_t>((ka + 1) % 4)];
        boost::add_edge(static_cast<std::size_t>(na), static_cast<std::size_t>(nb),
                        Segment{static_cast<std::size_t>(from_b ? nb : na)}, g);
      };
      if (count == 2) {
        add(crossed[0], crossed[1]);
        continue;
      }
      // Saddle: the corners alternate in sign. The centre value (mean of the corners) decides
      // which pair of opposite corners is joined; if that pairs a core crossing with a registry
      // one while the other choice would not, the other choice is taken: a core contour and a
      // registry contour never meet.
      const double centre = 0.25 * (t_[c0] + t_[c1] + t_[c2] + t_[c3]);
      bool cut_c1_c3 = (centre >= 0.0) == (t_[c0] >= 0.0);  // c0-c2 joined: cut corners 1 and 3
      const auto pure = [&](int ka, int kb) {
        return (e[static_cast<std::size_t>(ka)] >= 0) == (e[static_cast<std::size_t>(kb)] >= 0);
      };
      const bool pure_13 = pure(0, 1) && pure(2, 3), pure_02 = pure(3, 0) && pure(1, 2);
      if (cut_c1_c3 && !pure_13 && pure_02) cut_c1_c3 = false;
      if (!cut_c1_c3 && !pure_02 && pure_13) cut_c1_c3 = true;
      if (cut_c1_c3) {
        add(0, 1);
        add(2, 3);
      } else {
        add(3, 0);
        add(1, 2);
      }
    }
  }
}

// Orders the crossings of one connected component into a polyline (unwrapped in a periodic cell)
// and sets its kind.
void Tracer::build_line(const std::vector<std::size_t>& nodes, const Graph& g, Line& line,
                        std::vector<std::size_t>& order) const {
  std::size_t start = nodes.front();
  bool closed = true;
  for (const std::size_t v : nodes) {
    if (boost::degree(v, g) < 2) {
      start = v;
      closed = false;
      break;
    }
  }
  order.clear();
  order.push_back(start);
  std::size_t prev = std::numeric_limits<std::size_t>::max(), cur = start;
  while (true) {
    std::size_t next = std::numeric_limits<std::size_t>::max();
    for (auto [it, end] = boost::adjacent_vertices(cur, g); it != end; ++it) {
      if (*it != prev) {
        next = *it;
        break;
      }
    }
    if (next == std::numeric_limits<std::size_t>::max() || next == start) break;
    order.push_back(next);
    prev = cur;
    cur = next;
  }
  const double L0 = n0_ * f_.d, L1 = n1_ * f_.d;
  const auto wrap = [](double delta, double L) { return delta - image_offset(delta, L); };
  line.points.clear();
  line.points.reserve(order.size());
  line.points.push_back(crossings_[order.front()].at);
  for (std::size_t k = 1; k < order.size(); ++k) {
    const Point a = crossings_[order[k]].at, b = line.points.back();
    double dx = a.x - b.x, dy = a.y - b.y;
    if (f_.periodic) {
      dx = wrap(dx, L0);
      dy = wrap(dy, L1);
    }
    line.points.push_back(Point{b.x + dx, b.y + dy});
  }
  line.kind = closed ? LineKind::loop : LineKind::open;
  if (closed && f_.periodic && order.size() > 1) {
    // The closing segment: a loop comes back to its first vertex, a wrapping line to an image.
    const Point first = line.points.front(), last = line.points.back();
    const Point a = crossings_[order.front()].at, b = crossings_[order.back()].at;
    const double dx = wrap(a.x - b.x, L0), dy = wrap(a.y - b.y, L1);
    if (std::hypot(last.x + dx - first.x, last.y + dy - first.y) > 1e-6 * f_.d) {
      line.kind = LineKind::wrapping;
      line.points.push_back(Point{last.x + dx, last.y + dy});
      order.push_back(order.front());
    }
  }
  line.interior_ends = 0;
  if (!closed) {
    for (const std::size_t end : {order.front(), order.back()}) {
      if (crossings_[end].cells_seen > static_cast<int>(boost::degree(end, g)))
        ++line.interior_ends;
    }
  }
}

void Tracer::measure(Line& line, std::vector<std::size_t>& order) const {
  const auto& P = line.points;
  const std::size_t m = P.size();
  const bool loop = line.kind == LineKind::loop;
  const std::size_t segments = loop ? m : m - 1;
  line.angle_deg.assign(segments, 0.0);
  line.length = 0.0;
  double screw_length = 0.0, angle_sum = 0.0;
  const auto vertex = [&](long k) -> const Point& {
    const auto mm = static_cast<long>(m);
    if (loop) return P[static_cast<std::size_t>(((k % mm) + mm) % mm)];
    return P[static_cast<std::size_t>(std::clamp(k, 0L, mm - 1))];
  };
  const long w = o_.tangent_half_window;
  for (std::size_t k = 0; k < segments; ++k) {
    const auto kk = static_cast<long>(k);
    const Point& a = vertex(kk);
    const Point& b = vertex(kk + 1);
    const double seg = std::hypot(b.x - a.x, b.y - a.y);
    const Point& ta = vertex(kk - w);
    const Point& tb = vertex(kk + 1 + w);
    double tx = tb.x - ta.x, ty = tb.y - ta.y;
    if (tx == 0.0 && ty == 0.0) {
      tx = b.x - a.x;
      ty = b.y - a.y;
    }
    // The angle to b, which lies along the tip's first axis (x for the aligned tip).
    frame_.to_tip(tx, ty, tx, ty);
    const double angle = std::atan2(std::abs(ty), std::abs(tx)) * 180.0 / std::numbers::pi;
    line.angle_deg[k] = angle;
    line.length += seg;
    angle_sum += seg * angle;
    if (angle < o_.screw_angle_deg) screw_length += seg;
  }
  line.mean_angle_deg = line.length > 0.0 ? angle_sum / line.length : 0.0;
  line.screw_fraction = line.length > 0.0 ? screw_length / line.length : 0.0;
  line.edge_fraction = line.length > 0.0 ? 1.0 - line.screw_fraction : 0.0;

  line.x_min = line.x_max = P.front().x;
  line.y_min = line.y_max = P.front().y;
  for (const Point& p : P) {
    line.x_min = std::min(line.x_min, p.x);
    line.x_max = std::max(line.x_max, p.x);
    line.y_min = std::min(line.y_min, p.y);
    line.y_max = std::max(line.y_max, p.y);
  }
  const double ex = line.x_max - line.x_min, ey = line.y_max - line.y_min;
  line.aspect_ratio = ey > 0.0 ? ex / ey : std::numeric_limits<double>::infinity();

  line.area = 0.0;
  if (loop && m >= 3) {
    // Shoelace about the first vertex, for round-off on lattice coordinates far from 0.
    double a2 = 0.0, cx = 0.0, cy = 0.0;
    const Point o = P.front();
    for (std::size_t k = 0; k < m; ++k) {
      const Point& p = P[k];
      const Point& q = P[(k + 1) % m];
      const double px = p.x - o.x, py = p.y - o.y, qx = q.x - o.x, qy = q.y - o.y;
      const double cross = px * qy - qx * py;
      a2 += cross;
      cx += (px + qx) * cross;
      cy += (py + qy) * cross;
    }
    if (a2 != 0.0) {
      line.centroid = Point{o.x + cx / (3.0 * a2), o.y + cy / (3.0 * a2)};
      if (a2 < 0.0) {  // clockwise: reverse so that the inside is on the left
        std::reverse(line.points.begin() + 1, line.points.end());
        std::reverse(order.begin() + 1, order.end());
        std::reverse(line.angle_deg.begin(), line.angle_deg.end());
      }
      line.area = 0.5 * std::abs(a2);
      return;
    }
  }
  // Not a loop (or a degenerate one): length-weighted centroid of the segments.
  double sx = 0.0, sy = 0.0, total = 0.0;
  for (std::size_t k = 0; k < segments; ++k) {
    const Point& a = vertex(static_cast<long>(k));
    const Point& b = vertex(static_cast<long>(k) + 1);
    const double seg = std::hypot(b.x - a.x, b.y - a.y);
    sx += seg * 0.5 * (a.x + b.x);
    sy += seg * 0.5 * (a.y + b.y);
    total += seg;
  }
  line.centroid = total > 0.0 ? Point{sx / total, sy / total} : P.front();
}

// Burgers vector and sense from the registry index on either side of each crossing, and the
// site on the slipped side of each crossing (for the slipped region). On a core (s_x = d/2 mod
// d) the side where tau_x > 0 has the higher index; `registry_consistency` is the fraction of
// crossings where the indices agree with that.
void Tracer::sense(Line& line, const std::vector<std::size_t>& order, const Graph& g,
                   std::vector<std::size_t>& slipped_sites) const {
  const std::size_t m = order.size();
  // Whether the points run along the segments' orientation (positive stress on the left):
  // geometry alone is unreliable where crossings coincide at a site with tau_x = 0.
  int aligned_votes = 0;
  const std::size_t steps = line.kind == LineKind::loop ? m : m - 1;
  for (std::size_t k = 0; k < steps; ++k) {
    const std::size_t u = order[k], v = order[(k + 1) % m];
    if (u == v) continue;
    const auto [edge, exists] = boost::edge(u, v, g);
    if (exists) aligned_votes += g[edge].from == u ? 1 : -1;
  }
  const bool positive_left = aligned_votes >= 0;
  std::unordered_map<long, int> votes;
  int voters = 0;
  std::vector<long> jumps(m, 0);
  std::vector<std::uint8_t> q_left(m, 0);
  for (std::size_t k = 0; k < m; ++k) {
    const Crossing& c = crossings_[order[k]];
    const bool q_positive = t_[c.q] >= 0.0;
    q_left[k] = q_positive == positive_left ? 1 : 0;
    // A site exactly on the core (s_x = d/2 mod d) has no index: such crossings do not vote.
    const double pp = phase(c.p), pq = phase(c.q) - static_cast<double>(c.seam);
    if (std::abs(std::abs(pp - std::floor(pp)) - 0.5) < 1e-9 ||
        std::abs(std::abs(pq - std::floor(pq)) - 0.5) < 1e-9) {
      jumps[k] = std::numeric_limits<long>::min();
      continue;
    }
    const long np = std::lround(pp), nq = std::lround(pq);
    jumps[k] = q_left[k] ? nq - np : np - nq;
    ++votes[jumps[k]];
    ++voters;
  }
  long best = 0;
  int best_votes = -1;
  for (const auto& [jump, count] : votes) {
    if (count > best_votes || (count == best_votes && std::abs(jump) < std::abs(best))) {
      best = jump;
      best_votes = count;
    }
  }
  line.burgers = static_cast<int>(best);
  line.registry_consistency =
      voters > 0 ? static_cast<double>(best_votes) / static_cast<double>(voters) : 0.0;
  // The slipped side has the index changed by slip_sign: it is on the left if the jump
  // n_left - n_right has the sign of slip_sign.
  const bool slipped_left = (best > 0 ? 1 : -1) == o_.slip_sign;
  slipped_sites.clear();
  for (std::size_t k = 0; k < m; ++k) {
    if (jumps[k] != best) continue;
    const Crossing& c = crossings_[order[k]];
    slipped_sites.push_back((q_left[k] != 0) == slipped_left ? c.q : c.p);
  }
}

// Open pieces of one core, cut where the jagged contact edge cuts into it, joined end to start
// (DetectOptions::join_distance): candidate links from the end of one piece to the start of
// another with the same Burgers vector, both ends on the contact edge, taken nearest first with
// each end used once. Chains become one open line each: the gaps are segments of it (the core
// runs on through the cells the marching squares skip), counted in its length and character
// like the traced ones. Joins make no loops: a link that would close a chain is left out, so a
// loop is what the marching squares close, as without joins (a small half-loop nucleated at the
// edge, its two ends a few d apart, stays an open line; a core along the whole edge stays one
// open line with both ends at one gap). registry_consistency is the pieces' weighted by their
// crossings (points).
std::vector<Piece> Tracer::join(std::vector<Piece> pieces) const {
  std::vector<std::size_t> open;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Line& l = pieces[k].line;
    if (l.kind == LineKind::open && l.burgers != 0) open.push_back(k);
  }
  struct Link {
    double gap;
    std::size_t from, to;
  };
  std::vector<Link> links;
  for (const std::size_t a : open) {
    if (!pieces[a].edge_end[1]) continue;
    const Point end = pieces[a].line.points.back();
    for (const std::size_t b : open) {
      if (b == a || !pieces[b].edge_end[0] || pieces[b].line.burgers != pieces[a].line.burgers)
        continue;
      const Point start = pieces[b].line.points.front();
      const double gap = std::hypot(start.x - end.x, start.y - end.y);
      if (gap <= o_.join_distance) links.push_back(Link{gap, a, b});
    }
  }
  if (links.empty()) return pieces;
  std::sort(links.begin(), links.end(), [](const Link& l, const Link& r) {
    return std::tie(l.gap, l.from, l.to) < std::tie(r.gap, r.from, r.to);
  });
  constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> next(pieces.size(), none), prev(pieces.size(), none);
  for (const Link& l : links) {
    if (next[l.from] != none || prev[l.to] != none) continue;
    // A link that would close a chain is not made: joins make no loops (see above).
    std::size_t head = l.from;
    while (prev[head] != none)
      head = prev[head];
    if (head == l.to) continue;
    next[l.from] = l.to;
    prev[l.to] = l.from;
  }

  std::vector<Piece> out;
  const auto chain = [&](std::size_t first) {
    Piece merged;
    Line& line = merged.line;
    line.pieces = 0;
    std::size_t last = first;
    double consistency = 0.0, weight = 0.0;
    for (std::size_t k = first;;) {
      Piece& p = pieces[k];
      line.points.insert(line.points.end(), p.line.points.begin(), p.line.points.end());
      merged.slipped.insert(merged.slipped.end(), p.slipped.begin(), p.slipped.end());
      const auto w = static_cast<double>(p.line.points.size());
      consistency += w * p.line.registry_consistency;
      weight += w;
      ++line.pieces;
      last = k;
      k = next[k];
      if (k == none) break;
    }
    line.burgers = pieces[first].line.burgers;
    line.registry_consistency = weight > 0.0 ? consistency / weight : 0.0;
    line.kind = LineKind::open;
    merged.edge_end = {pieces[first].edge_end[0], pieces[last].edge_end[1]};
    line.interior_ends = (merged.edge_end[0] ? 0 : 1) + (merged.edge_end[1] ? 0 : 1);
    std::vector<std::size_t> order;  // measure() reorders only loops' points (and order)
    measure(line, order);
    out.push_back(std::move(merged));
  };
  // No chain closes, so every piece is a head (prev none) or reached from one.
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (prev[k] != none) continue;
    if (next[k] == none) {
      out.push_back(std::move(pieces[k]));
    } else {
      chain(k);
    }
  }
  return out;
}

FrameLines Tracer::run() {
  FrameLines out;
  out.d = f_.d;
  out.periodic = f_.periodic;
  if (f_.periodic) out.cell = {n0_ * f_.d, n1_ * f_.d};
  out.unit_burgers = {frame_.spacing() * frame_.cos(), frame_.spacing() * frame_.sin()};
  find_crossings();
  out.core_crossings = crossings_.size();
  out.registry_crossings = registry_crossings_;

  const std::size_t n = f_.block.shape.count();
  double cx = 0.0, cy = 0.0;
  for (int i0 = 0; i0 < n0_; ++i0) {
    for (int i1 = 0; i1 < n1_; ++i1) {
      if (!valid_[site(i0, i1)]) continue;
      ++out.contact_sites;
      cx += f_.block.x(i0, f_.d);
      cy += f_.block.y(i1, f_.d);
    }
  }
  if (out.contact_sites > 0) {
    const auto count = static_cast<double>(out.contact_sites);
    out.contact_centre = Point{cx / count, cy / count};
    out.contact_radius = std::sqrt(count / std::numbers::pi) * f_.d;
  }

  Graph g(crossings_.size());
  march(g);
  std::vector<std::size_t> component(crossings_.size());
  const std::size_t components =
      crossings_.empty() ? 0 : boost::connected_components(g, component.data());
  std::vector<std::vector<std::size_t>> members(components);
  for (std::size_t v = 0; v < crossings_.size(); ++v)
    members[component[v]].push_back(v);

  // Domains: contact sites joined across every grid edge not cut by a core.
  std::vector<std::uint32_t> rank(n, 0), parent(n, 0);
  boost::disjoint_sets<std::uint32_t*, std::uint32_t*> sets(rank.data(), parent.data());
  for (std::size_t s = 0; s < n; ++s) {
    if (valid_[s]) sets.make_set(static_cast<std::uint32_t>(s));
  }
  for (int i0 = 0; i0 < n0_; ++i0) {
    for (int i1 = 0; i1 < n1_; ++i1) {
      const std::size_t p = site(i0, i1);
      if (!valid_[p]) continue;
      for (int axis = 0; axis < 2; ++axis) {
        int j0 = 0, j1 = 0;
        if (!step(i0, i1, axis, j0, j1)) continue;
        const std::size_t q = site(j0, j1);
        if (valid_[q] && edge_node_[edge_id(p, axis)] < 0) {
          sets.union_set(static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q));
        }
      }
    }
  }

  std::vector<std::size_t> order;
  std::vector<Piece> pieces;
  for (const auto& nodes : members) {
    if (nodes.size() < 2) continue;  // an isolated crossing: a core clipped by the contact edge
    Piece piece;
    Line& line = piece.line;
    build_line(nodes, g, line, order);
    if (line.points.size() < 2) continue;
    if (line.kind == LineKind::open) {
      for (int e = 0; e < 2; ++e) {
        const std::size_t end = e == 0 ? order.front() : order.back();
        piece.edge_end[static_cast<std::size_t>(e)] =
            crossings_[end].cells_seen <= static_cast<int>(boost::degree(end, g));
      }
    }
    measure(line, order);
    sense(line, order, g, piece.slipped);
    if (line.kind != LineKind::loop && line.burgers != 0 &&
        (line.burgers > 0 ? 1 : -1) != o_.slip_sign) {
      // Open and wrapping lines run with the slipped side on their left.
      std::reverse(line.points.begin(), line.points.end());
      std::reverse(line.angle_deg.begin(), line.angle_deg.end());
      std::swap(piece.edge_end[0], piece.edge_end[1]);
      line.burgers = -line.burgers;
    }
    pieces.push_back(std::move(piece));
  }
  // In a periodic cell every site is in contact: there is no edge to join across.
  if (!f_.periodic && o_.join_distance > 0.0) pieces = join(std::move(pieces));

  std::vector<std::uint32_t> line_root;
  for (Piece& piece : pieces) {
    Line& line = piece.line;
    if (line.length < o_.min_length) {
      ++out.dropped_short;
      continue;
    }
    if (line.pieces > 1) out.joined_pieces += static_cast<std::size_t>(line.pieces);
    std::unordered_map<std::uint32_t, int> roots;
    for (const std::size_t s : piece.slipped)
      ++roots[sets.find_set(static_cast<std::uint32_t>(s))];
    std::uint32_t root = std::numeric_limits<std::uint32_t>::max();
    int most = 0;
    for (const auto& [r, c] : roots) {
      if (c > most || (c == most && r < root)) {
        root = r;
        most = c;
      }
    }
    line_root.push_back(root);
    out.lines.push_back(std::move(line));
  }

  // Regions: one per distinct slipped-side domain, filled in one pass in (X, Y) order.
  std::vector<std::int32_t> region_of_root;
  int regions = 0;
  for (std::size_t k = 0; k < out.lines.size(); ++k) {
    if (line_root[k] == std::numeric_limits<std::uint32_t>::max()) continue;
    if (region_of_root.empty()) region_of_root.assign(n, -1);
    std::int32_t& r = region_of_root[line_root[k]];
    if (r < 0) r = regions++;
    out.lines[k].slipped_region = r;
  }
  out.regions.resize(static_cast<std::size_t>(regions));
  if (regions > 0) {
    for (int i0 = 0; i0 < n0_; ++i0) {
      for (int i1 = 0; i1 < n1_; ++i1) {
        const std::size_t s = site(i0, i1);
        if (!valid_[s]) continue;
        const std::int32_t r = region_of_root[sets.find_set(static_cast<std::uint32_t>(s))];
        if (r < 0) continue;
        out.regions[static_cast<std::size_t>(r)].push_back(
            site_key(f_.block.origin0 + i0, f_.block.origin1 + i1));
      }
    }
  }
  return out;
}

}  // namespace

FrameLines find_lines(const FieldView& field, const DetectOptions& options) {
  field.validate();
  options.validate();
  if (field.block.shape.count() >= std::numeric_limits<std::uint32_t>::max()) {
    reject("FieldView.block.shape", std::to_string(field.block.shape.count()) + " sites",
           "fewer than 2^32");
  }
  return Tracer(field, options).run();
}

}  // namespace asperity::tracking
