#include "tools/simulate/motion.hpp"
#include "tools/simulate/angles.hpp"
#include "tools/simulate/random_stream.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace dammloam::sim {

namespace {

constexpr double kLimitDs = 0.01;      // metres of path per speed-limit sample
constexpr double kGaitSpeed = 0.6;     // m/s at which the gait motions reach full strength
constexpr double kGaitLag = 0.3;       // s, low-pass of the gait strength (keeps it C1)
constexpr double kDriftSmoothing = 1.0;  // s, each of the two low-passes on the speed drift
constexpr double kArriveTolerance = 0.01;  // m short of the path end counts as arrived

// The carrier's own SplitMix64 stream, seeded from a different constant than the range noise:
// the motion stream never shares numbers with the noise stream of the same seed.
using Rng = SplitMix64;

// 0 at x <= 0, 1 at x >= 1, raised cosine in between (continuous slope 0 at both ends).
double RaisedCosine(double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  return 0.5 * (1.0 - std::cos(kPi * x));
}

}  // namespace

std::vector<std::string> MotionNames() { return {"constant", "handheld", "legged", "wheeled", "vehicle"}; }

std::optional<MotionKind> ParseMotionKind(std::string_view name) {
  if (name == "constant") return MotionKind::Constant;
  if (name == "handheld") return MotionKind::Handheld;
  if (name == "legged") return MotionKind::Legged;
  if (name == "wheeled") return MotionKind::Wheeled;
  if (name == "vehicle") return MotionKind::Vehicle;
  return std::nullopt;
}

std::string_view MotionName(MotionKind kind) {
  switch (kind) {
    case MotionKind::Constant: return "constant";
    case MotionKind::Handheld: return "handheld";
    case MotionKind::Legged: return "legged";
    case MotionKind::Wheeled: return "wheeled";
    case MotionKind::Vehicle: return "vehicle";
  }
  return "unknown";
}

CarrierParams ToParams(const HandheldProfile& p) {
  CarrierParams c;
  c.speed_min = p.speed_min;
  c.speed_max = p.speed_max;
  c.speed_time_constant = p.speed_time_constant;
  c.gait_hz_min = p.gait_hz_min;
  c.gait_hz_max = p.gait_hz_max;
  c.gait_speed_modulation = p.gait_speed_modulation;
  c.accel = p.accel;
  c.lateral_accel = p.lateral_accel;
  c.stops_per_minute = p.stops_per_minute;
  c.stop_min = p.stop_min;
  c.stop_max = p.stop_max;
  c.bob = p.bob;
  c.lateral_sway = p.lateral_sway;
  c.yaw_sway_deg = p.yaw_sway_deg;
  c.gait_pitch_deg = p.gait_pitch_deg;
  c.gait_roll_deg = p.gait_roll_deg;
  c.tilt_deg = p.tilt_deg;
  c.shake_deg = p.shake_deg;
  c.shake_hz_min = p.shake_hz_min;
  c.shake_hz_max = p.shake_hz_max;
  c.vibration = p.vibration;
  c.sensor_height = p.sensor_height;
  c.look_arounds_per_minute = p.look_arounds_per_minute;
  c.look_around_deg_min = p.look_around_deg_min;
  c.look_around_deg_max = p.look_around_deg_max;
  c.look_around_rate_deg_s = p.look_around_rate_deg_s;
  c.drops = p.drops;
  c.drop_height_min = p.drop_height_min;
  c.drop_height_max = p.drop_height_max;
  c.drop_catch_accel = p.drop_catch_accel;
  c.drop_recover = p.drop_recover;
  return c;
}

CarrierParams ToParams(const LeggedProfile& p) {
  CarrierParams c;
  c.speed_min = p.speed_min;
  c.speed_max = p.speed_max;
  c.speed_time_constant = p.speed_time_constant;
  c.gait_hz_min = p.gait_hz_min;
  c.gait_hz_max = p.gait_hz_max;
  c.gait_speed_modulation = p.gait_speed_modulation;
  c.sharp_gait = true;
  c.accel = p.accel;
  c.lateral_accel = p.lateral_accel;
  c.stops_per_minute = p.stops_per_minute;
  c.stop_min = p.stop_min;
  c.stop_max = p.stop_max;
  c.bob = p.bob;
  c.lateral_sway = p.lateral_sway;
  c.yaw_sway_deg = p.yaw_sway_deg;
  c.gait_pitch_deg = p.gait_pitch_deg;
  c.gait_roll_deg = p.gait_roll_deg;
  c.tilt_deg = p.tilt_deg;
  c.shake_deg = p.shake_deg;
  c.shake_hz_min = p.shake_hz_min;
  c.shake_hz_max = p.shake_hz_max;
  c.shake_needs_motion = true;
  c.vibration = p.vibration;
  c.sensor_height = p.sensor_height;
  return c;
}

