#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/geometry/scan.hpp"
#include "core/geometry/se3.hpp"
#include "core/inertial/gyro_bias_filter.hpp"
#include "core/inertial/gyro_integration.hpp"
#include "core/inertial/gyro_use_config.hpp"
#include "core/inertial/imu_sample.hpp"
#include "core/inertial/gravity_estimate.hpp"
#include "core/inertial/inertial_config.hpp"
#include "core/inertial/velocity_increment.hpp"
#include "core/inertial/wheel_integration.hpp"
#include "core/inertial/wheel_sample.hpp"
#include "core/inertial/wheel_use_config.hpp"
#include "core/map/persistence_filter.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "core/odometry/compact_objects.hpp"
#include "core/odometry/frame_downsample.hpp"
#include "core/odometry/moving_points.hpp"
#include "core/odometry/odometry_config.hpp"
#include "core/odometry/odometry_result.hpp"
#include "core/preprocess/classified_scan.hpp"
#include "core/preprocess/downsample.hpp"
#include "core/registration/adaptive_threshold.hpp"
#include "core/registration/registration.hpp"

namespace dammloam {

// The registration half of the front end: deskew, class-aware downsampling, robust
// scan-to-map registration, map update. Owns all its state (no statics): any number of
// instances can run side by side.
class Odometry {
 public:
  Odometry(const OdometryConfig& config, const SensorModel& sensor);

  // R_world_sensor expected for the next scan (constant velocity over one scan period): the
  // feature stage uses it to judge "up".
  Eigen::Matrix3d PredictedOrientation() const;
  double ThresholdReferenceRange(double median_range) const;

  OdometryResult Register(ClassifiedScan&& scan);
  // Register without the map update, so a caller can hand the pose on first (the daemon's
  // latency); CommitMap() applies it, and so does the next Register, so the map a scan is
  // registered against never differs from Register's. Returns the update's time in ms.
  OdometryResult RegisterDeferringMap(ClassifiedScan&& scan);
  double CommitMap();

  // The local map, with any deferred update applied.
  const VoxelHashMap& local_map() {
    CommitMap();
    return map_;
  }
  const Eigen::Isometry3d& last_pose() const { return T_world_last_; }

  // Issue 55: use a gyroscope mounted at imu.T_sensor_imu. Without this call, or while no
  // samples cover a scan, that scan is the LiDAR's alone, bit-identical to before.
  void EnableImu(const ImuDescription& imu, const GyroUseConfig& config = {});
  // One IMU sample, LiDAR clock, handed over before the scan it covers is registered (up to
  // the scan's end). Rejected (false, counted) without EnableImu, when not after the previous
  // sample or with a non-finite stamp; a NaN reading is kept and makes the scans it falls in
  // fall back to the LiDAR alone.
  bool AddImu(const ImuSample& sample);
  std::size_t imu_samples_rejected() const { return imu_rejected_; }
  // The gyro bias estimate (IMU frame, rad/s); empty without EnableImu.
  std::optional<Eigen::Vector3d> gyro_bias() const;
  // With the accelerometer on (config accelerometer.enabled and EnableImu): gravity and its bias
  // as learned so far; null otherwise.
  const GravityEstimate* gravity_estimate() const { return gravity_ ? &*gravity_ : nullptr; }
  // Issue 55: use wheel odometry (the base twist, base frame at config.T_sensor_base). Without
  // this call, or while no samples cover a scan interval, that scan's prediction is the
  // constant-velocity model's, bit-identical to before.
  void EnableWheel(const WheelUseConfig& config);
  // One wheel sample, LiDAR clock, handed over before the scan it covers is registered (up to
  // the scan's middle at least). Rejected (false, counted by reason) without EnableWheel, with
  // a non-finite stamp or value, a stamp not after the previous one, or an absurd speed.
  bool AddWheel(const WheelSample& sample);
  const WheelRejections& wheel_rejections() const { return wheel_rejected_; }
  // Body-frame twist [v; w] per second of the constant-velocity model.
  const Vector6d& velocity() const { return velocity_; }

