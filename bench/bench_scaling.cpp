// Cost of one quasi-static step of the lateral force model against the contact size (issue 7,
// "Scaling"): the default scene's R, alpha and nu with a chosen a; the unknowns are the sites of
// the block that holds the contact. One step of 0.05 d from the relaxed loaded state at
// Dx = 0.05 d: its minimiser iterations, GF applications and wall time (the difference of a
// one-step and a two-step slide, so that set-up and planning are not counted), with the
// whole two-step run for reference. Prints one CSV line; bench/run_scaling.sh loops over a.
//
//   bench_scaling a [R] [threads] [header]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_scaling a [R] [threads] [header]\n");
    return 2;
  }
  interface::ContactScene scene {};
  scene.a = std::atof(argv[1]);
  if (argc > 2) scene.R = std::atof(argv[2]);
  const int threads = argc > 3 ? std::atoi(argv[3]) : 1;
  if (argc > 4) {
    std::printf(
        "a,R,a_over_bcore0,contact_sites,unknowns,block,fft_grid,threads,step_iterations,"
        "step_gf,step_wall_s,run_wall_s\n");
  }
  slide::SlideOptions o;
  o.protocol = slide::Protocol::reference;
  o.step = 0.05;
  o.fft.threads = threads;
  // Small contacts are timed several times (the minimum of each), large ones once.
  const int repeats = scene.a <= 64 ? 7 : (scene.a <= 128 ? 3 : 1);
  slide::SlideResult one, two;
  double wall_one = 1e300, wall_two = 1e300;
  for (int k = 0; k < repeats; ++k) {
    o.distance = 0.05;
    one = slide::slide(scene, o);
    o.distance = 0.10;
    two = slide::slide(scene, o);
    wall_one = std::min(wall_one, one.wall_s);
    wall_two = std::min(wall_two, two.wall_s);
  }
  const slide::TraceRow& step = two.trace.back();
  std::printf("%g,%g,%.4g,%zu,%zu,%dx%d,%dx%d,%d,%d,%zu,%.4f,%.4f\n", scene.a, scene.R,
              scene.a_over_bcore0(), two.contact_sites,
              2 * static_cast<std::size_t>(two.block.count()), two.block.n0, two.block.n1,
              two.fft_grid.n0, two.fft_grid.n1, threads, step.iterations, step.gf_applications,
              wall_two - wall_one, wall_two);
  return 0;
}
