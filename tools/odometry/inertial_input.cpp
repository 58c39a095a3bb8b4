#include "tools/odometry/inertial_input.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <filesystem>

#include "core/inertial/imu_horizon.hpp"
#include "core/inertial/wheel_horizon.hpp"
#include "io/bag/bag_reader.hpp"
#include "io/bag/imu_messages.hpp"
#include "io/motion_csv.hpp"
#include "io/sequence_meta.hpp"

namespace dammloam::tools {
namespace {

namespace fs = std::filesystem;

template <class Sample>
void LogStream(const fs::path& file, const std::vector<Sample>& samples, const io::StreamReadReport& report,
               const char* what) {
  if (samples.size() < 2) {
    spdlog::warn("{}: only {} usable {} samples", file.string(), samples.size(), what);
  } else {
    const double span = samples.back().t - samples.front().t;
    spdlog::info("{}: read {} {} samples, {:.1f} Hz over {:.2f} s (t {:.3f} .. {:.3f})",
                 file.string(), samples.size(), what, static_cast<double>(samples.size() - 1) / span, span,
                 samples.front().t, samples.back().t);
  }
  if (report.dropped() > 0) spdlog::warn("{}: {}", file.string(), report.Summary());
  // A gap (a stalled driver, lost packets) is no parse error but the estimator must know of it.
  if (samples.size() >= 3) {
    std::vector<double> steps;
    for (std::size_t k = 1; k < samples.size(); ++k) steps.push_back(samples[k].t - samples[k - 1].t);
    const auto largest = std::max_element(steps.begin(), steps.end());
    const double median = Median(steps);
    if (*largest > 3.0 * median) {
      const auto at = static_cast<std::size_t>(largest - steps.begin());
      spdlog::warn("{}: a gap of {:.3f} s after t {:.3f} ({:.0f} sample periods)", file.string(), *largest,
                   samples[at].t, *largest / median);
    }
  }
}

// A bag's sensor_msgs/Imu topic; the extrinsic and noise from --sensor-meta's meta.json keys.
InertialInput ReadBagInertialInput(const RunnerOptions& o) {
  InertialInput input;
  if (o.no_imu) return input;
  std::optional<io::BagImu> imu = io::ReadBagImu(o.sequence, o.imu_topic);
  if (!imu) return input;
  const std::string where = o.sequence.string() + " " + imu->topic;
  const std::optional<io::SequenceMeta> meta =
      o.sensor_meta.empty() ? std::nullopt : std::optional(io::ReadMeta(o.sensor_meta));
  if (meta) input.imu_description = io::ImuDescriptionOf(*meta);
  if (!(meta && meta->T_sensor_imu) && !o.quiet) {
    spdlog::warn("{}: no \"imu_extrinsic\" (--sensor-meta) for IMU frame '{}': assuming the Ouster "
                 "OS1's", where, imu->frame_id);
  }
  for (ImuSample& s : imu->samples) s.t -= input.imu_description.time_offset;
  if (!o.quiet) LogStream(where, imu->samples, imu->report, "IMU");
  input.imu = std::move(imu->samples);
  return input;
}

// A sequence directory's imu.csv and wheel.csv with meta.json's extrinsics.
InertialInput ReadSequenceInertialInput(const RunnerOptions& o) {
  InertialInput input;
  const fs::path dir = o.sequence;
  if (!fs::is_directory(dir) || !fs::exists(dir / "meta.json")) return input;
  const fs::path imu_csv = dir / "imu.csv", wheel_csv = dir / "wheel.csv";
  const bool want_imu = !o.no_imu && fs::exists(imu_csv);
  const bool want_wheel = !o.no_wheel && fs::exists(wheel_csv);
  if (!o.quiet && o.no_imu && fs::exists(imu_csv)) spdlog::info("{}: ignored (--no-imu)", imu_csv.string());
  if (!o.quiet && o.no_wheel && fs::exists(wheel_csv)) spdlog::info("{}: ignored (--no-wheel)", wheel_csv.string());
  if (!want_imu && !want_wheel) return input;

  const io::SequenceMeta meta = io::ReadMeta(dir / "meta.json");
  if (want_imu) {
    io::StreamReadReport report;
    std::vector<ImuSample> samples = io::ReadImuCsv(imu_csv, &report);
    const ImuDescription description = io::ImuDescriptionOf(meta);
    if (!meta.T_sensor_imu && !o.quiet) {
      spdlog::warn("{}: no \"imu_extrinsic\" in meta.json: assuming the Ouster OS1's", imu_csv.string());
    }
    for (ImuSample& s : samples) s.t -= description.time_offset;
    if (!o.quiet) LogStream(imu_csv, samples, report, "IMU");
    input.imu_description = description;
    input.imu = std::move(samples);
  }
  if (want_wheel) {
    io::StreamReadReport report;
    std::vector<WheelSample> samples = io::ReadWheelCsv(wheel_csv, &report);
    if (meta.T_sensor_base) {
      input.T_sensor_base = *meta.T_sensor_base;
    } else if (!o.quiet) {
      spdlog::warn("{}: no \"base_extrinsic\" in meta.json: assuming the base at the sensor", wheel_csv.string());
    }
    if (!o.quiet) LogStream(wheel_csv, samples, report, "wheel odometry");
    input.wheel = std::move(samples);
  }
  return input;
}

}  // namespace

ImuFeed::ImuFeed(const InertialInput& input, Odometry& odometry) : odometry_(odometry) {
  if (!input.imu || input.imu->empty()) return;
  samples_ = &*input.imu;
  odometry_.EnableImu(input.imu_description);
}

void ImuFeed::Through(double t) {
  if (!samples_) return;
  while (next_ < samples_->size() && (*samples_)[next_].t <= t + kImuLookAhead) {
    odometry_.AddImu((*samples_)[next_++]);
  }
}

void ImuFeed::Count(const OdometryResult& result) {
  ++scans_;
  if (result.gyro) ++by_coverage_[static_cast<std::size_t>(*result.gyro)];
  accelerometer_used_ += result.accelerometer_used ? 1 : 0;
}

void ImuFeed::Log() const {
  if (!samples_) {
    spdlog::info("IMU: not used (none in the input, or --no-imu): poses are the LiDAR's alone");
    return;
  }
  const std::size_t used = by_coverage_[static_cast<std::size_t>(GyroCoverage::kCovered)];
  std::string why;
  for (GyroCoverage c : {GyroCoverage::kNoSamples, GyroCoverage::kGap, GyroCoverage::kSaturated,
                         GyroCoverage::kNonFinite}) {
    const std::size_t n = by_coverage_[static_cast<std::size_t>(c)];
    if (n > 0) why += fmt::format("{}{} {}", why.empty() ? "" : ", ", n, Name(c));
  }
  const Eigen::Vector3d bias = odometry_.gyro_bias().value_or(Eigen::Vector3d::Zero()) * 180.0 / M_PI;
  spdlog::info("IMU: gyro used on {} of {} scans, {} fell back to the LiDAR alone{}{}{}; {} samples "
               "rejected (out of order); gyro bias estimate {:.4f} {:.4f} {:.4f} deg/s",
               used, scans_, scans_ - used, why.empty() ? "" : " (", why, why.empty() ? "" : ")",
               odometry_.imu_samples_rejected(), bias.x(), bias.y(), bias.z());
  if (const GravityEstimate* g = odometry_.gravity_estimate()) {
    const Eigen::Vector3d b = g->bias();
    spdlog::info("IMU: accelerometer drove the motion prior on {} of {} scans; gravity {:.3f} m/s^2, "
                 "accelerometer bias estimate {:.3f} {:.3f} {:.3f} m/s^2",
                 accelerometer_used_, scans_, g->gravity().norm(), b.x(), b.y(), b.z());
  }
}

WheelFeed::WheelFeed(const InertialInput& input, Odometry& odometry) : odometry_(odometry) {
  if (!input.wheel || input.wheel->empty()) return;
  samples_ = &*input.wheel;
  WheelUseConfig config;
  config.T_sensor_base = input.T_sensor_base;
  odometry_.EnableWheel(config);
}

void WheelFeed::Through(double t) {
  if (!samples_) return;
  while (next_ < samples_->size() && (*samples_)[next_].t <= t + kWheelLookAhead) {
    odometry_.AddWheel((*samples_)[next_++]);
  }
}

void WheelFeed::Count(const OdometryResult& result) {
  ++scans_;
  if (result.wheel) ++by_coverage_[static_cast<std::size_t>(*result.wheel)];
}

void WheelFeed::Log() const {
  if (!samples_) {
    spdlog::info("wheel odometry: not used (none in the input, or --no-wheel)");
    return;
  }
  const std::size_t used = by_coverage_[static_cast<std::size_t>(WheelCoverage::kCovered)];
  std::string why;
  for (WheelCoverage c : {WheelCoverage::kNoSamples, WheelCoverage::kGap}) {
    const std::size_t n = by_coverage_[static_cast<std::size_t>(c)];
    if (n > 0) why += fmt::format("{}{} {}", why.empty() ? "" : ", ", n, Name(c));
  }
  const WheelRejections& r = odometry_.wheel_rejections();
  const std::size_t fell = by_coverage_[static_cast<std::size_t>(WheelCoverage::kNoSamples)] +
                           by_coverage_[static_cast<std::size_t>(WheelCoverage::kGap)];
  spdlog::info("wheel odometry: used on {} of {} scans (the first has no interval), {} fell back to "
               "the LiDAR's motion model{}{}{}; samples refused: {} non-finite, {} duplicate stamp, "
               "{} out of order, {} absurd speed", used, scans_, fell,
               why.empty() ? "" : " (", why, why.empty() ? "" : ")", r.non_finite, r.duplicate,
               r.out_of_order, r.absurd);
}

InertialInput ReadInertialInput(const RunnerOptions& o) {
  return io::IsBagPath(o.sequence) ? ReadBagInertialInput(o) : ReadSequenceInertialInput(o);
}

}  // namespace dammloam::tools
