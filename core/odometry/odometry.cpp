#include "core/odometry/odometry.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/preprocess/deskew.hpp"
#include "core/registration/degeneracy_weights.hpp"

namespace dammloam {

namespace {

// KISS-ICP's adaptive threshold: pairs farther than kGateSigmas sigma are outliers, and the
// robust kernel's scale is sigma / kGateSigmas.
constexpr double kGateSigmas = 3.0;

class Stopwatch {
 public:
  double LapMs() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

double MedianRange(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> ranges;
  ranges.reserve(points.size());
  for (const Eigen::Vector3d& p : points) ranges.push_back(p.norm());
  if (ranges.empty()) return 0.0;
  auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
  std::nth_element(ranges.begin(), mid, ranges.end());
  return *mid;
}

void TransformScan(const Eigen::Isometry3d& T, ClassifiedScan& scan) {
  if (T.isApprox(Eigen::Isometry3d::Identity())) return;
  std::vector<Eigen::Vector3d>& points = scan.scan.points;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 8192), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) points[i] = T * points[i];
  });
  const Eigen::Matrix3f R = T.linear().cast<float>();
  std::vector<Eigen::Vector3f>& normals = scan.normals;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, normals.size(), 8192), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) normals[i] = R * normals[i];
  });
}

PersistenceFilter::Config PersistenceConfig(double map_voxel, const MovingPointsConfig& moving) {
  PersistenceFilter::Config config;
  config.voxel_size = map_voxel;
  config.min_age = moving.map_after;
  config.max_gap = moving.map_after_max_gap;
  return config;
}

// Drops the indices of moving points (moving empty: none moves).
void WithoutMoving(std::vector<std::size_t>& indices, const std::vector<std::uint8_t>& moving) {
  if (moving.empty()) return;
  indices.erase(std::remove_if(indices.begin(), indices.end(),
                               [&](std::size_t i) { return moving[i] != 0; }),
                indices.end());
}

// The published labels: a moving point's class is Moving, whatever its shape, and the class
// counts follow (they still sum to the scan's points).
void LabelMoving(const std::vector<std::uint8_t>& moving, std::vector<PointClass>& labels,
                 ClassCounts& counts) {
  if (moving.size() != labels.size()) return;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (moving[i] == 0 || labels[i] == PointClass::Moving) continue;
    std::uint32_t& count = counts[Index(labels[i])];
    if (count > 0) --count;
    labels[i] = PointClass::Moving;
    ++counts[Index(PointClass::Moving)];
  }
}

// values[indices] into `out` (its capacity reused); empty values give an empty out.
template <typename T>
const std::vector<T>& GatherInto(const std::vector<T>& values,
                                 const std::vector<std::size_t>& indices, std::vector<T>& out) {
  out.clear();
  if (values.empty()) return out;
  out.reserve(indices.size());
  for (std::size_t i : indices) out.push_back(values[i]);
  return out;
}

template <typename T>
std::vector<T> Gather(const std::vector<T>& values, const std::vector<std::size_t>& indices) {
  std::vector<T> out;
  GatherInto(values, indices, out);
  return out;
}

}  // namespace

Odometry::Odometry(const OdometryConfig& config, const SensorModel& sensor)
    : config_(config),
      sensor_(sensor),
      downsampler_(config.downsample),
      map_(AutoVoxelSize(config.map, 0.0), config.map.max_distance,
           config.map.max_points_per_voxel),
      threshold_(config.registration.initial_threshold,
                 config.registration.min_motion_threshold, config.map.max_distance),
      moving_(config.moving, sensor),
      compact_objects_(config.compact_objects),
      persistence_(PersistenceConfig(AutoVoxelSize(config.map, 0.0), config.moving)),
      translation_filter_(config.motion_prior),
      health_(config.health) {}

// A rotation error displaces a point in proportion to its range. KISS-ICP measures it at the
// sensor's maximum range; where the scene is much smaller (a corridor) that inflates the
// correspondence gate and the robust kernel many times over what the points ever moved.
double Odometry::ThresholdReferenceRange(double median_range) const {
  const double factor = config_.threshold_range_factor;
  if (!(factor > 0.0) || !(median_range > 0.0)) return config_.map.max_distance;
  return std::min(factor * median_range, config_.map.max_distance);
}

Eigen::Matrix3d Odometry::PredictedOrientation() const {
  return (T_world_last_ * ExpSE3(velocity_ * sensor_.scan_period)).linear();
}

void Odometry::Initialise(Frame& frame) {
  const double median_range = MedianRange(frame.scan.scan.points);
  map_ = VoxelHashMap(AutoVoxelSize(config_.map, median_range), config_.map.max_distance,
                      config_.map.max_points_per_voxel);
  persistence_ = PersistenceFilter(PersistenceConfig(map_.voxel_size(), config_.moving));
  threshold_ = AdaptiveThreshold(config_.registration.initial_threshold,
                                 config_.registration.min_motion_threshold,
                                 ThresholdReferenceRange(median_range));
  first_scan_raw_ = std::move(frame.raw);
  first_scan_gyro_ = frame.gyro_scan;
  initialised_ = true;
}

// The world frame stays the first scan's start frame (its reported pose is unchanged); only
// its mid-scan pose and its points in the map change.
void Odometry::RebuildMapFromFirstScan(const Vector6d& velocity) {
  ClassifiedScan first = std::move(*first_scan_raw_);
  first_scan_raw_.reset();
  const std::optional<GyroTrack> gyro = std::move(first_scan_gyro_);
  first_scan_gyro_.reset();
  T_world_last_ = DeskewToMidScan(first, velocity, gyro ? &*gyro : nullptr).inverse();
  map_ = VoxelHashMap(map_.voxel_size(), config_.map.max_distance,
                      config_.map.max_points_per_voxel);
  persistence_.Clear();
  UpdateMap(first, T_world_last_);
}

void Odometry::UpdateMap(const ClassifiedScan& scan, const Eigen::Isometry3d& T_world_sensor,
                         const std::vector<std::uint8_t>& moving,
                         const std::vector<std::uint8_t>& compact) {
  MapInput& in = map_input_;
  std::vector<std::size_t>& kept = in.indices;
  map_sampler_.Select(scan.scan.points, scan.labels,
                      config_.map_frame_voxel_factor * map_.voxel_size(), kept);
  WithoutMoving(kept, moving);
  KeepPersistent(kept, scan, T_world_sensor, compact);
  map_.Update(GatherInto(scan.scan.points, kept, in.points), GatherInto(scan.labels, kept, in.labels),
              GatherInto(scan.normals, kept, in.normals), T_world_sensor);
}

