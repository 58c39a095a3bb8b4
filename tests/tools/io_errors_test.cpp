// Every kind of broken input gives an IoError whose message names the file and the problem.
#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <limits>

#include "tests/tools/test_support.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "io/sequence_io.hpp"

namespace dammloam::io {
namespace {

using test::IoErrorOf;
using test::TempDir;
using test::WriteText;

constexpr const char* kMeta =
    R"({"sensor": "test", "rings": 4, "columns": 8, "scan_period": 0.1, "min_range": 0.3,
        "max_range": 100.0, "point_layout": "xyzitr"})";

ReadOptions StrictOptions() {
  ReadOptions options;
  options.strict = true;
  return options;
}

void WriteFloats(const std::filesystem::path& file, const std::vector<float>& values) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
}

// A valid 3-scan sequence of 2 points each; tests then break one thing.
class BrokenSequence : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir() / "scans");
    WriteText(dir() / "meta.json", kMeta);
    WriteText(dir() / "times.txt", "0.0\n0.1\n0.2\n");
    for (int i = 0; i < 3; ++i) WriteScan(i, {1, 2, 3, 10, 0.0f, 0, 4, 5, 6, 20, 0.05f, 3});
  }
  void WriteScan(int index, const std::vector<float>& values) {
    WriteFloats(dir() / "scans" / ScanFileName(static_cast<std::size_t>(index)), values);
  }
  const std::filesystem::path& dir() const { return tmp_.path(); }
  Scan ReadFirst(const ReadOptions& options = {}) const {
    return SequenceReader::Open(dir(), options).ReadScan(0);
  }

 private:
  TempDir tmp_;
};

TEST_F(BrokenSequence, ValidBaselineReads) {
  const Scan scan = ReadFirst();
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_EQ(scan.rings[1], 3);
  EXPECT_FLOAT_EQ(scan.times[1], 0.05f);
}

TEST_F(BrokenSequence, MissingDirectory) {
  EXPECT_IO_ERROR(SequenceReader::Open(dir() / "nowhere"), "nowhere", "does not exist");
}

TEST_F(BrokenSequence, MissingMetaJson) {
  std::filesystem::remove(dir() / "meta.json");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "missing");
}

TEST_F(BrokenSequence, MissingTimesTxt) {
  std::filesystem::remove(dir() / "times.txt");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt", "missing");
}

TEST_F(BrokenSequence, MissingScansDirectory) {
  std::filesystem::remove_all(dir() / "scans");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "scans", "missing scans directory");
}

TEST_F(BrokenSequence, GapInScanFiles) {
  std::filesystem::remove(dir() / "scans/000001.bin");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "000001.bin", "missing scan file");
}

TEST_F(BrokenSequence, ScanFileRemovedAfterOpen) {
  const SequenceReader reader = SequenceReader::Open(dir());
  std::filesystem::remove(dir() / "scans/000002.bin");
  EXPECT_IO_ERROR(reader.ReadScan(2), "000002.bin", "missing scan file");
}

TEST_F(BrokenSequence, ScanCountDiffersFromTimesCount) {
  WriteText(dir() / "times.txt", "0.0\n0.1\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt", "has 2 times", "3 scan files");
  WriteScan(3, {});
  WriteText(dir() / "times.txt", "0.0\n0.1\n0.2\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt", "has 3 times", "4 scan files");
}

TEST_F(BrokenSequence, FileSizeNotMultipleOfPointSize) {
  WriteScan(1, {1, 2, 3, 10, 0.0f, 0, 4, 5});
  const SequenceReader reader = SequenceReader::Open(dir());
  EXPECT_IO_ERROR(reader.ReadScan(1), "000001.bin", "size 32 bytes", "24-byte point record");
}

TEST_F(BrokenSequence, NonIncreasingTimes) {
  WriteText(dir() / "times.txt", "0.0\n0.2\n0.2\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt:3", "not greater than the previous");
  WriteText(dir() / "times.txt", "0.3\n0.2\n0.4\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt:2", "strictly increasing");
}

TEST_F(BrokenSequence, NonNumericTimes) {
  WriteText(dir() / "times.txt", "0.0\n0.1x\n0.2\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt:2", "'0.1x' is not a time");
  WriteText(dir() / "times.txt", "0.0\nnan\n0.2\n");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "times.txt:2", "is not a time");
}

