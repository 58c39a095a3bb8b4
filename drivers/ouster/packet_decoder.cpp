#include "drivers/ouster/packet_decoder.hpp"

#include <string>
#include <utility>

#include "drivers/bytes.hpp"

namespace dammloam::drivers::ouster {
namespace {

bool IsFusa(Profile p) { return p == Profile::kFusaRng15Rfl8Nir8Dual; }

// RNG15 profiles carry range in units of 8 mm and near-IR in units of 16.
std::uint32_t Range15(const std::uint8_t* px) { return std::uint32_t{LoadLE<std::uint16_t>(px) & 0x7FFFu} << 3; }
std::uint32_t Range19(const std::uint8_t* px) { return LoadLE<std::uint32_t>(px) & 0x7FFFFu; }

}  // namespace

PacketLayout LayoutFor(const Metadata& meta) {
  PacketLayout l;
  const bool legacy = meta.profile == Profile::kLegacy;
  l.packet_header = legacy ? 0 : 32;
  l.packet_footer = legacy ? 0 : 32;
  l.column_header = legacy ? 16 : 12;
  l.column_footer = legacy ? 4 : 0;
  switch (meta.profile) {
    case Profile::kLegacy: l.pixel = 12; break;
    case Profile::kRng19Rfl8Sig16Nir16: l.pixel = 12; break;
    case Profile::kRng19Rfl8Sig16Nir16Dual: l.pixel = 16; break;
    case Profile::kRng15Rfl8Nir8: l.pixel = 4; break;
    case Profile::kFusaRng15Rfl8Nir8Dual: l.pixel = 8; break;
  }
  l.column = l.column_header + static_cast<std::size_t>(meta.pixels_per_column) * l.pixel + l.column_footer;
  l.packet = l.packet_header + static_cast<std::size_t>(meta.columns_per_packet) * l.column + l.packet_footer;
  return l;
}

bool ColumnValid(Profile profile, std::uint64_t status) {
  if (profile == Profile::kLegacy) return status == 0xFFFFFFFFu;
  return (status & 0x1u) != 0;
}

PacketDecoder::PacketDecoder(Metadata meta) : meta_(std::move(meta)), layout_(LayoutFor(meta_)) {}

void PacketDecoder::StartFrame(std::uint32_t frame_id) {
  frame_.Reset(meta_.pixels_per_column, meta_.columns_per_frame);
  frame_.frame_id = frame_id;
  frame_open_ = true;
}

void PacketDecoder::DropIncompleteFrame() {
  if (!frame_open_) return;
  diag_.Count("partial_frames", "frame " + std::to_string(frame_.frame_id) + " ended with " +
                                    std::to_string(frame_.columns_received) + " of " +
                                    std::to_string(meta_.columns_in_window()) + " columns; dropped");
  frame_open_ = false;
}

void PacketDecoder::Flush() { DropIncompleteFrame(); }

std::optional<LidarFrame> PacketDecoder::Push(std::span<const std::uint8_t> packet) {
  diag_.Count("packets");
  if (packet.size() != layout_.packet) {
    diag_.Count(packet.size() < layout_.packet ? "short_packets" : "wrong_size_packets",
                "lidar packet of " + std::to_string(packet.size()) + " bytes, expected " +
                    std::to_string(layout_.packet) + " for profile " + std::string(Name(meta_.profile)) +
                    " with " + std::to_string(meta_.pixels_per_column) + " beams; ignored");
    return std::nullopt;
  }
  const std::uint8_t* p = packet.data();
  std::uint32_t frame_id = 0;
  if (meta_.profile == Profile::kLegacy) {
    frame_id = LoadLE<std::uint16_t>(p + 10);  // in the first column's header
  } else if (IsFusa(meta_.profile)) {
    frame_id = LoadLE<std::uint32_t>(p + 4);
  } else {
    frame_id = LoadLE<std::uint16_t>(p + 2);
  }

  // A straggler of the frame just emitted must not cut the next frame short.
  if (last_emitted_id_ && *last_emitted_id_ == frame_id) {
    diag_.Count("late_packets", "packet for frame " + std::to_string(frame_id) + " after it was complete; ignored");
    return std::nullopt;
  }
  if (frame_open_ && frame_.frame_id != frame_id) DropIncompleteFrame();
  if (!frame_open_) StartFrame(frame_id);

  for (int c = 0; c < meta_.columns_per_packet; ++c) {
    DecodeColumn(p + layout_.packet_header + static_cast<std::size_t>(c) * layout_.column, frame_id);
  }
  if (frame_.columns_received < meta_.columns_in_window()) return std::nullopt;

  frame_.complete = true;
  frame_open_ = false;
  last_emitted_id_ = frame_id;
  diag_.Count("frames");
  return std::move(frame_);
}

void PacketDecoder::DecodeColumn(const std::uint8_t* col, std::uint32_t frame_id) {
  const std::uint64_t ts = LoadLE<std::uint64_t>(col);
  const std::uint16_t mid = LoadLE<std::uint16_t>(col + 8);
  if (meta_.profile == Profile::kLegacy && LoadLE<std::uint16_t>(col + 10) != frame_id) {
    diag_.Count("mixed_frame_columns", "LEGACY packet whose columns disagree on the frame id; column ignored");
    return;
  }
  if (mid >= meta_.columns_per_frame) {
    diag_.Count("bad_measurement_ids", "measurement id " + std::to_string(mid) + " >= columns_per_frame");
    return;
  }
  const int W = meta_.columns_per_frame;
  if (frame_.column_received[mid] != 0) {
    diag_.Count("duplicate_columns", "column " + std::to_string(mid) + " received twice in frame " +
                                         std::to_string(frame_id) + "; kept the first");
    return;
  }
  std::uint64_t status = 0;
  if (meta_.profile == Profile::kLegacy) {
    status = LoadLE<std::uint32_t>(col + layout_.column - 4);
    frame_.encoder_count[mid] = LoadLE<std::uint32_t>(col + 12);
  } else {
    status = LoadLE<std::uint16_t>(col + 10);
  }
  frame_.column_received[mid] = 1;
  if (meta_.column_in_window(mid)) ++frame_.columns_received;
  frame_.timestamp[mid] = ts;
  frame_.measurement_id[mid] = mid;
  frame_.status[mid] = status;
  if (!ColumnValid(meta_.profile, status)) {
    diag_.Count("invalid_columns", "column with status not valid; its pixels are left empty");
    return;
  }

  const std::uint8_t* px = col + layout_.column_header;
  for (int h = 0; h < meta_.pixels_per_column; ++h, px += layout_.pixel) {
    const std::size_t i = static_cast<std::size_t>(h) * static_cast<std::size_t>(W) + mid;
    switch (meta_.profile) {
      case Profile::kLegacy:
        frame_.range[i] = LoadLE<std::uint32_t>(px) & 0xFFFFFu;
        frame_.reflectivity[i] = px[4];
        frame_.signal[i] = LoadLE<std::uint16_t>(px + 6);
        frame_.near_ir[i] = LoadLE<std::uint16_t>(px + 8);
        break;
      case Profile::kRng19Rfl8Sig16Nir16:
        frame_.range[i] = Range19(px);
        frame_.reflectivity[i] = px[4];
        frame_.signal[i] = LoadLE<std::uint16_t>(px + 6);
        frame_.near_ir[i] = LoadLE<std::uint16_t>(px + 8);
        break;
      case Profile::kRng19Rfl8Sig16Nir16Dual:
        frame_.range[i] = Range19(px);
        frame_.reflectivity[i] = px[3];
        frame_.range2[i] = Range19(px + 4);
        frame_.reflectivity2[i] = px[7];
        frame_.signal[i] = LoadLE<std::uint16_t>(px + 8);
        frame_.signal2[i] = LoadLE<std::uint16_t>(px + 10);
        frame_.near_ir[i] = LoadLE<std::uint16_t>(px + 12);
        break;
      case Profile::kRng15Rfl8Nir8:
        frame_.range[i] = Range15(px);
        frame_.reflectivity[i] = px[2];
        frame_.near_ir[i] = static_cast<std::uint16_t>(px[3] << 4);
        break;
      case Profile::kFusaRng15Rfl8Nir8Dual:
        frame_.range[i] = Range15(px);
        frame_.reflectivity[i] = px[2];
        frame_.near_ir[i] = static_cast<std::uint16_t>(px[3] << 4);
        frame_.range2[i] = Range15(px + 4);
        frame_.reflectivity2[i] = px[6];
        break;
    }
  }
}

}  // namespace dammloam::drivers::ouster
