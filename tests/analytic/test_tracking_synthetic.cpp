// Dislocation lines in synthetic snapshots with known answers (MODEL.md section 7; tracking/).
//
// Fields (tracking/synthetic.hpp): elliptical slipped islands with a Peierls-Nabarro profile
// sigma = 1/2 - atan(h / w) / pi across their edges (h: signed distance to the ellipse), on a
// Hertz-like contact of radius 60 d, s_x = X - sigma d + registry offset + noise and
// tau_x = -tau_max sin(2 pi s_x / d) (+ noise). The cores are the ellipses themselves.
//
// Answers and tolerances:
// - islands: one line per island, loops for islands inside the contact and an open line for
//   the island cut by the contact edge; semi-axes (half the extents) within 1 d, centroid within
//   0.5 d, aspect ratio within 10 %, enclosed area within 5 % of pi ax ay, b = -d x-hat
//   (index -1 inside a counter-clockwise loop); vertices within 0.05 d of the ellipse without
//   noise or offset for w >= 2 (the linear interpolation error of a smooth core; 0.1 d for the
//   narrow w = 1), 0.5 d with noise (0.02 d
//   on s_x, 5 % of tau_max on tau_x), 0.6 d with a registry offset A, which moves the core
//   itself by up to A pi w (0.31 d for A = 0.1, w = 1; 0.47 d for A = 0.05, w = 3); registry
//   index consistent with the stress sign at > 99.9 % of the crossings without noise, > 80 % with
//   noise (noise flips tau_x at sites within ~0.01 d of the core); screw fraction (length within
//   45 degrees of b) within 0.06 of the ellipse's own without noise or offset (measured
//   0.032-0.041: the tangent, a chord over three segments, misclassifies short arcs near the
//   four 45-degree points, a larger share of the small loops, the r = 3 d circle 19 d round),
//   0.12 with noise or an offset (measured 0.029-0.076: an offset bends the core of a small loop
//   by up to 0.47 d); classing screw as edge would miss by |2 f - 1|, 0.37-0.58 on the
//   ellipses (0 on the circle).
// - registry only (offsets of 0.3 d that make tau_x change sign, plus noise): no lines.
// - sequences: a loop that appears at frame 1, shrinks and is gone at frame 8 gives exactly one
//   nucleation (frame 1) and one annihilation (frame 8); two loops that grow into each other
//   give exactly one merge (the first frame where they overlap) and, run backwards, one split.
// - cores along the contact's jagged edge: the pieces the traced cells cut them into are joined
//   into one line per core (EdgeLines, below, with its answers).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <ostream>

#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/synthetic.hpp"
#include "asperity/tracking/tracker.hpp"

using namespace asperity;
using namespace asperity::tracking;

namespace {

SyntheticOptions contact_options() {
  SyntheticOptions o;
  o.block = LatticeBlock{.shape = {130, 130}, .origin0 = -65, .origin1 = -65};
  o.contact_radius = 60.0;
  return o;
}

// The screw fraction of an ellipse: the share of its length where the tangent is within 45
// degrees of x (DetectOptions::screw_angle_deg; b along x). On x = ax cos t, y = ay sin t the
// tangent is (-ax sin t, ay cos t): screw where ay |cos t| < ax |sin t|. Arc length by the
// midpoint rule over 100 000 steps of t (converged far below the tolerances).
double ellipse_screw_fraction(const Island& e) {
  const int n = 100000;
  double screw = 0.0, total = 0.0;
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * std::numbers::pi * (k + 0.5) / n;
    const double tx = e.ax * std::abs(std::sin(t)), ty = e.ay * std::abs(std::cos(t));
    const double ds = std::hypot(tx, ty);
    total += ds;
    if (ty < tx) screw += ds;
  }
  return screw / total;
}

double ellipse_distance(const Point& p, const Island& e) {
  // Radial distance to the ellipse: enough for points within a fraction of d of it.
  const double ux = (p.x - e.cx) / e.ax, uy = (p.y - e.cy) / e.ay;
  const double r = std::hypot(ux, uy);
  const double gx = ux / e.ax, gy = uy / e.ay;
  return (r - 1.0) * r / std::hypot(gx, gy);
}

