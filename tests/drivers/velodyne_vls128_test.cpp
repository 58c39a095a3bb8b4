// VLS-128 (Alpha Prime) decoding, on packets built byte by byte from the published packet format
// (the real strongest-return capture is checked in velodyne_test.cpp; there is no real dual-return
// one). Format, per the Velodyne VLS-128 user manual:
//   1206-byte payload = 12 data blocks of 100 bytes, a 4-byte timestamp (us past the hour, LE)
//   and 2 factory bytes (return mode: 0x37 strongest, 0x38 last, 0x39 dual; product id 0xA1).
//   Block = flag bytes 0xFF then 0xEE/0xDD/0xCC/0xBB (laser bank 0..3, lasers bank*32..+31),
//   azimuth (uint16 LE, 0.01 deg), 32 x {distance uint16 LE in 4 mm, reflectivity byte}.
//   Single return: 3 firing sequences per packet, each = 4 consecutive blocks (banks 0..3) with
//   the sequence's azimuth. Dual return: one sequence; blocks 2b and 2b+1 hold bank b's two
//   returns and blocks 8..11 are padding; when both returns are the same echo the second block
//   repeats the first, and such a repeat is not a second point (as for VLP-16/32C dual mode).
//   Timing: a sequence lasts 53.3 us; laser L fires in group g = L / 8 at (g + g / 8) * 2.665 us
//   (one maintenance slot after group 7); the packet timestamp is 8.7 us into the first sequence.
// The expectations below are computed from that description, not from the decoder's code.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "drivers/bytes.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"

