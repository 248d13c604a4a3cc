// One slide of the lateral force model spread over MPI ranks (issue 26) against the same slide
// on one process, under mpirun with 1, 2 and 3 ranks (3: uneven slabs, one of them padding
// only). Every rank also runs the serial slide, with the serial FFTW engine.
// Expected: the same path. Every sum of the slide and its minimisers is made row by row and the
// rows' partials added in row order (Comm::ordered_sum, minimize/kernels.hpp), so the ranks
// change no sum; only the distributed FFT could round differently (measured: it does not here,
// and the paths agree bit for bit). Asserted: the 1e-10 relative on mu and on Fx, Fz and
// the energy of every trace row; the decisions (the tip positions of the adaptive steps, which
// slipped, how many sites) exactly. Then checkpoints: a distributed slide stopped after its third checkpoint
// hands over every row (on rank 0), and that state resumed on one process ends where the
// uninterrupted slide ends; a serial checkpoint resumed over the ranks likewise.
#include <mpi.h>

#include <cmath>
#include <optional>

#include <gtest/gtest.h>

#include "asperity/core/fft/fftw_mpi_engine.hpp"
#include "asperity/core/fft/mpi_comm.hpp"
#include "asperity/core/slide/slider.hpp"

namespace asperity::slide {
namespace {

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

// a = 24 d, R = 200 d: a / b_core^0 = 4.9, two slip events within the automatic distance
// capped by max_slips, about a second on one process.
interface::ContactScene scene() {
  interface::ContactScene s;
  s.a = 24.0;
  s.R = 200.0;
  return s;
}
SlideOptions options() {
  SlideOptions o;
  o.max_slips = 2;
  o.path_frame_every = 8;  // path frames through the slips: made collectively
  o.path_frame_slips = 1;
  return o;
}

void expect_close(double a, double b, const char* what, std::size_t row) {
  EXPECT_NEAR(a, b, 1e-10 * std::max(1.0, std::abs(b))) << what << " of row " << row;
}

void expect_same_path(const SlideResult& got, const SlideResult& want) {
  ASSERT_EQ(got.trace.size(), want.trace.size());
  for (std::size_t i = 0; i < want.trace.size(); ++i) {
    const TraceRow &g = got.trace[i], &w = want.trace[i];
    EXPECT_EQ(g.Dx, w.Dx) << "row " << i;
    EXPECT_EQ(g.slip, w.slip) << "row " << i;
    EXPECT_EQ(g.slipped_sites, w.slipped_sites) << "row " << i;
    expect_close(g.Fx, w.Fx, "Fx", i);
    expect_close(g.Fz, w.Fz, "Fz", i);
    expect_close(g.energy, w.energy, "energy", i);
    expect_close(g.area, w.area, "area", i);
  }
  EXPECT_EQ(got.slip_events, want.slip_events);
  EXPECT_NEAR(got.mu, want.mu, 1e-10 * want.mu);
  EXPECT_EQ(got.peak_Dx, want.peak_Dx);
  EXPECT_EQ(got.contact_sites, want.contact_sites);
}

class SlideMpi : public ::testing::Test {
 protected:
  par::MpiComm comm{MPI_COMM_WORLD};
  SlideParallel parallel() const {
    return {.engine = fft::mpi_engine_factory(MPI_COMM_WORLD), .comm = &comm};
  }
};

TEST_F(SlideMpi, FollowsTheSerialPath) {
  const SlideResult serial = slide(scene(), options());
  ASSERT_FALSE(serial.failed);
  ASSERT_EQ(serial.slip_events, 2);
  const SlideResult spread = slide(scene(), options(), SlideControl{.parallel = parallel()});
  ASSERT_FALSE(spread.failed) << spread.stop_reason;
  expect_same_path(spread, serial);
  // The frames are whole on rank 0 (every row, gathered), and nowhere else.
  ASSERT_FALSE(serial.snapshots.empty());
  ASSERT_EQ(spread.snapshots.size(), serial.snapshots.size());
  for (std::size_t k = 0; k < serial.snapshots.size(); ++k) {
    const Snapshot &g = spread.snapshots[k], &w = serial.snapshots[k];
    EXPECT_EQ(g.label, w.label);
    if (world_rank() != 0) {
      EXPECT_TRUE(g.ux.empty()) << g.label;
      continue;
    }
    ASSERT_EQ(g.ux.size(), w.ux.size()) << g.label;
    for (std::size_t i = 0; i < w.ux.size(); ++i) {
      ASSERT_NEAR(g.ux[i], w.ux[i], 1e-10) << g.label << " site " << i;
      ASSERT_NEAR(g.uy[i], w.uy[i], 1e-10) << g.label << " site " << i;
      ASSERT_EQ(g.in_contact[i], w.in_contact[i]) << g.label << " site " << i;
      ASSERT_NEAR(g.tau_x[i], w.tau_x[i], 1e-9) << g.label << " site " << i;
    }
  }
}

// Stops a slide at its third checkpoint; returns the state handed over.
SlideState stopped_at_third_checkpoint(const SlideParallel& parallel) {
  std::optional<SlideState> last;
  int taken = 0;
  const SlideControl control{.checkpoint =
                                 [&](const SlideState& st) {
                                   last = st;
                                   ++taken;
                                 },
                             .checkpoint_every_s = 0.0,
                             .stop_requested = [&] { return taken >= 3; },
                             .parallel = parallel};
  const SlideResult r = slide(scene(), options(), control);
  EXPECT_TRUE(r.interrupted);
  return *last;
}

TEST_F(SlideMpi, CheckpointsResumeOnAnyNumberOfRanks) {
  const SlideResult serial = slide(scene(), options());
  // Over the ranks, resumed on one process (rank 0 holds the whole state).
  const SlideState spread_state = stopped_at_third_checkpoint(parallel());
  if (world_rank() == 0) {
    ASSERT_EQ(spread_state.current.u.size(), 2 * block_side(scene()) * block_side(scene()));
    const SlideResult resumed = slide(scene(), options(), SlideControl{.start = &spread_state});
    expect_same_path(resumed, serial);
  }
  // On one process, resumed over the ranks (every rank read the same whole state).
  const SlideState serial_state = stopped_at_third_checkpoint({});
  const SlideResult resumed =
      slide(scene(), options(), SlideControl{.start = &serial_state, .parallel = parallel()});
  expect_same_path(resumed, serial);
}

}  // namespace
}  // namespace asperity::slide
