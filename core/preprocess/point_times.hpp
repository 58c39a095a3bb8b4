#pragma once
#include <cstdint>
#include <string_view>

#include "core/geometry/scan.hpp"

namespace dammloam {

// Whether a scan's per-point times can drive its deskew. Recorders and drivers that motion-
// compensate the cloud themselves often keep the time field but fill it with one value (0),
// and some write times that have nothing to do with when each point was fired. Deskewing with
// either bends a cloud that is already straight, so such a scan is registered as instantaneous.
enum class PointTimeCheck : std::uint8_t {
  kUsable = 0,
  kAbsent,            // the scan carries no per-point time
  kConstant,          // the times span less than kMinTimeSpan of the scan period (all equal)
  kNotFiringOrder,    // points of one time lie all around the sensor: not a spinning firing order
  kNotFinite,         // a time is NaN or infinite
};

constexpr std::string_view Name(PointTimeCheck c) {
  switch (c) {
    case PointTimeCheck::kUsable: return "usable";
    case PointTimeCheck::kAbsent: return "absent";
    case PointTimeCheck::kConstant: return "constant";
    case PointTimeCheck::kNotFiringOrder: return "not_firing_order";
    case PointTimeCheck::kNotFinite: return "not_finite";
  }
  return "unknown";
}

// Times spread over less than this share of the scan period carry no motion worth correcting
// (1 % of 0.1 s: 1 ms, 1 cm at 10 m/s).
constexpr double kMinTimeSpan = 0.01;

// Judges the times of `scan` (scan_period: seconds per revolution). A spinning sensor fires
// its columns in azimuth order, so the points fired within one short slice of the revolution
// all lie in one narrow sector around the sensor; times that break this are not firing times.
PointTimeCheck CheckPointTimes(const Scan& scan, double scan_period);

}  // namespace dammloam
