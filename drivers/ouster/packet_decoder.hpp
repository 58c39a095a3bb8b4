#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "drivers/diagnostics.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/metadata.hpp"

namespace dammloam::drivers::ouster {

// Byte layout of one lidar packet for a profile (header, columns, footer).
struct PacketLayout {
  std::size_t packet_header = 0;
  std::size_t column_header = 0;
  std::size_t pixel = 0;
  std::size_t column_footer = 0;
  std::size_t packet_footer = 0;
  std::size_t column = 0;  // whole column incl. header/footer
  std::size_t packet = 0;  // whole packet
};
PacketLayout LayoutFor(const Metadata& meta);

// True when a column's status word marks its data valid.
bool ColumnValid(Profile profile, std::uint64_t status);

// Turns lidar packets into frames, assembled by frame id. A frame is returned as soon as
// every column of the column window has arrived; a frame left incomplete when the next one
// starts (or at Flush) is dropped and counted, never returned. Packets are expected in frame
// order (a direct link does not reorder); a late packet of the frame just emitted is ignored.
class PacketDecoder {
 public:
  explicit PacketDecoder(Metadata meta);

  // Feeds one UDP payload. Returns a frame when this packet completed one.
  std::optional<LidarFrame> Push(std::span<const std::uint8_t> packet);
  // End of input: counts a pending incomplete frame.
  void Flush();

  const Metadata& metadata() const { return meta_; }
  const PacketLayout& layout() const { return layout_; }
  const Diagnostics& diagnostics() const { return diag_; }
  Diagnostics& diagnostics() { return diag_; }

 private:
  void StartFrame(std::uint32_t frame_id);
  void DropIncompleteFrame();
  void DecodeColumn(const std::uint8_t* col, std::uint32_t frame_id);

  Metadata meta_;
  PacketLayout layout_;
  Diagnostics diag_;
  LidarFrame frame_;
  bool frame_open_ = false;
  std::optional<std::uint32_t> last_emitted_id_;
};

}  // namespace dammloam::drivers::ouster