namespace dammloam::drivers::velodyne {
namespace {

using Packet = std::vector<std::uint8_t>;

constexpr int kLasers = 128;
constexpr double kUnitM = 0.004;
constexpr double kSequenceUs = 53.3;
constexpr double kSlotUs = 2.665;
constexpr double kStampUs = 8.7;
constexpr double kPeriod = 0.1;                                  // 600 rpm
constexpr double kCentidegPerSequence = 360000.0 * kSequenceUs * 1e-6;  // 19.188 at 600 rpm
constexpr double kCapture0 = 7212.0;                             // 2 h 12 s; timestamps 12 s past the hour
constexpr std::uint32_t kUsec0 = 12'000'000;
constexpr std::uint8_t kStrongest = 0x37;
constexpr std::uint8_t kDual = 0x39;
constexpr std::uint8_t kVls128Id = 0xA1;

Calibration Vls128Calibration() {
  return LoadCalibration(std::filesystem::path(DAMMLOAM_DRIVERS_CALIBRATION_DIR) / "VLS128.yaml");
}

// Every laser gets its own range (10.000 .. 13.556 m), so a decoded point's range names its laser.
std::uint16_t RawFor(int laser) { return static_cast<std::uint16_t>(2500 + 7 * laser); }
int LaserOfRange(double range) { return static_cast<int>(std::lround((range / kUnitM - 2500.0) / 7.0)); }

double FiringUs(int laser) {
  const int group = laser / 8;
  return (group + group / 8) * kSlotUs;
}

double Deg(double rad) { return rad * 180.0 / M_PI; }
double WrapDeg(double d) { return std::remainder(d, 360.0); }  // to [-180, 180]
double AzimuthDeg(const Eigen::Vector3d& p) { return Deg(std::atan2(-p.y(), p.x())); }  // clockwise

void PutLE16(Packet& p, std::size_t at, std::uint16_t v) {
  p[at] = static_cast<std::uint8_t>(v & 0xFF);
  p[at + 1] = static_cast<std::uint8_t>(v >> 8);
}

void PutLE32(Packet& p, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

// One data block of `bank` at `azimuth`; distances are RawFor(laser) + extra.
void WriteBlock(Packet& p, int block, int bank, std::uint16_t azimuth, std::uint8_t reflectivity, int extra = 0) {
  static constexpr std::array<std::uint8_t, 4> kBankFlag = {0xEE, 0xDD, 0xCC, 0xBB};
  const std::size_t at = static_cast<std::size_t>(block) * 100;
  p[at] = 0xFF;
  p[at + 1] = kBankFlag[static_cast<std::size_t>(bank)];
  PutLE16(p, at + 2, azimuth);
  for (int k = 0; k < 32; ++k) {
    const std::size_t ch = at + 4 + static_cast<std::size_t>(k) * 3;
    PutLE16(p, ch, static_cast<std::uint16_t>(RawFor(bank * 32 + k) + extra));
    p[ch + 2] = reflectivity;
  }
}

void WriteFactory(Packet& p, std::uint32_t usec, std::uint8_t mode, std::uint8_t product) {
  PutLE32(p, 1200, usec);
  p[1204] = mode;
  p[1205] = product;
}

// Single-return packet: sequence s fills blocks 4s..4s+3; its reflectivity byte is 10 + s.
Packet SinglePacket(const std::array<std::uint16_t, 3>& azimuths, std::uint32_t usec) {
  Packet p(kPacketSize, 0);
  for (int s = 0; s < 3; ++s) {
    for (int bank = 0; bank < 4; ++bank) {
      WriteBlock(p, 4 * s + bank, bank, azimuths[static_cast<std::size_t>(s)], static_cast<std::uint8_t>(10 + s));
    }
  }
  WriteFactory(p, usec, kStrongest, kVls128Id);
  return p;
}

// Lasers whose two returns are the same echo: the sensor then repeats the first in the second.
bool SameEcho(int laser) { return laser % 3 == 0; }
constexpr int kSecondExtra = 500;  // the second return is 2 m farther (500 x 4 mm)
constexpr std::uint8_t kFirstRefl = 50;
constexpr std::uint8_t kSecondRefl = 40;

// Dual-return packet: one sequence, bank b's returns in blocks 2b, 2b+1 (the second one 2 m
// farther, or a copy of the first for SameEcho lasers), blocks 8..11 zero padding.
Packet DualPacket(std::uint16_t azimuth, std::uint32_t usec) {
  Packet p(kPacketSize, 0);
  for (int bank = 0; bank < 4; ++bank) {
    WriteBlock(p, 2 * bank, bank, azimuth, kFirstRefl);
    WriteBlock(p, 2 * bank + 1, bank, azimuth, kSecondRefl, kSecondExtra);
    for (int k = 0; k < 32; ++k) {
      if (!SameEcho(bank * 32 + k)) continue;
      const std::size_t first = static_cast<std::size_t>(2 * bank) * 100 + 4 + static_cast<std::size_t>(k) * 3;
      std::copy_n(p.begin() + static_cast<std::ptrdiff_t>(first), 3, p.begin() + static_cast<std::ptrdiff_t>(first + 100));
    }
  }
  WriteFactory(p, usec, kDual, kVls128Id);
  return p;
}

struct Stream {
  std::vector<Packet> packets;
  std::vector<double> capture;
  std::vector<double> first_unwrapped_cd;  // unwrapped azimuth of each packet's first sequence
};

// Packets of a sensor spinning at 600 rpm from `start_deg` for `revolutions` turns.
Stream Spin(double start_deg, double revolutions) {
  Stream st;
  const auto sequences = static_cast<int>(revolutions * 36000.0 / kCentidegPerSequence);
  for (int first = 0; first + 3 <= sequences; first += 3) {
    std::array<std::uint16_t, 3> az{};
    for (int s = 0; s < 3; ++s) {
      const double unwrapped = start_deg * 100.0 + (first + s) * kCentidegPerSequence;
      az[static_cast<std::size_t>(s)] = static_cast<std::uint16_t>(std::llround(unwrapped) % 36000);
    }
    const double dt = first * kSequenceUs * 1e-6;
    st.packets.push_back(SinglePacket(az, kUsec0 + static_cast<std::uint32_t>(std::llround(dt * 1e6))));
    st.capture.push_back(kCapture0 + dt + 2e-4);  // arrival a little after the firing
    st.first_unwrapped_cd.push_back(start_deg * 100.0 + first * kCentidegPerSequence);
  }
  return st;
}

// Dual-return packets (one sequence each) of a sensor spinning at 600 rpm.
Stream DualSpin(double start_deg, double revolutions) {
  Stream st;
  const auto sequences = static_cast<int>(revolutions * 36000.0 / kCentidegPerSequence);
  for (int i = 0; i < sequences; ++i) {
    const double unwrapped = start_deg * 100.0 + i * kCentidegPerSequence;
    const double dt = i * kSequenceUs * 1e-6;
    st.packets.push_back(DualPacket(static_cast<std::uint16_t>(std::llround(unwrapped) % 36000),
                                    kUsec0 + static_cast<std::uint32_t>(std::llround(dt * 1e6))));
    st.capture.push_back(kCapture0 + dt + 2e-4);
    st.first_unwrapped_cd.push_back(unwrapped);
  }
  return st;
}

struct Decoded {
  std::vector<Scan> scans;
  Diagnostics diag;
};

Decoded DecodeStream(const Stream& st, DecoderConfig config = {.model = Model::kVLS128}) {
  Decoder decoder(config, Vls128Calibration());
  Decoded out;
  for (std::size_t i = 0; i < st.packets.size(); ++i) {
    if (auto s = decoder.Push(st.packets[i], st.capture[i])) out.scans.push_back(std::move(*s));
  }
  decoder.Flush();
  out.diag = decoder.diagnostics();
  return out;
}

// Ring the format implies: rank of the laser's elevation, 0 = highest.
std::vector<int> ElevationRanks(const Calibration& cal) {
  std::vector<int> order(kLasers);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return cal.lasers[static_cast<std::size_t>(a)].vert_correction > cal.lasers[static_cast<std::size_t>(b)].vert_correction;
  });
  std::vector<int> rank(kLasers);
  for (int r = 0; r < kLasers; ++r) rank[static_cast<std::size_t>(order[static_cast<std::size_t>(r)])] = r;
  return rank;
}

// Points of the one complete revolution of `Spin(200, 1.6)`: sequences in [360, 720) deg.
std::size_t SequencesInSecondTurn(const Stream& st, int per_packet = 3) {
  std::size_t n = 0;
  for (double first : st.first_unwrapped_cd) {
    for (int s = 0; s < per_packet; ++s) {
      const long long u = std::llround(first + s * kCentidegPerSequence);
      if (u >= 36000 && u < 72000) ++n;
    }
  }
  return n;
}

// Index of the packet whose first sequence is half a turn into the complete revolution.
std::size_t MidScanPacket(const Stream& st) {
  std::size_t i = 0;
  while (st.first_unwrapped_cd[i] < 54000.0) ++i;
  return i;
}

// Every point's range is one of the ranges the packets carried and its ring is its laser's.
void ExpectUncorrupted(const Scan& scan) {
  const std::vector<int> rank = ElevationRanks(Vls128Calibration());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.points[i].norm();
    const int laser = LaserOfRange(r);
    ASSERT_TRUE(laser >= 0 && laser < kLasers) << "point " << i << " range " << r;
    ASSERT_NEAR(r, RawFor(laser) * kUnitM, 1e-6) << "point " << i;
    ASSERT_EQ(scan.rings[i], rank[static_cast<std::size_t>(laser)]) << "point " << i;
  }
}