 private:
  struct SourcePoints {
    std::vector<Eigen::Vector3d> points;
    std::vector<PointClass> labels;
    std::vector<float> times;  // firing time relative to mid-scan, s (empty without deskew)
  };
  // One scan on its way through RegisterAndUpdate.
  struct Frame {
    ClassifiedScan scan;                 // deskewed, in the mid-scan frame
    std::optional<ClassifiedScan> raw;   // as it came, while the motion model is unproven
    Eigen::Isometry3d T_mid_start = Eigen::Isometry3d::Identity();
    SourcePoints source;                 // the downsampled registration source
    Eigen::Isometry3d T_pred = Eigen::Isometry3d::Identity();   // constant-velocity prediction
    Eigen::Isometry3d T_guess = Eigen::Isometry3d::Identity();  // where registration started
    std::vector<std::uint8_t> moving;    // per point of scan; empty: nothing judged moving
    // Per point of scan, 1 where it is kept out of registration and map: moving, or on a compact
    // object that would hold the weak axis (CompactObjects); empty: none.
    std::vector<std::uint8_t> set_aside;
    std::size_t objects_set_aside = 0;   // points of compact objects among them
    // Per point of scan, 1 on a compact object facing the weak direction, set aside or not
    // (empty: none found); the map takes them only after compact_objects.map_after.
    std::vector<std::uint8_t> compact;
    bool held_at_prediction = false;     // along a degenerate direction (HoldAliasedAxis)
    // The gyro's rotation through the scan and from the previous scan's middle to this one's,
    // both set or neither (not covered: the scan is the LiDAR's alone).
    std::optional<GyroTrack> gyro_scan, gyro_interval;
    // Wheel odometry from the previous scan's middle to this one's (not covered: none).
    std::optional<WheelTrack> wheel_interval;
    // The accelerometer over the same interval (config_.accelerometer; not covered: none), and
    // the velocity it predicts at this scan's middle (world) once gravity is known.
    std::optional<VelocityIncrement> accel_interval;
    std::optional<Eigen::Vector3d> accel_velocity;
    // With it: the directions (world projector) along which the accelerometer was used; along
    // the others the constant-velocity model stands.
    Eigen::Matrix3d accel_trusted = Eigen::Matrix3d::Zero();
    // Directions (world projector) along which the scan was deskewed from the accelerometer's
    // velocity at its start (TrackAccelInScan): its start pose is extrapolated there.
    Eigen::Matrix3d start_by_accel = Eigen::Matrix3d::Zero();
  };
  // The gyro's tracks for a scan starting at t_start; `why` says whether they cover it.
  struct GyroTracks {
    std::optional<GyroTrack> scan, interval;
  };
  GyroTracks TrackGyro(double t_start, std::optional<GyroCoverage>& why) const;
  GyroCalibration Calibration() const;
  std::optional<WheelTrack> TrackWheel(double t_start, std::optional<WheelCoverage>& why) const;
  // The wheels' translation covariance in the world frame, inverted (the prior's information).
  Eigen::Matrix3d WheelTranslationInformation(const Frame& frame) const;
  void DropOldWheelSamples();
  // The accelerometer (odometry_accel.cpp).
  std::optional<VelocityIncrement> TrackAccel(const GyroTracks& gyro,
                                              std::optional<AccelCoverage>& why) const;
  bool UsesAccel(const Frame& frame) const;
  // The scan's own acceleration track (start frame), for the deskew; R_world_start: the scan
  // start's orientation.
  std::optional<AccelerationTrack> TrackAccelInScan(const GyroTrack& scan_track,
                                                    const Eigen::Matrix3d& R_world_start) const;
  void PredictWithAccel(Frame& frame, double dt) const;
  // The velocity change from the previous scan's middle to this one's that the accelerometer
  // measured (world), and the directions (world projector) along which gravity is known well
  // enough to use it. Needs UsesAccel(frame).
  struct AccelChange {
    Eigen::Vector3d velocity;
    Eigen::Matrix3d trusted;
  };
  AccelChange VelocityChangeByAccel(const Frame& frame, double dt) const;
  void LearnGravity(const Frame& frame, const RegistrationResult& reg,
                    const Eigen::Vector3d& velocity_before, double dt);
  // With `gyro`: its rotation through the scan, the constant velocity's translation.
  Eigen::Isometry3d DeskewToMidScan(ClassifiedScan& scan, const Vector6d& velocity,
                                    const GyroTrack* gyro = nullptr) const;
  Eigen::Isometry3d DeskewWithGyro(ClassifiedScan& scan, const Vector6d& velocity,
                                   const GyroTrack& gyro,
                                   const std::optional<Eigen::Vector3d>& v_start = {},
                                   const AccelerationTrack* bend = nullptr) const;
  // The constant-velocity model's translation per second in the world frame over dt.
  Eigen::Vector3d WorldVelocity(double dt) const;
  // The pose `velocity` predicts after dt; its rotation the gyro's where the frame has one.
  Eigen::Isometry3d Predict(const Vector6d& velocity, double dt, const Frame& frame) const;
  // Prior(dt, holds) with the gyro's information on the rotation where the frame has one.
  MotionPrior PriorFor(const Frame& frame, double dt, bool holds);
  Eigen::Matrix3d GyroRotationInformation(const Frame& frame) const;
  // The bias filter learns from how the registered rotation departs from the gyro's.
  void LearnGyroBias(const Frame& frame, const RegistrationResult& reg);
  void DropOldImuSamples();
  // The registration source: the downsampled scan without what is set aside (frame.set_aside,
  // decided here).
  void SelectSource(Frame& frame);
  void DetectMoving(Frame& frame, double dt);
  double MidScanStamp(double t_start) const;
  std::size_t RemoveMovedAway(const Eigen::Isometry3d& T_world_sensor);
  // Scans dt apart follow each other (a sparser stream, kept at 2-5 Hz, or after drops: not).
  bool Consecutive(double dt) const;
  // The constant-velocity prediction's prior over a scan interval dt.
  // measured_acceleration_sigma > 0: the velocity's change over dt was measured to within it
  // (the accelerometer), not assumed constant.
  MotionPrior Prior(double dt, bool holds, double measured_acceleration_sigma = 0.0,
                    const Eigen::Matrix3d& measured = Eigen::Matrix3d::Zero());
  void CorrectInScanMotion(Frame& frame, const RegistrationResult& reg) const;
  // Full mode: the velocity after a registration, from the translation filter.
  // `predicted_velocity` (world): the accelerometer's, else the prediction's mean velocity.
  Vector6d FilteredVelocity(const Eigen::Isometry3d& T_pred, const Eigen::Isometry3d& T_new,
                            const RegistrationResult& reg, double dt,
                            const std::optional<Eigen::Vector3d>& predicted_velocity = {});
  Matrix6d PoseCovariance(const RegistrationResult& reg);
  void RebuildMapFromFirstScan(const Vector6d& velocity);
  void Initialise(Frame& frame);
  void UpdateMap(const ClassifiedScan& scan, const Eigen::Isometry3d& T_world_sensor,
                 const std::vector<std::uint8_t>& moving = {},
                 const std::vector<std::uint8_t>& compact = {});
  // Of the map candidates, those whose place has persisted (all of them on the first scan).
  // Points on compact objects (`compact`, per point of scan; empty: none) wait longer.
  void KeepPersistent(std::vector<std::size_t>& kept, const ClassifiedScan& scan,
                      const Eigen::Isometry3d& T_world_sensor,
                      const std::vector<std::uint8_t>& compact);
  OdometryResult RegisterAndUpdate(ClassifiedScan&& scan, bool defer_map);
  // The steps of RegisterAndUpdate, in order.
  OdometryResult NewResult(const ClassifiedScan& scan);
  OdometryStatus Admit(const Scan& scan) const;
  double TimeStep(double t_start, OdometryStatus& status);
  // The frame of a scan with what the IMU and wheels measured over its interval dt.
  Frame Deskew(ClassifiedScan&& scan, GyroTracks gyro, std::optional<WheelTrack> wheel,
               std::optional<VelocityIncrement> accel, double dt) const;
  RegistrationResult RegisterFrame(Frame& frame, double dt);
  RegistrationResult RegisterSource(const Frame& frame, const MotionPrior& prior,
                                    double gate_widening = 1.0);
  bool HoldAliasedAxis(const Frame& frame, const MotionPrior& prior, RegistrationResult& reg) const;
  Tracking JudgeFit(const Frame& frame, const RegistrationResult& reg, OdometryResult& result) const;
  RegistrationResult WideningFrom(Frame& frame, const Eigen::Isometry3d& guess, std::size_t& lookups);
  // A registration tried from one guess, judged as JudgeFit judges the first one.
  struct Attempt {
    RegistrationResult reg;
    OdometryResult judged;
    Tracking tracking = Tracking::kLost;
  };
  Attempt AttemptFrom(Frame& frame, const Eigen::Isometry3d& guess, std::size_t& lookups);
  static RegistrationResult Adopt(Attempt best, std::size_t lookups, OdometryResult& result);
  RegistrationResult Reacquire(Frame& frame, double dt, const RegistrationResult& first,
                               OdometryResult& result);
  RegistrationResult AcrossTheGap(Frame& frame, double dt, const RegistrationResult& standing,
                                  OdometryResult& result);
  // Counts a lost scan; true once config_.health says the map is to be started over.
  bool StartOverAfterLoss();
  void Restart(Frame& frame);
  RegistrationResult RedeskewAndRegister(Frame& frame, const Eigen::Isometry3d& T_measured, double dt);
  Eigen::Isometry3d StartPose(const Frame& frame, const Eigen::Isometry3d& T_mid,
                              bool first) const;
  static double Deviation(const Eigen::Isometry3d& T_pred, const Eigen::Isometry3d& T);
  void Describe(const RegistrationResult& reg, OdometryResult& result);
  OdometryResult Unregistered(OdometryResult result, const Frame& frame, OdometryStatus status);
  // What one lost scan adds to the pose's covariance: a walker's metre and a turn of 18 deg
  // (1 sigma) that the odometry could not see.
  static constexpr double kLostTranslationVariance = 1.0;   // m^2
  static constexpr double kLostRotationVariance = 0.1;      // rad^2
  void UpdateMotionModel(const Frame& frame, const RegistrationResult& reg, double dt,
                         OdometryStatus status);
  void InsertIntoMap(const ClassifiedScan& scan, const std::vector<std::uint8_t>& moving,
                     const std::vector<std::uint8_t>& compact,
                     const Eigen::Isometry3d& T_world_sensor, bool defer);
  OdometryResult Finish(OdometryResult result, Frame&& frame, const Eigen::Isometry3d& T_new);

