#pragma once
#include <cstdint>
#include <deque>
#include <vector>
#include <string_view>

namespace dammloam {

// How well the odometry is following the sensor, per scan. A robot has to know when its pose
// is no longer measured: a registration in a fast turn can end in the wrong basin with a
// quarter of its usual pairs, and nothing else in the result says so.
enum class Tracking : std::uint8_t {
  kTracking = 0,  // the scan fitted the map as well as recent scans did
  kDegraded = 1,  // registered, but the fit or the prediction was off: trust the pose less
  kLost = 2,      // not registered: too little fit (or no data); the pose is the prediction
};

constexpr std::string_view Name(Tracking t) {
  switch (t) {
    case Tracking::kTracking: return "tracking";
    case Tracking::kDegraded: return "degraded";
    case Tracking::kLost: return "lost";
  }
  return "unknown";
}

struct TrackingHealthConfig {
  // The share of source points that found a pair, against its median over recent registered
  // scans: what a good fit looks like here (a share, so that a scene with fewer points is not
  // mistaken for a failure). On the simulated presets the pair count of a registered scan
  // stays >= 0.76 of its recent median; at the real hall's first failure it fell to 0.23.
  int reference_scans = 20;
  double degraded_pair_share = 0.6;  // below this fraction of the median: degraded
  double lost_pair_share = 0.35;     // below this fraction: lost
  // Consecutive lost scans after which the odometry starts its local map over at the
  // prediction instead of waiting for a map it no longer overlaps (0: never).
  int restart_after_lost_scans = 10;
  // The fastest the carrier turns (a hand-held sensor swung sideways: 120 deg/s): re-acquisition
  // tries predictions turned by up to this times the interval, at most 90 deg. At 10 Hz that is
  // 20 deg, so a scan turned further than a hand can turn it stays lost.
  double max_turn_rate_deg_s = 200.0;
  // A registration that turned this far from the prediction (deg) is searched again as well:
  // a prediction tens of degrees off can converge into a neighbouring basin that fits well.
  double search_after_turn_deg = 25.0;
  // The registered pose lay this many correspondence gates from the prediction: its pairs were
  // found from a guess that far off, so the basin may be the wrong one (degraded).
  double max_innovation_gates = 1.0;
};

// What one registration tells about its fit.
struct FitEvidence {
  bool converged = false;
  double paired_share = 0.0;  // of the registration's source points
  double innovation = 0.0;  // metres, registered pose against the prediction
  double gate = 0.0;        // metres, the correspondence gate registration started with
};

// Judges each registration against the recent ones: paired share against its median over the
// last registered scans, convergence, innovation against the gate. Lost when the pairs collapse, or
// when an unconverged registration also lost many of them.
class TrackingHealth {
 public:
  explicit TrackingHealth(const TrackingHealthConfig& config) : config_(config) {}
  Tracking Judge(const FitEvidence& fit) const;
  // The paired share is below degraded_pair_share of the reference (once there is one): the
  // registration may sit in the wrong basin, even where it converged.
  bool FewPairs(double paired_share) const;
  // A registered scan (tracking or degraded): its paired share joins the reference.
  void Record(double paired_share);
  // The map was started over: what good fits looked like no longer applies.
  void Clear() { recent_shares_.clear(); }
  double ReferenceShare() const;  // 0 until a scan has been registered

 private:
  TrackingHealthConfig config_;
  std::deque<double> recent_shares_;
  mutable std::vector<double> sorted_shares_;  // ReferenceShare's buffer (one thread uses this)
};

}  // namespace dammloam