// ---- 1. one packet: range, ring, elevation, azimuth and time of every point ------------------

// A packet starting exactly at the scan phase, closed by a second packet back at the phase.
Scan DecodeOnePacket(const std::array<std::uint16_t, 3>& az, Diagnostics* diag) {
  Decoder decoder(DecoderConfig{.model = Model::kVLS128, .scan_phase_deg = az[0] / 100.0}, Vls128Calibration());
  EXPECT_FALSE(decoder.Push(SinglePacket(az, kUsec0), kCapture0).has_value());
  auto scan = decoder.Push(SinglePacket(az, kUsec0 + 160), kCapture0 + 160e-6);
  *diag = decoder.diagnostics();
  return scan.value_or(Scan{});
}

TEST(Vls128Decoder, EveryChannelHasItsRangeRingElevationAzimuthAndTime) {
  const Calibration cal = Vls128Calibration();
  ASSERT_EQ(cal.lasers.size(), 128u);
  const std::vector<int> rank = ElevationRanks(cal);
  const std::array<std::uint16_t, 3> az = {10000, 10019, 10038};  // 19 cd per sequence ~ 600 rpm
  Diagnostics diag;
  const Scan scan = DecodeOnePacket(az, &diag);
  ASSERT_EQ(scan.size(), 3u * kLasers) << diag.Summary();
  ASSERT_TRUE(scan.has_times() && scan.has_rings());
  EXPECT_EQ(diag.Get("product_id_mismatch") + diag.Get("bad_blocks"), 0u) << diag.Summary();
  // The earliest firing is 8.7 us before the packet timestamp.
  EXPECT_NEAR(scan.t_start, kCapture0 - kStampUs * 1e-6, 1e-7);
  std::set<std::pair<int, int>> seen;  // (sequence, laser)
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d& p = scan.points[i];
    const int laser = LaserOfRange(p.norm());
    ASSERT_TRUE(laser >= 0 && laser < kLasers);
    const int seq = static_cast<int>(scan.intensities[i]) - 10;
    ASSERT_TRUE(seq >= 0 && seq < 3) << "intensity " << scan.intensities[i];
    seen.emplace(seq, laser);
    const Laser& l = cal.lasers[static_cast<std::size_t>(laser)];
    EXPECT_NEAR(p.norm(), RawFor(laser) * kUnitM, 0.01) << "laser " << laser;
    EXPECT_EQ(scan.rings[i], rank[static_cast<std::size_t>(laser)]) << "laser " << laser;
    EXPECT_NEAR(std::asin(p.z() / p.norm()), l.vert_correction, 1e-9) << "laser " << laser;
    // Azimuth: the sequence's azimuth advanced by the rotation until this laser fires (19 cd
    // per 53.3 us; the last sequence reuses the previous gap), minus the laser's azimuth offset.
    const double fired = (az[static_cast<std::size_t>(seq)] + 19.0 * FiringUs(laser) / kSequenceUs) / 100.0;
    EXPECT_NEAR(WrapDeg(AzimuthDeg(p) - (fired - Deg(l.rot_correction))), 0.0, 5e-4)
        << "laser " << laser << " sequence " << seq;
    EXPECT_NEAR(scan.times[i], (seq * kSequenceUs + FiringUs(laser)) * 1e-6, 1e-9) << "laser " << laser;
  }
  EXPECT_EQ(seen.size(), 3u * kLasers);  // each (sequence, laser) exactly once
}

