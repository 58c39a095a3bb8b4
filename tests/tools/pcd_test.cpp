#include <gtest/gtest.h>

#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tests/tools/test_support.hpp"
#include "io/io_error.hpp"
#include "io/pcd/labelled_pcd.hpp"

namespace dammloam::io {
namespace {

using test::TempDir;

LabelledCloud SampleCloud() {
  LabelledCloud cloud;
  for (int i = 0; i < 25; ++i) {
    cloud.points.emplace_back(0.5 * i, -1.25 * i, 3.0);
    cloud.intensities.push_back(static_cast<float>(i));
    cloud.labels.push_back(static_cast<PointClass>(i % 5));
    cloud.normals.push_back(Eigen::Vector3d(i, 1.0, 2.0).normalized());
  }
  return cloud;
}

void ExpectSame(const LabelledCloud& a, const LabelledCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(b.labels.size(), a.size());
  ASSERT_EQ(b.normals.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(b.points[i].isApprox(a.points[i].cast<float>().cast<double>(), 1e-7));
    EXPECT_EQ(b.intensities[i], a.intensities[i]);
    EXPECT_EQ(b.labels[i], a.labels[i]);
    EXPECT_TRUE(b.normals[i].isApprox(a.normals[i], 1e-6));
  }
}

TEST(LabelledPcd, RoundTripInEveryEncoding) {
  TempDir tmp;
  const LabelledCloud cloud = SampleCloud();
  for (const auto encoding : {PcdEncoding::kBinary, PcdEncoding::kBinaryCompressed, PcdEncoding::kAscii}) {
    const auto file = tmp / ("map" + std::to_string(static_cast<int>(encoding)) + ".pcd");
    WriteLabelledPcd(file, cloud, encoding);
    ExpectSame(cloud, ReadLabelledPcd(file));
  }
}

TEST(LabelledPcd, MissingFieldsAreLeftEmptyOrZero) {
  TempDir tmp;
  LabelledCloud cloud;
  cloud.points = {{1, 2, 3}, {4, 5, 6}};
  WriteLabelledPcd(tmp / "bare.pcd", cloud);
  const LabelledCloud read = ReadLabelledPcd(tmp / "bare.pcd");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read.labels, (std::vector<PointClass>{PointClass::Unknown, PointClass::Unknown}));
  EXPECT_EQ(read.intensities, (std::vector<float>{0.0f, 0.0f}));
}

TEST(LabelledPcd, ErrorsNameTheFile) {
  TempDir tmp;
  LabelledCloud cloud = SampleCloud();
  cloud.labels.pop_back();
  std::string error = test::IoErrorOf([&] { WriteLabelledPcd(tmp / "bad.pcd", cloud); });
  EXPECT_NE(error.find("bad.pcd"), std::string::npos) << error;
  EXPECT_NE(error.find("labels has 24 entries for 25 points"), std::string::npos) << error;

  error = test::IoErrorOf([&] { ReadLabelledPcd(tmp / "absent.pcd"); });
  EXPECT_NE(error.find("absent.pcd"), std::string::npos) << error;

  test::WriteText(tmp / "label.pcd",
                  "VERSION .7\nFIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
                  "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3 4\n1 2 3 9\n");
  error = test::IoErrorOf([&] { ReadLabelledPcd(tmp / "label.pcd"); });
  EXPECT_NE(error.find("label.pcd: point 1 has label 9"), std::string::npos) << error;

  test::WriteText(tmp / "garbage.pcd", "this is not a point cloud\n");
  error = test::IoErrorOf([&] { ReadLabelledPcd(tmp / "garbage.pcd"); });
  EXPECT_NE(error.find("garbage.pcd"), std::string::npos) << error;

  test::WriteText(tmp / "xy.pcd",
                  "VERSION .7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\n"
                  "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n");
  error = test::IoErrorOf([&] { ReadLabelledPcd(tmp / "xy.pcd"); });
  EXPECT_NE(error.find("xy.pcd: PCD has no x y z fields"), std::string::npos) << error;

  test::WriteText(tmp / "short.pcd",
                  "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                  "WIDTH 100\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 100\nDATA binary\n1234");
  error = test::IoErrorOf([&] { ReadLabelledPcd(tmp / "short.pcd"); });
  EXPECT_NE(error.find("short.pcd"), std::string::npos) << error;
}

// A real HDL-32E scan saved by PCL (x y z intensity, binary): read without labels or normals.
TEST(LabelledPcd, ReadsRealHdl32Pcd) {
  const auto file = test::DataDir() / "hdl32_pair_fast_gicp" / "251370668.pcd";
  DAMMLOAM_REQUIRE_DATA(file);
  const LabelledCloud cloud = ReadLabelledPcd(file);
  ASSERT_EQ(cloud.size(), 69088u);
  EXPECT_TRUE(cloud.labels.empty());
  EXPECT_TRUE(cloud.normals.empty());
  ASSERT_EQ(cloud.intensities.size(), cloud.size());
  std::size_t at_origin = 0;
  double max_range = 0.0;
  for (const auto& p : cloud.points) {
    if (p.isZero()) ++at_origin;
    max_range = std::max(max_range, p.norm());
  }
  EXPECT_EQ(at_origin, 5032u);
  EXPECT_NEAR(max_range, 77.6, 0.1);
}

}  // namespace
}  // namespace dammloam::io
