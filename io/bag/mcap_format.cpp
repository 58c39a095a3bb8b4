#include "io/bag/mcap_format.hpp"

#include <cstdio>

namespace dammloam::io::mcap {

std::string OpcodeName(std::uint8_t opcode) {
  static constexpr const char* kNames[] = {
      "",          "Header",     "Footer",          "Schema",     "Channel",
      "Message",   "Chunk",      "MessageIndex",    "ChunkIndex", "Attachment",
      "AttachmentIndex", "Statistics", "Metadata",  "MetadataIndex", "SummaryOffset",
      "DataEnd"};
  if (opcode >= 1 && opcode <= 0x0F) return kNames[opcode];
  char text[24];
  std::snprintf(text, sizeof(text), "opcode 0x%02x", opcode);
  return text;
}

}  // namespace dammloam::io::mcap