// ---- 2. more than one revolution: one complete scan ------------------------------------------

// The decoder's stand-in for a time at or past the scan period.
const float kClampedTime = std::nextafter(static_cast<float>(kPeriod), 0.0f);

// Per ring, in scan order: azimuth increases, and (clamped points aside) so does time, which
// is the azimuth swept at 600 rpm (3600 deg/s) to within 5 us.
void ExpectTimeFollowsAzimuth(const Scan& scan) {
  std::vector<std::vector<std::size_t>> by_ring(kLasers);
  for (std::size_t i = 0; i < scan.size(); ++i) by_ring[static_cast<std::size_t>(scan.rings[i])].push_back(i);
  for (int ring = 0; ring < kLasers; ++ring) {
    const auto& idx = by_ring[static_cast<std::size_t>(ring)];
    double swept = 0.0;
    for (std::size_t k = 1; k < idx.size(); ++k) {
      const double step = WrapDeg(AzimuthDeg(scan.points[idx[k]]) - AzimuthDeg(scan.points[idx[k - 1]]));
      ASSERT_GT(step, 0.0) << "ring " << ring << " point " << k;
      swept += step;
      if (scan.times[idx[k]] == kClampedTime) continue;  // see MoreThanOneRevolution...
      ASSERT_GT(scan.times[idx[k]], scan.times[idx[k - 1]]) << "ring " << ring << " point " << k;
      ASSERT_NEAR(scan.times[idx[k]] - scan.times[idx[0]], swept / 3600.0, 5e-6) << "ring " << ring;
    }
    EXPECT_NEAR(swept, 360.0, 0.5) << "ring " << ring;
  }
}

