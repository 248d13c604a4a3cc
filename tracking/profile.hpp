// Stress profiles through a snapshot (MODEL.md sections 3 and 7): the local shear stress along
// the lattice row through the tip centre (along x, the sliding direction) or the column through
// it (along y), the envelope tau_max = alpha p(r) that bounds it, and where dislocation lines
// cross the profile. At a core tau_x changes sign between about +tau_max and -tau_max (MODEL.md
// 7); an arrested core sits where the stress it feels stays below the local Peierls stress,
// which the caller draws beside it (nucleation::local_peierls_stress). The seed's Fig. 9 is this
// figure for its a/b_core^0 = 278 contact.
//
// Only the tracking/ library: plain fields in, plain structs out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

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

}  // namespace asperity::tracking
