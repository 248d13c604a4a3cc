// Stress profiles through a snapshot (MODEL.md sections 3 and 7): the local shear stress along
// the lattice row through the tip centre (along x, the sliding direction) or the column through
// it (along y), the envelope tau_max = alpha p(r) that bounds it, and where dislocation lines
// cross the profile. At a core tau_x changes sign between about +tau_max and -tau_max (MODEL.md
// 7); an arrested core sits where the stress it feels stays below the local Peierls stress,
// which the caller draws beside it (nucleation::local_peierls_stress). The stress it feels is
// not tau_x at the core (that is the core's own swing) but tau_x weighted by the core's slip
// density (and tau_y by the change of u_y), the Peierls-Nabarro force per Burgers vector
// (core_stress). The seed's Fig. 9 is this figure for its a/b_core^0 = 278 contact. The same
// weight all along every line (front_stresses), against the local Peierls stress at each
// stretch's angle (MODEL.md 6), and where a front moved between two states (front_moves).
//
// Only the tracking/ library: plain fields in, plain structs out.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/slide/frames.hpp"
#include "asperity/tracking/lines.hpp"

namespace asperity::tracking {

enum class ProfileAxis { x, y };
std::string to_string(ProfileAxis axis);

struct StressProfile {
  ProfileAxis axis = ProfileAxis::x;
  // The profile runs along `axis` through the tip centre (Dx, 0): along x the row Y = 0, along
  // y the column of sites nearest X = Dx (its lattice x is `through`, d).
  double through = 0.0;
  double centre = 0.0;           // coordinate of the tip centre along the axis (d): Dx or 0
  std::vector<double> position;  // site coordinate along the axis minus `centre` (d)
  std::vector<double> tau_x, tau_y, tau_max, pressure;  // per site (G)
  // Registry offset s_x - X per site (d): it changes by one period d across a core and hardly
  // elsewhere (the interface is held in registry). Empty if the snapshot has no s_x, or under a
  // tip out of registry (angle or mismatch: its registry runs along the tip's axis, and s_x - X
  // then drifts at every bond), where the stress a core holds is not measured.
  std::vector<double> offset;
  // u_y per site (d; s_y - Y in a contact), where the snapshot has it (and `offset`): a mixed
  // line's core has a displacement across b too, and core_stress weighs tau_y by its change.
  std::vector<double> offset_y;
  std::vector<std::uint8_t> in_contact;
  double tau_max_peak = 0.0;  // largest tau_max of the frame (G): alpha p0 of a Hertz contact
};

// Throws std::invalid_argument if the snapshot's fields do not match its block or the row or
// column through the tip centre lies outside it.
StressProfile stress_profile(const slide::Snapshot& snapshot, ProfileAxis axis);

// Where a line of `lines` crosses the profile's row or column.
struct CoreCrossing {
  double position = 0.0;   // along the axis, minus the profile's centre (d)
  double angle_deg = 0.0;  // character of the crossing segment: 0 screw, 90 edge (Line::angle_deg)
  std::size_t line = 0;    // index in FrameLines::lines
  LineKind kind = LineKind::open;
};

// Crossings in increasing position; a vertex exactly on the row counts once.
std::vector<CoreCrossing> core_crossings(const FrameLines& lines, const StressProfile& profile);

// The stress on a core where it crosses the profile: tau_x averaged across the core with its
// slip density as the weight (the Peierls-Nabarro force on the core per Burgers vector),
//
//   tau_core = sum_k (rho_k tau_k + rho_y,k tau_y,k) / sum_k rho_k,
//
// over the bonds k between neighbouring profile sites in [from, to] (profile coordinates, d; a
// bond cut by an end counts by its fraction inside) whose sites are in the contact, rho_k the
// change of the registry offset s_x - X over the bond and tau_k the mean tau_x of its two
// sites; rho_y,k the change of u_y and tau_y,k the mean tau_y (a mixed core moves u_y too: the
// work on a moving core is sum du . tau over both components). Why this weight: the core's own
// stress is K * rho with an odd kernel K (a straight
// line, a translation-invariant elastic medium), and
// sum rho (K * rho) = 0 for any rho, so the core's own +-tau_max swing drops out, whatever the
// core's shape, and what is left is the stress of everything else (the load, other lines, the
// line's curvature). At equilibrium that is what the lattice holds the core against, so
// |tau_core| is at most the local Peierls stress of the segment, and equal to it where the
// core creeps at threshold. `slip` is sum_k rho_k (d): about +-d for a resolved core; a cut
// that holds less of the core (a window too narrow, the contact's edge) weighs less of it.
struct CoreStress {
  double tau = 0.0;   // (G); NaN if no bond of the window has a slip
  double slip = 0.0;  // sum of rho_k over the window (d)
  int bonds = 0;      // bonds in the window

