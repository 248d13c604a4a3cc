// What the line-search methods of minimizer.hpp (lbfgs, newton, cg) share (internal to
// core/minimize): the line search along a direction (du, df) with df = K du, free of GF
// applications because the pair is linear along the line (SOLVERS.md, "Free-boundary contact"),
// and the G-preconditioned steepest descent they fall back on.
#pragma once

#include <span>
#include <vector>

#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize::detail {

// The line search of an iteration, from run.x along (du, df) with slope d0 < 0 into run.trial:
// the strong Wolfe conditions on the slope (strong = false: the weak ones, enough for the
// quasi-Newton methods) with curvature parameter c2, the Armijo condition relaxed by the energy
// resolution, the step capped so that no site moves more than max_displacement. Returns false if
// no point with an energy within round-off of the start and a flatter slope was found.
bool search_line(Relaxation& run, std::span<const double> du, std::span<const double> df, double d0,
                 double c2, bool strong);

// The G-preconditioned steepest descent direction (du, df) = -(G r, r) at run.x, with G r into
// z; returns its slope r.du, negative unless r is numerically zero in the G metric. G alone:
// G r . r > 0 whatever the interface filter does.
double steepest_descent(Relaxation& run, std::vector<double>& z, std::vector<double>& du,
                        std::vector<double>& df);

}  // namespace asperity::minimize::detail
