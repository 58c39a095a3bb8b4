#include "drivers/velodyne/decoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "drivers/bytes.hpp"

namespace dammloam::drivers::velodyne {
namespace {

constexpr int kBlocks = 12;
constexpr std::size_t kBlockSize = 100;
constexpr double kHour = 3600.0;

struct Timing {
  double block_us;    // time between consecutive firing blocks
  double channel_us;  // offset of channel k within its block = (k / group) * channel_us
  int group;          // channels fired together
  double stamp_us = 0.0;  // how far into the first firing the packet timestamp points
};

Timing TimingOf(Model m) {
  switch (m) {
    case Model::kVLP16: return {110.592, 2.304, 1};   // 2 sequences of 16 per block (55.296 us each)
    case Model::kVLP32C: return {55.296, 2.304, 2};   // pairs fire together
    case Model::kHDL32E: return {46.08, 1.152, 1};
    // VLS-128 user manual, firing timing table: a 53.3 us sequence fires 16 groups of 8 lasers
    // 2.665 us apart, with one maintenance slot after group 7 (see Vls128FiringUs), and the
    // packet timestamp ("top of the hour") is aligned 8.7 us into the first sequence.
    case Model::kVLS128: return {53.3, 2.665, 8, 8.7};
  }
  return {55.296, 2.304, 1};
}

std::uint8_t ProductId(Model m) {
  switch (m) {
    case Model::kVLP16: return 0x22;
    case Model::kVLP32C: return 0x28;
    case Model::kHDL32E: return 0x21;
    case Model::kVLS128: return 0xA1;
  }
  return 0;
}

std::string Hex(std::uint8_t v) {
  static constexpr char kDigits[] = "0123456789abcdef";
  return std::string("0x") + kDigits[v >> 4] + kDigits[v & 15];
}

// Firing time of a VLS-128 laser within its sequence. Lasers 64..127 (groups 8..15) fire one
// 2.665 us slot later than a plain group * 2.665 us because of the maintenance slot between
// groups 7 and 8 (VLS-128 user manual timing table; also how ROS velodyne and nebula time them).
double Vls128FiringUs(int laser, const Timing& t) {
  const int group = laser / t.group;
  return (group + group / 8) * t.channel_us;
}

// Laser bank (0..3) a block's flag names, or -1 when the flag is invalid for the model: the
// VLS-128 flags its four banks of 32 lasers, the other models use 0xFFEE on every block.
int BankOf(Model m, std::uint16_t flag) {
  if (m != Model::kVLS128) return flag == 0xEEFF ? 0 : -1;
  switch (flag) {
    case 0xEEFF: return 0;
    case 0xDDFF: return 1;
    case 0xCCFF: return 2;
    case 0xBBFF: return 3;
    default: return -1;
  }
}

// Metres per distance count, fixed by each model's packet format (user manuals).
double PacketUnit(Model m) { return (m == Model::kVLP32C || m == Model::kVLS128) ? 0.004 : 0.002; }

std::string Metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g m", v);
  return buf;
}

constexpr double kRadPerCentideg = M_PI / 18000.0;

}  // namespace

Decoder::Decoder(DecoderConfig config, Calibration calibration)
    : config_(config), cal_(std::move(calibration)) {
  const int n = LaserCount(config_.model);
  if (static_cast<int>(cal_.lasers.size()) != n) {
    throw DriverError("calibration has " + std::to_string(cal_.lasers.size()) + " lasers but model " +
                      std::string(Name(config_.model)) + " has " + std::to_string(n));
  }
  if (config_.rpm < 60.0 || config_.rpm > 1500.0) throw DriverError("rpm must be within [60, 1500]");
  unit_m_ = PacketUnit(config_.model);
  const double stated = cal_.distance_resolution;
  if (stated > 0.0 && std::abs(stated - unit_m_) > 1e-9) {
    diag_.Count("calibration_unit_ignored",
                cal_.source + " says distance_resolution " + Metres(stated) + ", but " +
                    std::string(Name(config_.model)) + " packets count distance in " + Metres(unit_m_) +
                    "; using " + Metres(unit_m_));
  }
}