  // Whether the window holds most of one core: |slip| >= min_slip d. A core cut by the contact's
  // edge holds about half (its stress is then that of its inner side, not the one driving it);
  // two cores in one window hold about 0 or 2.
  [[nodiscard]] bool resolved(double min_slip = 0.75) const {
    const double s = std::abs(slip);
    return std::isfinite(tau) && s >= min_slip && s <= 2.0 - min_slip;
  }
};
// Throws std::invalid_argument if the profile has no registry offset or from > to.
CoreStress core_stress(const StressProfile& profile, double from, double to);

// core_stress of each crossing in a window centred on it: CrossingOptions::widths local core widths
// either side (b_core = d G / tau_max at the profile site nearest the crossing, MODEL.md 3; tau in
// G, lengths in d), cut at halfway to the neighbouring crossings, so that no window holds two
// cores, and at the first site out of the contact on either side. The window leaves out the core's
// tail, which decays only as 1/x^2. In a loaded Peierls cell (tests/analytic/test_core_stress.cpp)
// a centred window of 4 b_core either side missed the load by 9e-5 tau_max at b_core = 2 d (0.15%
// of that core's tau_P) and 1.7e-6 tau_max at 6 d (3% of its tiny tau_P); one cut to 1.3 b_core at
// 6 d missed it by 8e-5 tau_max, 1.6 times tau_P. So a cut window is not resolved, whatever slip it
// holds, and for wide cores (b_core > 5 d or so, tau_P < 1e-4 tau_max) even the full window's
// error is a sizeable part of tau_P.
struct CrossingStress {
  CoreStress stress;
  double half_width = 0.0;  // of the window (d)
  double tau_max = 0.0;     // at the site nearest the crossing (G)
  bool cut = false;         // the window is narrower than `widths` b_core

  [[nodiscard]] bool resolved() const { return !cut && stress.resolved(); }
};
struct CrossingOptions {
  double widths = 4.0;  // window around each crossing, in local core widths either side

  // Each setting described once (core/common/settings.hpp): key widths; track_loops lifts it
  // under "profiles.".
  static const settings::Table<CrossingOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated setting
};
// Throws std::invalid_argument if the options are invalid or the profile has no registry offset.
std::vector<CrossingStress> crossing_stresses(const StressProfile& profile,
                                              const std::vector<CoreCrossing>& cores,
                                              const CrossingOptions& options = {});

// The stress held along the whole of every line, not only where it crosses the two axes: at
// points `step` apart along each line, the sites of a stretch `span` long around the point
// (each site belongs to its nearest line) within `widths` local core widths of the stretch's
// mean curve, in order of their registry offset s_x - X, make one profile across it, and
// core_stress' weight over it (tau_x by the change of s_x - X, tau_y by that of u_y, over the
// neighbouring pairs) is the stress that stretch holds: the Peierls-Nabarro force on it per
// Burgers vector and length. As on a profile the window is cut halfway to another line, at the
// first site out of the contact and at the block's edge, and a cut window is not resolved.
//
// Why pool a stretch rather than take a row: a straight line normal to (m_x, m_y) is a chain of
// sites d / |m| apart along its normal, each site of the lattice a copy of one of them. The
// whole chain's sum is the exact weight of core_stress (the core's own stress cancels). One row
// across the line steps m_x sites of the chain and samples one of m_x cosets, for which it does
// not: in a loaded cell at b_core = 2 d single rows or columns across (2, 1) and (1, 3) lines
// miss the load by up to 2 and 6 times tau_P (tests/analytic/test_core_stress.cpp). A
// stretch at least |m| d long holds every site of the chain; the offset falls monotonically
// across the core, so in its order the sites are the chain in order, copies side by side, and
// pairs of copies add nothing: the sum is the chain's, for any direction whose period |m| d
// fits in the span. Across a curved line it is that of its local direction, and where the
// stretch holds kinks each site still falls in order across its own piece of core. The default
// span of 32 d holds every direction up to |m| = 32 (within 1.8 degrees of screw or edge the
// period is longer; a stretch then lies on a pure screw or edge piece, and its kinks weigh by
// their share of it). The value is the stretch's mean, so on a line shorter than `stretches`
// spans the stretch is shortened to a `stretches`-th of it (a loop 100 d round: 16.7 d),
// which holds directions only up to |m| about that long. Beside the local Peierls stress at
// the stretch's angle (MODEL.md 6) it says which parts of a held front are at threshold and
// which are below it.
struct FrontOptions {
  double widths = 4.0;           // window across the line, in local core widths either side
  double span = 32.0;            // length of the stretch pooled (d): >= |m| d of a direction m
  double stretches = 6.0;        // ... and at most the line's length over this many (>= 3)
  double step = 4.0;             // spacing of the points along each line (d)
  double max_half_width = 32.0;  // windows longer than this are cut to it (d)

