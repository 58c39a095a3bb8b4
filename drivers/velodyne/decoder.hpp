#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/geometry/scan.hpp"
#include "drivers/diagnostics.hpp"
#include "drivers/velodyne/calibration.hpp"

namespace dammloam::drivers::velodyne {

inline constexpr std::size_t kPacketSize = 1206;

// How a VLS-128 laser's azimuth is derived from its block's azimuth.
enum class Vls128Azimuth {
  // VLS-128 user manual: a block's azimuth is the one of the sequence's first firing group; each
  // laser adds the rotation until its own group fires (up to 0.8 of a sequence's rotation).
  kFiringTime,
  // What nebula and ROS velodyne compute: only lasers 96..127 of a packet's first two sequences
  // are advanced, and angles are rounded to 0.01 deg. Up to 0.15 deg off for the other lasers at
  // 600 rpm; only for comparing with clouds those drivers made.
  kNebula,
};

struct DecoderConfig {
  Model model = Model::kVLP16;
  double rpm = 600.0;             // nominal spin rate: scan period = 60 / rpm
  double min_range = 0.3;         // metres; closer returns are dropped
  double max_range = 300.0;
  double scan_phase_deg = 0.0;    // scans are cut when the azimuth crosses this angle
  bool dual_both_returns = true;  // dual mode: keep the second return when it differs
  // The first scan of a stream is complete only if it starts this close after the phase.
  double start_tolerance_deg = 5.0;
  Vls128Azimuth vls128_azimuth = Vls128Azimuth::kFiringTime;
};

// Decodes 1206-byte data packets into scans cut at the scan phase. Only scans that began at a
// phase crossing and ended at the next one are returned; partial scans (stream start/end) are
// counted and dropped.
class Decoder {
 public:
  // Throws DriverError when the calibration does not fit the model. A calibration whose
  // distance_resolution contradicts the model's packet unit is counted as
  // "calibration_unit_ignored" (message names the file and both values) and the packet unit used.
  Decoder(DecoderConfig config, Calibration calibration);

  // Feeds one UDP payload with its capture time (s). Returns a scan when this packet closed one.
  std::optional<Scan> Push(std::span<const std::uint8_t> packet, double capture_time);
  // End of input: the scan in progress is partial; it is counted and dropped.
  void Flush();

  SensorModel sensor_model() const;
  const Diagnostics& diagnostics() const { return diag_; }

 private:
  std::optional<Scan> FinishScan();
  double PacketTime(std::uint32_t usec_past_hour, double capture_time);
  // Firing sequence of a block within its packet (0-based), which sets the block's time.
  int FiringSlot(int block, bool dual) const;
  void UpdateGapWithinPacket(const std::uint8_t* packet, int block, std::uint16_t azimuth, bool dual);
  // Rotation (0.01 deg per firing sequence) applied to a block's lasers.
  double InterpolationGap(int block, bool dual) const;
  // Horizontal angle (rad, clockwise from above) of a laser fired `offset_us` into its block.
  double LaserAzimuth(double block_azimuth, double gap, double offset_us, const Laser& cal) const;
  // VLS-128 dual-return packets hold one firing sequence: the gap comes from the previous one.
  void GapFromPreviousPacket(std::uint16_t azimuth, double packet_time);
  // True when `azimuth` wrapped past the scan phase since the previous block.
  bool CrossPhase(std::uint16_t azimuth);
  // Appends one data block's returns; `pair_first` is the first block of a dual-return pair.
  void AddBlock(const std::uint8_t* block, int slot, int bank, double gap_centideg, double packet_time,
                const std::uint8_t* pair_first);

  DecoderConfig config_;
  Calibration cal_;
  double unit_m_ = 0.002;
  Diagnostics diag_;

  Scan scan_;  // in progress; times hold absolute seconds until FinishScan
  std::vector<double> abs_times_;
  bool scan_started_at_phase_ = false;
  std::optional<int> prev_rel_;      // azimuth of the last block, relative to the phase
  double last_gap_ = 0.0;            // centidegrees between consecutive firings
  std::optional<double> last_packet_time_;
  struct DualFiring {
    std::uint16_t azimuth;
    double time;
  };
  std::optional<DualFiring> prev_dual_;  // last VLS-128 dual packet's firing, for its gap
  std::uint32_t last_usec_ = 0;
};

}  // namespace dammloam::drivers::velodyne