void Odometry::KeepPersistent(std::vector<std::size_t>& kept, const ClassifiedScan& scan,
                              const Eigen::Isometry3d& T_world_sensor,
                              const std::vector<std::uint8_t>& compact) {
  if (!config_.moving.enabled || !(config_.moving.map_after > 0.0)) return;
  std::vector<Eigen::Vector3d> world;
  world.reserve(kept.size());
  for (std::size_t i : kept) world.push_back(T_world_sensor * scan.scan.points[i]);
  if (map_.empty()) {
    persistence_.Accept(world, T_world_sensor.translation(), scan.scan.t_start);
    return;
  }
  const std::vector<double> age =
      persistence_.ObservedFor(world, T_world_sensor.translation(), scan.scan.t_start);
  const double compact_age = std::max(config_.moving.map_after, config_.compact_objects.map_after);
  std::size_t n = 0;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const bool on_object = kept[k] < compact.size() && compact[kept[k]] != 0;
    if (age[k] >= (on_object ? compact_age : config_.moving.map_after) - 1e-9) kept[n++] = kept[k];
  }
  kept.resize(n);
}

// Deskew with the constant-velocity motion over one period, then express the scan in the frame
// of its middle (as KISS-ICP does). Registering the start frame instead couples a velocity
// error into the next pose with the opposite sign, and the two feed each other into a growing
// oscillation; around the middle the error averages out. Poses are kept internally at
// mid-scan and reported at the scan start, as sequence.md asks. Returns T_mid_start.
Eigen::Isometry3d Odometry::DeskewToMidScan(ClassifiedScan& scan, const Vector6d& velocity,
                                            const GyroTrack* gyro) const {
  if (!config_.deskew || !scan.scan.has_times()) return Eigen::Isometry3d::Identity();
  if (gyro) return DeskewWithGyro(scan, velocity, *gyro);
  const Vector6d xi_scan = velocity * sensor_.scan_period;
  const Eigen::Isometry3d T_mid_start = ExpSE3(-0.5 * xi_scan);
  DeskewScan(scan, ExpSE3(xi_scan), sensor_.scan_period, T_mid_start);
  return T_mid_start;
}

// The gyro measured how the sensor turned through the scan (a hand's shake reverses within
// it); the translation is the constant velocity's, which the scan's data corrects, and with
// `bend` what the accelerometer adds to it.
Eigen::Isometry3d Odometry::DeskewWithGyro(ClassifiedScan& scan, const Vector6d& velocity,
                                           const GyroTrack& gyro,
                                           const std::optional<Eigen::Vector3d>& v_start,
                                           const AccelerationTrack* bend) const {
  const double period = sensor_.scan_period;
  const Vector6d xi = velocity * period;
  const double t_start = scan.scan.t_start;
  const auto start_point = [&](double tau) {
    Eigen::Isometry3d T = ExpSE3((tau / period) * xi);
    if (v_start) T.translation() = tau * *v_start;
    if (bend) T.translation() += bend->At(t_start + tau);
    T.linear() = gyro.At(t_start + tau);
    return T;
  };
  const Eigen::Isometry3d T_mid_start = start_point(0.5 * period).inverse();
  DeskewScanAlong(scan, [&](double tau) { return T_mid_start * start_point(tau); });
  return T_mid_start;
}

void Odometry::SelectSource(Frame& frame) {
  const ClassifiedScan& scan = frame.scan;
  std::vector<std::size_t>& idx = source_indices_;
  downsampler_.Select(scan.scan.points, scan.labels, idx);
  WithoutMoving(idx, frame.moving);
  frame.set_aside = frame.moving;
  frame.objects_set_aside = 0;
  frame.compact.clear();
  if (config_.compact_objects.enabled && initialised_) {
    // Objects facing the scan's weakest direction: where they make it look observed, the rest
    // of the scan's weakest direction is this one.
    const WeakestAxis weakest = WeakestAxisOf(scan.normals, idx);
    const std::vector<std::uint8_t>& objects =
        compact_objects_.Find(scan.scan.points, scan.labels, scan.normals, weakest.direction,
                              T_world_last_.linear());
    // Only where the map makes them wait longer than the rest (off by default): per scan work.
    if (config_.moving.enabled && config_.compact_objects.map_after > config_.moving.map_after) {
      frame.compact = MapLater(scan.labels, scan.normals, weakest, objects, config_.compact_objects);
    }
    if (!objects.empty() &&
        ObjectsWitnessTheWeakAxis(scan.normals, idx, objects, config_.compact_objects)) {
      if (frame.set_aside.empty()) frame.set_aside.assign(objects.size(), 0);
      for (std::size_t i = 0; i < objects.size(); ++i) {
        frame.set_aside[i] |= objects[i];
        frame.objects_set_aside += objects[i];
      }
      WithoutMoving(idx, objects);
    }
  }
  SourcePoints source{Gather(scan.scan.points, idx), Gather(scan.labels, idx), {}};
  if (config_.deskew && scan.scan.has_times()) {
    source.times = Gather(scan.scan.times, idx);
    const float half = static_cast<float>(0.5 * sensor_.scan_period);
    for (float& t : source.times) t -= half;
  }
  frame.source = std::move(source);
}

bool Odometry::Consecutive(double dt) const { return dt <= 1.5 * sensor_.scan_period; }

// The deskew velocity is the mean over the interval since the last registered scan. Between
// sparse scans (a stream kept at 2 Hz) a trot's 0.36 rad/s pitch rate averages out, so the
// scan's own turn rate may depart from it in proportion to the interval. Its linear velocity
// may not: freed, it let a 2 Hz corridor walk (seed 3) slide 10 m along the weak axis.
MotionPrior Odometry::Prior(double dt, bool holds, double measured_acceleration_sigma,
                           const Eigen::Matrix3d& measured) {
  if (!UsesMotionPrior(config_.registration.mode)) return {holds, {}, 0.0};
  const Eigen::Matrix3d covariance =
      translation_filter_.Predict(dt, measured_acceleration_sigma, measured);
  const double sparse = Consecutive(dt) ? 1.0 : dt / sensor_.scan_period;
  return {holds, covariance.ldlt().solve(Eigen::Matrix3d::Identity()),
          config_.max_angular_acceleration * dt * dt, config_.in_scan_velocity_sigma,
          sparse * config_.in_scan_rate_sigma, config_.in_scan_angular_acceleration_sigma,
          config_.in_scan_spin_axis_acceleration_sigma};
}

