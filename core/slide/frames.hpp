// Field snapshots of a slide (MODEL.md section 5, "Snapshot of a state") and the sink that takes
// them as they are made.
//
// A slide through hundreds of slips makes thousands of frames (each the size of the block of
// sites: about 65 MB at a = 510 d). Holding them until the slide ends made the memory and the
// checkpoints of a slide grow with the number of slips; instead the slide hands each frame to a
// FrameSink when it is made, and the caller writes it and drops it (apps/common: NetCDF files).
// Without a sink the frames are collected in SlideResult::snapshots, which suits short slides
// and tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/interface/tip_lattice.hpp"

namespace asperity::slide {

// The label stem of slip event `event` (1, 2, ...): "slip_001"; its frames are labelled
// stem + "_before", "_after" and "_path". The one place the labels are spelt (the slide that
// makes them, track_loops that selects them).
inline std::string slip_label(int event) {
  std::string digits = std::to_string(event);
  if (digits.size() < 3) digits.insert(0, 3 - digits.size(), '0');
  return "slip_" + digits;
}

// One field snapshot of the contact (MODEL.md section 5), on the block of sites.
struct Snapshot {
  std::string label;   // "peak", "slip_001_before", "slip_001_after", "slip_001_path"
  int iteration = -1;  // minimiser iteration of a relaxation-path frame, else -1
  double Dx = 0.0, Fx = 0.0, Fz = 0.0, energy = 0.0;
  LatticeBlock block;  // site (i0, i1) is at ((origin0 + i0) d, (origin1 + i1) d)
  // Per block site, block-major (i0 * n1 + i1):
  std::vector<double> ux, uy;             // displacement (d)
  std::vector<double> sx, sy;             // relative position s = X + u - (Dx, 0) (d)
  std::vector<double> tau_x, tau_y;       // local shear stress f / d^2 (G)
  std::vector<double> tau_max, pressure;  // envelope and pressure (G): Hertz in the LFM; the
                                          // explicit model's alpha p and p = -f_z / d^2
  std::vector<double> uz;                 // explicit model: normal displacement (d); LFM: empty
  std::vector<std::uint8_t> in_contact;
  // The tip's lattice (interface/tip_lattice.hpp): the registry of a site is
  // rho = Q(-angle) (sx, sy) / ((1 + mismatch) d), which tracking follows (docs/tracking.md).
  interface::TipLattice tip;
  // Of a slip's "before" and "after" states: the sites whose registry index changed in the slip
  // (TraceRow::slipped_sites); 0 for every other frame. Not stored in the NetCDF frames.
  int slipped_sites = 0;
  // Of a slip's "after" state: what the slide had cost when it accepted it, earlier sessions of a
  // resumed slide included (SlideProgressInfo's counts); the difference between two slips is the
  // cost of the steps, bracketing and flow between them. 0 for every other frame. Not stored in
  // the NetCDF frames. The GF count is an uninterrupted slide's (work a resumed slide repeats is
  // counted once); the wall time also holds each session's set-up and, for a killed run, the
  // work lost after its last checkpoint.
  std::size_t gf_applications = 0;
  double wall_s = 0.0;  // (s)
  // Of a replayed slip's "before" and "after" states (SlideOptions::replay_cycle): the slip event
  // whose states these are, carried on by whole periods (its slipped sites, forces and lines);
  // 0 for a computed slip and every other frame. Not stored in the NetCDF frames.
  int replay_of = 0;
};

// Receives the frames of a slide as they are made (SlideControl::frames). Called from the
// sliding thread. A slip's relaxation path comes once the relaxation is accepted as that slip
// (a relaxation that is undone or that does not slip leaves no frames); until then the slide
// holds it as displacements (PathFrame, slider.hpp). Implementations may throw (a full disk): the
// slide then ends with the exception.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // A state: "start" (the loaded contact at Dx = 0, before the slide), "peak" (at the end),
  // "slip_NNN_before", "slip_NNN_after", "last_good".
  virtual void state(const Snapshot& frame) = 0;
  // A frame of the relaxation path of a computed slip ("slip_NNN_path"), in iteration order,
  // after the slip's "before" and "after" states.
  virtual void path_frame(const Snapshot& frame) = 0;
  // A slip replayed from the repeating cycle (SlideOptions::replay_cycle): its path is the one
  // handed over under `source`, carried on by `periods` lattice periods of length `period`
  // (Dx + periods period, block origin0 + periods), under `label`. A sink that kept no such path
  // ignores it.
  virtual void replayed_path(const std::string& source, int periods, double period,
                             const std::string& label) = 0;
  // Whether relaxation paths are wanted at all: a sink that drops them spares the slide the
  // work of making them.
  [[nodiscard]] virtual bool wants_paths() const { return true; }
};

// A sink that keeps nothing: a slide whose frames are not wanted (a sweep point without
// snapshots) holds none either.
class DiscardFrames final : public FrameSink {
 public:
  void state(const Snapshot& /*frame*/) override {}
  void path_frame(const Snapshot& /*frame*/) override {}
  void replayed_path(const std::string& /*source*/, int /*periods*/, double /*period*/,
                     const std::string& /*label*/) override {}
  [[nodiscard]] bool wants_paths() const override { return false; }
};

}  // namespace asperity::slide
