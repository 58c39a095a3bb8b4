#include "core/backend/loop_closing_backend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/backend/global_map.hpp"
#include "core/backend/odometry_chain.hpp"
#include "core/backend/point_to_plane_icp.hpp"
#include "core/backend/reason_text.hpp"

namespace dammloam::backend {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// A keyframe keeps the scan without its moving points: people and cars in its cloud would be
// matched by loop verification at their old places and saved into the map as trails.
void KeepStaticPoints(const OdometryResult& result, Keyframe& kf) {
  if (result.labels.size() != result.deskewed_points.size()) {
    kf.points = result.deskewed_points;
    return;
  }
  const auto moving = static_cast<std::size_t>(
      std::count(result.labels.begin(), result.labels.end(), PointClass::Moving));
  if (moving == 0) {
    kf.points = result.deskewed_points;
    kf.labels = result.labels;
    return;
  }
  kf.points.reserve(result.labels.size() - moving);
  kf.labels.reserve(result.labels.size() - moving);
  kf.occluders.reserve(moving);
  for (std::size_t i = 0; i < result.labels.size(); ++i) {
    if (result.labels[i] == PointClass::Moving) {
      kf.occluders.push_back(result.deskewed_points[i]);
      continue;
    }
    kf.points.push_back(result.deskewed_points[i]);
    kf.labels.push_back(result.labels[i]);
  }
}

// The front end's covariance is of a left (world-frame) perturbation of the scan's pose; an
// edge's is of its end pose seen from the previous keyframe: position in that keyframe's frame,
// rotation in the scan's own. Without the lever arm -[t]x, rotation noise 100 m from the world
// origin would count as metres of translation noise and leave the odometry edges there
// nearly free next to any loop.
Matrix6d InKeyframeFrame(const Matrix6d& world_covariance, const Eigen::Isometry3d& T_world_scan,
                         const Eigen::Isometry3d& T_world_keyframe) {
  const Eigen::Matrix3d R_keyframe_world = T_world_keyframe.rotation().transpose();
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = R_keyframe_world;
  J.topRightCorner<3, 3>() = -R_keyframe_world * Hat(T_world_scan.translation());
  J.bottomRightCorner<3, 3>() = T_world_scan.rotation().transpose();
  return J * world_covariance * J.transpose();
}

}  // namespace

LoopClosingBackend::LoopClosingBackend(const BackendConfig& config)
    : config_(config),
      verifier_(config.verifier),
      selector_(config.keyframes),
      database_(config.database),
      graph_(config.pose_graph) {}

void LoopClosingBackend::AddScan(const OdometryResult& result) {
  std::lock_guard lock(shared_mutex_);
  if (last_scan_) {
    if (result.scan_index <= *last_scan_) return;  // replayed or out of order
    path_length_ += (result.T_world_sensor.translation() - last_position_).norm();
    covariance_since_keyframe_ +=
        InKeyframeFrame(result.covariance, result.T_world_sensor, last_keyframe_odom_);
  } else {
    first_scan_ = result.scan_index;
  }
  last_scan_ = result.scan_index;
  last_position_ = result.T_world_sensor.translation();
  if (selector_.Consider(result.T_world_sensor)) {
    PendingKeyframe pending;
    Keyframe& kf = pending.keyframe;
    kf.id = next_keyframe_id_++;
    kf.scan_index = result.scan_index;
    kf.stamp = result.stamp;
    kf.T_world_sensor_odom = result.T_world_sensor;
    kf.T_world_sensor = result.T_world_sensor;
    kf.edge_covariance = covariance_since_keyframe_;
    KeepStaticPoints(result, kf);
    pending.path_length = path_length_;
    inbox_.push_back(std::move(pending));
    keyframe_scans_.push_back(result.scan_index);
    covariance_since_keyframe_.setZero();
    last_keyframe_odom_ = result.T_world_sensor;
  }
}