Vector6d Odometry::FilteredVelocity(const Eigen::Isometry3d& T_pred,
                                    const Eigen::Isometry3d& T_new,
                                    const RegistrationResult& reg, double dt,
                                    const std::optional<Eigen::Vector3d>& predicted_velocity) {
  const Eigen::Vector3d t_last = T_world_last_.translation();
  const Eigen::Vector3d v_pred =
      predicted_velocity ? *predicted_velocity : Eigen::Vector3d((T_pred.translation() - t_last) / dt);
  const Eigen::Vector3d v =
      translation_filter_.Update(v_pred, T_new.translation() - T_pred.translation(),
                                reg.PositionInformation());
  world_velocity_ = v;
  Eigen::Isometry3d T_velocity = T_new;
  T_velocity.translation() = t_last + v * dt;
  return LogSE3(T_world_last_.inverse() * T_velocity) / dt;
}

// Along an observed direction the map anchors the pose, so its uncertainty is this scan's; along
// a degenerate one each scan's uncertainty adds to what has built up since the direction was
// last observed.
Matrix6d Odometry::PoseCovariance(const RegistrationResult& reg) {
  const Eigen::Matrix3d P = DegenerateProjector(reg.degeneracy);
  const Eigen::Matrix3d C = reg.covariance.topLeftCorner<3, 3>();
  const Eigen::Matrix3d Q = Eigen::Matrix3d::Identity() - P;
  unobserved_covariance_ = P * (unobserved_covariance_ + C) * P;
  Matrix6d pose = reg.covariance;
  pose.topLeftCorner<3, 3>() = Q * C * Q + unobserved_covariance_;
  return pose;
}

OdometryResult Odometry::Register(ClassifiedScan&& scan) {
  return RegisterAndUpdate(std::move(scan), false);
}

OdometryResult Odometry::RegisterDeferringMap(ClassifiedScan&& scan) {
  return RegisterAndUpdate(std::move(scan), true);
}

double Odometry::CommitMap() {
  if (!pending_map_update_) return 0.0;
  Stopwatch watch;
  UpdateMap(pending_map_update_->scan, pending_map_update_->T_world_sensor,
            pending_map_update_->moving, pending_map_update_->compact);
  pending_map_update_.reset();
  return watch.LapMs();
}

// One scan through the paper's pipeline: deskew -> select -> register -> update. A scan that
// cannot be registered leaves every piece of state as it was.
OdometryResult Odometry::RegisterAndUpdate(ClassifiedScan&& scan, bool defer_map) {
  CommitMap();
  Stopwatch watch;
  OdometryResult result = NewResult(scan);
  result.status = Admit(scan.scan);
  if (!Registered(result.status)) {
    // No data is no measurement; a repeated stamp changes nothing.
    if (result.status != OdometryStatus::kNonIncreasingStamp) result.tracking = Tracking::kLost;
    result.pose_covariance = last_pose_covariance_;
    return result;
  }
  result.point_times = CheckPointTimes(scan.scan, sensor_.scan_period);
  // Times that are not firing times would bend the cloud: dropped, never guessed.
  if (result.point_times != PointTimeCheck::kUsable) scan.scan.times.clear();
  const double dt = TimeStep(scan.scan.t_start, result.status);
  GyroTracks gyro = TrackGyro(scan.scan.t_start, result.gyro);
  std::optional<WheelTrack> wheel = TrackWheel(scan.scan.t_start, result.wheel);
  std::optional<VelocityIncrement> accel = TrackAccel(gyro, result.accelerometer);
  Frame frame = Deskew(std::move(scan), std::move(gyro), std::move(wheel), std::move(accel), dt);
  result.timings.deskew_ms = watch.LapMs();
  if (initialised_) DetectMoving(frame, dt);
  SelectSource(frame);
  result.timings.downsample_ms = watch.LapMs();
  Eigen::Isometry3d T_new = Eigen::Isometry3d::Identity();
  if (!initialised_) {
    Initialise(frame);
    result.status = OdometryStatus::kFirstScan;
  } else {
    // The prediction advances the filter; a scan that is not registered must leave it as it was.
    const TranslationFilter filter_before = translation_filter_;
    if (gyro_bias_) gyro_bias_->Propagate(dt);
    RegistrationResult reg = RegisterFrame(frame, dt);
    result.tracking = JudgeFit(frame, reg, result);
    if (frame.held_at_prediction && result.tracking == Tracking::kTracking) {
      result.tracking = Tracking::kDegraded;
    }
    if (result.status == OdometryStatus::kTimeGap) reg = AcrossTheGap(frame, dt, reg, result);
    const bool poor_fit = result.tracking == Tracking::kLost || health_.FewPairs(result.paired_share) ||
                          result.turn_innovation_deg > config_.health.search_after_turn_deg;
    if (poor_fit && reg.enough_correspondences) reg = Reacquire(frame, dt, reg, result);
    result.timings.registration_ms = watch.LapMs();
    Describe(reg, result);
    if (result.tracking == Tracking::kLost) {
      const OdometryStatus why = reg.enough_correspondences ? OdometryStatus::kLost
                                                            : OdometryStatus::kTooFewCorrespondences;
      translation_filter_ = filter_before;
      if (!StartOverAfterLoss()) return Unregistered(std::move(result), frame, why);
      Restart(frame);
      result.status = OdometryStatus::kRestarted;
      T_new = frame.T_pred;
    } else {
      consecutive_lost_ = 0;
      CorrectInScanMotion(frame, reg);
      result.timings.deskew_ms += watch.LapMs();
      result.pose_covariance = PoseCovariance(reg);
      last_pose_covariance_ = result.pose_covariance;
      health_.Record(result.paired_share);
      T_new = reg.T_world_sensor;
      if (result.tracking == Tracking::kTracking) LearnGyroBias(frame, reg);
      const Eigen::Vector3d velocity_before = world_velocity_;
      const bool velocity_known = world_velocity_known_ && result.status == OdometryStatus::kOk;
      UpdateMotionModel(frame, reg, dt, result.status);
      result.accelerometer_used = frame.accel_velocity.has_value();
      if (velocity_known && result.tracking == Tracking::kTracking) {
        LearnGravity(frame, reg, velocity_before, dt);
      }
    }
  }
  InsertIntoMap(frame.scan, frame.set_aside, frame.compact, T_new, defer_map);
  if (config_.moving.enabled) {
    moving_.AddView(frame.scan.scan.points, frame.scan.labels, T_new,
                    MidScanStamp(frame.scan.scan.t_start));
    result.map_points_moved_away = RemoveMovedAway(T_new);
  }
  result.timings.map_update_ms = watch.LapMs();
  DropOldImuSamples();
  DropOldWheelSamples();
  return Finish(std::move(result), std::move(frame), T_new);
}