TEST(Vls128Decoder, MoreThanOneRevolutionGivesExactlyOneCompleteScan) {
  const Stream st = Spin(200.0, 1.6);  // 200 deg .. wrap .. full turn .. wrap .. ~56 deg
  const Decoded d = DecodeStream(st);
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("partial_scans"), 2u);  // the head before the first wrap and the tail
  EXPECT_EQ(d.diag.Get("bad_blocks"), 0u) << d.diag.Summary();
  const Scan& scan = d.scans[0];
  // The scan is cut per firing sequence, so the sequence fired just before the phase comes back
  // ends up to 42.6 us past it: at exactly 600 rpm its last lasers can fire >= 0.1 s after the
  // scan's first point. The decoder clamps those times (and counts them) rather than move the
  // points to the next scan; at most that one sequence's 128 points are affected.
  const auto clamped = std::count(scan.times.begin(), scan.times.end(), kClampedTime);
  EXPECT_EQ(static_cast<std::uint64_t>(clamped), d.diag.Get("times_clamped"));
  EXPECT_LE(clamped, kLasers);
  EXPECT_EQ(scan.size(), SequencesInSecondTurn(st) * kLasers);
  ASSERT_TRUE(scan.has_times() && scan.has_rings());
  EXPECT_GE(*std::min_element(scan.times.begin(), scan.times.end()), 0.0f);
  EXPECT_LT(*std::max_element(scan.times.begin(), scan.times.end()), static_cast<float>(kPeriod));
  const std::set<int> rings(scan.rings.begin(), scan.rings.end());
  EXPECT_EQ(rings.size(), 128u);
  EXPECT_EQ(*rings.begin(), 0);
  EXPECT_EQ(*rings.rbegin(), 127);
  ExpectUncorrupted(scan);
  ExpectTimeFollowsAzimuth(scan);
}

// ---- 3. dual return and damaged packets --------------------------------------------------------

// A point of a dual-return scan: which laser, and whether it is the second return.
struct DualPoint {
  int laser;
  bool second;
};

// The reflectivity tells the returns apart; each must carry exactly its laser's range.
DualPoint IdentifyDual(const Scan& scan, std::size_t i) {
  const bool second = scan.intensities[i] == kSecondRefl;
  EXPECT_TRUE(second || scan.intensities[i] == kFirstRefl) << "point " << i;
  const double raw = scan.points[i].norm() / kUnitM - (second ? kSecondExtra : 0);
  const int laser = static_cast<int>(std::lround((raw - 2500.0) / 7.0));
  EXPECT_TRUE(laser >= 0 && laser < kLasers) << "point " << i;
  EXPECT_NEAR(raw, RawFor(laser), 1e-3) << "point " << i;
  return {laser, second};
}

// The first returns alone, as a scan the single-return checks apply to.
Scan FirstReturns(const Scan& scan) {
  Scan out;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.intensities[i] != kFirstRefl) continue;
    out.points.push_back(scan.points[i]);
    out.intensities.push_back(scan.intensities[i]);
    out.rings.push_back(scan.rings[i]);
    out.times.push_back(scan.times[i]);
  }
  return out;
}

int DifferingLasers() {
  int n = 0;
  for (int l = 0; l < kLasers; ++l) n += SameEcho(l) ? 0 : 1;
  return n;
}

