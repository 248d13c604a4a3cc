// tracking/ (MODEL.md section 7): option and input validation, line kinds in periodic cells,
// orientation and sense conventions, and the tracker's bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <string>

#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"
#include "asperity/tracking/synthetic.hpp"
#include "asperity/tracking/tracker.hpp"

using namespace asperity;
using namespace asperity::tracking;

namespace {

void expect_rejects(const auto& make_invalid, const std::string& field) {
  try {
    make_invalid();
    FAIL() << "expected std::invalid_argument naming " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(TrackingOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(DetectOptions{}.validate());
  EXPECT_NO_THROW(TrackOptions{}.validate());
  EXPECT_NO_THROW(FrontOptions{}.validate());
  EXPECT_NO_THROW(SyntheticOptions{}.validate());
}

// validate() comes from the settings tables: a violation names the key (as track_loops' flags
// and the Python keywords do) and what is allowed.
TEST(TrackingOptions, ViolationsNameTheSetting) {
  expect_rejects([] { DetectOptions{.min_length = -1}.validate(); }, "min_length = -1: allowed");
  expect_rejects([] { DetectOptions{.slip_sign = 0}.validate(); }, "slip_sign = \"0\": allowed");
  expect_rejects([] { DetectOptions{.screw_angle_deg = 90}.validate(); }, "screw_angle_deg = 90");
  expect_rejects([] { DetectOptions{.join_distance = -1}.validate(); }, "join_distance = -1");
  expect_rejects([] { DetectOptions{.join_distance = INFINITY}.validate(); }, "join_distance =");
  expect_rejects([] { DetectOptions{.tangent_half_window = 17}.validate(); },
                 "tangent_half_window = 17");
  expect_rejects([] { TrackOptions{.min_overlap = 0}.validate(); }, "min_overlap = 0");
  expect_rejects([] { TrackOptions{.max_centroid_distance = NAN}.validate(); },
                 "max_centroid_distance =");
  expect_rejects([] { Tracker(TrackOptions{.arrest_area = -1}); }, "arrest_area = -1");
  expect_rejects([] { TrackOptions{.centre_fraction = 1.5}.validate(); }, "centre_fraction = 1.5");
  expect_rejects([] { FrontOptions{.span = 0}.validate(); }, "span = 0: allowed: > 0 d");
  expect_rejects([] { FrontOptions{.stretches = 2.5}.validate(); },
                 "stretches = 2.5: allowed: >= 3");
  expect_rejects([] { FrontOptions{.step = INFINITY}.validate(); }, "step =");
  expect_rejects([] { FrontOptions{.widths = -1}.validate(); }, "widths = -1");
  expect_rejects([] { FrontOptions{.max_half_width = 0}.validate(); }, "max_half_width = 0");
  expect_rejects([] { SyntheticOptions{.registry_offset = 0.5}.validate(); },
                 "SyntheticOptions.registry_offset");
}

// Each row of the tables reads and writes its own field: a value set through the row is the
// field's, and no other row's value changes (a row wired to the wrong member fails).
template <class Root>
void expect_rows_reach_their_fields(const std::map<std::string, settings::Value>& values) {
  const settings::Table<Root>& table = Root::settings();
  ASSERT_EQ(table.size(), values.size());
  for (const settings::Setting<Root>& row : table) {
    SCOPED_TRACE(row.key);
    ASSERT_TRUE(values.contains(row.key));
    const settings::Value v = values.at(row.key);
    ASSERT_NO_THROW(row.check(v));
    ASSERT_NE(v, row.get(Root{}));  // a value the default is not
    Root r;
    row.set(r, v);
    EXPECT_EQ(row.get(r), v);
    for (const settings::Setting<Root>& other : table) {
      if (other.key == row.key) continue;
      EXPECT_EQ(other.get(r), other.get(Root{})) << other.key;
    }
  }
}

// Sets every row of Root's table to its value in `values`.
template <class Root>
Root all_set(const std::map<std::string, settings::Value>& values) {
  Root r;
  for (const settings::Setting<Root>& row : Root::settings())
    row.set(r, values.at(row.key));
  return r;
}

TEST(TrackingOptions, EachRowReachesItsField) {
  const std::map<std::string, settings::Value> detect = {{"min_length", 3.0},
                                                         {"join_distance", 0.5},
                                                         {"slip_sign", std::string("1")},
                                                         {"tangent_half_window", 2LL},
                                                         {"screw_angle_deg", 30.0}};
  const std::map<std::string, settings::Value> track = {{"min_overlap", 0.5},
                                                        {"max_centroid_distance", 4.0},
                                                        {"max_motion", 10.0},
                                                        {"arrest_area", 1.5},
                                                        {"centre_fraction", 0.25}};
  const std::map<std::string, settings::Value> front = {
      {"span", 16.0}, {"stretches", 4.0}, {"step", 2.0}, {"widths", 3.0}, {"max_half_width", 24.0}};
  expect_rows_reach_their_fields<DetectOptions>(detect);
  expect_rows_reach_their_fields<TrackOptions>(track);
  expect_rows_reach_their_fields<FrontOptions>(front);
  expect_rows_reach_their_fields<CrossingOptions>({{"widths", 3.0}});
  EXPECT_EQ(all_set<CrossingOptions>({{"widths", 3.0}}).widths, 3.0);
  expect_rejects([] { CrossingOptions{.widths = 0}.validate(); },
                 "widths = 0: allowed: > 0 b_core");
  // Each key's field by name, all set at once to distinct values: two rows wired to each
  // other's members (span and max_half_width share a default of 32) fail here.
  const auto d = all_set<DetectOptions>(detect);
  EXPECT_EQ(d.min_length, 3.0);
  EXPECT_EQ(d.join_distance, 0.5);
  EXPECT_EQ(d.slip_sign, 1);
  EXPECT_EQ(d.tangent_half_window, 2);
  EXPECT_EQ(d.screw_angle_deg, 30.0);
  const auto t = all_set<TrackOptions>(track);
  EXPECT_EQ(t.min_overlap, 0.5);
  EXPECT_EQ(t.max_centroid_distance, 4.0);
  EXPECT_EQ(t.max_motion, 10.0);
  EXPECT_EQ(t.arrest_area, 1.5);
  EXPECT_EQ(t.centre_fraction, 0.25);
  const auto f = all_set<FrontOptions>(front);
  EXPECT_EQ(f.span, 16.0);
  EXPECT_EQ(f.stretches, 4.0);
  EXPECT_EQ(f.step, 2.0);
  EXPECT_EQ(f.widths, 3.0);
  EXPECT_EQ(f.max_half_width, 24.0);
}

TEST(FieldView, SizesAndShapeAreChecked) {
  const SyntheticField f = synthetic_field(SyntheticOptions{}, {});
  FieldView v = f.view();
  EXPECT_NO_THROW(v.validate());
  v.tau_x = v.tau_x.subspan(1);
  expect_rejects([&] { find_lines(v); }, "FieldView.tau_x");
  v = f.view();
  v.in_contact = {};  // allowed: contact from tau_max
  EXPECT_NO_THROW(find_lines(v));
  v.block.shape = {1, 4096};
  expect_rejects([&] { v.validate(); }, "FieldView.block.shape");
}

TEST(Lines, EmptyAndUniformFieldsHaveNoLines) {
  const FrameLines f = find_lines(synthetic_field(SyntheticOptions{}, {}).view());
  EXPECT_TRUE(f.lines.empty());
  EXPECT_EQ(f.contact_sites, 64u * 64u);
}

TEST(Lines, LoopSenseAndOrientation) {
  // Index -1 inside (slip_sign -1): counter-clockwise, inside on the left: b = -d x-hat.
  const FrameLines f = find_lines(synthetic_field(SyntheticOptions{}, {{0, 0, 12, 8}}).view());
  ASSERT_EQ(f.lines.size(), 1u);
  const Line& l = f.lines[0];
  EXPECT_EQ(l.kind, LineKind::loop);
  EXPECT_EQ(l.burgers, -1);
  EXPECT_GT(l.area, 0.0);
  // Counter-clockwise: the signed (shoelace) area of the vertices is positive, and it is the area.
  double signed_area = 0.0;
  for (std::size_t k = 0; k < l.points.size(); ++k) {
    const Point& p = l.points[k];
    const Point& q = l.points[(k + 1) % l.points.size()];
    signed_area += 0.5 * (p.x * q.y - q.x * p.y);
  }
  EXPECT_NEAR(signed_area, l.area, 1e-9 * l.area);
  ASSERT_GE(l.slipped_region, 0);
  // The slipped region is the inside: about pi 12 8 sites.
  EXPECT_NEAR(static_cast<double>(f.regions[static_cast<std::size_t>(l.slipped_region)].size()),
              std::numbers::pi * 96.0, 15.0);
  EXPECT_TRUE(std::is_sorted(f.regions[0].begin(), f.regions[0].end()));
  // The opposite sense: index +1 inside; the slipped side (lower index) is then outside.
  SyntheticOptions o;
  o.slip_sign = 1;
  const FrameLines g = find_lines(synthetic_field(o, {{0, 0, 12, 8}}).view());
  ASSERT_EQ(g.lines.size(), 1u);
  EXPECT_EQ(g.lines[0].burgers, 1);
  EXPECT_GT(g.regions[0].size(), 64u * 64u / 2);
}

// A tip lattice out of registry (FieldView::tip): the lines follow the registry along the tip's
// first axis. A loop written in that registry (rho_1 = the aligned field's s_x / d, the stress
// along the axis its tau_x, rho_2 = Y / d_tip) and turned into the substrate's frame is found
// as the aligned field's loop: the same vertices and Burgers index.
TEST(Lines, LoopInTheFrameOfARotatedTip) {
  const SyntheticField a = synthetic_field(SyntheticOptions{}, {{0, 0, 12, 8}});
  const FrameLines fa = find_lines(a.view());
  ASSERT_EQ(fa.lines.size(), 1u);
  const interface::TipLattice tip { .angle = 3.0, .mismatch = 0.02 };
  const interface::TipFrame frame(tip, 1.0);
  const std::size_t n = a.sx.size();
  std::vector<double> sx(n), sy(n), tau_x(n), tau_y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double Y = a.block.y(static_cast<int>(i % 64), 1.0);
    frame.to_substrate(a.sx[i] * frame.spacing(), Y, sx[i], sy[i]);
    frame.to_substrate(a.tau_x[i], 0.0, tau_x[i], tau_y[i]);
  }
  FieldView v = a.view();
  v.sx = sx;
  v.tau_x = tau_x;
  v.sy = sy;
  v.tau_y = tau_y;
  v.tip = tip;
  const FrameLines fr = find_lines(v);
  ASSERT_EQ(fr.lines.size(), 1u);
  const Line &la = fa.lines[0], &lr = fr.lines[0];
  EXPECT_EQ(lr.kind, LineKind::loop);
  EXPECT_EQ(lr.burgers, la.burgers);
  ASSERT_EQ(lr.points.size(), la.points.size());
  for (std::size_t k = 0; k < la.points.size(); ++k) {
    EXPECT_NEAR(lr.points[k].x, la.points[k].x, 1e-9);
    EXPECT_NEAR(lr.points[k].y, la.points[k].y, 1e-9);
  }
  EXPECT_NEAR(lr.area, la.area, 1e-6);
  // The character is measured against b, along the tip's axis 3 degrees off x. The segments'
  // directions are the aligned field's (same vertices), so each angle to b is the aligned
  // angle turned by 3 degrees one way or the other (by the segment's sense of turn), folded
  // into [0, 90]: a segment along x is 3 degrees off screw, one along y 3 degrees off edge.
  ASSERT_EQ(lr.angle_deg.size(), la.angle_deg.size());
  const auto fold = [](double t) { return t < 0.0 ? -t : (t > 90.0 ? 180.0 - t : t); };
  int turned = 0;
  for (std::size_t k = 0; k < la.angle_deg.size(); ++k) {
    const double aligned = la.angle_deg[k], rotated = lr.angle_deg[k];
    EXPECT_NEAR(
        std::min(std::abs(rotated - fold(aligned + 3.0)), std::abs(rotated - fold(aligned - 3.0))),
        0.0, 1e-9)
        << k << ": " << aligned << " -> " << rotated;
    if (std::abs(rotated - aligned) > 2.0) ++turned;
  }
  EXPECT_GT(turned, static_cast<int>(la.angle_deg.size()) / 2);
  // Without sy and tau_y a rotated tip's view is refused.
  v.sy = {};
  EXPECT_THROW((void)find_lines(v), std::invalid_argument);
}

TEST(Lines, BandInPeriodicCellGivesTwoWrappingScrewLines) {
  SyntheticOptions o;
  o.block = LatticeBlock{.shape = {48, 64}, .origin0 = 0, .origin1 = 0};
  o.periodic = true;
  const FrameLines f = find_lines(synthetic_field(o, {{10, 32.3, 1e7, 8}}).view());
  ASSERT_EQ(f.lines.size(), 2u);
  for (const Line& l : f.lines) {
    EXPECT_EQ(l.kind, LineKind::wrapping);
    EXPECT_NEAR(l.length, 48.0, 1e-6);
    EXPECT_DOUBLE_EQ(l.screw_fraction, 1.0);
    EXPECT_NEAR(l.mean_angle_deg, 0.0, 1e-6);
    EXPECT_EQ(l.burgers, -1);  // open and wrapping lines: slipped side on the left
    EXPECT_NEAR(std::abs(l.centroid.y - 32.3), 8.0, 0.05);
  }
  // The same band without periodicity: two open lines ending at the block's sides.
  o.periodic = false;
  const FrameLines g = find_lines(synthetic_field(o, {{10, 32.3, 1e7, 8}}).view());
  ASSERT_EQ(g.lines.size(), 2u);
  for (const Line& l : g.lines)
    EXPECT_EQ(l.kind, LineKind::open);
}

TEST(Lines, EdgeBandIsEdgeCharacter) {
  SyntheticOptions o;
  o.block = LatticeBlock{.shape = {64, 48}, .origin0 = 0, .origin1 = 0};
  o.periodic = true;
  const FrameLines f = find_lines(synthetic_field(o, {{32.3, 0, 8, 1e7}}).view());
  ASSERT_EQ(f.lines.size(), 2u);
  for (const Line& l : f.lines) {
    EXPECT_DOUBLE_EQ(l.edge_fraction, 1.0);
    EXPECT_NEAR(l.mean_angle_deg, 90.0, 1e-6);
  }
}

TEST(Lines, LoopAcrossPeriodicSidesIsOneLoop) {
  SyntheticOptions o;
  o.block = LatticeBlock{.shape = {64, 64}, .origin0 = 0, .origin1 = 0};
  o.periodic = true;
  const FrameLines f = find_lines(synthetic_field(o, {{0, 0, 10, 10}}).view());
  ASSERT_EQ(f.lines.size(), 1u);
  EXPECT_EQ(f.lines[0].kind, LineKind::loop);
  EXPECT_NEAR(f.lines[0].area, std::numbers::pi * 100.0, 0.03 * std::numbers::pi * 100.0);
  EXPECT_NEAR(f.lines[0].length, 2.0 * std::numbers::pi * 10.0, 1.0);
  EXPECT_EQ(location_class(f, f.lines[0].centroid, 0.5), "cell");
}

TEST(Lines, LocationClasses) {
  FrameLines f;
  f.contact_radius = 40.0;
  EXPECT_EQ(location_class(f, {5, 5}, 0.5), "centre");
  EXPECT_EQ(location_class(f, {3, -38}, 0.5), "side");
  EXPECT_EQ(location_class(f, {38, 3}, 0.5), "front");
  EXPECT_EQ(location_class(f, {-38, 3}, 0.5), "back");
}

TEST(Lines, SiteKeysSortByXThenY) {
  EXPECT_LT(site_key(-3, 100), site_key(-2, -100));
  EXPECT_LT(site_key(4, -7), site_key(4, -6));
  EXPECT_LT(site_key(-1, 2147483647), site_key(0, -2147483648LL));
}

// A synthetic contact snapshot: the field of synthetic_field() with the tip at Dx (the field's
// coordinates are lattice coordinates either way), tau_y = 0 and p = tau_max / 0.7.
slide::Snapshot snapshot_of(const SyntheticField& f, double Dx) {
  slide::Snapshot s;
  s.Dx = Dx;
  s.block = f.block;
  s.sx = f.sx;
  s.tau_x = f.tau_x;
  s.tau_max = f.tau_max;
  s.tau_y.assign(f.tau_x.size(), 0.0);
  for (const double t : f.tau_max)
    s.pressure.push_back(t / 0.7);
  s.in_contact = f.in_contact;
  s.ux.assign(f.tau_x.size(), 0.0);
  s.uy = s.ux;
  return s;
}

// The census adds its lines up as the header says, on a frame made by hand: two nested loops
// bounding one slipped ring (a domain both lines share counts once), an open line with its own
// domain, a wrapping line without one.
TEST(Census, SumsByKindAndCountsASharedDomainOnce) {
  FrameLines f;
  f.d = 0.5;
  f.contact_sites = 1000;
  f.regions = {std::vector<std::int64_t>(300), std::vector<std::int64_t>(40)};
  const auto line = [](LineKind kind, double length, double area, double screw, int region) {
    Line l;
    l.kind = kind;
    l.length = length;
    l.area = area;
    l.screw_fraction = screw;
    l.edge_fraction = 1.0 - screw;
    l.slipped_region = region;
    l.x_min = -area / 20.0;
    l.x_max = area / 20.0;
    l.y_min = -area / 40.0;
    l.y_max = area / 40.0;
    l.centroid = {area / 100.0, -1.0};
    return l;
  };
  f.lines = {line(LineKind::loop, 60.0, 200.0, 0.5, 0), line(LineKind::loop, 30.0, 50.0, 0.8, 0),
             line(LineKind::open, 10.0, 0.0, 1.0, 1), line(LineKind::wrapping, 5.0, 0.0, 0.0, -1)};
  const LineCensus c = census(f);
  EXPECT_EQ(c.lines, 4);
  EXPECT_EQ(c.loops, 2);
  EXPECT_EQ(c.open_lines, 1);
  EXPECT_EQ(c.wrapping_lines, 1);
  EXPECT_EQ(c.contact_sites, 1000u);
  EXPECT_DOUBLE_EQ(c.loop_area, 250.0);
  EXPECT_DOUBLE_EQ(c.loop_length, 90.0);
  EXPECT_DOUBLE_EQ(c.open_length, 15.0);
  EXPECT_DOUBLE_EQ(c.loop_screw_fraction, (0.5 * 60.0 + 0.8 * 30.0) / 90.0);
  EXPECT_DOUBLE_EQ(c.largest_loop_area, 200.0);
  EXPECT_DOUBLE_EQ(c.largest_loop_x_extent, 20.0);
  EXPECT_DOUBLE_EQ(c.largest_loop_y_extent, 10.0);
  EXPECT_DOUBLE_EQ(c.largest_loop_screw_fraction, 0.5);
  EXPECT_DOUBLE_EQ(c.largest_loop_cx, 2.0);
  EXPECT_DOUBLE_EQ(c.largest_loop_cy, -1.0);
  EXPECT_DOUBLE_EQ(c.slipped_area, (300 + 40) * 0.25);  // the ring once, times d^2
}

TEST(Profile, RowAndColumnThroughTheTipCentre) {
  SyntheticOptions o;
  o.contact_radius = 24.0;
  o.tau_peak = 0.5;
  const SyntheticField f = synthetic_field(o, {{0, 0, 12, 8}});
  const slide::Snapshot s = snapshot_of(f, 2.6);
  const StressProfile px = stress_profile(s, ProfileAxis::x);
  ASSERT_EQ(px.position.size(), 64u);  // the block's 64 sites along x, X = -32 ... 31
  EXPECT_EQ(px.through, 0.0);
  EXPECT_EQ(px.centre, 2.6);
  EXPECT_DOUBLE_EQ(px.position.front(), -32.0 - 2.6);
  // The largest envelope is the contact centre's, tau_peak (the site at r = 0).
  EXPECT_EQ(px.tau_max_peak, 0.5);
  // Site X = 0, Y = 0: block index (32, 32).
  const std::size_t centre = 32 * 64 + 32;
  EXPECT_EQ(px.tau_x[32], s.tau_x[centre]);
  EXPECT_EQ(px.tau_max[32], 0.5);
  EXPECT_DOUBLE_EQ(px.pressure[32], 0.5 / 0.7);
  // Along y: the column of sites nearest X = Dx = 2.6, X = 3.
  const StressProfile py = stress_profile(s, ProfileAxis::y);
  EXPECT_EQ(py.through, 3.0);
  EXPECT_EQ(py.centre, 0.0);
  EXPECT_EQ(py.tau_x[32], s.tau_x[35 * 64 + 32]);
  EXPECT_EQ(py.in_contact[0], 0);  // Y = -32: outside the 24 d contact
  EXPECT_EQ(py.in_contact[32], 1);
  // A tip whose centre column is off the block is refused.
  EXPECT_THROW(stress_profile(snapshot_of(f, 40.0), ProfileAxis::y), std::invalid_argument);
}

TEST(Profile, CoresCrossTheAxesWhereTheLoopIs) {
  // An elliptical loop of semi-axes 12 d along x and 8 d along y about (0, 0): along x it is
  // crossed at x = +-12 d by edge segments, along y (column X = 0) at y = +-8 d by screw ones.
  // The marching-squares trace interpolates tau_x linearly between sites: within 0.3 d.
  SyntheticOptions o;
  o.contact_radius = 24.0;
  const SyntheticField f = synthetic_field(o, {{0, 0, 12, 8}});
  const FrameLines lines = find_lines(f.view());
  ASSERT_EQ(lines.lines.size(), 1u);
  const slide::Snapshot s = snapshot_of(f, 0.0);
  const auto along_x = core_crossings(lines, stress_profile(s, ProfileAxis::x));
  ASSERT_EQ(along_x.size(), 2u);
  EXPECT_NEAR(along_x[0].position, -12.0, 0.3);
  EXPECT_NEAR(along_x[1].position, 12.0, 0.3);
  for (const auto& c : along_x) {
    EXPECT_GT(c.angle_deg, 60.0);
    EXPECT_EQ(c.kind, LineKind::loop);
    EXPECT_EQ(c.line, 0u);
  }
  const auto along_y = core_crossings(lines, stress_profile(s, ProfileAxis::y));
  ASSERT_EQ(along_y.size(), 2u);
  EXPECT_NEAR(along_y[0].position, -8.0, 0.3);
  EXPECT_NEAR(along_y[1].position, 8.0, 0.3);
  for (const auto& c : along_y)
    EXPECT_LT(c.angle_deg, 30.0);
}

TEST(Profile, CrossingsOfAHandMadeLineAreExact) {
  // A square loop with vertices on the row y = 0: each vertex on the row counts once, and an
  // open line through the row is crossed once.
  FrameLines f;
  Line loop;
  loop.kind = LineKind::loop;
  loop.points = {{-3, 0}, {1, -4}, {5, 0}, {1, 4}};
  loop.angle_deg = {45, 45, 45, 45};
  Line open;
  open.kind = LineKind::open;
  open.points = {{7.5, -2}, {7.5, 2}};
  open.angle_deg = {90};
  f.lines = {loop, open};
  StressProfile p;
  p.axis = ProfileAxis::x;
  p.centre = 0.5;
  const auto c = core_crossings(f, p);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_DOUBLE_EQ(c[0].position, -3.5);
  EXPECT_DOUBLE_EQ(c[1].position, 4.5);
  EXPECT_DOUBLE_EQ(c[2].position, 7.0);
  EXPECT_EQ(c[2].line, 1u);
  EXPECT_EQ(c[2].kind, LineKind::open);
  EXPECT_EQ(to_string(ProfileAxis::y), "y");
  // Open lines that end on the row, arriving from above, from below, and leaving it either way:
  // each is crossed there once.
  for (const auto& [from, to] : {std::pair{Point{9, 2}, Point{9, 0}},
                                 {Point{9, -2}, Point{9, 0}},
                                 {Point{9, 0}, Point{9, 2}},
                                 {Point{9, 0}, Point{9, -2}}}) {
    Line end;
    end.kind = LineKind::open;
    end.points = {from, to};
    end.angle_deg = {90};
    f.lines = {end};
    const auto e = core_crossings(f, p);
    ASSERT_EQ(e.size(), 1u) << from.y << " -> " << to.y;
    EXPECT_DOUBLE_EQ(e[0].position, 8.5);
  }
}

// core_stress on a hand-made profile: sites at x = -20 ... 20 d, a Peierls-Nabarro core at
// xi = 0.5 d (offset (1/pi) arctan((x - xi)/zeta), zeta = 2 d) and tau_x = sigma + an odd
// function of x - xi (the core's own swing, of amplitude 0.4 G). Sites and bonds are symmetric
// about xi, so the weight rho pairs each bond with its mirror, where the odd part changes sign:
// the average is sigma to round-off.
TEST(Profile, CoreStressWeighsOutTheCoresOwnSwing) {
  const double xi = 0.5, zeta = 2.0, sigma = 0.037, pi = std::acos(-1.0);
  StressProfile p;
  for (int k = -20; k <= 21; ++k) {
    const double x = k;
    p.position.push_back(x);
    p.offset.push_back(std::atan((x - xi) / zeta) / pi);
    p.tau_x.push_back(sigma - 0.8 * zeta * (x - xi) / ((x - xi) * (x - xi) + zeta * zeta));
    p.in_contact.push_back(1);
  }
  const CoreStress whole = core_stress(p, -20.0, 21.0);
  EXPECT_EQ(whole.bonds, 41);
  EXPECT_NEAR(whole.tau, sigma, 1e-14);
  EXPECT_NEAR(whole.slip, (std::atan(20.5 / zeta) - std::atan(-20.5 / zeta)) / pi, 1e-14);
  EXPECT_GT(whole.slip, 0.9);  // most of the core's period d lies in the window
  EXPECT_TRUE(whole.resolved());
  EXPECT_FALSE(core_stress(p, 0.0, 21.0).resolved());  // half of the core: its inner side
  // A window symmetric about xi, narrower: still sigma, less of the slip.
  const CoreStress narrow = core_stress(p, -3.0, 4.0);
  EXPECT_EQ(narrow.bonds, 7);
  EXPECT_NEAR(narrow.tau, sigma, 1e-14);
  EXPECT_LT(narrow.slip, whole.slip);
  // An off-centre window keeps more of one side of the swing: the weighting is not a plain
  // mean that hides it. The bonds x in [2, 6] alone lie on the negative side of the swing.
  EXPECT_LT(core_stress(p, 2.0, 6.0).tau, sigma - 0.05);
  // Bonds with an end outside the contact are left out; with no bond left there is no stress.
  p.in_contact[20] = 0;  // x = 0: the bonds [-1, 0] and [0, 1]
  EXPECT_EQ(core_stress(p, -20.0, 21.0).bonds, 39);
  EXPECT_TRUE(std::isnan(core_stress(p, -0.5, 0.5).tau));
  EXPECT_THROW(core_stress(p, 1.0, 0.0), std::invalid_argument);
  p.offset.clear();
  EXPECT_THROW(core_stress(p, -20.0, 21.0), std::invalid_argument);
}

// The profile carries the snapshot's registry offset s_x - X, site for site.
TEST(Profile, CarriesTheRegistryOffset) {
  SyntheticOptions o;
  o.contact_radius = 24.0;
  const SyntheticField f = synthetic_field(o, {{0, 0, 12, 8}});
  slide::Snapshot s = snapshot_of(f, 2.6);
  s.sx.resize(s.tau_x.size());
  for (std::size_t i = 0; i < s.sx.size(); ++i)
    s.sx[i] = 0.001 * static_cast<double>(i);
  const StressProfile px = stress_profile(s, ProfileAxis::x);
  // Site X = 5 (block index 37), Y = 0 (index 32).
  EXPECT_DOUBLE_EQ(px.offset[37], 0.001 * (37 * 64 + 32) - 5.0);
  const StressProfile py = stress_profile(s, ProfileAxis::y);  // column X = 3 (index 35)
  EXPECT_DOUBLE_EQ(py.offset[10], 0.001 * (35 * 64 + 10) - 3.0);
  s.sx.clear();
  EXPECT_TRUE(stress_profile(s, ProfileAxis::x).offset.empty());
}

TEST(Tracker, FirstFrameLinesGetIdsWithoutEvents) {
  Tracker t;
  const FrameLines f = find_lines(synthetic_field(SyntheticOptions{}, {{0, 0, 12, 8}}).view());
  const auto ids = t.add(f);
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_TRUE(t.events().empty());
  const auto same = t.add(f);  // unchanged: arrested, same id
  EXPECT_EQ(same, ids);
  ASSERT_EQ(t.events().size(), 1u);
  EXPECT_EQ(t.events()[0].type, EventType::arrest);
  const auto none = t.add(FrameLines{});
  EXPECT_TRUE(none.empty());
  ASSERT_EQ(t.events().size(), 2u);
  EXPECT_EQ(t.events()[1].type, EventType::annihilation);
  EXPECT_EQ(t.frames(), 3);
  EXPECT_EQ(to_string(EventType::reconnection), "reconnection");
  EXPECT_EQ(to_string(LineKind::wrapping), "wrapping");
}

// A loop gliding across the side of a periodic cell: find_lines unwraps it from its first
// crossing (the lowest site index), so its centroid jumps by the cell's side (64 d) once it no
// longer touches x = 0. Compared by minimum image it stays one line, one id, with no
// nucleation or annihilation.
TEST(Tracker, ALoopGlidingAcrossAPeriodicSideKeepsItsId) {
  SyntheticOptions o;
  o.block = LatticeBlock{.shape = {64, 64}, .origin0 = 0, .origin1 = 0};
  o.periodic = true;
  Tracker t;
  int id = -1;
  double first_x = 0.0, lowest_x = 1e9, highest_x = -1e9;
  for (int step = 0; step <= 14; ++step) {
    const double cx = 2.0 - step;  // 2 d ... -12 d
    const FrameLines f = find_lines(synthetic_field(o, {{cx, 0, 8, 8}}).view());
    ASSERT_EQ(f.lines.size(), 1u) << "cx " << cx;
    EXPECT_EQ(f.cell.x, 64.0);
    const auto ids = t.add(f);
    if (step == 0) {
      id = ids[0];
      first_x = f.lines[0].centroid.x;
    }
    EXPECT_EQ(ids[0], id) << "cx " << cx;
    lowest_x = std::min(lowest_x, f.lines[0].centroid.x);
    highest_x = std::max(highest_x, f.lines[0].centroid.x);
  }
  // The jump the minimum image absorbs did happen.
  EXPECT_NEAR(first_x, 2.0, 0.5);
  EXPECT_GT(highest_x - lowest_x, 32.0);
  for (const Event& e : t.events()) {
    EXPECT_NE(e.type, EventType::nucleation);
    EXPECT_NE(e.type, EventType::annihilation);
  }
}

}  // namespace

// The stress held along a whole loop (front_stresses) on a synthetic elliptical loop in a
// uniform envelope: every point of the loop is sampled, in order along it, on the line, with the
// character of the ellipse's tangent there (the stretch's parabola, 32 d of a loop 318 d
// round), and resolved away from the block's edge. The synthetic tau_x is the core's own swing
// alone (no load, no other line), odd across the core: what the weight leaves of it is the
// lattice's sampling of the profile, which must lie well below the Peierls stresses it is
// compared with (0.06 tau_max for the edge line at b_core = 2 d, 0.01 for (8, 1),
// tests/analytic/test_core_stress.cpp): held to 2e-3 tau_max.
TEST(Profile, FrontSamplesAWholeLoopInOrder) {
  SyntheticOptions o;
  o.block = {.shape = {192, 192}, .origin0 = -96, .origin1 = -96};
  o.tau_peak = 0.5;  // uniform (no contact disk): b_core = 2 d, windows of 8 d
  o.core_width = 1.0;
  const SyntheticField f = synthetic_field(o, {{0, 0, 60, 40}});
  const slide::Snapshot s = snapshot_of(f, 0.0);
  const FrameLines lines = find_lines(f.view());
  ASSERT_EQ(lines.lines.size(), 1u);
  const Line& loop = lines.lines[0];
  ASSERT_EQ(loop.kind, LineKind::loop);
  const std::vector<FrontStress> front = front_stresses(s, lines);
  const FrontOptions defaults;
  EXPECT_EQ(front.size(), static_cast<std::size_t>(std::floor(loop.length / defaults.step)));
  double worst = 0.0, worst_angle = 0.0;
  for (std::size_t j = 0; j < front.size(); ++j) {
    const FrontStress& p = front[j];
    EXPECT_EQ(p.line, 0u);
    EXPECT_NEAR(p.arc, defaults.step * static_cast<double>(j), 1e-9);
    // On the ellipse (x/60)^2 + (y/40)^2 = 1, to the trace's precision.
    EXPECT_NEAR(std::hypot(p.at.x / 60.0, p.at.y / 40.0), 1.0, 0.015) << p.at.x << ", " << p.at.y;
    // The tangent's angle to x: (-a sin t, b cos t) at (a cos t, b sin t).
    const double t = std::atan2(p.at.y / 40.0, p.at.x / 60.0);
    const double tangent = std::atan2(std::abs(40.0 * std::cos(t)), std::abs(60.0 * std::sin(t))) *
                           180.0 / std::acos(-1.0);
    worst_angle = std::max(worst_angle, std::abs(p.angle_deg - tangent));
    EXPECT_NEAR(p.angle_deg, tangent, 2.0) << p.at.x << ", " << p.at.y;
    EXPECT_TRUE(p.resolved()) << p.at.x << ", " << p.at.y;
    EXPECT_NEAR(p.half_width, 8.0, 1e-12);
    EXPECT_NEAR(std::abs(p.held.slip), 1.0, 0.1);
    EXPECT_LE(std::abs(p.held.tau), 2e-3 * 0.5) << p.at.x << ", " << p.at.y;
    worst = std::max(worst, std::abs(p.held.tau) / 0.5);
  }
  // Around the loop's closure (arc 0) a stretch pools as many sites as anywhere else: the
  // stretch wraps round instead of stopping at the first vertex.
  const auto [fewest, most] = std::minmax_element(
      front.begin(), front.end(),
      [](const FrontStress& a, const FrontStress& b) { return a.held.bonds < b.held.bonds; });
  EXPECT_GT(front.front().held.bonds, 0.8 * most->held.bonds);
  EXPECT_GT(fewest->held.bonds, 0.8 * most->held.bonds);
  std::printf("synthetic loop: %zu points, largest |held| %.3e tau_max, angle off by %.2f deg\n",
              front.size(), worst, worst_angle);
  for (const FrontStress& p : front)
    EXPECT_EQ(p.span, 32.0);  // the loop is 318 d round: more than 6 spans
  // A loop 100 d round (radius 16 d) is pooled over a sixth of it, 16.7 d.
  const SyntheticField small = synthetic_field(o, {{0, 0, 16, 16}});
  const FrameLines small_lines = find_lines(small.view());
  ASSERT_EQ(small_lines.lines.size(), 1u);
  const std::vector<FrontStress> small_front = front_stresses(snapshot_of(small, 0.0), small_lines);
  ASSERT_FALSE(small_front.empty());
  for (const FrontStress& p : small_front) {
    EXPECT_NEAR(p.span, small_lines.lines[0].length / 6.0, 1e-9);
    const double t = std::atan2(p.at.y, p.at.x);  // the tangent is normal to the radius
    const double tangent =
        std::atan2(std::abs(std::cos(t)), std::abs(std::sin(t))) * 180.0 / std::acos(-1.0);
    EXPECT_NEAR(p.angle_deg, tangent, 2.0) << p.at.x << ", " << p.at.y;
    EXPECT_TRUE(p.resolved());
    EXPECT_LE(std::abs(p.held.tau), 2e-3 * 0.5) << p.at.x << ", " << p.at.y;
  }
  // The loop's +x end bulges out (a disk of radius 4 d on it): the sites whose registry index
  // changes lie there, and each is given to a point of the front's +x end.
  const SyntheticField moved = synthetic_field(o, {{0, 0, 60, 40}, {60, 0, 4, 4}});
  const slide::Snapshot later = snapshot_of(moved, 0.0);
  const FrontMoves m = front_moves(registry_indices(s), later, front);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < s.sx.size(); ++i)
    changed += std::lround(s.sx[i]) != std::lround(later.sx[i]) ? 1 : 0;
  EXPECT_GT(changed, 20u);
  EXPECT_EQ(m.moved, changed);
  EXPECT_EQ(m.elsewhere, 0u);
  std::size_t given = 0;
  for (std::size_t k = 0; k < front.size(); ++k) {
    given += static_cast<std::size_t>(m.sites[k]);
    if (m.sites[k] > 0) {
      EXPECT_GT(front[k].at.x, 40.0) << front[k].at.y;
    }
  }
  EXPECT_EQ(given, changed);
  // A slip far from every line (a new loop) is elsewhere.
  const slide::Snapshot apart =
      snapshot_of(synthetic_field(o, {{0, 0, 60, 40}, {0, 75, 6, 6}}), 0.0);
  EXPECT_GT(front_moves(registry_indices(s), apart, front).elsewhere, 50u);
  EXPECT_EQ(front_moves(registry_indices(s), s, front).moved, 0u);
  // Windows are cut halfway to another line and at the contact's edge: two loops 10 d apart
  // (x = -5 and 5) in a contact of radius 60 d whose far ends lie 4 d inside its edge.
  SyntheticOptions pair = o;
  pair.contact_radius = 60.0;
  const SyntheticField two = synthetic_field(pair, {{-30, 0, 25, 20}, {30, 0, 25, 20}});
  const FrameLines two_lines = find_lines(two.view());
  ASSERT_EQ(two_lines.lines.size(), 2u);
  int facing = 0, outer = 0, free = 0;
  for (const FrontStress& p : front_stresses(snapshot_of(two, 0.0), two_lines)) {
    if (std::abs(p.at.x) < 6.0 && std::abs(p.at.y) < 4.0) {  // facing the other loop
      ++facing;
      EXPECT_TRUE(p.cut) << p.at.x << ", " << p.at.y;
      // Halfway (5-5.5 d here) and the site of slack the rule allows (front_stresses).
      EXPECT_GE(p.half_width, 5.0) << p.at.x << ", " << p.at.y;
      EXPECT_LE(p.half_width, 7.0) << p.at.x << ", " << p.at.y;
    } else if (std::abs(p.at.x) > 54.0 && std::abs(p.at.y) < 4.0) {  // 4-6 d from the edge
      ++outer;
      EXPECT_TRUE(p.cut) << p.at.x << ", " << p.at.y;
      EXPECT_FALSE(p.resolved());
    } else if (std::abs(std::abs(p.at.x) - 30.0) < 4.0) {  // the loops' tops and bottoms
      // 24 d inside the edge and over 30 d from the other loop: the window is not cut.
      ++free;
      EXPECT_FALSE(p.cut) << p.at.x << ", " << p.at.y;
    }
  }
  EXPECT_GT(facing, 0);
  EXPECT_GT(outer, 0);
  EXPECT_GT(free, 0);
  // Options are checked.
  EXPECT_THROW(front_stresses(s, lines, {.stretches = 2.0}), std::invalid_argument);
  EXPECT_THROW(front_stresses(s, lines, {.stretches = 0.5}), std::invalid_argument);
  EXPECT_THROW(front_stresses(s, lines, {.span = 0.0}), std::invalid_argument);
  EXPECT_THROW(front_stresses(s, lines, {.step = -1.0}), std::invalid_argument);
  EXPECT_THROW(front_stresses(s, lines, {.widths = 0.0}), std::invalid_argument);
  // No s_x: nothing is measured.
  slide::Snapshot bare = s;
  bare.sx.clear();
  EXPECT_TRUE(front_stresses(bare, lines).empty());
}