OdometryResult Odometry::NewResult(const ClassifiedScan& scan) {
  OdometryResult result;
  result.stamp = scan.scan.t_start;
  result.scan_index = next_index_++;
  result.class_counts = scan.class_counts;
  result.T_world_sensor = last_start_pose_;  // what a rejected scan reports
  result.velocity = velocity_;
  result.timings.projection_ms = scan.projection_ms;
  result.timings.normals_ms = scan.normals_ms;
  result.timings.classification_ms = scan.classification_ms;
  return result;
}

// Reject what cannot be registered before touching any state.
OdometryStatus Odometry::Admit(const Scan& scan) const {
  if (scan.empty()) return OdometryStatus::kEmptyScan;
  if (static_cast<int>(scan.size()) < config_.min_points) return OdometryStatus::kTooFewPoints;
  if (initialised_ && scan.t_start <= last_stamp_) return OdometryStatus::kNonIncreasingStamp;
  return OdometryStatus::kOk;
}

// The time since the last registered scan; after a longer gap than the motion model can
// bridge, the model starts over (and the status says so).
double Odometry::TimeStep(double t_start, OdometryStatus& status) {
  if (!initialised_) return sensor_.scan_period;
  const double dt = t_start - last_stamp_;
  if (dt > config_.max_time_gap) {
    velocity_before_gap_ = velocity_;
    velocity_.setZero();
    world_velocity_known_ = false;
    translation_filter_.Reset();
    motion_model_holds_ = false;
    last_scan_degenerate_ = false;
    status = OdometryStatus::kTimeGap;
  }
  return dt;
}

Odometry::Frame Odometry::Deskew(ClassifiedScan&& scan, GyroTracks gyro,
                                 std::optional<WheelTrack> wheel,
                                 std::optional<VelocityIncrement> accel, double dt) const {
  Frame frame;
  frame.gyro_scan = std::move(gyro.scan);
  frame.gyro_interval = std::move(gyro.interval);
  frame.wheel_interval = std::move(wheel);
  frame.accel_interval = std::move(accel);
  // Without a motion model that has held (start, reset, sharp acceleration) the deskew is a
  // guess; the raw scan is kept so that it can be redone with the measured motion.
  if (config_.deskew && scan.scan.has_times() && !motion_model_holds_) frame.raw = scan;
  frame.scan = std::move(scan);
  if (frame.gyro_interval && config_.deskew && frame.scan.scan.has_times()) {
    // The carrier's velocity is held in the world, not in the sensor frame: a hand swings the
    // sensor 60-90 deg between sparse scans while the walk goes on the same way.
    const Eigen::Matrix3d R_world_start =
        T_world_last_.linear() * frame.gyro_interval->At(frame.scan.scan.t_start);
    Eigen::Vector3d v_world = WorldVelocity(sensor_.scan_period);
    const std::optional<AccelerationTrack> bend = TrackAccelInScan(*frame.gyro_scan, R_world_start);
    // A bounce's velocity turns within a scan interval: along the directions gravity is trusted
    // the start's is the middle's as the accelerometer predicts it, less what the scan's first
    // half added.
    if (bend && UsesAccel(frame)) {
      const AccelChange change = VelocityChangeByAccel(frame, dt);
      const double t_mid = frame.scan.scan.t_start + 0.5 * sensor_.scan_period;
      const Eigen::Vector3d v_start =
          world_velocity_ + change.velocity - R_world_start * bend->VelocityAt(t_mid);
      v_world += change.trusted * (v_start - v_world);
      frame.start_by_accel = change.trusted;
    }
    frame.T_mid_start = DeskewWithGyro(frame.scan, velocity_, *frame.gyro_scan,
                                       R_world_start.transpose() * v_world, bend ? &*bend : nullptr);
    return frame;
  }
  frame.T_mid_start =
      DeskewToMidScan(frame.scan, velocity_, frame.gyro_scan ? &*frame.gyro_scan : nullptr);
  return frame;
}

double Odometry::MidScanStamp(double t_start) const { return t_start + 0.5 * sensor_.scan_period; }

// Judged at the predicted pose, before registration, so that what moves never pulls it: the
// prediction is centimetres off, well inside the margin of the test.
void Odometry::DetectMoving(Frame& frame, double dt) {
  if (!config_.moving.enabled) return;
  const Eigen::Isometry3d T_pred = T_world_last_ * ExpSE3(velocity_ * dt);
  frame.moving = moving_.Detect(frame.scan.scan.points, frame.scan.labels, T_pred,
                                MidScanStamp(frame.scan.scan.t_start), &map_);
}

// Map points that the newest scan saw through are gone from where they were mapped: a car
// that has left, a person's trail. Ground and roof stay (no ray sees through a floor).
std::size_t Odometry::RemoveMovedAway(const Eigen::Isometry3d& T_world_sensor) {
  const DepthView* view = moving_.newest_view();
  if (!view || ++scans_since_removal_ < static_cast<std::uint64_t>(config_.remove_moved_away_every)) {
    return 0;
  }
  scans_since_removal_ = 0;
  const Eigen::Vector3d origin = T_world_sensor.translation();
  return map_.RemovePointsIf(origin, config_.moving.max_range, [&](const MapPoint& p) {
    if (!CanMove(p.label)) return false;
    const double distance = (p.position - origin).norm();
    return distance <= config_.moving.max_range && view->SeesThrough(p.position, moving_.Margin(distance));
  });
}