TEST(Vls128Decoder, DualReturnStreamGivesOneCompleteScanWithBothReturns) {
  const Stream st = DualSpin(200.0, 1.6);
  const Decoded d = DecodeStream(st);
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("partial_scans"), 2u);
  EXPECT_EQ(d.diag.Get("bad_blocks"), 0u) << d.diag.Summary();  // padding blocks are not parsed
  const Scan& scan = d.scans[0];
  const std::size_t firings = SequencesInSecondTurn(st, 1);
  // Both returns where they differ, one point where the sensor repeated the first return.
  EXPECT_EQ(scan.size(), firings * static_cast<std::size_t>(kLasers + DifferingLasers()));
  ASSERT_TRUE(scan.has_times() && scan.has_rings());
  EXPECT_GE(*std::min_element(scan.times.begin(), scan.times.end()), 0.0f);
  EXPECT_LT(*std::max_element(scan.times.begin(), scan.times.end()), static_cast<float>(kPeriod));
  const std::set<int> rings(scan.rings.begin(), scan.rings.end());
  EXPECT_EQ(rings.size(), 128u);

  const std::vector<int> rank = ElevationRanks(Vls128Calibration());
  std::vector<std::size_t> firsts(kLasers, 0);
  std::vector<std::size_t> seconds(kLasers, 0);
  std::set<std::pair<int, float>> first_firings;  // (laser, time)
  std::vector<std::pair<int, float>> second_firings;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const DualPoint dp = IdentifyDual(scan, i);
    ASSERT_TRUE(dp.laser >= 0 && dp.laser < kLasers);
    EXPECT_EQ(scan.rings[i], rank[static_cast<std::size_t>(dp.laser)]) << "point " << i;
    if (dp.second) {
      ++seconds[static_cast<std::size_t>(dp.laser)];
      second_firings.emplace_back(dp.laser, scan.times[i]);
    } else {
      ++firsts[static_cast<std::size_t>(dp.laser)];
      first_firings.emplace(dp.laser, scan.times[i]);
    }
  }
  for (int l = 0; l < kLasers; ++l) {
    EXPECT_EQ(firsts[static_cast<std::size_t>(l)], firings) << "laser " << l;
    EXPECT_EQ(seconds[static_cast<std::size_t>(l)], SameEcho(l) ? 0u : firings) << "laser " << l;
  }
  // Both returns of a pulse share its firing time.
  for (const auto& f : second_firings) EXPECT_TRUE(first_firings.contains(f)) << "laser " << f.first;
  // One sequence per packet: the first returns follow the rotation like a single-return scan.
  ExpectTimeFollowsAzimuth(FirstReturns(scan));
}

// Two dual packets 19 cd apart between a lead-in packet and a closing one back at the phase.
// A dual packet holds one sequence, so the rotation during it must come from the packet before.
TEST(Vls128Decoder, DualPacketChannelsHaveTheirAzimuthAndTime) {
  const Calibration cal = Vls128Calibration();
  const std::array<std::uint16_t, 3> az = {9981, 10000, 10019};  // lead-in, then the scan's two
  Decoder decoder(DecoderConfig{.model = Model::kVLS128, .scan_phase_deg = az[1] / 100.0}, cal);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto us = static_cast<std::uint32_t>(53 * i);
    EXPECT_FALSE(decoder.Push(DualPacket(az[i], kUsec0 + us), kCapture0 + us * 1e-6).has_value());
  }
  const auto scan = decoder.Push(DualPacket(az[1], kUsec0 + 159), kCapture0 + 159e-6);
  ASSERT_TRUE(scan.has_value()) << decoder.diagnostics().Summary();
  ASSERT_EQ(scan->size(), 2u * static_cast<std::size_t>(kLasers + DifferingLasers()));
  EXPECT_NEAR(scan->t_start, kCapture0 + (53 - kStampUs) * 1e-6, 1e-7);
  for (std::size_t i = 0; i < scan->size(); ++i) {
    const DualPoint dp = IdentifyDual(*scan, i);
    ASSERT_TRUE(dp.laser >= 0 && dp.laser < kLasers);
    const Laser& l = cal.lasers[static_cast<std::size_t>(dp.laser)];
    const double t_us = scan->times[i] * 1e6;
    const int seq = t_us > 48.0 ? 1 : 0;  // packets 53 us apart; the latest laser fires at 42.64 us
    EXPECT_NEAR(t_us, seq * 53.0 + FiringUs(dp.laser), 1e-3) << "laser " << dp.laser;
    const double fired = (az[static_cast<std::size_t>(seq) + 1] + 19.0 * FiringUs(dp.laser) / kSequenceUs) / 100.0;
    EXPECT_NEAR(WrapDeg(AzimuthDeg(scan->points[i]) - (fired - Deg(l.rot_correction))), 0.0, 5e-4)
        << "laser " << dp.laser << " sequence " << seq << (dp.second ? " second" : " first");
  }
}

