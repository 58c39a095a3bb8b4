// Bad recordings: truncated files, corrupt chunks and CRCs, unknown compression, a wrong
// schema, broken metadata. Each must be an io::IoError whose message names the file, the record
// and its byte offset; none may crash (the fuzz targets in tests/fuzz push further).
#include <gtest/gtest.h>

#include <fstream>

#include "io/bag/bag_scans.hpp"
#include "io/bag/mcap_reader.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam {
namespace {

std::vector<char> ReadBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void WriteBytes(const std::filesystem::path& file, const std::vector<char>& bytes) {
  std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint64_t LoadU64(const std::vector<char>& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<std::uint8_t>(b[at + static_cast<std::size_t>(i)]);
  return v;
}

// Offset of the first top-level Chunk record (opcode 6), walking records after the magic.
std::size_t FirstChunk(const std::vector<char>& b) {
  for (std::size_t at = 8; at + 9 <= b.size(); at += 9 + LoadU64(b, at + 1)) {
    if (b[at] == 0x06) return at;
  }
  ADD_FAILURE() << "no chunk";
  return 0;
}

// Reads every scan; returns the IoError's text ("<no error>" when it reads through).
std::string ReadError(const std::filesystem::path& file) {
  try {
    io::BagScans bag(file, {"", io::RecordedCloudLimits()});
    while (bag.Next()) {
    }
  } catch (const io::IoError& e) {
    return e.what();
  }
  return "<no error>";
}

class BagErrors : public ::testing::Test {
 protected:
  void SetUp() override { test::WriteSequence(tmp_ / "seq", test::TestScans(3, 400)); }
  std::filesystem::path Mcap(const std::string& options) {
    const auto out = tmp_ / "a.mcap";
    test::RunNode("write_mcap.cjs", "{\"sequence\": \"" + (tmp_ / "seq").string() +
                                        "\", \"out\": \"" + out.string() + "\", " + options + "}");
    return out;
  }
  test::TempDir tmp_;
};

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST_F(BagErrors, TruncatedFileNamesWhereItEnds) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("compression": "zstd")");
  auto bytes = ReadBytes(file);
  for (const std::size_t keep : {bytes.size() / 2, bytes.size() - 3, std::size_t{20}, std::size_t{5}}) {
    WriteBytes(file, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(keep)));
    const std::string error = ReadError(file);
    EXPECT_HAS(error, file.string());
    EXPECT_TRUE(error.find("truncated") != std::string::npos ||
                error.find("not an MCAP file") != std::string::npos) << error;
  }
}

TEST_F(BagErrors, CorruptUncompressedChunkFailsItsCrc) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("compression": "none")");
  auto bytes = ReadBytes(file);
  const std::size_t chunk = FirstChunk(bytes);
  bytes[chunk + 9 + 40 + 600] ^= 0x40;  // inside the first message's point data
  WriteBytes(file, bytes);
  const std::string error = ReadError(file);
  EXPECT_HAS(error, file.string() + ": Chunk record at byte " + std::to_string(chunk));
  EXPECT_HAS(error, "(corrupt chunk)");
}

TEST_F(BagErrors, CorruptZstdChunkIsAnErrorNamingTheChunk) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("compression": "zstd")");
  auto bytes = ReadBytes(file);
  const std::size_t chunk = FirstChunk(bytes);
  for (std::size_t i = 0; i < 64; ++i) bytes[chunk + 9 + 44 + 30 + i] ^= 0x5a;
  WriteBytes(file, bytes);
  EXPECT_HAS(ReadError(file), file.string() + ": Chunk record at byte " + std::to_string(chunk));
}

TEST_F(BagErrors, UnknownCompressionIsNamed) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("compression": "zstd")");
  auto bytes = ReadBytes(file);
  const std::size_t chunk = FirstChunk(bytes);
  // Chunk content: start, end, uncompressed size (8 each), crc (4), compression length (4).
  ASSERT_EQ(std::string(bytes.begin() + static_cast<long>(chunk + 9 + 32), bytes.begin() + static_cast<long>(chunk + 9 + 36)), "zstd");
  bytes[chunk + 9 + 35] = 'x';
  WriteBytes(file, bytes);
  const std::string error = ReadError(file);
  EXPECT_HAS(error, "Chunk record at byte " + std::to_string(chunk));
  EXPECT_HAS(error, "unknown compression 'zstx' (supported: none, zstd, lz4)");
}

TEST_F(BagErrors, CorruptSummaryFailsItsCrc) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("compression": "zstd")");
  auto bytes = ReadBytes(file);
  const std::size_t summary = LoadU64(bytes, bytes.size() - 8 - 29 + 9);
  bytes[summary + 12] ^= 0x01;
  WriteBytes(file, bytes);
  const std::string error = ReadError(file);
  EXPECT_HAS(error, "summary CRC");
  EXPECT_HAS(error, "Footer record at byte " + std::to_string(bytes.size() - 8 - 29));
}

TEST_F(BagErrors, WrongSchemaNamesTheMessageAndMember) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = Mcap(R"("payload": "string", "chunked": false)");
  const std::string error = ReadError(file);
  EXPECT_HAS(error, file.string() + ": Message record at byte ");
  EXPECT_HAS(error, "truncated");
}

TEST_F(BagErrors, NotAnMcapFile) {
  test::WriteText(tmp_ / "x.mcap", "this is not an MCAP recording, only text long enough\n");
  EXPECT_HAS(ReadError(tmp_ / "x.mcap"), "not an MCAP file (no MCAP magic at byte 0)");
}

TEST_F(BagErrors, BrokenRosbag2Metadata) {
  std::filesystem::create_directories(tmp_ / "bag");
  test::WriteText(tmp_ / "bag" / "metadata.yaml", "rosbag2_bagfile_information:\n  version: 5\n");
  EXPECT_HAS(ReadError(tmp_ / "bag"), "metadata.yaml: missing key 'storage_identifier'");
  test::WriteText(tmp_ / "bag" / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
                  "  relative_file_paths: [bag_0.db3]\n");
  test::WriteText(tmp_ / "bag" / "bag_0.db3", "garbage, not SQLite");
  EXPECT_HAS(ReadError(tmp_ / "bag"), "bag_0.db3: ");
  test::WriteText(tmp_ / "bag" / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: leveldb\n"
                  "  relative_file_paths: [bag_0.db3]\n");
  EXPECT_HAS(ReadError(tmp_ / "bag"), "storage_identifier 'leveldb' is not supported");
}

}  // namespace
}  // namespace dammloam
