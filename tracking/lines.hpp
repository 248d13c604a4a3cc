// Dislocation lines in one snapshot (MODEL.md section 7).
//
// A core is where the local shear stress tau_x changes sign between about +tau_max and -tau_max
// on the unstable branch of the registry potential: the relative position s_x passes d/2
// (mod d), cos(2 pi s_x / d) < 0 there. The other sign changes of tau_x, at s_x near 0 (mod d),
// are sites in registry under a small elastic offset and are never cores. The branch is told by
// cos(2 pi s_x / d) interpolated to the zero like the stress; where s_x jumps by more than d/2
// between neighbours (cores narrower than d: large contacts) interpolation cannot tell, and the
// registry index n = round(s_x / d - X / d) of the two sites does (s_x is stored unwrapped): it
// changes across a core, not across a zero in registry. Cores are traced by marching squares on the
// normalised stress tau_x / tau_max with linear interpolation along the grid edges (sub-atomic
// precision; the phase is interpolated instead across jumps > d/2), and the pieces are joined into
// lines as the connected components of a Boost.Graph graph whose vertices are the edge crossings.
// The side of each crossing where tau_x > 0 must have the higher index (registry_consistency); the
// index jump gives the line's Burgers vector b = (n_left - n_right) d x-hat and its sense.
// Under a tip lattice out of registry (rotated by theta, spacing d_tip; FieldView::tip) the same
// on the tip's first axis: s_x / d becomes rho_1 (tip_lattice.hpp), tau_x the stress along that
// axis, and b = (n_left - n_right) d_tip along it; the lines found are then the misfit
// dislocations that accommodate the rotation and mismatch, which exist without nucleation.
//
// Only the tracking/ library: plain fields in, plain structs out (apps/ reads and writes files).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/shape.hpp"
#include "asperity/core/slide/frames.hpp"

namespace asperity::tracking {

struct Point {
  double x = 0.0, y = 0.0;  // lattice coordinates (d)
};

// The multiple of a periodic side L nearest a coordinate difference `delta`: delta minus it is
// the minimum image. 0 where L <= 0 (no period along that axis).
inline double image_offset(double delta, double L) {
  return L > 0.0 ? L * std::round(delta / L) : 0.0;
}

// One frame's per-site fields on a block of lattice sites, block-major (i0 * n1 + i1) like
// slide::Snapshot. Views: the caller keeps the data alive during find_lines().
struct FieldView {
  LatticeBlock block;     // shape and lattice origin: site (i0, i1) is at ((origin0 + i0) d, ...)
  double d = 1.0;         // lattice spacing (unit of length)
  bool periodic = false;  // the block is one whole periodic cell: lines wrap around its sides
  std::span<const double> sx;       // relative position along x, X + ux - Dx (d)
  std::span<const double> tau_x;    // local shear stress along x (G)
  std::span<const double> tau_max;  // envelope (G); sites with tau_max <= 0 are not in contact
  std::span<const std::uint8_t> in_contact;  // 1: in contact; empty: every site with tau_max > 0
  // A tip lattice out of registry (interface/tip_lattice.hpp): the registry followed is then
  // rho_1 = (cos theta s_x + sin theta s_y) / d_tip along the tip's first axis, the stress its
  // conjugate cos theta tau_x + sin theta tau_y, and b lies along that axis (b = burgers d_tip
  // times the axis). sy and tau_y may be empty for the aligned tip.
  std::span<const double> sy;     // relative position along y, Y + uy (d)
  std::span<const double> tau_y;  // local shear stress along y (G)
  interface::TipLattice tip;

  // Throws std::invalid_argument naming the violated constraint (shape >= 2 x 2, d > 0, field
  // sizes equal to the site count; periodic cells at least 3 x 3).
  void validate() const;
};

// The fields of a contact-simulator snapshot (d = 1, the snapshot's unit of length).
FieldView view_of(const slide::Snapshot& snapshot, bool periodic = false);

enum class LineKind {
  loop,     // closed inside the contact (or contractible in a periodic cell)
  open,     // both ends on the edge of the contact (or of a non-periodic block)
  wrapping  // closes only through the sides of a periodic cell
};
std::string to_string(LineKind kind);

struct DetectOptions {
  // Lines shorter than this are dropped (d), after the join (join_distance): where a core
  // grazes the jagged edge of the contact it leaves stubs of a few d; noise makes
  // closed contours of about one cell. A loop of length 2 d (radius 0.3 d) is below the lattice
  // resolution anyway.
  double min_length = 2.0;
  // Sign of the registry-index change of a site that slips: -1 when the tip slides along +x
  // (s = X + u - Dx drops by d), +1 along -x. Selects the slipped side of each line.
  int slip_sign = -1;
  // The tangent of a segment is the chord over this many segments on either side plus itself:
  // marching-squares vertices of a noisy field zigzag at the grid scale.
  int tangent_half_window = 1;
  // A piece of line whose tangent makes an angle below this with b = d x-hat counts as screw,
  // otherwise edge (degrees).
  double screw_angle_deg = 45.0;
  // Open lines are joined end to start across gaps up to this long (d; 0: never). A core that
  // runs along the contact's round edge, as the screw lines where loops nucleate (MODEL.md 5),
  // leaves the traced cells (those with four sites in contact) wherever the jagged edge cuts
  // into it and comes back a row further in: traced alone it is a piece per lattice row it
  // crosses. Two pieces are joined when the end of one (on the contact edge) lies within this
  // distance of the start of the other (on the edge too) and both have the same Burgers vector;
  // since open lines run with their slipped side on the left, one's end meets the next one's
  // start. Nearest gaps first, each end used once. Joins make no loops (a link that would close
  // a chain is left out): loops are what the marching squares close, as without joins. Not in a
  // periodic cell, which has no edge. In the states just before the first slip at R = 800 d the
  // gaps joined are at most 2.62 d (a = 200 d) and 2.81 d (a = 300 d), and the nearest end left
  // is 5.95 and 5.16 d away: every distance from 3 to 5 d gives the same two lines, and 4 d is
  // the middle of that plateau (docs/tracking.md, step 3).
  double join_distance = 4.0;