TEST(Vls128Decoder, DualReturnFirstOnlyWhenSecondReturnsAreOff) {
  const Stream st = DualSpin(200.0, 1.6);
  const Decoded d = DecodeStream(st, DecoderConfig{.model = Model::kVLS128, .dual_both_returns = false});
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  const Scan& scan = d.scans[0];
  EXPECT_EQ(scan.size(), SequencesInSecondTurn(st, 1) * kLasers);
  for (std::size_t i = 0; i < scan.size(); ++i) ASSERT_EQ(scan.intensities[i], kFirstRefl) << "point " << i;
  ExpectUncorrupted(scan);
}

// A dual packet among single-return ones (return mode switched) adds its one sequence.
TEST(Vls128Decoder, DualPacketInSingleReturnStreamAddsItsSequence) {
  Stream st = Spin(200.0, 1.6);
  const std::size_t clean = DecodeStream(st).scans.at(0).size();
  const std::size_t mid = MidScanPacket(st);
  st.packets[mid] = DualPacket(static_cast<std::uint16_t>(std::llround(st.first_unwrapped_cd[mid]) % 36000),
                               LoadLE<std::uint32_t>(st.packets[mid].data() + 1200));
  const Decoded d = DecodeStream(st);
  EXPECT_EQ(d.diag.Get("bad_blocks"), 0u) << d.diag.Summary();
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  EXPECT_EQ(d.scans[0].size(), clean - 3 * kLasers + kLasers + static_cast<std::size_t>(DifferingLasers()));
  for (std::size_t i = 0; i < d.scans[0].size(); ++i) {
    if (d.scans[0].intensities[i] == kFirstRefl || d.scans[0].intensities[i] == kSecondRefl) IdentifyDual(d.scans[0], i);
  }
}

// A wrong product id is diagnosed and the packet decoded as the configured model (some firmware
// reports another model's id), so a VLS-128 payload still yields the same scan.
TEST(Vls128Decoder, WrongProductIdIsCountedAndDecodedAsConfigured) {
  Stream st = Spin(200.0, 1.6);
  const Scan clean = DecodeStream(st).scans.at(0);
  st.packets[MidScanPacket(st)][1205] = 0x28;  // VLP-32C
  const Decoded d = DecodeStream(st);
  EXPECT_EQ(d.diag.Get("product_id_mismatch"), 1u) << d.diag.Summary();
  const auto& msgs = d.diag.messages();
  EXPECT_TRUE(std::any_of(msgs.begin(), msgs.end(), [](const std::string& m) {
    return m.starts_with("product_id_mismatch") && m.find("0x28") != std::string::npos;
  }));
  ASSERT_EQ(d.scans.size(), 1u);
  ASSERT_EQ(d.scans[0].size(), clean.size());
  EXPECT_EQ(d.scans[0].points, clean.points);
  EXPECT_EQ(d.scans[0].times, clean.times);
}

TEST(Vls128Decoder, TruncatedPacketAndBadBlockAreCountedAndSkipped) {
  Stream st = Spin(200.0, 1.6);
  const std::size_t clean = DecodeStream(st).scans.at(0).size();
  const std::size_t mid = MidScanPacket(st);
  st.packets[mid].resize(1000);
  st.packets[mid + 10][5 * 100 + 1] = 0xAA;  // block 5: not one of the four bank flags
  const Decoded d = DecodeStream(st);
  EXPECT_EQ(d.diag.Get("wrong_size_packets"), 1u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("bad_blocks"), 1u) << d.diag.Summary();
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  EXPECT_EQ(d.scans[0].size(), clean - 3 * kLasers - 32);
  const std::set<int> rings(d.scans[0].rings.begin(), d.scans[0].rings.end());
  EXPECT_EQ(rings.size(), 128u);
  ExpectUncorrupted(d.scans[0]);
  ExpectTimeFollowsAzimuth(d.scans[0]);
}

}  // namespace
}  // namespace dammloam::drivers::velodyne