RegistrationResult Odometry::RegisterFrame(Frame& frame, double dt) {
  frame.T_pred = Predict(velocity_, dt, frame);
  if (frame.gyro_interval && !frame.wheel_interval) {
    frame.T_pred.translation() = T_world_last_.translation() + dt * WorldVelocity(dt);
  }
  if (UsesAccel(frame)) PredictWithAccel(frame, dt);
  frame.T_guess = frame.T_pred;
  const MotionPrior prior = PriorFor(frame, dt, motion_model_holds_);
  RegistrationResult reg;
  // The scan (and on the first registration the map's first scan) was deskewed with a guess,
  // a constant-velocity model that has not held yet, while the wheels measured the motion: the
  // guess would hold the map back by the motion within a scan, and the wheels' prior would keep
  // the registration there (a carrier started while driving at 1.5 m/s stayed 7.6 cm behind).
  if (frame.raw && frame.wheel_interval) {
    reg = RedeskewAndRegister(frame, frame.T_pred, dt);
  } else {
    reg = RegisterSource(frame, prior);
    if (frame.raw && reg.enough_correspondences &&
        Deviation(frame.T_pred, reg.T_world_sensor) > config_.motion_model_max_deviation) {
      const std::size_t first_lookups = reg.searched_points;
      reg = RedeskewAndRegister(frame, reg.T_world_sensor, dt);
      reg.searched_points += first_lookups;  // the scan's work counts both registrations
    }
  }
  first_scan_raw_.reset();
  if (!Consecutive(dt)) frame.held_at_prediction = HoldAliasedAxis(frame, prior, reg);
  return reg;
}

// Between sparse scans, along a degenerate direction the scan hardly measures the position: a
// registration that went much farther along it than the prediction's uncertainty allows
// followed a look-alike feature a stride away (a door recess, a lamp), not the carrier. The
// prediction stands there. Not at the sensor's rate: there the registration starts within
// centimetres, and its move along a weak axis is what the recesses measured (held there, the
// hand-held corridor seed 1 drifted to 2.0 m APE from 0.017 m).
bool Odometry::HoldAliasedAxis(const Frame& frame, const MotionPrior& prior,
                               RegistrationResult& reg) const {
  const double gate = config_.degenerate_gate_sigmas;
  if (gate <= 0.0 || !reg.enough_correspondences || prior.translation_information.isZero()) {
    return false;
  }
  const Eigen::Matrix3d covariance = prior.translation_information.inverse();
  const Eigen::Vector3d step = reg.T_world_sensor.translation() - frame.T_pred.translation();
  bool held = false;
  for (Eigen::Index i = 0; i < 3; ++i) {
    if (!reg.degeneracy.degenerate[static_cast<std::size_t>(i)]) continue;
    const Eigen::Vector3d u = reg.degeneracy.eigenvectors.col(i);
    const double along = u.dot(step);
    if (std::abs(along) <= gate * std::sqrt(u.dot(covariance * u))) continue;
    reg.T_world_sensor.translation() -= along * u;
    held = true;
  }
  return held;
}

RegistrationResult Odometry::RegisterSource(const Frame& frame, const MotionPrior& prior,
                                            double gate_widening) {
  RegistrationConfig registration = config_.registration;
  // Degeneracy hysteresis: once a scan was degenerate, the next one is until the ratio
  // clears the (higher) release ratio.
  if (last_scan_degenerate_) {
    registration.degenerate_eigenvalue_ratio = registration.degenerate_release_ratio;
  }
  const double sigma = gate_widening * threshold_.Sigma();
  map_.TakeChanges(map_changes_);
  registration_.shapes.Forget(map_changes_);
  return RegisterScan(frame.source.points, frame.source.labels, map_, frame.T_guess,
                      kGateSigmas * sigma, sigma / kGateSigmas, registration, prior,
                      frame.source.times, &registration_);
}

// Registration measured how the scan's own motion departs from the velocity it was deskewed
// with: the scan is deskewed again by that departure, so that the map and the published cloud
// get the points where the registration put them.
void Odometry::CorrectInScanMotion(Frame& frame, const RegistrationResult& reg) const {
  const double period = sensor_.scan_period;
  const bool turns = !reg.scan_angular_acceleration.isZero(0.0);
  if (!reg.scan_twist.isZero(0.0)) {
    const Eigen::Isometry3d T_mid_start = ExpSE3(-0.5 * period * reg.scan_twist);
    const Eigen::Isometry3d T_start_end = ExpSE3(period * reg.scan_twist);
    if (turns) {
      DeskewAndTurn(frame.scan, T_start_end, period, T_mid_start, reg.scan_angular_acceleration,
                    reg.scan_mean_time_sq);
    } else {
      DeskewScan(frame.scan, T_start_end, period, T_mid_start);
    }
    frame.T_mid_start = T_mid_start * frame.T_mid_start;
  } else if (turns) {
    TurnByAngularAcceleration(frame.scan, reg.scan_angular_acceleration, period,
                              reg.scan_mean_time_sq);
  }
}

// Deskew again with the motion measured (by a first registration or by the wheels) and refine
// from there: a sensor that starts while moving is otherwise registered with its whole scan
// smeared.
RegistrationResult Odometry::RedeskewAndRegister(Frame& frame, const Eigen::Isometry3d& T_measured,
                                                 double dt) {
  const Vector6d measured = LogSE3(T_world_last_.inverse() * T_measured) / dt;
  // On the first registration the map is the first scan, smeared under the same guess: it is
  // rebuilt with the measured motion, or only one of the two would be corrected.
  if (first_scan_raw_) RebuildMapFromFirstScan(measured);
  frame.scan = std::move(*frame.raw);
  frame.raw.reset();
  frame.T_mid_start =
      DeskewToMidScan(frame.scan, measured, frame.gyro_scan ? &*frame.gyro_scan : nullptr);
  frame.start_by_accel.setZero();
  SelectSource(frame);
  frame.T_guess = Predict(measured, dt, frame);
  translation_filter_.Reset();  // the velocity it predicted with was wrong
  frame.accel_velocity.reset();
  return RegisterSource(frame, PriorFor(frame, dt, false));
}

// The scan start lies between the previous and this scan's middles, whose poses the data fixed;
// interpolating there uses the motion measured across the start instead of the motion one scan
// earlier. Causal: both poses are known when this scan's pose is published.
Eigen::Isometry3d Odometry::StartPose(const Frame& frame, const Eigen::Isometry3d& T_mid,
                                       bool first) const {
  const Eigen::Isometry3d extrapolated = Normalized(T_mid * frame.T_mid_start);
  // Without deskew a scan is taken as instantaneous at its start.
  const bool deskewed = config_.deskew && frame.scan.scan.has_times();
  if (!config_.interpolate_start_pose || !deskewed || first) return extrapolated;
  const double half = 0.5 * sensor_.scan_period;
  const double dt = frame.scan.scan.t_start - last_stamp_;
  // Between sparse scans the motion across the start is not the mean over the interval: the
  // scan's own (measured) motion extrapolates better.
  if (!Consecutive(dt)) return extrapolated;
  const double f = std::clamp((dt - half) / dt, 0.0, 1.0);
  Eigen::Isometry3d interpolated = T_world_last_ * ExpSE3(f * LogSE3(T_world_last_.inverse() * T_mid));
  // The gyro measured the turn from the start to the middle: a swing that accelerates within
  // the interval leaves the geodesic midpoint of the two orientations degrees off (2 deg per
  // step on 4 % of the hand-held aggressive run's steps).
  if (frame.gyro_scan) interpolated.linear() = extrapolated.linear();
  // Likewise the accelerometer measured how the start-to-middle translation departs from the
  // mean over the interval: a running bounce's 5 m/s^2 RMS put the midpoint 1.3 cm RMS off
  // vertically, every scan (handheld-aggressive seed 1).
  if (!frame.start_by_accel.isZero(0.0)) {
    interpolated.translation() +=
        frame.start_by_accel * (extrapolated.translation() - interpolated.translation());
  }
  return Normalized(interpolated);
}