  // Each setting described once (core/common/settings.hpp): keys min_length, join_distance,
  // slip_sign, tangent_half_window, screw_angle_deg; track_loops lifts them under "lines.",
  // the Python binding takes them as keywords.
  static const settings::Table<DetectOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated setting
};

struct Line {
  LineKind kind = LineKind::open;
  // Vertices (d): loops counter-clockwise without repeating the first vertex; open and wrapping
  // lines run with their slipped side on the left (so burgers = slip_sign for a single jump);
  // lines through the sides of a periodic cell are unwrapped (continuous, may leave the cell).
  std::vector<Point> points;
  // Per segment (points[k] -> points[k + 1], for loops also the closing one): angle between the
  // tangent and b, folded into [0, 90] degrees (0: screw, 90: edge); b along the tip's first
  // axis out of registry.
  std::vector<double> angle_deg;
  int burgers = 0;  // registry-index jump n_left - n_right along the points: b = burgers d x-hat
                    // (burgers d_tip along the tip's first axis out of registry)
  double registry_consistency = 0.0;  // fraction of the line's crossings with that jump
  int interior_ends = 0;  // ends of an open line inside the contact (a broken trace; normally 0)
  int pieces = 1;  // traced pieces joined across the contact's edge (DetectOptions::join_distance)
  double length = 0.0;  // d
  double area = 0.0;    // enclosed area of a loop (d^2); 0 for other lines
  Point centroid;       // loops: of the enclosed area; other lines: of the line
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;  // bounding box (d)
  double aspect_ratio = 0.0;  // x extent / y extent; infinite for a line along x
  double screw_fraction = 0.0, edge_fraction = 0.0;  // length fractions (sum 1)
  double mean_angle_deg = 0.0;                       // length-weighted mean of angle_deg
  int slipped_region = -1;  // index in FrameLines::regions of the domain on the slipped side
};

// Key of lattice site (X, Y) in FrameLines::regions: sorting keys sorts sites by (X, Y).
inline std::int64_t site_key(long long X, long long Y) {
  return static_cast<std::int64_t>(X * 4294967296LL + (Y + 2147483648LL));
}

struct FrameLines {
  std::vector<Line> lines;
  // Domains on the slipped side of the lines: the contact sites connected to the line's slipped
  // side without crossing a core, as sorted site_key()s. Several lines may share one.
  std::vector<std::vector<std::int64_t>> regions;
  double d = 1.0;
  bool periodic = false;
  // The Burgers vector of a line with burgers = 1 (d): d_tip along the tip's first axis,
  // (d, 0) for the aligned tip. A line's b is burgers times it.
  Point unit_burgers{1.0, 0.0};
  // A periodic cell's sides (d). Its lines are unwrapped from their first crossing, so the same
  // line can sit one image away in the next frame: the tracker compares lines by minimum image.
  Point cell;
  Point contact_centre;         // centroid of the contact sites (d)
  double contact_radius = 0.0;  // radius of the disk of the same area (d)
  std::size_t contact_sites = 0;
  std::size_t core_crossings = 0;      // grid edges crossed by a core
  std::size_t registry_crossings = 0;  // sign changes of tau_x in registry: rejected
  std::size_t dropped_short = 0;       // lines shorter than DetectOptions::min_length
  std::size_t joined_pieces = 0;       // traced pieces of the lines made by joins (join_distance)
};

// Throws std::invalid_argument if the field or the options are invalid.
FrameLines find_lines(const FieldView& field, const DetectOptions& options = {});

// A line's Burgers vector (d): burgers times the frame's unit_burgers.
inline Point burgers_vector(const Line& line, const FrameLines& frame) {
  return {line.burgers * frame.unit_burgers.x, line.burgers * frame.unit_burgers.y};
}

// Where a point sits relative to the contact, for nucleation and annihilation sites: "centre"
// (within centre_fraction of the radius), else "side" (|y - yc| > |x - xc|), "front" (ahead in
// +x, the sliding direction) or "back"; "cell" for a periodic cell.
std::string location_class(const FrameLines& frame, Point p, double centre_fraction);

}  // namespace asperity::tracking
