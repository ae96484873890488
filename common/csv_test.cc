#include "common/csv.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"

namespace ttz {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(Csv, ReadsHeaderCommentsQuotesAndLineNumbers) {
  const auto t = ReadCsv(Write("a.csv", "# comment\nLat_Deg, lon ,\"name\"\n\n54.1,-4.5,\"Bray, Hill\"\n54.2,-4.6,x\n"));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.FindColumn({"lat", "lat_deg"}), 0);
  EXPECT_EQ(t.FindColumn({"LON"}), 1);
  EXPECT_EQ(t.FindColumn({"elevation"}), -1);
  EXPECT_EQ(t.Cell(0, 2), "Bray, Hill");
  EXPECT_EQ(t.lines[0], 4);
  EXPECT_DOUBLE_EQ(t.Number(1, 0), 54.2);
}

TEST(Csv, TakesTheHeaderFromTheLastCommentWhenTheFirstLineIsData) {
  const auto t = ReadCsv(Write("b.csv", "# x_m,y_m,w_tr_right_m,w_tr_left_m\n1,2,3,4\n"));
  EXPECT_EQ(t.FindColumn({"w_tr_left_m"}), 3);
}

TEST(Csv, ErrorsNameFileLineAndColumn) {
  const auto bad = Write("c.csv", "lat,lon\n54,-4\n54,abc\n");
  const auto t = ReadCsv(bad);
  try {
    t.Number(1, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bad + ":3: column 'lon'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadCsv(Write("d.csv", "lat,lon\n54,nan\n")).Number(0, 1), InputError);
  EXPECT_THROW(ReadCsv(Write("e.csv", "")), InputError);
  EXPECT_THROW(ReadCsv(Write("f.csv", "1,2\n3,4\n")), InputError);
  EXPECT_THROW(ReadCsv(Write("g.csv", "lat,lon\n1,2,3\n")), InputError);
  EXPECT_THROW(ReadCsv(::testing::TempDir() + "missing.csv"), InputError);
}

}  // namespace
}  // namespace ttz