double Odometry::Deviation(const Eigen::Isometry3d& T_pred, const Eigen::Isometry3d& T) {
  return (T_pred.inverse() * T).translation().norm();
}

// How the registration fitted, against the recent ones (TrackingHealth).
Tracking Odometry::JudgeFit(const Frame& frame, const RegistrationResult& reg,
                            OdometryResult& result) const {
  if (!reg.enough_correspondences) return Tracking::kLost;
  const std::size_t source = frame.source.points.size();
  result.paired_share = source == 0 ? 0.0 : double(reg.num_planar + reg.num_point) / double(source);
  result.innovation = Deviation(frame.T_pred, reg.T_world_sensor);
  result.turn_innovation_deg =
      Eigen::AngleAxisd((frame.T_pred.inverse() * reg.T_world_sensor).rotation()).angle() * 180.0 / M_PI;
  return health_.Judge({reg.converged, result.paired_share, result.innovation,
                        kGateSigmas * threshold_.Sigma()});
}

// Registration from `guess` with gates 4x, 2x, then 1x the usual, without the motion prior
// that would hold it near a wrong prediction. Adds the map look-ups to `lookups`.
RegistrationResult Odometry::WideningFrom(Frame& frame, const Eigen::Isometry3d& guess,
                                          std::size_t& lookups) {
  MotionPrior none;
  none.holds = false;
  frame.T_guess = guess;
  RegistrationResult reg;
  for (double widening : {4.0, 2.0, 1.0}) {
    reg = RegisterSource(frame, none, widening);
    lookups += reg.searched_points;
    if (!reg.enough_correspondences) break;
    frame.T_guess = reg.T_world_sensor;
  }
  frame.T_guess = frame.T_pred;
  return reg;
}

Odometry::Attempt Odometry::AttemptFrom(Frame& frame, const Eigen::Isometry3d& guess,
                                         std::size_t& lookups) {
  Attempt attempt;
  attempt.reg = WideningFrom(frame, guess, lookups);
  attempt.tracking = JudgeFit(frame, attempt.reg, attempt.judged);
  return attempt;
}

// A searched pose is never called tracking: it was not where the motion model said.
RegistrationResult Odometry::Adopt(Attempt best, std::size_t lookups, OdometryResult& result) {
  best.reg.searched_points = lookups;
  result.tracking = best.tracking == Tracking::kTracking ? Tracking::kDegraded : best.tracking;
  result.paired_share = best.judged.paired_share;
  result.innovation = best.judged.innovation;
  result.turn_innovation_deg = best.judged.turn_innovation_deg;
  return best.reg;
}

// A registration that lost its fit, or paired far fewer points than recent scans did, may have
// started outside the right basin: a fast turn (a hand-held sensor swung sideways, a U-turn
// between sparse scans) leaves the prediction tens of degrees off, a jolt leaves it far.
// Registered again from the prediction turned about the vertical by 0, +-20, +-40, +-60 and
// +-90 deg (as far as the carrier can turn in the interval), each with widening gates; the
// one that pairs the most points is taken if it is not lost and pairs more than the first
// registration, else the first registration stands (lost or degraded, as judged).
RegistrationResult Odometry::Reacquire(Frame& frame, double dt, const RegistrationResult& first,
                                       OdometryResult& result) {
  std::size_t lookups = first.searched_points;
  std::optional<Attempt> best;
  const double first_share = result.tracking == Tracking::kLost ? -1.0 : result.paired_share;
  // With the gyro the turn since the last scan is measured: only the prediction is tried.
  const double reach =
      frame.gyro_interval ? 0.0 : std::min(90.0, config_.health.max_turn_rate_deg_s * dt);
  for (double degrees : {0.0, 20.0, -20.0, 40.0, -40.0, 60.0, -60.0, 90.0, -90.0}) {
    if (std::abs(degrees) > reach + 1e-9) continue;
    Eigen::Isometry3d guess = frame.T_pred;
    guess.linear() = Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * guess.linear();
    Attempt attempt = AttemptFrom(frame, guess, lookups);
    if (attempt.tracking == Tracking::kLost) continue;
    const double best_share = best ? best->judged.paired_share : first_share;
    if (attempt.judged.paired_share > best_share) best = std::move(attempt);
  }
  if (!best) {
    RegistrationResult kept = first;
    kept.searched_points = lookups;
    return kept;
  }
  translation_filter_.Reset();  // the velocity it predicted with was wrong
  return Adopt(std::move(*best), lookups, result);
}

// After a gap (the sensor covered, a driver restarted) the carrier may have stood or driven
// on: both are tried, each from a wide gate narrowing to the usual, and the better fit is
// kept (more of the scan paired; the registration from standstill on a tie). The winner's
// start is the prediction it is judged against.
RegistrationResult Odometry::AcrossTheGap(Frame& frame, double dt, const RegistrationResult& standing,
                                          OdometryResult& result) {
  if (velocity_before_gap_.isZero()) return standing;
  const Eigen::Isometry3d T_standing = frame.T_pred;
  std::size_t lookups = standing.searched_points;
  Attempt best = AttemptFrom(frame, T_standing, lookups);
  const Eigen::Isometry3d T_driving = Predict(velocity_before_gap_, dt, frame);
  frame.T_pred = T_driving;
  Attempt driving = AttemptFrom(frame, T_driving, lookups);
  const bool drove = driving.reg.enough_correspondences &&
                     (!best.reg.enough_correspondences ||
                      driving.judged.paired_share > best.judged.paired_share);
  if (drove) best = std::move(driving);
  frame.T_pred = drove ? T_driving : T_standing;
  frame.T_guess = frame.T_pred;
  if (!best.reg.enough_correspondences) return standing;
  return Adopt(std::move(best), lookups, result);
}

