// Scenes and slide settings that several test files share, set up once here so that a test that
// names one means the same contact everywhere.
#pragma once

#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/slide/types.hpp"

namespace asperity::test {

// The smallest Regime III contact the suite slides whole: R = 20 d, a = 15 d, alpha = 0.7,
// nu = 0.5 (the defaults otherwise). a / b_core^0 = 20 with b_core^0 = 0.75 d, and the edge
// Peierls stress at the centre is 0.36 tau_max (tests/analytic/test_regime_three.cpp), so loops
// nucleate and are arrested: more than ten slip events, friction rising with Dx.
inline interface::ContactScene regime_three_small() {
  interface::ContactScene scene;
  scene.a = 15.0;
  scene.R = 20.0;
  return scene;
}

// The creep settings of the Regime III long runs (data/scenes/regime3_R800_growth.toml): the
// step grows by a factor 2 while steps are stable, and slips are relaxed by the flow with the
// interface preconditioner (what "auto" picks there). One FFT thread, so that the bits compared
// do not depend on the machine's thread count.
inline void use_creep_settings(slide::SlideOptions& options) {
  options.fft.threads = 1;
  options.step_growth = 2.0;
  options.slip_minimizer = slide::slip_minimizer_from(options.minimizer, minimize::Method::flow,
                                                      minimize::Preconditioner::interface);
}

}  // namespace asperity::test