std::vector<LoopEvent> LoopClosingBackend::Process() {
  std::lock_guard process_lock(process_mutex_);
  std::vector<PendingKeyframe> pending;
  {
    std::lock_guard lock(shared_mutex_);
    pending.swap(inbox_);
  }
  std::vector<LoopEvent> events;
  bool disagrees = false;
  for (PendingKeyframe& p : pending) {
    const std::uint32_t id = p.keyframe.id;
    IntegrateKeyframe(std::move(p));
    for (LoopEvent& event : DetectLoops(id, disagrees)) events.push_back(std::move(event));
  }
  if (disagrees) {
    std::vector<Eigen::Isometry3d> before;
    before.reserve(keyframes_.size());
    for (const Keyframe& kf : keyframes_) before.push_back(kf.T_world_sensor);
    const PoseGraphSummary solve = Optimize();
    ReportCorrections(events, before, solve);
  } else if (!pending.empty()) {
    PublishCorrections(keyframes_.size() - pending.size());
  }
  return events;
}

PoseGraphSummary LoopClosingBackend::Optimize() {
  const PoseGraphSummary summary = graph_.Optimize();
  ++optimizations_;
  for (Keyframe& kf : keyframes_) kf.T_world_sensor = graph_.Pose(kf.id);
  PublishCorrections(0);
  return summary;
}

void LoopClosingBackend::IntegrateKeyframe(PendingKeyframe pending) {
  Keyframe& kf = pending.keyframe;
  const auto kept = VoxelDownsampleIndices(kf.points, config_.keyframe_voxel_size);
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
  for (std::size_t i : kept) {
    points.push_back(kf.points[i]);
    if (!kf.labels.empty()) labels.push_back(kf.labels[i]);
  }
  kf.points = std::move(points);
  kf.labels = std::move(labels);
  kf.occluders = VoxelDownsample(kf.occluders, config_.keyframe_voxel_size);
  kf.descriptor = MakeScanContext(kf.points, config_.scan_context);

  // New nodes start from the corrected previous keyframe plus odometry's relative motion, so
  // the part of the trajectory after a loop closure follows the correction.
  if (keyframes_.empty()) {
    graph_.AddNode(kf.T_world_sensor_odom);
  } else {
    const Keyframe& previous = keyframes_.back();
    const Eigen::Isometry3d T_prev_kf =
        previous.T_world_sensor_odom.inverse() * kf.T_world_sensor_odom;
    kf.T_world_sensor = previous.T_world_sensor * T_prev_kf;
    graph_.AddNode(kf.T_world_sensor);
    graph_.AddOdometryEdge(previous.id, kf.id, T_prev_kf, kf.edge_covariance);
  }
  database_.Add(kf.descriptor);
  keyframe_path_.push_back(pending.path_length);
  dropped_.push_back(0);
  stored_.push_back(kf.id);
  keyframes_.push_back(std::move(kf));
}

std::optional<ScanContextCandidate> LoopClosingBackend::NearestOldKeyframe(
    std::uint32_t query_id) const {
  const Eigen::Vector3d position = keyframes_[query_id].T_world_sensor.translation();
  const auto exclude = static_cast<std::uint32_t>(std::max(0, config_.database.exclude_recent));
  std::optional<std::uint32_t> nearest;
  double best = config_.proximity_radius;
  for (const std::uint32_t id : stored_) {
    if (id + exclude >= query_id) break;
    const double d = (keyframes_[id].T_world_sensor.translation() - position).norm();
    if (d < best) {
      best = d;
      nearest = id;
    }
  }
  if (!nearest) return std::nullopt;
  return ScanContextCandidate{
      *nearest, CompareScanContexts(keyframes_[query_id].descriptor, keyframes_[*nearest].descriptor)};
}