// Wheeled robots and vehicles drive piecewise target speeds with stops and a vibration.
template <class Profile>
CarrierParams PiecewiseSpeedParams(const Profile& p) {
  CarrierParams c;
  c.speed_min = p.speed_min;
  c.speed_max = p.speed_max;
  c.speed_time_constant = 0.0;  // piecewise target speeds
  c.hold_min = p.hold_min;
  c.hold_max = p.hold_max;
  c.accel = p.accel;
  c.lateral_accel = p.lateral_accel;
  c.stops_min = p.stops_min;
  c.stops_max = p.stops_max;
  c.stop_min = p.stop_min;
  c.stop_max = p.stop_max;
  c.shake_deg = p.vibration_deg;
  c.shake_hz_min = p.vibration_hz_min;
  c.shake_hz_max = p.vibration_hz_max;
  c.shake_needs_motion = true;
  c.vibration = p.vibration;
  c.sensor_height = p.sensor_height;
  return c;
}

CarrierParams ToParams(const WheeledProfile& p) { return PiecewiseSpeedParams(p); }

CarrierParams ToParams(const VehicleProfile& p) {
  CarrierParams c = PiecewiseSpeedParams(p);
  c.pitch_per_accel_deg = p.pitch_per_accel_deg;
  c.roll_per_lateral_accel_deg = p.roll_per_lateral_accel_deg;
  c.suspension_time_constant = p.suspension_time_constant;
  return c;
}

double CarrierMotion::Wave::operator()(double t) const { return amplitude * std::sin(omega * t + phase); }