SensorModel Decoder::sensor_model() const {
  SensorModel m;
  m.rings = LaserCount(config_.model);
  m.scan_period = 60.0 / config_.rpm;
  // Columns = firings per revolution, e.g. VLP-16 at 600 rpm fires every 55.296 us -> ~1808.
  const Timing t = TimingOf(config_.model);
  const double firing_us = config_.model == Model::kVLP16 ? t.block_us / 2.0 : t.block_us;
  m.columns = static_cast<int>(std::lround(m.scan_period * 1e6 / firing_us));
  std::vector<double> angles(static_cast<std::size_t>(m.rings));
  for (const Laser& l : cal_.lasers) angles[static_cast<std::size_t>(l.ring)] = l.vert_correction * 180.0 / M_PI;
  m.vertical_angles_deg = angles;
  m.min_range = config_.min_range;
  m.max_range = std::min(config_.max_range, 200.0);
  return m;
}

double Decoder::PacketTime(std::uint32_t usec, double capture_time) {
  double t = 0.0;
  if (!last_packet_time_) {
    // Anchor the "microseconds past the hour" to the hour nearest the capture time.
    const double hour_start = std::floor(capture_time / kHour) * kHour;
    t = hour_start + usec * 1e-6;
    if (t - capture_time > kHour / 2) t -= kHour;
    if (capture_time - t > kHour / 2) t += kHour;
  } else {
    // Continue from the previous packet so the hour rollover is seamless.
    double dt = (static_cast<double>(usec) - static_cast<double>(last_usec_)) * 1e-6;
    if (dt < -kHour / 2) dt += kHour;
    if (dt > kHour / 2) dt -= kHour;
    t = *last_packet_time_ + dt;
  }
  last_packet_time_ = t;
  last_usec_ = usec;
  return t;
}

std::optional<Scan> Decoder::Push(std::span<const std::uint8_t> packet, double capture_time) {
  diag_.Count("packets");
  if (packet.size() != kPacketSize) {
    diag_.Count("wrong_size_packets", "packet of " + std::to_string(packet.size()) +
                                          " bytes, a Velodyne data packet has 1206; ignored");
    return std::nullopt;
  }
  const std::uint8_t* p = packet.data();
  const std::uint8_t return_mode = p[1204];
  const std::uint8_t product = p[1205];
  if (product != ProductId(config_.model)) {
    diag_.Count("product_id_mismatch",
                "packet product id " + Hex(product) + " is not the one of the configured model " +
                    std::string(Name(config_.model)) + " (" + Hex(ProductId(config_.model)) +
                    "); decoding as configured");
  }
  const bool dual = return_mode == 0x39;
  const bool vls = config_.model == Model::kVLS128;
  const double packet_time = PacketTime(LoadLE<std::uint32_t>(p + 1200), capture_time);
  if (dual && vls) GapFromPreviousPacket(LoadLE<std::uint16_t>(p + 2), packet_time);

  std::optional<Scan> done;
  // VLS-128 dual: one firing sequence in blocks 0..7; blocks 8..11 are padding, never parsed.
  const int blocks = (dual && vls) ? 8 : kBlocks;
  for (int b = 0; b < blocks; ++b) {
    const std::uint8_t* block = p + static_cast<std::size_t>(b) * kBlockSize;
    const int bank = BankOf(config_.model, LoadLE<std::uint16_t>(block));
    const std::uint16_t az = LoadLE<std::uint16_t>(block + 2);
    if (bank < 0 || az >= 36000) {
      diag_.Count("bad_blocks", "data block with a bad flag or azimuth >= 360 deg; skipped");
      continue;
    }
    UpdateGapWithinPacket(p, b, az, dual);
    if (CrossPhase(az)) {
      if (auto s = FinishScan()) done = std::move(s);  // at most one crossing per packet
      scan_started_at_phase_ = true;                   // the scan this crossing opens
    }
    const bool second = dual && (b % 2 == 1);  // dual: blocks come in pairs with the same azimuth
    AddBlock(block, FiringSlot(b, dual), bank, InterpolationGap(b, dual), packet_time,
             second ? block - kBlockSize : nullptr);
  }
  return done;
}

