// Regression tier: friction_sweep --peek writes the states a point's checkpoint holds, for
// track_loops while a long point runs. The point is tests/regression/sweep_largest_slip.toml's
// (R = 40 d, a = 24 d, Regime III, the flow for slips); its slide is run here with a checkpoint
// at every accepted step of its slip flows, and one taken inside its first slip flow is put where
// the sweep keeps the point's checkpoint. --peek must write the last accepted state, the peak
// and the paused flow's state (slide::paused_slip) as the library makes them, remove a flow.nc
// that a state between steps no longer holds, refuse a checkpoint of another problem (exit 1),
// and leave the checkpoint alone.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/core/slide/slider.hpp"

namespace {

namespace fs = std::filesystem;
using asperity::slide::SlideState;
using asperity::slide::Snapshot;

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The sweep scene as the slide scene of its one point: the [sweep] table out, a and R into
// [contact] (every other key is the same text, so the problem's fingerprint is the sweep's).
asperity::app::SlideScene point_scene(const std::string& sweep_text) {
  std::istringstream in(sweep_text);
  std::string line, text;
  bool in_sweep = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') in_sweep = line.rfind("[sweep]", 0) == 0;
    if (in_sweep) continue;
    text += line + "\n";
    if (line.rfind("[contact]", 0) == 0) text += "a = 24.0\nR = 40.0\n";
  }
  return asperity::app::read_slide_scene_text(text, "sweep_largest_slip.toml as a slide scene");
}

int run(const std::string& command) {
  return std::system(command.c_str());
}

// Fields stored as float or double: compared as the float they are at least.
void expect_same_fields(const Snapshot& want, const Snapshot& got, const std::string& what) {
  ASSERT_EQ(want.ux.size(), got.ux.size()) << what;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < want.ux.size(); ++i) {
    differ += static_cast<float>(want.ux[i]) != static_cast<float>(got.ux[i]) ||
              static_cast<float>(want.uy[i]) != static_cast<float>(got.uy[i]) ||
              static_cast<float>(want.tau_x[i]) != static_cast<float>(got.tau_x[i]) ||
              want.in_contact[i] != got.in_contact[i];
  }
  EXPECT_EQ(differ, 0u) << what << ": sites whose fields differ";
  EXPECT_DOUBLE_EQ(want.Dx, got.Dx) << what;
  EXPECT_DOUBLE_EQ(want.Fx, got.Fx) << what;
  EXPECT_EQ(want.label, got.label) << what;
  EXPECT_EQ(want.iteration, got.iteration) << what;
}

TEST(FrictionSweepPeek, WritesTheStatesOfACheckpointInsideASlipFlow) {
  const fs::path dir = WORK_DIR;
  fs::remove_all(dir);
  const fs::path point = dir / "points" / "a24_R40";
  fs::create_directories(point);
  const asperity::app::SlideScene s = point_scene(read_text(SCENE));
  ASSERT_TRUE(s.options.slip_minimizer.has_value());
  std::vector<SlideState> inside;
  std::optional<SlideState> between;
  const auto r = asperity::slide::slide(
      s.contact, s.options,
      asperity::slide::SlideControl{
          .checkpoint =
              [&](const SlideState& st) {
                if (st.pending &&
                    (inside.empty() || inside.front().pending->Dx == st.pending->Dx)) {
                  inside.push_back(st);
                } else if (!st.pending && !inside.empty() && !between) {
                  between = st;
                }
              },
          .checkpoint_every_s = 1e-9});
  ASSERT_FALSE(r.failed) << r.stop_reason;
  ASSERT_GE(inside.size(), 3u) << "no slip flow long enough to pause in";
  ASSERT_TRUE(between.has_value());
  const SlideState& paused = inside[inside.size() / 2];
  // What the sweep would have written: the point's fingerprint, snapshots=0 (no --figures).
  const std::string settings = asperity::app::slide_fingerprint(s) + " snapshots=0";
  asperity::app::write_checkpoint(point / "checkpoint.cbor",
                                  {.settings = settings, .state = paused});
  const auto written = fs::last_write_time(point / "checkpoint.cbor");

  const std::string peek = std::string(FRICTION_SWEEP) + " " + SCENE + " --out " + dir.string() +
                           " --peek > " + (dir / "peek.txt").string() + " 2>&1";
  ASSERT_EQ(run(peek), 0) << read_text(dir / "peek.txt");
  const std::string said = read_text(dir / "peek.txt");
  const auto p = asperity::slide::paused_slip(s.contact, s.options, paused);
  EXPECT_NE(said.find("paused at iteration " + std::to_string(p.iteration) + ": " +
                      std::to_string(p.slipped_sites) + " sites slipped"),
            std::string::npos)
      << said;
  EXPECT_GT(p.slipped_sites, 0) << "the middle of the first slip flow";
  // How far from rest the paused state is: the library's number, above the flow's tolerance in
  // the middle of a slip.
  char residual[64];
  std::snprintf(residual, sizeof residual, "max |r| = %.3g G d^2", p.max_force);
  EXPECT_NE(said.find(residual), std::string::npos) << said;
  EXPECT_GT(p.max_force, s.options.slip_minimizer->force_tolerance);
  auto want = asperity::slide::snapshot_of(s.contact, p.state, "flow");
  want.iteration = p.iteration;
  const auto flow = asperity::app::read_snapshots(point / "peek" / "flow.nc");
  ASSERT_EQ(flow.size(), 1u);
  expect_same_fields(want, flow[0], "flow.nc");
  const auto accepted = asperity::app::read_snapshots(point / "peek" / "accepted.nc");
  ASSERT_EQ(accepted.size(), 1u);
  expect_same_fields(asperity::slide::snapshot_of(s.contact, paused.current, "accepted"),
                     accepted[0], "accepted.nc");
  const auto peak = asperity::app::read_snapshots(point / "peek" / "peak.nc");
  ASSERT_EQ(peak.size(), 1u);
  expect_same_fields(asperity::slide::snapshot_of(s.contact, paused.peak, "peak"), peak[0],
                     "peak.nc");
  EXPECT_EQ(fs::last_write_time(point / "checkpoint.cbor"), written) << "--peek wrote to it";

  // A checkpoint between steps: no flow.nc (the one above is removed).
  asperity::app::write_checkpoint(point / "checkpoint.cbor",
                                  {.settings = settings, .state = *between});
  ASSERT_EQ(run(peek), 0) << read_text(dir / "peek.txt");
  EXPECT_FALSE(fs::exists(point / "peek" / "flow.nc"));
  EXPECT_NE(read_text(dir / "peek.txt").find("no slip flow paused in it"), std::string::npos);
  const auto later = asperity::app::read_snapshots(point / "peek" / "accepted.nc");
  ASSERT_EQ(later.size(), 1u);
  EXPECT_DOUBLE_EQ(later[0].Dx, between->current.Dx);

  // A checkpoint of another problem (another alpha) is refused, naming the item.
  asperity::app::SlideScene other = s;
  other.contact.alpha = 0.6;
  asperity::app::write_checkpoint(
      point / "checkpoint.cbor",
      {.settings = asperity::app::slide_fingerprint(other) + " snapshots=0", .state = paused});
  EXPECT_EQ(WEXITSTATUS(run(peek)), 1);
  EXPECT_NE(read_text(dir / "peek.txt").find("checkpoint of another problem"), std::string::npos)
      << read_text(dir / "peek.txt");
}

}  // namespace