std::vector<LoopEvent> LoopClosingBackend::DetectLoops(std::uint32_t query_id, bool& disagrees) {
  std::vector<LoopEvent> events;
  const Keyframe& query = keyframes_[query_id];
  // The nearest old keyframe in the corrected map goes first: where drift is still small it is
  // the revisit itself, which a descriptor cannot single out in a corridor that looks the same
  // all along. Scan Context's candidates cover the places drift has carried far off.
  std::vector<ScanContextCandidate> candidates;
  if (const auto nearest = NearestOldKeyframe(query_id)) candidates.push_back(*nearest);
  for (const ScanContextCandidate& c : database_.Query(query.descriptor)) {
    if (candidates.empty() || c.id != candidates.front().id) candidates.push_back(c);
  }
  int verified = 0;
  for (const ScanContextCandidate& candidate : candidates) {
    if (verified++ >= config_.max_verifications_per_keyframe) break;
    const Keyframe& old = keyframes_[candidate.id];
    const double path = keyframe_path_[query_id] - keyframe_path_[candidate.id];
    LoopEvent event = verifier_.Verify(query, old, candidate.match, path);
    if (event.accepted) {
      // The registration's own covariance (free along what the loop cannot see) plus a floor
      // for what it does not model: correlated points, keyframe downsampling, deskew.
      Matrix6d covariance = event.covariance;
      covariance.diagonal().head<3>().array() +=
          config_.loop_translation_sigma * config_.loop_translation_sigma;
      covariance.diagonal().tail<3>().array() +=
          config_.loop_rotation_sigma * config_.loop_rotation_sigma;
      if (!ConsistentWithOdometry(event, covariance)) {
        events.push_back(std::move(event));
        continue;
      }
      graph_.AddLoopEdge(old.id, query.id, event.T_candidate_query, covariance);
      // A loop that agrees with the map stays out of the graph: it would correct nothing, and
      // the loops' registrations share a bias (a corridor seen from the other direction) that
      // the next solve would spread over a good trajectory. It still counts as a loop of the map.
      if (DisagreesWithMap(event)) {
        disagrees = true;
      } else {
        graph_.RemoveLastEdge();
      }
      loops_.push_back({old.id, query.id, event.T_candidate_query});
      // Where the loop puts the query, next to the old keyframe: the corrected map is locally
      // consistent there even when the query's own corrected pose is still off by the drift.
      const Eigen::Vector3d position = old.T_world_sensor * event.T_candidate_query.translation();
      events.push_back(std::move(event));
      if (config_.revisit_drop_distance > 0.0 &&
          DistanceToStoredKeyframe(position, query_id) <= config_.revisit_drop_distance) {
        DropCloud(query_id);
      }
      break;  // one verified loop per keyframe is enough evidence
    }
    events.push_back(std::move(event));
  }
  return events;
}

bool LoopClosingBackend::ConsistentWithOdometry(LoopEvent& event,
                                                const Matrix6d& loop_covariance) const {
  if (config_.odometry_consistency_chi2 <= 0.0) return true;
  const ChainNoise noise{config_.pose_graph.min_translation_sigma,
                         config_.pose_graph.min_rotation_sigma, config_.odometry_heading_drift};
  OdometryChain chain =
      ComposeOdometryChain(keyframes_, event.candidate_keyframe, event.query_keyframe, noise);
  chain.covariance *= config_.odometry_covariance_scale;
  // Judged against the corrected map: loops accepted earlier have removed drift that the
  // odometry chain still carries, and a look-alike place stays as far off there.
  chain.T_from_to = keyframes_[event.candidate_keyframe].T_world_sensor.inverse() *
                    keyframes_[event.query_keyframe].T_world_sensor;
  event.odometry_chi2 = ConsistencyChi2(chain, event.T_candidate_query, loop_covariance);
  event.odometry_chi2_bound = config_.odometry_consistency_chi2;
  if (event.odometry_chi2 <= event.odometry_chi2_bound) return true;
  const Eigen::Vector3d offset =
      event.T_candidate_query.translation() - chain.T_from_to.translation();
  const double turn = Eigen::AngleAxisd(chain.T_from_to.rotation().transpose() *
                                        event.T_candidate_query.rotation()).angle();
  const Eigen::Vector3d sigma = chain.covariance.diagonal().head<3>().cwiseSqrt();
  const double turn_sigma = std::sqrt(chain.covariance.diagonal().tail<3>().maxCoeff());
  event.accepted = false;
  event.reason = ReasonText(
      "inconsistent with odometry: chi2 %.1f > %.1f (offset %.2f, %.2f, %.2f m and %.2f deg from "
      "odometry's relative pose; odometry sigma %.2f, %.2f, %.2f m, %.2f deg)",
      event.odometry_chi2, event.odometry_chi2_bound, offset.x(), offset.y(), offset.z(),
      turn * kRadToDeg, sigma.x(), sigma.y(), sigma.z(), turn_sigma * kRadToDeg);
  return false;
}