int Decoder::FiringSlot(int block, bool dual) const {
  // Dual pairs share one firing; VLS-128 uses 4 banks per firing, and its dual packet holds a
  // single firing sequence, so all its blocks fire at the packet's first sequence time.
  if (config_.model == Model::kVLS128) return dual ? 0 : block / 4;
  return dual ? block / 2 : block;
}

void Decoder::UpdateGapWithinPacket(const std::uint8_t* p, int b, std::uint16_t az, bool dual) {
  // Gap to the next firing's azimuth, for interpolating each channel's own angle. A VLS-128
  // dual packet has no next firing (see GapFromPreviousPacket).
  if (config_.model == Model::kVLS128 && dual) return;
  const int next = b + (config_.model == Model::kVLS128 ? 4 : (dual ? 2 : 1));
  if (next >= kBlocks) return;
  const double gap = (LoadLE<std::uint16_t>(p + static_cast<std::size_t>(next) * kBlockSize + 2) + 36000 - az) % 36000;
  if (gap > 0 && gap < 300) last_gap_ = gap;  // ignore jumps (sector edges, lost packets)
}

double Decoder::InterpolationGap(int block, bool dual) const {
  if (config_.model != Model::kVLS128 || config_.vls128_azimuth == Vls128Azimuth::kFiringTime) return last_gap_;
  // nebula takes the gap to the next block, which is the next sequence only for a sequence's
  // last block, and none for the packet's last block; in dual packets the next pair of blocks
  // is the same sequence (blocks 6, 7 look at padding there: not reproduced).
  return (!dual && block % 4 == 3 && block < 8) ? last_gap_ : 0.0;
}

double Decoder::LaserAzimuth(double block_azimuth, double gap, double offset_us, const Laser& cal) const {
  // The gap spans one firing period (block or sequence); the laser adds its share of it.
  const double swept = gap * std::min(1.0, offset_us / TimingOf(config_.model).block_us);
  if (config_.model == Model::kVLS128 && config_.vls128_azimuth == Vls128Azimuth::kNebula) {
    const double cd = std::round(block_azimuth + swept - cal.rot_correction / kRadPerCentideg);
    return std::fmod(cd + 36000.0, 36000.0) * kRadPerCentideg;
  }
  return (block_azimuth + swept) * kRadPerCentideg - cal.rot_correction;
}

void Decoder::GapFromPreviousPacket(std::uint16_t az, double packet_time) {
  // The rotation per firing is the azimuth advance since the previous packet divided by the
  // sequences elapsed, so a lost packet does not double it. Beyond 100 sequences the advance
  // could have wrapped past a full turn, so the old gap is kept.
  if (prev_dual_ && az < 36000) {
    const double sequences = std::round((packet_time - prev_dual_->time) * 1e6 / TimingOf(config_.model).block_us);
    if (sequences >= 1 && sequences <= 100) {
      const double gap = ((az + 36000 - prev_dual_->azimuth) % 36000) / sequences;
      if (gap > 0 && gap < 300) last_gap_ = gap;
    }
  }
  prev_dual_.reset();
  if (az < 36000) prev_dual_ = DualFiring{az, packet_time};
}

bool Decoder::CrossPhase(std::uint16_t az) {
  const int rel = (az - static_cast<int>(std::lround(config_.scan_phase_deg * 100.0)) % 36000 + 72000) % 36000;
  const bool crossed = prev_rel_ && rel < *prev_rel_;
  // The stream's first scan counts as complete only when it starts just after the phase.
  if (!prev_rel_) scan_started_at_phase_ = rel <= config_.start_tolerance_deg * 100.0;
  prev_rel_ = rel;
  return crossed;
}