CarrierMotion::CarrierMotion(const CarrierParams& params, const Path& path, bool closed,
                             double duration, double arrive_time, std::uint64_t seed,
                             const std::vector<SpeedZone>& slow_zones)
    : params_(params), path_length_(path.length()), closed_(closed) {
  Rng rng{seed ^ 0x6D6F74696F6E5EEDull};
  rng.Next();
  duration = std::max(duration, 1.0);
  const double horizon = duration + std::max(10.0, 0.5 * duration);
  const std::size_t n = static_cast<std::size_t>(std::ceil(horizon / kDt)) + 2;
  const double v_mid = 0.5 * (params_.speed_min + params_.speed_max);
  const double v_half = 0.5 * (params_.speed_max - params_.speed_min);
  const double accel = std::max(params_.accel, 0.05);

  // Gait.
  if (params_.gait_hz_max > 0.0) gait_hz_ = rng.Range(params_.gait_hz_min, params_.gait_hz_max);
  gait_phase_ = rng.Range(0.0, 2.0 * kPi);

  // Base speed: a smoothed random walk (two low-passes over an Ornstein-Uhlenbeck process,
  // squashed into [min, max]) or piecewise-constant targets joined by raised-cosine changes.
  base_.resize(n);
  if (params_.speed_time_constant > 0.0) {
    const double tau = params_.speed_time_constant;
    double x = rng.Gaussian(), f1 = x, f2 = x;
    const double kick = std::sqrt(2.0 * kDt / tau);
    for (std::size_t k = 0; k < n; ++k) {
      base_[k] = v_mid + v_half * std::tanh(1.2 * f2);
      x += -x / tau * kDt + kick * rng.Gaussian();
      f1 += (x - f1) * kDt / kDriftSmoothing;
      f2 += (f1 - f2) * kDt / kDriftSmoothing;
    }
  } else {
    double from = rng.Range(params_.speed_min, params_.speed_max), to = from;
    double change_at = 0.0, change_len = 0.0;  // the first change is scheduled at t = 0
    for (std::size_t k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) * kDt;
      if (t >= change_at + change_len) {
        from = to;
        to = rng.Range(params_.speed_min, params_.speed_max);
        change_at = change_at + change_len + rng.Range(params_.hold_min, params_.hold_max);
        // Raised cosine: peak acceleration pi/2 * dv / T.
        change_len = std::max(1.0, 0.5 * kPi * std::abs(to - from) / accel);
        // Until the next change starts, hold `from`.
      }
      base_[k] = t < change_at ? from : from + (to - from) * RaisedCosine((t - change_at) / change_len);
    }
  }

  // Start ramp and stops, as a multiplicative envelope on the speed.
  const double v_peak = params_.speed_max * (1.0 + params_.gait_speed_modulation);
  const double ramp = 0.5 * kPi * v_peak / accel;
  int stops = 0;
  if (params_.stops_per_minute > 0.0) {
    stops = std::max(1, static_cast<int>(std::lround(params_.stops_per_minute * duration / 60.0)));
  } else if (params_.stops_max > 0) {
    stops = params_.stops_min +
            static_cast<int>(rng.Uniform() * (params_.stops_max - params_.stops_min + 1));
  }
  std::vector<double> stop_at, stop_len;
  const double lo = std::max(0.1 * duration, 2.0 * ramp), hi = 0.9 * duration - 2.0 * ramp;
  for (int i = 0; i < stops && hi > lo; ++i) {
    for (int attempt = 0; attempt < 100; ++attempt) {
      const double t = rng.Range(lo, hi);
      const bool clear = std::none_of(stop_at.begin(), stop_at.end(), [&](double other) {
        return std::abs(other - t) < 2.0 * ramp + params_.stop_max + 5.0;
      });
      if (!clear) continue;
      stop_at.push_back(t);
      stop_len.push_back(rng.Range(params_.stop_min, params_.stop_max));
      break;
    }
  }
  envelope_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * kDt;
    double e = RaisedCosine(t / ramp);
    for (std::size_t i = 0; i < stop_at.size(); ++i) {
      const double a = stop_at[i], b = a + ramp + stop_len[i];  // stopped during [a + ramp, b]
      if (t > a && t < b + ramp) e *= t < b ? 1.0 - RaisedCosine((t - a) / ramp) : RaisedCosine((t - b) / ramp);
    }
    envelope_[k] = e;
  }

  // Speed limit along the path: curves (lateral acceleration) and, on an open path, the end,
  // each approached and left at the carrier's acceleration.
  const std::size_t m = static_cast<std::size_t>(std::ceil(path_length_ / kLimitDs)) + 1;
  limit_.assign(std::max<std::size_t>(m, 2), 1e9);
  for (std::size_t i = 0; i < limit_.size(); ++i) {
    const double kappa = std::abs(path.Curvature(std::min(static_cast<double>(i) * kLimitDs, path_length_)));
    if (kappa > 1e-9) limit_[i] = std::sqrt(params_.lateral_accel / kappa);
  }
  ApplySlowZones(slow_zones);
  if (!closed_) {  // stop exactly at the end: v^2 = 2 a (L - s)
    for (std::size_t i = 0; i < limit_.size(); ++i) {
      const double left = std::max(path_length_ - static_cast<double>(i) * kLimitDs, 0.0);
      limit_[i] = std::min(limit_[i], std::sqrt(2.0 * accel * left));
    }
  }
  const double step = 2.0 * accel * kLimitDs;
  for (std::size_t i = 1; i < limit_.size(); ++i) limit_[i] = std::min(limit_[i], std::sqrt(limit_[i - 1] * limit_[i - 1] + step));
  for (std::size_t i = limit_.size() - 1; i-- > 0;) limit_[i] = std::min(limit_[i], std::sqrt(limit_[i + 1] * limit_[i + 1] + step));

  // Fit the walk to its planned arrival: the distance is monotone in the scale, so bisect.
  if (arrive_time > 0.0 && !closed_) {
    constexpr double kLo = 0.8, kHi = 1.25;
    if (Integrate(kHi, nullptr, nullptr) >= arrive_time) {
      scale_ = kHi;
    } else if (Integrate(kLo, nullptr, nullptr) <= arrive_time) {
      scale_ = kLo;
    } else {
      double a = kLo, b = kHi;
      for (int i = 0; i < 24; ++i) {
        const double mid = 0.5 * (a + b);
        (Integrate(mid, nullptr, nullptr) > arrive_time ? a : b) = mid;
      }
      scale_ = 0.5 * (a + b);
    }
  }
  Integrate(scale_, &s_, &v_);

  // Gait strength: follows the speed through a low-pass, so it (and its slope) is continuous.
  g_.resize(n);
  dg_.resize(n);
  double g = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double target = std::min(1.0, v_[k] / kGaitSpeed);
    g_[k] = g;
    dg_[k] = (target - g) / kGaitLag;
    g += dg_[k] * kDt;
  }
  ComputeSuspension(path);

  // Body motion: phases and frequencies drawn once per seed.
  bob_phase_ = rng.Range(0.0, 2.0 * kPi);
  sway_phase_ = rng.Range(0.0, 2.0 * kPi);
  yaw_phase_ = rng.Range(0.0, 2.0 * kPi);
  pitch_phase_ = rng.Range(0.0, 2.0 * kPi);
  roll_phase_ = rng.Range(0.0, 2.0 * kPi);
  auto waves = [&](int count, double rms, double hz_lo, double hz_hi) {
    std::vector<Wave> w;
    if (rms <= 0.0) return w;
    for (int i = 0; i < count; ++i) {
      w.push_back({rms * std::sqrt(2.0 / count), 2.0 * kPi * rng.Range(hz_lo, hz_hi), rng.Range(0.0, 2.0 * kPi)});
    }
    return w;
  };
  auto slow = [&](double amplitude) {
    std::vector<Wave> w;
    if (amplitude <= 0.0) return w;
    w.push_back({0.7 * amplitude, 2.0 * kPi * rng.Range(0.1, 0.2), rng.Range(0.0, 2.0 * kPi)});
    w.push_back({0.4 * amplitude, 2.0 * kPi * rng.Range(0.25, 0.45), rng.Range(0.0, 2.0 * kPi)});
    return w;
  };
  tilt_roll_ = slow(params_.tilt_deg * kDegToRad);
  tilt_pitch_ = slow(params_.tilt_deg * kDegToRad);
  const double shake = params_.shake_deg * kDegToRad;
  shake_roll_ = waves(3, shake, params_.shake_hz_min, params_.shake_hz_max);
  shake_pitch_ = waves(3, shake, params_.shake_hz_min, params_.shake_hz_max);
  shake_yaw_ = waves(3, shake, params_.shake_hz_min, params_.shake_hz_max);
  vib_z_ = waves(3, params_.vibration, params_.shake_hz_min, params_.shake_hz_max);
  vib_y_ = waves(3, params_.vibration, params_.shake_hz_min, params_.shake_hz_max);
  // Drawn last, so that every other motion of a seed stays what it was without them.
  const int looks = static_cast<int>(std::lround(params_.look_arounds_per_minute * duration / 60.0));
  double next = 3.0;  // after the start ramp
  for (int i = 0; i < looks && next < duration - 3.0; ++i) {
    const double degrees = rng.Range(params_.look_around_deg_min, params_.look_around_deg_max);
    const double sign = rng.Uniform() < 0.5 ? -1.0 : 1.0;
    // The raised cosine's peak rate is amplitude * pi / length.
    const double length = degrees * kPi / params_.look_around_rate_deg_s;
    const double gap = rng.Range(0.5, 2.0) * 60.0 / params_.look_arounds_per_minute;
    look_arounds_.push_back({next, length, sign * degrees * kDegToRad});
    next += length + gap;
  }
  // Drawn after the look-arounds, and only when there are drops: no other seed changes.
  for (int i = 0; i < params_.drops && duration > 10.0; ++i) {
    const double start = rng.Range(0.3, 0.7) * duration;
    drops_.push_back({start, rng.Range(params_.drop_height_min, params_.drop_height_max)});
  }
}

