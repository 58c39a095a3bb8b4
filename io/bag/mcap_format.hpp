#pragma once
// MCAP container constants (https://mcap.dev/spec): every record is opcode (uint8), content
// length (uint64 little-endian), content. The file starts and ends with the magic.
#include <cstdint>
#include <string>

namespace dammloam::io::mcap {

inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr std::size_t kRecordPrefix = 9;   // opcode + length
inline constexpr std::size_t kFooterContent = 20;  // summary_start, summary_offset_start, crc

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// "Chunk" for 0x06, "opcode 0x42" for anything unknown: for error messages.
std::string OpcodeName(std::uint8_t opcode);

}  // namespace dammloam::io::mcap
