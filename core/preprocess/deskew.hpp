#pragma once
#include <Eigen/Geometry>
#include <functional>

#include "core/preprocess/classified_scan.hpp"

namespace dammloam {

// Motion compensation under a constant-velocity model: a point fired at time t (seconds since
// the scan start) was measured in the sensor frame at fraction s = t / scan_period of the
// scan's motion, so it moves to the scan-start frame by ScaleMotion(T_start_end, s)
// (T_start_end: the sensor pose at scan end expressed in the scan-start frame), and from there
// to the output frame by T_out_start (identity: the points stay in the scan-start frame).
// Normals are rotated by the same rotation. Scans without per-point times are left unchanged,
// as are all scans when scan_period is not positive.
void DeskewScan(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                const Eigen::Isometry3d& T_out_start = Eigen::Isometry3d::Identity());

// Motion compensation with a motion measured per firing time (an IMU's rotation): the point
// fired at time t (seconds since the scan start) moves to the output frame by T_out_point(t),
// its normal by that rotation. T_out_point is called once per firing time, from several
// threads at once. Scans without per-point times are left unchanged.
void DeskewScanAlong(ClassifiedScan& scan,
                     const std::function<Eigen::Isometry3d(double)>& T_out_point);

// The second-order part of in-scan motion that a constant velocity leaves out: a point fired
// tau = t - scan_period / 2 seconds off mid-scan is turned about the sensor origin by
// ExpSO3(0.5 (tau^2 - mean_time_sq) angular_acceleration) (sensor frame, rad/s^2), its normal
// with it. Scans without per-point times are left unchanged.
void TurnByAngularAcceleration(ClassifiedScan& scan, const Eigen::Vector3d& angular_acceleration,
                               double scan_period, double mean_time_sq);

// DeskewScan, then TurnByAngularAcceleration, in one pass over the points: the same arithmetic
// per point (the same result to the bit), half the memory traffic.
void DeskewAndTurn(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                   const Eigen::Isometry3d& T_out_start,
                   const Eigen::Vector3d& angular_acceleration, double mean_time_sq);

}  // namespace dammloam