bool Odometry::StartOverAfterLoss() {
  ++consecutive_lost_;
  const int limit = config_.health.restart_after_lost_scans;
  return limit > 0 && consecutive_lost_ >= limit;
}

// The map no longer overlaps what the sensor sees (it was carried away, or the scene changed
// while it was covered): started over at the prediction, with this scan, as at the first scan
// but in the same world frame.
void Odometry::Restart(Frame& frame) {
  map_ = VoxelHashMap(map_.voxel_size(), config_.map.max_distance, config_.map.max_points_per_voxel);
  registration_.shapes = ShapeCache();
  persistence_.Clear();
  moving_.Clear();
  health_.Clear();
  velocity_.setZero();
  world_velocity_known_ = false;
  translation_filter_.Reset();
  motion_model_holds_ = false;
  last_scan_degenerate_ = false;
  consecutive_lost_ = 0;
  frame.moving.clear();
  frame.set_aside.clear();
  frame.compact.clear();
}

void Odometry::Describe(const RegistrationResult& reg, OdometryResult& result) {
  result.correspondence_gate = kGateSigmas * threshold_.Sigma();
  result.covariance = reg.covariance;
  result.degeneracy = reg.degeneracy;
  result.alpha = reg.alpha;
  result.num_correspondences = reg.num_planar + reg.num_point;
  result.iterations = reg.iterations;
  result.searched_points = reg.searched_points;
  result.converged = reg.converged;
}

// Too few pairs, or a fit judged lost: nothing is learnt; the pose reported is the prediction,
// at the scan start like every other pose, and its covariance grows by what a lost scan can hide.
OdometryResult Odometry::Unregistered(OdometryResult result, const Frame& frame,
                                      OdometryStatus status) {
  result.status = status;
  result.tracking = Tracking::kLost;
  result.T_world_sensor = Normalized(frame.T_pred * frame.T_mid_start);
  last_pose_covariance_.topLeftCorner<3, 3>() += kLostTranslationVariance * Eigen::Matrix3d::Identity();
  last_pose_covariance_.bottomRightCorner<3, 3>() += kLostRotationVariance * Eigen::Matrix3d::Identity();
  result.pose_covariance = last_pose_covariance_;
  return result;
}

void Odometry::UpdateMotionModel(const Frame& frame, const RegistrationResult& reg, double dt,
                                 OdometryStatus status) {
  const Eigen::Isometry3d& T_new = reg.T_world_sensor;
  if (status != OdometryStatus::kTimeGap) {
    threshold_.UpdateModelDeviation(frame.T_pred.inverse() * T_new);
  }
  velocity_frame_ = T_world_last_.linear();
  if (UsesMotionPrior(config_.registration.mode)) {
    velocity_ = FilteredVelocity(frame.T_guess, T_new, reg, dt, frame.accel_velocity);
  } else {
    velocity_ = LogSE3(T_world_last_.inverse() * T_new) / dt;
    world_velocity_ = (T_new.translation() - T_world_last_.translation()) / dt;
  }
  world_velocity_known_ = true;
  motion_model_holds_ = Deviation(frame.T_pred, T_new) <= config_.motion_model_max_deviation;
  last_scan_degenerate_ = reg.degeneracy.AnyDegenerate();
}

void Odometry::InsertIntoMap(const ClassifiedScan& scan, const std::vector<std::uint8_t>& moving,
                             const std::vector<std::uint8_t>& compact,
                             const Eigen::Isometry3d& T_world_sensor, bool defer) {
  if (!defer) {
    UpdateMap(scan, T_world_sensor, moving, compact);
    return;
  }
  // UpdateMap leaves the moving points out when the update is applied, as it does here.
  ClassifiedScan copy;
  copy.scan.t_start = scan.scan.t_start;
  copy.scan.points = scan.scan.points;
  copy.labels = scan.labels;
  copy.normals = scan.normals;
  pending_map_update_.emplace(PendingMapUpdate{std::move(copy), T_world_sensor, moving, compact});
}

OdometryResult Odometry::Finish(OdometryResult result, Frame&& frame,
                                const Eigen::Isometry3d& T_new) {
  result.map_points = map_.NumPoints();
  result.T_world_sensor =
      StartPose(frame, T_new, result.status == OdometryStatus::kFirstScan);
  T_world_last_ = T_new;
  last_stamp_ = frame.scan.scan.t_start;
  last_start_pose_ = result.T_world_sensor;
  result.velocity = velocity_;
  // Reported in the start frame.
  TransformScan(result.T_world_sensor.inverse() * T_new, frame.scan);
  const StageTimings& t = result.timings;
  result.timings.total_ms = t.projection_ms + t.normals_ms + t.classification_ms + t.deskew_ms +
                            t.downsample_ms + t.registration_ms + t.map_update_ms;
  result.deskewed_points = std::move(frame.scan.scan.points);
  result.labels = std::move(frame.scan.labels);
  LabelMoving(frame.moving, result.labels, result.class_counts);
  result.normals = std::move(frame.scan.normals);
  result.moving = std::move(frame.moving);
  result.set_aside_points = frame.objects_set_aside;
  return result;
}

// ---- The gyroscope (issue 55) ----

void Odometry::EnableImu(const ImuDescription& imu, const GyroUseConfig& config) {
  imu_ = imu;
  gyro_config_ = config;
  gyro_bias_.emplace(imu.noise, config.bias);
  if (config_.accelerometer.enabled) gravity_.emplace(config_.accelerometer.gravity);
}

bool Odometry::AddImu(const ImuSample& sample) {
  const bool in_order = imu_samples_.empty() || sample.t > imu_samples_.back().t;
  if (!imu_ || !std::isfinite(sample.t) || !in_order) {
    ++imu_rejected_;
    return false;
  }
  imu_samples_.push_back(sample);
  return true;
}

std::optional<Eigen::Vector3d> Odometry::gyro_bias() const {
  if (!gyro_bias_) return std::nullopt;
  return gyro_bias_->bias();
}

GyroCalibration Odometry::Calibration() const {
  GyroCalibration calibration;
  calibration.R_sensor_imu = imu_->T_sensor_imu.linear();
  calibration.bias = gyro_bias_->bias();
  calibration.bias_covariance = gyro_bias_->covariance();
  calibration.noise_density = imu_->noise.gyro_noise_density;
  calibration.bias_random_walk = imu_->noise.gyro_bias_random_walk;
  return calibration;
}