bool LoopClosingBackend::DisagreesWithMap(LoopEvent& event) const {
  const double residual = graph_.LastEdgeResidual();
  event.map_chi2 = residual * residual;
  event.map_chi2_bound = config_.loop_optimize_residual * config_.loop_optimize_residual;
  event.started_optimization = event.map_chi2 > event.map_chi2_bound;
  event.reason +=
      event.started_optimization
          ? ReasonText("; disagrees with the map (chi2 %.2f > %.2f): graph re-solved",
                       event.map_chi2, event.map_chi2_bound)
          : ReasonText("; agrees with the map (chi2 %.2f <= %.2f): no correction", event.map_chi2,
                       event.map_chi2_bound);
  return event.started_optimization;
}

void LoopClosingBackend::ReportCorrections(std::vector<LoopEvent>& events,
                                           const std::vector<Eigen::Isometry3d>& before,
                                           const PoseGraphSummary& solve) const {
  for (LoopEvent& event : events) {
    if (!event.started_optimization || event.query_keyframe >= before.size()) continue;
    event.solve_ms = solve.solve_ms;
    event.graph_nodes = static_cast<std::uint32_t>(graph_.NumNodes());
    const Eigen::Isometry3d& T_old = before[event.query_keyframe];
    const Eigen::Isometry3d& T_new = keyframes_[event.query_keyframe].T_world_sensor;
    event.correction_m = (T_new.translation() - T_old.translation()).norm();
    event.correction_rad =
        Eigen::AngleAxisd(T_old.rotation().transpose() * T_new.rotation()).angle();
    event.reason += ReasonText(", query keyframe moved %.3f m, %.2f deg", event.correction_m,
                           event.correction_rad * kRadToDeg);
  }
}

double LoopClosingBackend::DistanceToStoredKeyframe(const Eigen::Vector3d& position,
                                                    std::uint32_t query_id) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (const std::uint32_t id : stored_) {
    if (id >= query_id) break;
    nearest = std::min(nearest, (keyframes_[id].T_world_sensor.translation() - position).norm());
  }
  return nearest;
}

void LoopClosingBackend::DropCloud(std::uint32_t id) {
  Keyframe& kf = keyframes_[id];
  // Swapped with empties: clear() would keep the capacity.
  std::vector<Eigen::Vector3d>().swap(kf.points);
  std::vector<PointClass>().swap(kf.labels);
  std::vector<Eigen::Vector3d>().swap(kf.occluders);
  kf.descriptor = ScanContext{};
  database_.Retire(id);
  dropped_[id] = 1;
  // The query is the newest keyframe, the last one stored.
  if (const auto it = std::find(stored_.rbegin(), stored_.rend(), id); it != stored_.rend()) {
    stored_.erase(std::next(it).base());
  }
}

void LoopClosingBackend::PublishCorrections(std::size_t first) {
  std::vector<Eigen::Isometry3d> corrections;
  corrections.reserve(keyframes_.size() - first);
  for (std::size_t id = first; id < keyframes_.size(); ++id) {
    const Keyframe& kf = keyframes_[id];
    corrections.push_back(kf.T_world_sensor * kf.T_world_sensor_odom.inverse());
  }
  std::lock_guard lock(shared_mutex_);
  corrections_.resize(first);
  corrections_.insert(corrections_.end(), corrections.begin(), corrections.end());
}