struct Case {
  const char* name;
  double core_width, registry_offset, noise_s, noise_tau, vertex_tolerance, min_consistency,
      screw_tolerance;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

class Islands : public ::testing::TestWithParam<Case> {};

TEST_P(Islands, CountShapeCentroidAndKind) {
  const Case c = GetParam();
  SyntheticOptions o = contact_options();
  o.core_width = c.core_width;
  o.registry_offset = c.registry_offset;
  o.noise_s = c.noise_s;
  o.noise_tau = c.noise_tau;
  const std::vector<Island> loops = {
      {-25, 20, 12, 6}, {20, 25, 6, 4}, {0, -25, 20, 10}, {32, -4, 3, 3}, {-40, -8, 5, 9}};
  const Island open{57, 0, 10, 8};  // cut by the contact edge at r = 60
  std::vector<Island> all = loops;
  all.push_back(open);
  const SyntheticField field = synthetic_field(o, all);
  const FrameLines f = find_lines(field.view());

  ASSERT_EQ(f.lines.size(), all.size());
  int n_loops = 0, n_open = 0;
  for (const Line& l : f.lines)
    (l.kind == LineKind::loop ? n_loops : n_open) += 1;
  EXPECT_EQ(n_loops, static_cast<int>(loops.size()));
  EXPECT_EQ(n_open, 1);

  double worst_vertex = 0.0, worst_axis = 0.0, worst_centroid = 0.0, worst_aspect = 0.0;
  double worst_screw = 0.0;
  for (const Island& e : all) {
    const Line* best = nullptr;
    for (const Line& l : f.lines) {
      if (!best || std::hypot(l.centroid.x - e.cx, l.centroid.y - e.cy) <
                       std::hypot(best->centroid.x - e.cx, best->centroid.y - e.cy)) {
        best = &l;
      }
    }
    ASSERT_NE(best, nullptr);
    const Line& l = *best;
    EXPECT_EQ(l.burgers, -1);
    EXPECT_GT(l.registry_consistency, c.min_consistency);
    EXPECT_EQ(l.interior_ends, 0);
    for (const Point& p : l.points)
      worst_vertex = std::max(worst_vertex, std::abs(ellipse_distance(p, e)));
    if (&e == &all.back()) {
      EXPECT_EQ(l.kind, LineKind::open) << "island cut by the contact edge";
      continue;
    }
    EXPECT_EQ(l.kind, LineKind::loop);
    const double ax = 0.5 * (l.x_max - l.x_min), ay = 0.5 * (l.y_max - l.y_min);
    worst_axis = std::max({worst_axis, std::abs(ax - e.ax), std::abs(ay - e.ay)});
    worst_centroid = std::max(worst_centroid, std::hypot(l.centroid.x - e.cx, l.centroid.y - e.cy));
    worst_aspect = std::max(worst_aspect, std::abs(l.aspect_ratio / (e.ax / e.ay) - 1.0));
    EXPECT_NEAR(l.area, std::numbers::pi * e.ax * e.ay, 0.05 * std::numbers::pi * e.ax * e.ay);
    worst_screw = std::max(worst_screw, std::abs(l.screw_fraction - ellipse_screw_fraction(e)));
  }
  EXPECT_LT(worst_axis, 1.0);
  EXPECT_LT(worst_centroid, 0.5);
  EXPECT_LT(worst_aspect, 0.10);
  EXPECT_LT(worst_vertex, c.vertex_tolerance);
  EXPECT_LT(worst_screw, c.screw_tolerance);
  RecordProperty("worst_screw_fraction_error", std::to_string(worst_screw));
  RecordProperty("worst_axis_error_d", std::to_string(worst_axis));
  RecordProperty("worst_centroid_error_d", std::to_string(worst_centroid));
  RecordProperty("worst_aspect_error", std::to_string(worst_aspect));
  RecordProperty("worst_vertex_distance_d", std::to_string(worst_vertex));
  std::printf(
      "%s: axes within %.3f d, centroids within %.3f d, aspect within %.2f %%, "
      "vertices within %.3f d, screw fractions within %.3f\n",
      c.name, worst_axis, worst_centroid, 100.0 * worst_aspect, worst_vertex, worst_screw);
}

INSTANTIATE_TEST_SUITE_P(
    Synthetic, Islands,
    ::testing::Values(Case{"clean_w2", 2.0, 0.0, 0.0, 0.0, 0.05, 0.999, 0.06},
                      Case{"clean_w1", 1.0, 0.0, 0.0, 0.0, 0.1, 0.999, 0.06},
                      Case{"clean_w4", 4.0, 0.0, 0.0, 0.0, 0.05, 0.999, 0.06},
                      Case{"noise_w2", 2.0, 0.0, 0.02, 0.05, 0.5, 0.8, 0.12},
                      Case{"offset_noise_w1", 1.0, 0.1, 0.02, 0.05, 0.6, 0.8, 0.12},
                      Case{"offset_w3", 3.0, 0.05, 0.0, 0.0, 0.6, 0.999, 0.12}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

// The census of a frame's lines (tracking/census.hpp) on three circular slipped islands inside
// the contact and one cut by its edge. Answers: 3 loops and 1 open line; the loops' areas sum to
// pi (15^2 + 8^2 + 5^2) d^2 within the 5 % of one loop's area above; the largest is the r = 15 d
// circle (extents 30 d within 2 d, twice the 1 d of a semi-axis; centroid within 0.5 d). A
// circle's tangent is within 45 degrees of x over exactly half its length, so the loops'
// length-weighted screw fraction is 1/2. The tangent is the chord over three marching-squares
// segments of a polygon inscribed in the circle, so near the four 45-degree points a segment is
// classed by a chord a few degrees off: measured 0.516 on this field (0.5 +- 0.016 is an arc of
// about 1.5 degrees misclassified at each of the eight boundaries); the tolerance 0.03 allows
// about 3 degrees. The slipped area is the contact sites inside the islands, counted here from
// the ellipses, plus some of the sites exactly on them: a site inside has sigma > 1/2 (registry
// index -1), one outside sigma < 1/2, and one on an ellipse (integer points of the circles)
// sigma = 1/2 and tau_x = 0, a site on the core itself, which the tracer joins to one side or the
// other by which of its edges the marching squares cut. So the count lies between the sites
// strictly inside and those inside or on the ellipses (1 117 and 1 148 on this field).
TEST(Census, LoopsAreasScrewFractionAndSlippedArea) {
  const std::vector<Island> islands = {
      {-25, 15, 15, 15}, {20, 20, 8, 8}, {10, -30, 5, 5}, {57, 0, 10, 8}};
  const SyntheticField field = synthetic_field(contact_options(), islands);
  const LineCensus c = census(find_lines(field.view()));
  EXPECT_EQ(c.lines, 4);
  EXPECT_EQ(c.loops, 3);
  EXPECT_EQ(c.open_lines, 1);
  EXPECT_EQ(c.wrapping_lines, 0);
  const double pi = std::numbers::pi;
  EXPECT_NEAR(c.loop_area, pi * (225 + 64 + 25), 0.05 * pi * (225 + 64 + 25));
  EXPECT_NEAR(c.largest_loop_area, pi * 225, 0.05 * pi * 225);
  EXPECT_NEAR(c.largest_loop_x_extent, 30.0, 2.0);
  EXPECT_NEAR(c.largest_loop_y_extent, 30.0, 2.0);
  EXPECT_NEAR(c.largest_loop_cx, -25.0, 0.5);
  EXPECT_NEAR(c.largest_loop_cy, 15.0, 0.5);
  EXPECT_NEAR(c.loop_screw_fraction, 0.5, 0.03);
  EXPECT_NEAR(c.largest_loop_screw_fraction, 0.5, 0.03);
  EXPECT_NEAR(c.loop_length, 2 * pi * (15 + 8 + 5), 0.05 * 2 * pi * (15 + 8 + 5));
  EXPECT_GT(c.open_length, 0.0);

  std::size_t inside = 0, on_edge = 0, contact = 0;
  const auto& b = field.block;
  for (int i0 = 0; i0 < b.shape.n0; ++i0) {
    for (int i1 = 0; i1 < b.shape.n1; ++i1) {
      const auto k = static_cast<std::size_t>(i0 * b.shape.n1 + i1);
      if (!field.in_contact[k]) continue;
      ++contact;
      const double x = b.origin0 + i0, y = b.origin1 + i1;
      double q = 2.0;  // the smallest (x/ax)^2 + (y/ay)^2 over the islands
      for (const Island& e : islands)
        q = std::min(q, std::pow((x - e.cx) / e.ax, 2) + std::pow((y - e.cy) / e.ay, 2));
      if (q < 1.0 - 1e-12) {
        ++inside;
      } else if (q <= 1.0 + 1e-12) {
        ++on_edge;
      }
    }
  }
  EXPECT_EQ(c.contact_sites, contact);
  EXPECT_GE(c.slipped_area, static_cast<double>(inside));
  EXPECT_LE(c.slipped_area, static_cast<double>(inside + on_edge));
  EXPECT_GT(on_edge, 0u) << "the bound is meant to be tested with sites on the cores";
  std::printf(
      "census: loop area %.1f (pi sum r^2 %.1f), screw fraction %.4f, slipped %.0f (inside %zu, "
      "on the cores %zu)\n",
      c.loop_area, pi * (225 + 64 + 25), c.loop_screw_fraction, c.slipped_area, inside, on_edge);

  // No lines: nothing counted, the fractions undefined.
  const LineCensus none = census(find_lines(synthetic_field(contact_options(), {}).view()));
  EXPECT_EQ(none.lines, 0);
  EXPECT_EQ(none.slipped_area, 0.0);
  EXPECT_TRUE(std::isnan(none.loop_screw_fraction));
  EXPECT_TRUE(std::isnan(none.largest_loop_screw_fraction));
}

TEST(Registry, ZeroCrossingsInRegistryAreNotCores) {
  for (const double noise : {0.0, 0.02}) {
    SyntheticOptions o = contact_options();
    o.registry_offset = 0.3;
    o.offset_wavelength = 20.0;
    o.noise_s = noise;
    o.noise_tau = noise;
    const FrameLines f = find_lines(synthetic_field(o, {}).view());
    EXPECT_GT(f.registry_crossings, 100u) << "the field must have zero crossings of tau_x";
    EXPECT_EQ(f.core_crossings, 0u);
    EXPECT_TRUE(f.lines.empty());
  }
}

std::vector<Event> run(const std::vector<std::vector<Island>>& frames,
                       std::vector<std::vector<int>>* ids = nullptr) {
  Tracker tracker;
  for (const auto& islands : frames) {
    SyntheticOptions o = contact_options();
    o.noise_s = 0.01;
    o.noise_tau = 0.02;
    const auto frame_ids = tracker.add(find_lines(synthetic_field(o, islands).view()));
    if (ids) ids->push_back(frame_ids);
  }
  return tracker.events();
}

int count(const std::vector<Event>& events, EventType type) {
  return static_cast<int>(std::count_if(events.begin(), events.end(),
                                        [type](const Event& e) { return e.type == type; }));
}

TEST(Sequence, ShrinkingLoopNucleatesAndAnnihilates) {
  std::vector<std::vector<Island>> frames(10);
  for (int k = 1; k <= 7; ++k) {  // frames 1..7: a loop around (5, -3) shrinking
    const double r = 16.0 - 2.0 * k;
    frames[static_cast<std::size_t>(k)] = {{5, -3, 1.6 * r, r}};
  }
  std::vector<std::vector<int>> ids;
  const auto events = run(frames, &ids);
  ASSERT_EQ(count(events, EventType::nucleation), 1);
  ASSERT_EQ(count(events, EventType::annihilation), 1);
  EXPECT_EQ(count(events, EventType::merge) + count(events, EventType::split) +
                count(events, EventType::reconnection),
            0);
  for (const Event& e : events) {
    if (e.type == EventType::nucleation) {
      EXPECT_EQ(e.frame, 1);
      EXPECT_EQ(e.location, "centre");
    }
    if (e.type == EventType::annihilation) {
      EXPECT_EQ(e.frame, 8);
    }
  }
  for (int k = 1; k <= 7; ++k) {  // one persistent id
    ASSERT_EQ(ids[static_cast<std::size_t>(k)].size(), 1u);
    EXPECT_EQ(ids[static_cast<std::size_t>(k)][0], ids[1][0]);
  }
  // Its slipped inside loses 1.6 pi (r^2 - (r - 2)^2) >= 50 d^2 a frame, far above arrest_area:
  // one retreat event when the shrinking starts (frame 2), none after while it goes on.
  ASSERT_EQ(count(events, EventType::retreat), 1);
  EXPECT_EQ(count(events, EventType::growth) + count(events, EventType::arrest), 0);
  for (const Event& e : events) {
    if (e.type != EventType::retreat) continue;
    EXPECT_EQ(e.frame, 2);
    EXPECT_LT(e.slipped_area_change, -50.0);
  }
  // The same frames backwards: a loop growing from the centre, one growth event.
  std::reverse(frames.begin(), frames.end());
  const auto backwards = run(frames);
  ASSERT_EQ(count(backwards, EventType::growth), 1);
  EXPECT_EQ(count(backwards, EventType::retreat) + count(backwards, EventType::arrest), 0);
  for (const Event& e : backwards) {
    if (e.type != EventType::growth) continue;
    EXPECT_GT(e.slipped_area_change, 50.0);
  }
}

TEST(Sequence, TwoLoopsMergeAndSplit) {
  // Circles of radius 5.5 at x = +-(12 - 2k): separate for k <= 3, one island from k = 4.
  std::vector<std::vector<Island>> frames;
  for (int k = 0; k <= 5; ++k) {
    const double c = 12.0 - 2.0 * k;
    frames.push_back({{-c, 4, 5.5, 5.5}, {c, 4, 5.5, 5.5}});
  }
  const auto forward = run(frames);
  ASSERT_EQ(count(forward, EventType::merge), 1);
  EXPECT_EQ(count(forward, EventType::nucleation) + count(forward, EventType::annihilation) +
                count(forward, EventType::split),
            0);
  for (const Event& e : forward) {
    if (e.type != EventType::merge) continue;
    EXPECT_EQ(e.frame, 4);
    EXPECT_EQ(e.before.size(), 2u);
    EXPECT_EQ(e.after.size(), 1u);
  }
  std::reverse(frames.begin(), frames.end());
  const auto backward = run(frames);
  ASSERT_EQ(count(backward, EventType::split), 1);
  EXPECT_EQ(count(backward, EventType::merge), 0);
  for (const Event& e : backward) {
    if (e.type == EventType::split) {
      EXPECT_EQ(e.frame, 2);
    }
  }
}

}  // namespace

// Cores along the contact's jagged edge (DetectOptions::join_distance). The slipped region is a
// disk of radius r_s = 59 d inside the contact of radius 60 d, with the sides covered by two
// ellipses centred on the contact edge at (+-60, 0) (semi-axes 25 and 35 d): inside the contact
// the core is then two arcs of the circle r = r_s, at the top and bottom, 1 d from the edge, the
// seed's "two screw lines at the top and bottom" (MODEL.md 5), ending where the ellipses cut them
// (and along the ellipses' short pieces out to the edge). The marching squares trace only cells
// with four sites in contact, and along a circle 1 d inside the edge such cells break off at
// every row where the staircase of the edge steps inward: traced alone, each arc is 17 pieces
// and 22 pieces shorter than min_length (measured: 34 lines, 44 dropped). Answers, with the
// default join_distance (4 d): exactly two open lines, b = -d x-hat, no interior ends, each
// spanning x = -x_c ... x_c to 0.5 d (x_c = 49.66 d where the circle meets the ellipses; their
// short pieces out to the edge reach 50.0 d), with the length of the arc between those points,
// 2 r_s asin(x_c / r_s) = 118.03 d, to 1 % (the polygon of crossings and the ellipses' pieces
// add 0.1-0.3 %: 118.19 and 118.33 d measured for w = 2 and 1 d, as for the same arcs 1.5 d
// inside the edge, which the marching squares trace whole). The same disk without the ellipses
// makes one chain all around: joins make no loops, so it is one open line (below).
namespace {
double arc_end_x(double r, const Island& e) {
  // x where the circle of radius r (centre 0) meets the ellipse e (upper half): bisection on the
  // angle between 0 (inside the ellipse) and pi/2 (outside).
  double lo = 0.0, hi = std::numbers::pi / 2;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double x = r * std::cos(mid), y = r * std::sin(mid);
    (std::pow((x - e.cx) / e.ax, 2) + std::pow((y - e.cy) / e.ay, 2) < 1.0 ? lo : hi) = mid;
  }
  return r * std::cos(lo);
}
}  // namespace

TEST(EdgeLines, PiecesAlongTheJaggedEdgeAreOneLinePerSide) {
  const double r_s = 59.0;
  const Island right{60, 0, 25, 35}, left{-60, 0, 25, 35};
  for (const double w : {1.0, 2.0}) {
    SyntheticOptions o = contact_options();
    o.core_width = w;
    const SyntheticField field = synthetic_field(o, {{0, 0, r_s, r_s}, right, left});

    DetectOptions alone;
    alone.join_distance = 0.0;
    const FrameLines cut = find_lines(field.view(), alone);
    EXPECT_GE(cut.lines.size() + cut.dropped_short, 20u) << "the arcs must come in pieces";
    EXPECT_EQ(cut.joined_pieces, 0u);

    const FrameLines f = find_lines(field.view());
    ASSERT_EQ(f.lines.size(), 2u) << "w = " << w;
    EXPECT_EQ(f.dropped_short, 0u);
    EXPECT_EQ(f.joined_pieces, cut.lines.size() + cut.dropped_short);
    const double x_c = arc_end_x(r_s, right);
    const double arc = 2.0 * r_s * std::asin(x_c / r_s);
    int top = 0;
    for (const Line& l : f.lines) {
      EXPECT_EQ(l.kind, LineKind::open);
      EXPECT_EQ(l.burgers, -1);
      EXPECT_EQ(l.interior_ends, 0);
      EXPECT_GT(l.pieces, 10);
      EXPECT_GT(l.registry_consistency, 0.999);
      EXPECT_NEAR(l.x_min, -x_c, 0.5);
      EXPECT_NEAR(l.x_max, x_c, 0.5);
      EXPECT_NEAR(l.length, arc, 0.01 * arc);
      top += l.centroid.y > 0.0 ? 1 : 0;
      std::printf("w %.0f: %s line of %d pieces, %.2f d (arc %.2f d), x %.2f..%.2f d\n", w,
                  l.centroid.y > 0.0 ? "top" : "bottom", l.pieces, l.length, arc, l.x_min, l.x_max);
    }
    EXPECT_EQ(top, 1);

    // Without the side ellipses the pieces run around the whole contact. Joins make no loops: one
    // open line whose two ends meet at the one gap left open (at most join_distance), with the
    // circle's length less that gap (to 1 %).
    const FrameLines ring = find_lines(synthetic_field(o, {{0, 0, r_s, r_s}}).view());
    ASSERT_EQ(ring.lines.size(), 1u);
    const Line& around = ring.lines.front();
    EXPECT_EQ(around.kind, LineKind::open);
    EXPECT_EQ(around.burgers, -1);
    EXPECT_EQ(around.interior_ends, 0);
    EXPECT_GT(around.pieces, 20);
    const Point first = around.points.front(), last = around.points.back();
    const double gap = std::hypot(first.x - last.x, first.y - last.y);
    EXPECT_LE(gap, DetectOptions{}.join_distance);
    const double circle = 2.0 * std::numbers::pi * r_s;
    EXPECT_NEAR(around.length + gap, circle, 0.01 * circle);
    std::printf("w %.0f: around the contact %d pieces, %.2f d + gap %.2f d (2 pi r_s %.2f d)\n", w,
                around.pieces, around.length, gap, circle);
  }
}

// Two half-loops at the edge whose nearest ends are a few d apart, more than join_distance,
// stay two lines; with a join distance above the gap they become one (so the test can fail).
TEST(EdgeLines, SeparateLinesAtTheEdgeAreNotJoined) {
  const SyntheticField field = synthetic_field(contact_options(), {{57, 8, 8, 5}, {57, -8, 8, 5}});
  const FrameLines f = find_lines(field.view());
  ASSERT_EQ(f.lines.size(), 2u);
  EXPECT_EQ(f.joined_pieces, 0u);
  double gap = std::numeric_limits<double>::infinity();
  for (const Line& a : f.lines) {
    EXPECT_EQ(a.kind, LineKind::open);
    EXPECT_EQ(a.pieces, 1);
    for (const Line& b : f.lines) {
      if (&a == &b) continue;
      gap = std::min(gap, std::hypot(b.points.front().x - a.points.back().x,
                                     b.points.front().y - a.points.back().y));
    }
  }
  const double join = DetectOptions{}.join_distance;
  EXPECT_GT(gap, join);
  EXPECT_LT(gap, 3.0 * join) << "the ends should be near the join distance";
  DetectOptions wide;
  wide.join_distance = gap + 0.1;
  const FrameLines joined = find_lines(field.view(), wide);
  ASSERT_EQ(joined.lines.size(), 1u);
  EXPECT_EQ(joined.lines.front().pieces, 2);
  std::printf("ends %.2f d apart: %zu lines at join distance %.1f d, %zu at %.2f d\n", gap,
              f.lines.size(), join, joined.lines.size(), wide.join_distance);
}