  OdometryConfig config_;
  SensorModel sensor_;
  ClassAwareDownsampler downsampler_;
  ClassVoxelSampler map_sampler_;
  // Buffers kept between scans (no allocation per scan): the source's indices, what goes into
  // the map, the map's changes for the shape cache.
  std::vector<std::size_t> source_indices_;
  struct MapInput {
    std::vector<std::size_t> indices;
    std::vector<Eigen::Vector3d> points;
    std::vector<PointClass> labels;
    std::vector<Eigen::Vector3f> normals;
  };
  MapInput map_input_;
  VoxelHashMap::Changes map_changes_;
  VoxelHashMap map_;
  // The shapes registration judged on map_ (kept while map_ keeps them) and its buffers.
  RegistrationWorkspace registration_;
  AdaptiveThreshold threshold_;
  MovingPoints moving_;
  CompactObjects compact_objects_;
  PersistenceFilter persistence_;
  std::uint64_t scans_since_removal_ = 0;
  bool initialised_ = false;
  double last_stamp_ = 0.0;
  std::uint64_t next_index_ = 0;
  Eigen::Isometry3d T_world_last_ = Eigen::Isometry3d::Identity();  // mid-scan
  Eigen::Isometry3d last_start_pose_ = Eigen::Isometry3d::Identity();  // as last reported
  Vector6d velocity_ = Vector6d::Zero();
  // The orientation of the frame velocity_ is expressed in (the pose it was measured from).
  Eigen::Matrix3d velocity_frame_ = Eigen::Matrix3d::Identity();
  // The last registration landed within config_.motion_model_max_deviation of its prediction.
  bool motion_model_holds_ = false;
  bool last_scan_degenerate_ = false;  // selects the release ratio (hysteresis)
  // Translation covariance accumulated along the directions degenerate since they were last
  // observed (world frame).
  Eigen::Matrix3d unobserved_covariance_ = Eigen::Matrix3d::Zero();
  TranslationFilter translation_filter_;
  TrackingHealth health_;
  int consecutive_lost_ = 0;
  Vector6d velocity_before_gap_ = Vector6d::Zero();  // the motion model's, when a gap reset it
  Matrix6d last_pose_covariance_ = Matrix6d::Zero();
  // The first scan before deskewing, until the first registration has measured the motion.
  std::optional<ClassifiedScan> first_scan_raw_;
  // A deferred map update: the registered scan (mid-scan frame) and its pose.
  struct PendingMapUpdate {
    ClassifiedScan scan;
    Eigen::Isometry3d T_world_sensor;
    std::vector<std::uint8_t> moving;
    std::vector<std::uint8_t> compact;
  };
  std::optional<PendingMapUpdate> pending_map_update_;
  // The gyroscope (EnableImu): its description, use, samples (LiDAR clock) and bias filter.
  std::optional<ImuDescription> imu_;
  GyroUseConfig gyro_config_;
  std::vector<ImuSample> imu_samples_;
  std::size_t imu_rejected_ = 0;
  std::optional<GyroBiasFilter> gyro_bias_;
  std::optional<GyroTrack> first_scan_gyro_;  // with first_scan_raw_
  // The accelerometer (config_.accelerometer.enabled with an IMU): gravity and bias as learned,
  // and the motion model's velocity at the last scan's middle (world frame), known once two
  // scans in a row were registered.
  std::optional<GravityEstimate> gravity_;
  Eigen::Vector3d world_velocity_ = Eigen::Vector3d::Zero();
  bool world_velocity_known_ = false;
  // Wheel odometry (EnableWheel): its use, samples (LiDAR clock) and what was refused.
  std::optional<WheelUseConfig> wheel_;
  std::vector<WheelSample> wheel_samples_;
  WheelRejections wheel_rejected_;
};

}  // namespace dammloam