// Free fall (z = -g t^2 / 2) through the drop height, a constant deceleration to rest, then a
// raised-cosine lift back: the offset and its rate are continuous, the acceleration steps.
double CarrierMotion::DropOffset(double t) const {
  constexpr double kG = 9.81;
  double z = 0.0;
  for (const Drop& drop : drops_) {
    double u = t - drop.start;
    if (u <= 0.0) continue;
    const double fall = std::sqrt(2.0 * drop.height / kG), v_fall = kG * fall;
    const double catch_accel = std::max(params_.drop_catch_accel, 1.0);
    const double catch_time = v_fall / catch_accel;
    const double lowest = -drop.height - 0.5 * v_fall * v_fall / catch_accel;
    if (u < fall) {
      z += -0.5 * kG * u * u;
      continue;
    }
    u -= fall;
    if (u < catch_time) {
      z += -drop.height - v_fall * u + 0.5 * catch_accel * u * u;
      continue;
    }
    u -= catch_time;
    z += lowest * (1.0 - RaisedCosine(u / std::max(params_.drop_recover, 0.1)));
  }
  return z;
}

void CarrierMotion::ApplySlowZones(const std::vector<SpeedZone>& zones) {
  for (const SpeedZone& zone : zones) {
    const auto first = static_cast<std::size_t>(std::max(zone.s_begin, 0.0) / kLimitDs);
    const auto last = static_cast<std::size_t>(std::max(zone.s_end, 0.0) / kLimitDs);
    for (std::size_t i = first; i <= last && i < limit_.size(); ++i) {
      limit_[i] = std::min(limit_[i], zone.max_speed);
    }
  }
}