TEST_F(BrokenSequence, MissingMetaKeys) {
  for (const std::string key : {"sensor", "rings", "columns", "scan_period"}) {
    std::string text = kMeta;
    const std::string quoted = "\"" + key + "\"";
    text.replace(text.find(quoted), quoted.size(), "\"renamed_" + key + "\"");
    WriteText(dir() / "meta.json", text);
    EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "missing required key " + quoted);
  }
}

TEST_F(BrokenSequence, BadMetaValues) {
  WriteText(dir() / "meta.json", R"({"sensor": "x", "rings": 4, "columns": 8, "scan_period": 0.1,
                                     "vertical_angles_deg": [1.0, 0.0, -1.0]})");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "vertical_angles_deg",
                  "has 3 values but \"rings\" is 4");
  WriteText(dir() / "meta.json", R"({"sensor": "x", "rings": -4, "columns": 8, "scan_period": 0.1})");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "\"rings\" must be a positive integer");
  WriteText(dir() / "meta.json", R"({"sensor": "x", "rings": 4, "columns": 8, "scan_period": "fast"})");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "\"scan_period\" must be a number");
  WriteText(dir() / "meta.json",
            R"({"sensor": "x", "rings": 4, "columns": 8, "scan_period": 0.1, "point_layout": "xyz"})");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "point_layout");
  WriteText(dir() / "meta.json", R"({"sensor": "x", "rings": 4,)");
  EXPECT_IO_ERROR(SequenceReader::Open(dir()), "meta.json", "not valid JSON");
}

TEST_F(BrokenSequence, NonFinitePointUnderStrict) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  WriteScan(0, {1, 2, 3, 10, 0.0f, 0, 4, nan, 6, 20, 0.05f, 3});
  EXPECT_EQ(ReadFirst().size(), 1u);
  EXPECT_IO_ERROR(ReadFirst(StrictOptions()), "000000.bin", "point 1", "NaN/inf");
}

TEST_F(BrokenSequence, NegativePointTime) {
  WriteScan(0, {1, 2, 3, 10, 0.0f, 0, 4, 5, 6, 20, -0.001f, 3});
  EXPECT_IO_ERROR(ReadFirst(), "000000.bin", "point 1", "time -0.001 s outside [0, scan_period=0.1)");
}

TEST_F(BrokenSequence, PointTimeNotBeforeScanPeriod) {
  WriteScan(0, {1, 2, 3, 10, 0.1f, 0, 4, 5, 6, 20, 0.05f, 3});
  EXPECT_IO_ERROR(ReadFirst(), "000000.bin", "point 0", "outside [0, scan_period");
}

TEST_F(BrokenSequence, RingOutOfRange) {
  WriteScan(0, {1, 2, 3, 10, 0.0f, 4, 4, 5, 6, 20, 0.05f, 3});
  EXPECT_IO_ERROR(ReadFirst(), "000000.bin", "point 0", "ring 4 is not an integer in [0, rings=4)");
  WriteScan(0, {1, 2, 3, 10, 0.0f, 1, 4, 5, 6, 20, 0.05f, 1.5f});
  EXPECT_IO_ERROR(ReadFirst(), "000000.bin", "point 1", "ring 1.5");
  WriteScan(0, {1, 2, 3, 10, 0.0f, -1, 4, 5, 6, 20, 0.05f, 1});
  EXPECT_IO_ERROR(ReadFirst(), "000000.bin", "point 0", "ring -1");
}

TEST(TumErrors, NameFileLineAndProblem) {
  TempDir tmp;
  EXPECT_IO_ERROR(ReadTum(tmp / "absent.tum"), "absent.tum", "cannot open");
  WriteText(tmp / "short.tum", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n");
  EXPECT_IO_ERROR(ReadTum(tmp / "short.tum"), "short.tum:2", "expected 8 values", "got 7");
  WriteText(tmp / "long.tum", "0 0 0 0 0 0 0 1 9\n");
  EXPECT_IO_ERROR(ReadTum(tmp / "long.tum"), "long.tum:1", "more than 8 values");
  WriteText(tmp / "text.tum", "# header\n0 0 0 zero 0 0 0 1\n");
  EXPECT_IO_ERROR(ReadTum(tmp / "text.tum"), "text.tum:2", "'zero' is not a finite number");
  WriteText(tmp / "quat.tum", "0 0 0 0 0 0 0 0\n");
  EXPECT_IO_ERROR(ReadTum(tmp / "quat.tum"), "quat.tum:1", "quaternion has zero norm");
}

}  // namespace
}  // namespace dammloam::io