  // Each setting described once (core/common/settings.hpp): keys span, stretches, step, widths,
  // max_half_width; track_loops lifts them under "front.", lines.json records them per frame,
  // the Python binding takes them as keywords.
  static const settings::Table<FrontOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated setting
};

struct FrontStress {
  Point at;                // on the line (d, lattice coordinates)
  double angle_deg = 0.0;  // character of the stretch (its mean curve's tangent at the point,
                           // to b): 0 screw, 90 edge
  std::size_t line = 0;    // index in FrameLines::lines
  LineKind kind = LineKind::open;
  double arc = 0.0;         // along the line from its first vertex to `at` (d)
  double tau_max = 0.0;     // at the site nearest `at` (G; 0 outside the block)
  double span = 0.0;        // of the stretch pooled (d): FrontOptions::span or less
  double half_width = 0.0;  // of the window across the line (d)
  bool cut = false;         // the window is narrower than `widths` b_core
  double bend = 0.0;        // largest distance of the stretch's points from its mean curve (d): the
                      // zigzag and kinks of the trace, about 0.2-0.8 d; infinite if degenerate
  CoreStress held;  // bonds: neighbouring pairs of pooled sites

  [[nodiscard]] bool resolved() const { return !cut && held.resolved(); }
};
// In order of line, then arc. Empty without s_x or under a tip out of registry (as the stress
// profiles). Throws std::invalid_argument if the options are invalid or the snapshot's fields
// do not match its block.
std::vector<FrontStress> front_stresses(const slide::Snapshot& snapshot, const FrameLines& lines,
                                        const FrontOptions& options = {});

// Where a front moved between two states of one contact: the contact sites of `after` whose
// registry index round(s_x / d) differs from the earlier state's at the same lattice site (the
// sites a slip moves along b; friction_sweep's slips.csv also counts jumps of s_y, only those
// of d/4 or more and only sites in contact in both states: at R = 800 d, a = 300 d both gave
// the same counts), each given to the nearest point of `front` (front_stresses of the earlier
// state) whose stretch covers it: within half its span plus its window's half-width. Beside
// each point's stress just before, it says at what stress each part of a held front gave way.
struct RegistryIndices {
  LatticeBlock block;
  std::vector<std::int32_t> index;  // round(s_x / d) per site, block-major
};
// Throws std::invalid_argument if the snapshot has no s_x.
RegistryIndices registry_indices(const slide::Snapshot& snapshot);

struct FrontMoves {
  std::vector<int> sites;     // per point of `front`: the moved sites given to it
  std::size_t moved = 0;      // every moved contact site (on both blocks)
  std::size_t elsewhere = 0;  // of those, covered by no point's stretch (a new line, say)
};
// Throws std::invalid_argument if `after`'s fields do not match its block or `before`'s
// indices do not match its.
FrontMoves front_moves(const RegistryIndices& before, const slide::Snapshot& after,
                       const std::vector<FrontStress>& front);

// What the closed loops of a frame hold where they cross the row through the tip centre (along
// x: a loop's edge ends) and the column (along y: its screw sides): the mean stress of the
// resolved crossings (crossing_stresses, default window) and the mean tau_max there, from which
// any Peierls law gives the local Peierls stress (MODEL.md 3, 6). A run's slips.csv keeps these
// per slip, so that whether a held loop creeps at its threshold can be read from the table.
struct LoopCoreStress {
  double stress = std::numeric_limits<double>::quiet_NaN();   // (G); NaN without a crossing
  double tau_max = std::numeric_limits<double>::quiet_NaN();  // (G)
  int crossings = 0;
};
// [0] along x, [1] along y. A profile outside the snapshot's block or a snapshot without s_x
// gives no crossings there.
std::array<LoopCoreStress, 2> loop_core_stress(const slide::Snapshot& snapshot,
                                               const FrameLines& lines);

}  // namespace asperity::tracking