// Through the scan (its deskew) and, after the first scan, from the previous scan's middle to
// this one's (its prediction). Both or neither: a scan the gyro does not wholly cover is the
// LiDAR's alone, as without an IMU.
Odometry::GyroTracks Odometry::TrackGyro(double t_start, std::optional<GyroCoverage>& why) const {
  GyroTracks tracks;
  if (!imu_) return tracks;
  const GyroCalibration calibration = Calibration();
  const std::span<const ImuSample> samples(imu_samples_);
  const double period = sensor_.scan_period;
  GyroTrack scan = IntegrateGyro(samples, t_start, t_start + period, calibration,
                                 gyro_config_.integration);
  GyroCoverage coverage = scan.coverage();
  if (coverage == GyroCoverage::kCovered && initialised_) {
    const double half = 0.5 * period;
    GyroTrack interval = IntegrateGyro(samples, last_stamp_ + half, t_start + half, calibration,
                                       gyro_config_.integration);
    coverage = interval.coverage();
    if (coverage == GyroCoverage::kCovered) tracks.interval = std::move(interval);
  }
  why = coverage;
  if (coverage == GyroCoverage::kCovered) tracks.scan = std::move(scan);
  return tracks;
}

Eigen::Vector3d Odometry::WorldVelocity(double dt) const {
  return velocity_frame_ * ExpSE3(velocity_ * dt).translation() / dt;
}

// The wheels measured the translation since the last scan's middle (and the turn, which the
// gyro measures better where there is one).
Eigen::Isometry3d Odometry::Predict(const Vector6d& velocity, double dt, const Frame& frame) const {
  Eigen::Isometry3d T = T_world_last_ * ExpSE3(velocity * dt);
  if (frame.wheel_interval) {
    T.translation() = T_world_last_ * frame.wheel_interval->motion.translation();
    if (!frame.gyro_interval) T.linear() = T_world_last_.linear() * frame.wheel_interval->motion.linear();
  }
  if (frame.gyro_interval) T.linear() = T_world_last_.linear() * frame.gyro_interval->Rotation();
  return T;
}

// The gyro's covariance (right perturbation at the scan's middle) in the world frame, plus
// what its noise model leaves out, inverted.
Eigen::Matrix3d Odometry::GyroRotationInformation(const Frame& frame) const {
  const Eigen::Matrix3d R = frame.T_pred.linear();
  const double e = gyro_config_.model_error;
  const Eigen::Matrix3d covariance = R * frame.gyro_interval->covariance() * R.transpose() +
                                     e * e * Eigen::Matrix3d::Identity();
  return covariance.ldlt().solve(Eigen::Matrix3d::Identity());
}

// The gyro measured the rotation since the last scan and within this one: its information
// replaces the constant-velocity model's on the orientation, and the scan's own turn may depart
// only a little from the gyro's deskew.
// The wheels' information replaces the constant-velocity model's on the position: a direction the
// scan does not observe then follows the measured motion, while the scan's far larger
// information keeps the directions it observes.
MotionPrior Odometry::PriorFor(const Frame& frame, double dt, bool holds) {
  MotionPrior prior =
      frame.accel_velocity
          ? Prior(dt, holds, config_.accelerometer.acceleration_sigma, frame.accel_trusted)
          : Prior(dt, holds);
  if (!UsesMotionPrior(config_.registration.mode)) return prior;
  if (frame.wheel_interval) prior.translation_information = WheelTranslationInformation(frame);
  if (!frame.gyro_interval) return prior;
  prior.rotation_information = GyroRotationInformation(frame);
  if (prior.scan_rate_sigma > 0.0) {
    prior.scan_rate_sigma = gyro_config_.in_scan_rate_sigma;
    prior.scan_angular_acceleration_sigma = gyro_config_.in_scan_angular_acceleration_sigma;
    if (!(prior.scan_angular_acceleration_sigma > 0.0)) prior.scan_spin_axis_acceleration_sigma = 0.0;
  }
  return prior;
}

// How the registered rotation departs from the gyro's prediction is what a bias error turned
// over the interval. The registration fused the gyro's prior, so its rotation lies between the
// scan's and the gyro's: learning from it is slower by the scan's share, but unbiased, since the
// departures average zero only once the bias is right. (Taking the prior's pull back out through
// the scan's marginal rotation information over-corrected: with the translation prior ignored,
// that marginal is too weak, and the x bias ran to 3x its true value on a hand-held run.)
// Standing still (the scans say so), the true rotation is zero to within standstill_sigma.
void Odometry::LearnGyroBias(const Frame& frame, const RegistrationResult& reg) {
  if (!frame.gyro_interval || !gyro_bias_) return;
  if (reg.data_information.isZero(0.0)) return;  // not the fused solve (a search, another mode)
  const double interval = frame.gyro_interval->t1() - frame.gyro_interval->t0();
  const Eigen::Matrix3d R_pred = frame.T_pred.linear();
  const Eigen::Matrix3d R_si = imu_->T_sensor_imu.linear();
  const Eigen::Isometry3d step = T_world_last_.inverse() * reg.T_world_sensor;
  const bool standing = step.translation().norm() < gyro_config_.standstill_translation &&
                        Eigen::AngleAxisd(step.linear()).angle() < gyro_config_.standstill_rotation;
  if (standing) {
    const double s = gyro_config_.standstill_sigma;
    gyro_bias_->Update(LogSO3(frame.gyro_interval->Rotation().transpose()),
                       s * s * Eigen::Matrix3d::Identity(), interval, R_si);
    return;
  }
  const Eigen::Vector3d departure = LogSO3(R_pred.transpose() * reg.T_world_sensor.linear());
  // The previous pose's rotation error enters the departure as much as this one's.
  const Eigen::Matrix3d C = R_pred.transpose() * reg.covariance.bottomRightCorner<3, 3>() * R_pred;
  const double floor = gyro_config_.min_measurement_sigma, e = gyro_config_.model_error;
  gyro_bias_->Update(departure, 2.0 * C + (floor * floor + e * e) * Eigen::Matrix3d::Identity(),
                     interval, R_si);
}

void Odometry::DropOldImuSamples() {
  if (imu_samples_.empty()) return;
  const double oldest = last_stamp_ - gyro_config_.history;
  const auto keep = std::lower_bound(imu_samples_.begin(), imu_samples_.end(), oldest,
                                     [](const ImuSample& s, double t) { return s.t < t; });
  // Erased in batches: moving the buffer once per scan would cost more than it frees.
  if (keep - imu_samples_.begin() >= 512) imu_samples_.erase(imu_samples_.begin(), keep);
}

}  // namespace dammloam
