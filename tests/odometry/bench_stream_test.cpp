// The benchmark's streaming runner (tools/benchmark/sim_run.hpp): every scan simulated once and
// given to one pipeline per mode, per-scan records kept, errors as dammloam-evaluate reports them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "tools/benchmark/sim_run.hpp"
#include "tools/simulate/presets.hpp"

namespace dammloam {
namespace {

OdometryConfig WithMode(RegistrationMode mode) {
  OdometryConfig config;
  config.registration.mode = mode;
  return config;
}

TEST(BenchStream, ModesSeeTheSameScansOfAPresetPrefix) {
  const auto preset = sim::FindPreset("wheeled-corridor");
  ASSERT_TRUE(preset);
  const sim::Simulator simulator(*preset, sim::Vlp16(), /*seed=*/1);
  const bench::ScanStream stream = bench::SimulatedStream(simulator, 60);
  ASSERT_EQ(stream.size(), 60u);

  std::size_t seen = 0;
  double last_stamp = 0.0;
  const auto traces = bench::StreamModes(
      stream, {WithMode(RegistrationMode::kPointToPoint), WithMode(RegistrationMode::kFull)},
      [&](const Scan& scan) {
        EXPECT_DOUBLE_EQ(scan.t_start, stream.ground_truth[seen].t);
        EXPECT_GT(scan.size(), 1000u);
        last_stamp = scan.t_start;
        ++seen;
      });
  EXPECT_EQ(seen, 60u);
  ASSERT_EQ(traces.size(), 2u);
  EXPECT_EQ(traces[0].mode, "point_to_point");
  EXPECT_EQ(traces[1].mode, "full");
  for (const bench::ModeTrace& trace : traces) {
    ASSERT_EQ(trace.scans.size(), stream.size()) << trace.mode;
    EXPECT_DOUBLE_EQ(trace.scans.back().stamp, last_stamp) << trace.mode;
    for (const bench::ScanRecord& r : trace.scans) {
      EXPECT_TRUE(Registered(r.status)) << trace.mode;
      EXPECT_GT(r.map_points, 0u) << trace.mode;
    }
  }

  const bench::TrajectoryErrors full = bench::EvaluateEstimate(stream.ground_truth, traces[1].Estimate());
  const bench::TrajectoryErrors p2p = bench::EvaluateEstimate(stream.ground_truth, traces[0].Estimate());
  std::printf("full: APE %.4f (max %.4f) RPE %.4f, frames median %.4f worst %.4f (scan %zu); "
              "p2p: APE %.4f\n",
              full.ape_rmse, full.ape_max, full.rpe_rmse, full.median_frame_m, full.worst_frame_m,
              full.worst_frame_index, p2p.ape_rmse);
  EXPECT_EQ(full.pairs, stream.size());
  EXPECT_EQ(full.frame_errors.size(), stream.size() - 1);
  // Measured (seed 1, 60 scans = the first 6 s of the walk): full APE RMSE 0.008 m, max 0.020 m,
  // frame errors median 0.009 m, worst 0.027 m; point-to-point APE 0.022 m.
  EXPECT_LT(full.ape_rmse, 0.05);
  EXPECT_GE(full.ape_max, full.ape_rmse);
  EXPECT_GE(full.worst_frame_m, full.median_frame_m);
  EXPECT_GT(full.median_frame_m, 0.0);
  EXPECT_DOUBLE_EQ(full.worst_frame_m, full.frame_errors[full.worst_frame_index - 1]);
  EXPECT_DOUBLE_EQ(full.worst_frame_m,
                   *std::max_element(full.frame_errors.begin(), full.frame_errors.end()));
  EXPECT_GT(bench::ProcStatusMiB("VmRSS"), 1.0);
  EXPECT_GE(bench::ProcStatusMiB("VmHWM"), bench::ProcStatusMiB("VmRSS"));
}

}  // namespace
}  // namespace dammloam