// The body's pitch and roll on its springs: proportional to the longitudinal and the lateral
// acceleration, each through two low-passes, so the angles and their rates stay continuous
// where the path's curvature or the speed profile changes abruptly.
void CarrierMotion::ComputeSuspension(const Path& path) {
  if (params_.pitch_per_accel_deg <= 0.0 && params_.roll_per_lateral_accel_deg <= 0.0) return;
  const std::size_t n = v_.size();
  const double pitch_gain = params_.pitch_per_accel_deg * kDegToRad;
  const double roll_gain = params_.roll_per_lateral_accel_deg * kDegToRad;
  const double a = kDt / std::max(params_.suspension_time_constant, kDt);
  suspension_pitch_.assign(n, 0.0);
  suspension_roll_.assign(n, 0.0);
  double p1 = 0.0, p2 = 0.0, r1 = 0.0, r2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t prev = k > 0 ? k - 1 : 0, next = std::min(k + 1, n - 1);
    const double dt = static_cast<double>(next - prev) * kDt;
    const double along = dt > 0.0 ? (v_[next] - v_[prev]) / dt : 0.0;
    double s = s_[k];
    if (closed_ && path_length_ > 0.0) s = std::fmod(s, path_length_);
    const double lateral = v_[k] * v_[k] * path.Curvature(s);
    // Nose down (positive pitch) when braking; outwards (left side up in a left turn).
    p1 += (-pitch_gain * along - p1) * a;
    p2 += (p1 - p2) * a;
    r1 += (roll_gain * lateral - r1) * a;
    r2 += (r1 - r2) * a;
    suspension_pitch_[k] = p2;
    suspension_roll_[k] = r2;
  }
}

double CarrierMotion::Suspension(const std::vector<double>& table, double t) const {
  if (table.empty()) return 0.0;
  const double x = std::max(t, 0.0) / kDt;
  const std::size_t k = static_cast<std::size_t>(x);
  if (k + 1 >= table.size()) return table.back();
  const double u = x - static_cast<double>(k);
  return table[k] + u * (table[k + 1] - table[k]);
}

double CarrierMotion::SpeedLimit(double s) const {
  if (closed_ && path_length_ > 0.0) {
    s = std::fmod(s, path_length_);
    if (s < 0.0) s += path_length_;
  }
  if (!closed_ && s >= path_length_) return 0.0;
  const double x = std::max(s, 0.0) / kLimitDs;
  const std::size_t i = static_cast<std::size_t>(x);
  if (i + 1 >= limit_.size()) return limit_.back();
  const double u = x - static_cast<double>(i);
  return limit_[i] + u * (limit_[i + 1] - limit_[i]);
}