void Decoder::AddBlock(const std::uint8_t* block, int slot, int bank, double gap, double packet_time,
                       const std::uint8_t* pair_first) {
  const Timing timing = TimingOf(config_.model);
  const double az_block = LoadLE<std::uint16_t>(block + 2);
  for (int k = 0; k < 32; ++k) {
    const std::uint8_t* ch = block + 4 + static_cast<std::size_t>(k) * 3;
    const std::uint16_t raw = LoadLE<std::uint16_t>(ch);
    if (raw == 0) continue;
    if (pair_first != nullptr) {  // second return of a dual pair
      if (!config_.dual_both_returns) continue;
      if (LoadLE<std::uint16_t>(pair_first + 4 + static_cast<std::size_t>(k) * 3) == raw) continue;  // same echo
    }

    int laser = k;
    double offset_us = 0.0;  // firing time within the block
    if (config_.model == Model::kVLP16) {
      laser = k % 16;
      offset_us = (k / 16) * 55.296 + laser * timing.channel_us;
    } else if (config_.model == Model::kVLS128) {
      laser = bank * 32 + k;
      offset_us = Vls128FiringUs(laser, timing);
    } else {
      offset_us = (k / timing.group) * timing.channel_us;
    }
    const double t = packet_time + (slot * timing.block_us + offset_us - timing.stamp_us) * 1e-6;

    const Laser& cal = cal_.lasers[static_cast<std::size_t>(laser)];
    const double distance = raw * unit_m_ + cal.dist_correction;
    if (distance < config_.min_range || distance > config_.max_range) {
      diag_.Count("out_of_range_returns");
      continue;
    }
    const double a = LaserAzimuth(az_block, gap, offset_us, cal);
    const double cos_v = std::cos(cal.vert_correction);
    const double sin_v = std::sin(cal.vert_correction);
    const double xy = distance * cos_v - cal.vert_offset_correction * sin_v;
    const double h = cal.horiz_offset_correction;
    // Velodyne azimuth grows clockwise seen from above; x forward, y left, z up.
    scan_.points.emplace_back(xy * std::cos(a) + h * std::sin(a), -xy * std::sin(a) + h * std::cos(a),
                              distance * sin_v + cal.vert_offset_correction * cos_v);
    scan_.intensities.push_back(static_cast<float>(ch[2]));
    scan_.rings.push_back(static_cast<std::int16_t>(cal.ring));
    abs_times_.push_back(t);
  }
}

std::optional<Scan> Decoder::FinishScan() {
  std::optional<Scan> out;
  const bool complete = scan_started_at_phase_;
  if (!scan_.points.empty()) {
    if (!complete) {
      diag_.Count("partial_scans", "scan that did not start at the scan phase (stream start) dropped");
    } else {
      const double period = 60.0 / config_.rpm;
      const double t0 = *std::min_element(abs_times_.begin(), abs_times_.end());
      const double t1 = *std::max_element(abs_times_.begin(), abs_times_.end());
      if (t1 - t0 >= 1.5 * period) {
        diag_.Count("scans_too_long", "scan spans " + std::to_string(t1 - t0) + " s, more than 1.5 scan periods "
                                      "(wrong --rpm or lost packets); dropped");
      } else {
        Scan s = std::move(scan_);
        s.t_start = t0;
        s.times.resize(abs_times_.size());
        const float max_t = std::nextafter(static_cast<float>(period), 0.0f);
        for (std::size_t i = 0; i < abs_times_.size(); ++i) {
          float t = static_cast<float>(abs_times_[i] - t0);
          if (t > max_t) {
            diag_.Count("times_clamped", "point time beyond the nominal scan period clamped (spin slower than --rpm)");
            t = max_t;
          }
          s.times[i] = t;
        }
        diag_.Count("scans");
        out = std::move(s);
      }
    }
  }
  scan_ = Scan{};
  abs_times_.clear();
  return out;
}

void Decoder::Flush() {
  if (!scan_.points.empty()) {
    diag_.Count("partial_scans", "scan still open at the end of the input (no closing phase crossing) dropped");
  }
  scan_ = Scan{};
  abs_times_.clear();
  prev_rel_.reset();
  prev_dual_.reset();
}

}  // namespace dammloam::drivers::velodyne
