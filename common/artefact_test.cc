#include "common/artefact.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/error.h"

namespace ttz {
namespace {

namespace fs = std::filesystem;

class Artefact : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("artefact_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  size_t FilesInDir() const { return std::distance(fs::directory_iterator(dir_), fs::directory_iterator()); }
  fs::path dir_;
};

TEST_F(Artefact, RoundTripsVectorsAndAttributes) {
  std::vector<double> big(100000);
  for (size_t i = 0; i < big.size(); ++i) big[i] = 0.5 * i;
  {
    ArtefactWriter w(Path("a.h5"), "ttz.test", 3);
    w.WriteVector("s", big, "m", "abscissa");
    w.WriteVector("left/lat", {54.1, 54.2}, "deg", "latitude");
    w.WriteIntVector("points/line", {2, 3, 4}, "1", "lines");
    w.WriteStringVector("names", {"a", "bb"}, "names");
    w.WriteAttribute("length_m", 60.7e3);
    w.WriteAttribute("iterations", int64_t{42});
    w.WriteAttribute("crs", "+proj=tmerc");
    w.WriteBoolAttribute("closed", true);
    w.Commit();
  }
  ArtefactReader r(Path("a.h5"), "ttz.test", 3);
  EXPECT_EQ(r.ReadVector("s", "m"), big);
  EXPECT_EQ(r.ReadVector("left/lat", "deg"), (std::vector<double>{54.1, 54.2}));
  EXPECT_EQ(r.ReadIntVector("points/line", "1"), (std::vector<int64_t>{2, 3, 4}));
  EXPECT_EQ(r.ReadStringVector("names"), (std::vector<std::string>{"a", "bb"}));
  EXPECT_DOUBLE_EQ(r.ReadDoubleAttribute("length_m"), 60.7e3);
  EXPECT_EQ(r.ReadIntAttribute("iterations"), 42);
  EXPECT_EQ(r.ReadStringAttribute("crs"), "+proj=tmerc");
  EXPECT_TRUE(r.ReadBoolAttribute("closed"));
  EXPECT_TRUE(r.HasDataset("left/lat"));
  EXPECT_FALSE(r.HasDataset("right/lat"));
  EXPECT_FALSE(r.HasDataset("left/lon"));
}

TEST_F(Artefact, ReaderRejectsWhatIsWrongNamingIt) {
  {
    ArtefactWriter w(Path("a.h5"), "ttz.road", 1);
    w.WriteVector("s", {0, 1}, "m", "abscissa");
    w.WriteStringVector("kind", {"design"}, "kinds");
    w.Commit();
  }
  const auto message = [&](auto f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { ArtefactReader(Path("a.h5"), "ttz.lap", 1); }).find("schema 'ttz.road' found, 'ttz.lap' expected"),
            std::string::npos);
  EXPECT_NE(message([&] { ArtefactReader(Path("a.h5"), "ttz.road", 2); }).find("schema_version 1 found, 2 expected"),
            std::string::npos);
  EXPECT_NE(message([&] { ArtefactReader(Path("a.h5"), "ttz.road", 3, 2); })
                .find("schema_version 1 found, 2 to 3 expected"),
            std::string::npos);
  EXPECT_EQ(ArtefactReader(Path("a.h5"), "ttz.road", 2, 1).schema_version(), 1);
  ArtefactReader r(Path("a.h5"), "ttz.road", 1);
  EXPECT_NE(message([&] { r.ReadVector("s", "km"); }).find("units 'm', 'km' expected"), std::string::npos);
  EXPECT_NE(message([&] { r.ReadVector("kappa", "1/m"); }).find("dataset 'kappa' is missing"), std::string::npos);
  EXPECT_NE(message([&] { r.ReadStringVector("s"); }).find("dataset 's' is not a 1-D variable-length string array"),
            std::string::npos);
  EXPECT_NE(message([&] { r.ReadVector("kind", "1"); }).find("dataset 'kind' is not a 1-D numeric array"),
            std::string::npos);
  EXPECT_NE(message([&] { r.ReadDoubleAttribute("length_m"); }).find("attribute 'length_m' is missing"),
            std::string::npos);
  EXPECT_NE(message([&] { ArtefactReader(Path("none.h5"), "ttz.road", 1); }).find("file not found"), std::string::npos);
  std::ofstream(Path("text.h5")) << "not hdf5";
  EXPECT_NE(message([&] { ArtefactReader(Path("text.h5"), "ttz.road", 1); }).find("not an HDF5 file"),
            std::string::npos);
}

TEST_F(Artefact, NothingIsLeftBehindUnlessCommitted) {
  {
    ArtefactWriter w(Path("a.h5"), "ttz.test", 1);
    w.WriteVector("s", {0, 1}, "m", "abscissa");
  }
  EXPECT_EQ(FilesInDir(), 0u);
  try {
    ArtefactWriter w(Path("b.h5"), "ttz.test", 1);
    throw std::runtime_error("failure half-way");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(FilesInDir(), 0u);
  EXPECT_THROW(ArtefactWriter("/nonexistent-dir/x.h5", "ttz.test", 1), InputError);
}

TEST_F(Artefact, CommitReplacesAnExistingFile) {
  std::ofstream(Path("a.h5")) << "old";
  ArtefactWriter w(Path("a.h5"), "ttz.test", 1);
  w.WriteVector("s", {0, 1}, "m", "abscissa");
  w.Commit();
  EXPECT_EQ(ArtefactReader(Path("a.h5"), "ttz.test", 1).ReadVector("s", "m").size(), 2u);
  EXPECT_EQ(FilesInDir(), 1u);
}

TEST(Sha256, OfAKnownString) {
  const std::string path = ::testing::TempDir() + "abc.txt";
  std::ofstream(path) << "abc";
  EXPECT_EQ(FileSha256(path), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace ttz