std::optional<Eigen::Isometry3d> LoopClosingBackend::CorrectedPoseOf(
    std::uint64_t scan_index, const Eigen::Isometry3d& T_world_sensor_odom) const {
  std::lock_guard lock(shared_mutex_);
  if (!last_scan_ || scan_index < *first_scan_ || scan_index > *last_scan_) return std::nullopt;
  if (corrections_.empty()) return T_world_sensor_odom;
  const auto first = keyframe_scans_.begin();
  const auto after = std::upper_bound(first, keyframe_scans_.end(), scan_index);
  const std::size_t at_or_before = after == first ? 0 : static_cast<std::size_t>(after - first) - 1;
  // Keyframes still in the inbox use the newest correction available.
  const std::size_t k = std::min(at_or_before, corrections_.size() - 1);
  return Normalized(corrections_[k] * T_world_sensor_odom);
}

Eigen::Isometry3d LoopClosingBackend::MapFromOdom() const {
  std::lock_guard lock(shared_mutex_);
  return corrections_.empty() ? Eigen::Isometry3d::Identity() : corrections_.back();
}

std::size_t LoopClosingBackend::NumKeyframes() const {
  std::lock_guard lock(process_mutex_);
  return keyframes_.size();
}

std::size_t LoopClosingBackend::NumAcceptedLoops() const {
  std::lock_guard lock(process_mutex_);
  return loops_.size();
}

std::size_t LoopClosingBackend::NumStoredKeyframes() const {
  std::lock_guard lock(process_mutex_);
  return stored_.size();
}

std::size_t LoopClosingBackend::NumOptimizations() const {
  std::lock_guard lock(process_mutex_);
  return optimizations_;
}

void LoopClosingBackend::SetSensor(const SensorModel& sensor) {
  std::lock_guard lock(process_mutex_);
  sensor_ = sensor;
}

MapData LoopClosingBackend::ExportMap() const {
  MapData map;
  std::optional<SensorModel> sensor;
  {
    std::lock_guard lock(process_mutex_);
    map = ExportGraph();
    sensor = sensor_;
  }
  // Outside the lock: judging the map against its keyframes takes about a second for 190,000
  // points (vacated_points.hpp), and loop closing goes on meanwhile.
  GlobalMap global = sensor ? AssembleGlobalMap(map.keyframes, config_.global_map_voxel_size, *sensor,
                                                config_.keyframe_voxel_size, config_.vacated)
                            : AssembleGlobalMap(map.keyframes, config_.global_map_voxel_size);
  map.global_points = std::move(global.points);
  map.global_labels = std::move(global.labels);
  map.vacated_points = global.vacated;
  return map;
}

MapData LoopClosingBackend::ExportGraph() const {
  MapData map;
  map.scan_context = config_.scan_context;
  // Saved ids are dense: a map holds only keyframes with a cloud.
  constexpr std::uint32_t kNotSaved = ~std::uint32_t{0};
  std::vector<std::uint32_t> saved_id(keyframes_.size(), kNotSaved);
  for (std::uint32_t id = 0; id < keyframes_.size(); ++id) {
    if (!HasCloud(id)) continue;
    saved_id[id] = static_cast<std::uint32_t>(map.keyframes.size());
    map.keyframes.push_back(keyframes_[id]);
    map.keyframes.back().id = saved_id[id];
  }
  for (const LoopConstraint& loop : loops_) {
    if (saved_id[loop.from] == kNotSaved || saved_id[loop.to] == kNotSaved) continue;
    map.loops.push_back({saved_id[loop.from], saved_id[loop.to], loop.T_from_to});
  }
  return map;
}

}  // namespace dammloam::backend