// Heun steps of ds/dt = envelope(t) * min(scale * base(t), limit(s)) * (1 + m sin(gait)).
// Returns the time the end of an open path is reached (infinity if never).
double CarrierMotion::Integrate(double scale, std::vector<double>* s_out, std::vector<double>* v_out) const {
  const std::size_t n = base_.size();
  const double omega = 2.0 * kPi * gait_hz_, m = params_.gait_speed_modulation;
  auto speed = [&](std::size_t k, double s) {
    const double t = static_cast<double>(k) * kDt;
    const double gait = gait_hz_ > 0.0 ? 1.0 + m * std::sin(omega * t + gait_phase_) : 1.0;
    return envelope_[k] * std::min(scale * base_[k], SpeedLimit(s)) * gait;
  };
  if (s_out) s_out->resize(n);
  if (v_out) v_out->resize(n);
  const bool track = !closed_ && !s_out;
  const double end = path_length_ - kArriveTolerance;
  double s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double v = speed(k, s);
    if (s_out) (*s_out)[k] = s;
    if (v_out) (*v_out)[k] = v;
    if (track && s >= end) return static_cast<double>(k) * kDt;
    if (k + 1 == n) break;
    const double predicted = speed(k + 1, s + kDt * v);
    s += 0.5 * kDt * (v + predicted);
    if (!closed_) s = std::min(s, path_length_);
  }
  return std::numeric_limits<double>::infinity();
}

CarrierMotion::Sample CarrierMotion::Eval(double t) const {
  if (!(t > 0.0)) return {0.0, v_.front(), g_.front()};
  const double x = t / kDt;
  const std::size_t k = static_cast<std::size_t>(x);
  if (k + 1 >= s_.size()) {
    const double extra = t - static_cast<double>(s_.size() - 1) * kDt;
    double s = s_.back() + v_.back() * extra;
    if (!closed_) s = std::min(s, path_length_);
    return {s, v_.back(), g_.back()};
  }
  // Cubic Hermite on [k, k+1] with the stored slopes: value and slope continuous at the nodes.
  const double u = x - static_cast<double>(k), u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  const double d00 = (6 * u2 - 6 * u) / kDt, d10 = 3 * u2 - 4 * u + 1, d01 = -d00, d11 = 3 * u2 - 2 * u;
  Sample out;
  out.s = h00 * s_[k] + h10 * kDt * v_[k] + h01 * s_[k + 1] + h11 * kDt * v_[k + 1];
  out.speed = d00 * s_[k] + d10 * v_[k] + d01 * s_[k + 1] + d11 * v_[k + 1];
  out.gait = h00 * g_[k] + h10 * kDt * dg_[k] + h01 * g_[k + 1] + h11 * kDt * dg_[k + 1];
  return out;
}

CarrierMotion::Body CarrierMotion::BodyAt(double t, double gait) const {
  auto sum = [t](const std::vector<Wave>& waves) {
    double v = 0.0;
    for (const Wave& w : waves) v += w(t);
    return v;
  };
  Body b;
  const double moving = params_.shake_needs_motion ? gait : 1.0;
  b.roll = sum(tilt_roll_) + moving * sum(shake_roll_);
  b.pitch = sum(tilt_pitch_) + moving * sum(shake_pitch_);
  b.yaw = moving * sum(shake_yaw_);
  for (const LookAround& look : look_arounds_) {
    const double u = (t - look.start) / look.length;
    if (u > 0.0 && u < 1.0) b.yaw += 0.5 * look.amplitude * (1.0 - std::cos(2.0 * kPi * u));
  }
  b.pitch += Suspension(suspension_pitch_, t);
  b.roll += Suspension(suspension_roll_, t);
  b.vertical = gait * sum(vib_z_);
  if (!drops_.empty()) b.vertical += DropOffset(t);
  b.lateral = gait * sum(vib_y_);
  if (gait_hz_ > 0.0 && gait > 0.0) {
    const double phase = 2.0 * kPi * gait_hz_ * t + gait_phase_;
    b.vertical += gait * params_.bob * std::sin(phase + bob_phase_);
    b.lateral += gait * params_.lateral_sway * std::sin(0.5 * phase + sway_phase_);
    b.yaw += gait * params_.yaw_sway_deg * kDegToRad * std::sin(0.5 * phase + yaw_phase_);
    // A trot pitches and rolls at the trot frequency with sharp peaks; a walker rolls from foot
    // to foot at half the step frequency.
    auto shape = [&](double x) {
      return params_.sharp_gait ? (std::sin(x) + 0.35 * std::sin(2.0 * x)) / 1.2 : std::sin(x);
    };
    b.pitch += gait * params_.gait_pitch_deg * kDegToRad * shape(phase + pitch_phase_);
    const double roll_phase = params_.sharp_gait ? phase : 0.5 * phase;
    b.roll += gait * params_.gait_roll_deg * kDegToRad * shape(roll_phase + roll_phase_);
  }
  return b;
}

}  // namespace dammloam::sim
