// dammloam-bench-backend: medians of Scan Context descriptor time, retrieval time at 1k and 10k
// keyframes, and pose-graph optimisation time against the number of nodes.
// Usage: dammloam-bench-backend [repeats]   (plain argv: no options worth a CLI parser)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <vector>

#include "core/backend/pose_graph.hpp"
#include "core/backend/scan_context.hpp"
#include "core/backend/scan_context_database.hpp"
#include "tools/simulate/simulator.hpp"

namespace {

using namespace dammloam;
using Clock = std::chrono::steady_clock;

double MedianMs(int repeats, const std::function<void()>& work) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto start = Clock::now();
    work();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

// A database of n descriptors: real ones from the simulator, re-used with random rotations.
backend::ScanContextDatabase MakeDatabase(const std::vector<backend::ScanContext>& real, int n) {
  backend::ScanContextDatabase db;
  std::mt19937 rng(1);
  for (int i = 0; i < n; ++i) {
    backend::ScanContext sc = real[static_cast<std::size_t>(i) % real.size()];
    // Perturb so that the tree is not full of exact duplicates.
    sc.grid = sc.grid.unaryExpr([&](float v) {
      return v > 0 ? v + 0.05f * std::uniform_real_distribution<float>(0, 1)(rng) : v;
    });
    sc.ring_key = backend::RingKey(sc.grid) +
                  Eigen::VectorXf::Random(sc.grid.rows()) * 0.01f;
    db.Add(sc);
  }
  return db;
}

void BenchScanContext(int repeats) {
  const sim::Simulator simulator(sim::SceneKind::Outdoor, sim::Os1_64());
  const Scan scan = simulator.SimulateScan(10);
  const backend::ScanContextConfig config;
  std::printf("scan context descriptor (%zu points): %.3f ms median\n", scan.size(),
              MedianMs(repeats, [&] { (void)backend::MakeScanContext(scan.points, config); }));
  std::vector<backend::ScanContext> real;
  for (int i = 0; i < 50; ++i) {
    real.push_back(backend::MakeScanContext(simulator.SimulateScan(i * 17).points, config));
  }
  for (int n : {1000, 10000}) {
    backend::ScanContextDatabase db = MakeDatabase(real, n);
    (void)db.Query(real[3]);  // builds the tree once, as the running back-end would have
    std::printf("scan context query at %5d keyframes: %.3f ms median\n", n,
                MedianMs(repeats, [&] { (void)db.Query(real[3]); }));
  }
}

void BenchPoseGraph(int repeats) {
  for (int nodes : {100, 500, 1000, 2000}) {
    int rejected = 0;
    const double ms = MedianMs(std::max(1, repeats / 4), [&] {
      backend::PoseGraph graph;
      std::mt19937 rng(2);
      std::normal_distribution<double> noise(0.0, 0.01);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      graph.AddNode(T);
      for (int i = 1; i < nodes; ++i) {
        Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
        step.translation() << 1.0 + noise(rng), noise(rng), 0.0;
        step.linear() = Eigen::AngleAxisd(2 * 3.14159265 / 100 + noise(rng), Eigen::Vector3d::UnitZ())
                            .toRotationMatrix();
        T = T * step;
        graph.AddNode(T);
        graph.AddOdometryEdge(i - 1, i, step, Matrix6d::Identity() * 1e-4);
        if (i >= 100) graph.AddLoopEdge(i - 100, i, Eigen::Isometry3d::Identity(), Matrix6d::Identity() * 1e-3);
      }
      rejected = graph.Optimize().rejected_loops;
    });
    std::printf("pose graph %5d nodes (loop edge every node after the first lap): %.1f ms median"
                " (%d loops pruned)\n", nodes, ms, rejected);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  BenchScanContext(repeats);
  BenchPoseGraph(repeats);
  return 0;
}
