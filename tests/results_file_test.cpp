// The results file (study/io/results_file.hpp): HDF5 round trips field by field, the netCDF-4
// dimension-scale layout, atomic replacement, rejection of damaged and foreign files, and the
// CSV export parsed back. Expected values are written out here, never produced by the code
// under test.
#include "study/io/results_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "study/formats/hdf5_file.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A 4 × 3 grid over (alpha, dt), the last axis fastest. Names are deliberately not in
// alphabetical order, so reading back by name instead of creation order would show.
StudyResults grid_results() {
  StudyResults r;
  r.plan_name = "hht-grid";
  r.plan_text = "name = \"hht-grid\"\n[grid]\nalpha = [-0.3, -0.2, -0.1, 0.0]\n# ünïcode ✓\n";
  r.study_kind = "grid";
  r.method = "hht";
  r.impactid_version = "0.1.0";
  r.git_revision = "0123456789ab";
  r.date = "2024-05-06T07:08:09Z";
  r.threads = 8;
  r.wall_time_s = 12.25;
  r.dimensions = {{"alpha", "1", {-0.3, -0.2, -0.1, 0.0}}, {"dt", "s", {1e-7, 2e-7, 5e-7}}};
  r.status = {0, 0, 1, 0, 2, 0, -1, -1, 0, 0, 1, -1};
  const auto masked = [&](std::vector<double> v) {  // NaN where a point is not ok
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (r.status[i] != 0) v[i] = kNaN;
    }
    return v;
  };
  r.parameters = {
      {"gamma",
       "1",
       "Newmark gamma",
       "",
       {0.8, 0.8, 0.8, 0.7, 0.7, 0.7, 0.6, 0.6, 0.6, 0.5, 0.5, 0.5}},
      {"beta",
       "1",
       "Newmark beta",
       "eq. 15",
       {0.4225, 0.4225, 0.4225, 0.36, 0.36, 0.36, 0.3025, 0.3025, 0.3025, 0.25, 0.25, 0.25}},
  };
  r.indicators = {
      {"p_max", "MPa", "largest sampled contact pressure", "",
       masked({1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5, 10.5, 11.5, 12.5})},
      {"eps_p", "1", "eps_p", "eq. 18: sum |p_exact - p| / sum |p_exact|",
       masked({0.1, 1.0 / 3.0, 0.3, -0.0, 0.4, 1e-300, 0.6, 0.7, 4.9e-324, 6.02e23, 1.1, 1.2})},
  };
  r.numeric_attributes = {{"best_objective", 0.125}, {"best_alpha", -0.1}, {"answer", 42.0}};
  r.text_attributes = {{"termination", "XTOL_REACHED"}, {"algorithm", "LN_COBYLA"}};
  return r;
}

// A list study: one dimension "point" = 0..K−1, the varied parameters as columns.
StudyResults list_results() {
  StudyResults r;
  r.plan_name = "list";
  r.plan_text = "[[point]]\ndelta = 0.5\n";
  r.study_kind = "list";
  r.method = "newmark";
  r.dimensions = {{"point", "1", {0, 1, 2}}};
  r.status = {0, -1, 1};
  r.parameters = {{"delta", "1", "delta", "", {0.5, 0.6, 0.7}}};
  r.indicators = {{"nop_p", "1", "nop_p", "number of peaks", {3, kNaN, kNaN}}};
  return r;
}

// An optimisation's table of evaluations, as study/studies/optimizer.cpp builds it.
StudyResults evaluation_results(std::size_t rows) {
  StudyResults r;
  r.plan_name = "optimize-hht";
  r.plan_text = "[optimize]\n";
  r.study_kind = "optimize";
  r.method = "hht";
  r.dimensions = {{"evaluation", "1", {}}};
  r.parameters = {{"alpha", "1", "HHT alpha", "", {}}, {"beta", "1", "beta", "", {}}};
  r.indicators = {{"eps_p", "1", "eps_p", "eq. 18", {}},
                  {"objective", "1", "objective", "sum of weight * indicator", {}},
                  {"feasible", "1", "feasible", "1 if ok and every constraint holds", {}}};
  for (std::size_t i = 0; i < rows; ++i) {
    r.dimensions[0].values.push_back(static_cast<double>(i));
    r.status.push_back(i % 3 == 2 ? 1 : 0);
    r.parameters[0].values.push_back(-0.01 * static_cast<double>(i));
    r.parameters[1].values.push_back(0.25 + 0.001 * static_cast<double>(i));
    r.indicators[0].values.push_back(i % 3 == 2 ? kNaN : 0.5 / static_cast<double>(i + 1));
    r.indicators[1].values.push_back(i % 3 == 2 ? 1e10 : 0.5 / static_cast<double>(i + 1));
    r.indicators[2].values.push_back(i % 3 == 2 ? 0.0 : 1.0);
  }
  if (rows > 0) {
    r.numeric_attributes = {{"best_evaluation", 0.0}, {"best_objective", 0.5}};
  }
  r.text_attributes = {{"algorithm", "LN_NELDERMEAD"}};
  return r;
}

// Bit-for-bit: NaNs stay NaNs (with their payload), -0.0 stays -0.0.
void expect_same_doubles(const std::vector<double>& expected, const std::vector<double>& actual,
                         const std::string& what) {
  ASSERT_EQ(expected.size(), actual.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(expected[i]), std::bit_cast<std::uint64_t>(actual[i]))
        << what << "[" << i << "]: " << expected[i] << " vs " << actual[i];
  }
}

void expect_same_columns(const std::vector<ResultColumn>& expected,
                         const std::vector<ResultColumn>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (std::size_t c = 0; c < expected.size(); ++c) {
    EXPECT_EQ(expected[c].name, actual[c].name);
    EXPECT_EQ(expected[c].units, actual[c].units) << expected[c].name;
    EXPECT_EQ(expected[c].long_name, actual[c].long_name) << expected[c].name;
    EXPECT_EQ(expected[c].definition, actual[c].definition) << expected[c].name;
    expect_same_doubles(expected[c].values, actual[c].values, expected[c].name);
  }
}

void expect_same_results(const StudyResults& expected, const StudyResults& actual) {
  EXPECT_EQ(expected.plan_name, actual.plan_name);
  EXPECT_EQ(expected.plan_text, actual.plan_text);
  EXPECT_EQ(expected.study_kind, actual.study_kind);
  EXPECT_EQ(expected.method, actual.method);
  EXPECT_EQ(expected.impactid_version, actual.impactid_version);
  EXPECT_EQ(expected.git_revision, actual.git_revision);
  EXPECT_EQ(expected.date, actual.date);
  EXPECT_EQ(expected.threads, actual.threads);
  EXPECT_EQ(expected.wall_time_s, actual.wall_time_s);
  ASSERT_EQ(expected.dimensions.size(), actual.dimensions.size());
  for (std::size_t d = 0; d < expected.dimensions.size(); ++d) {
    EXPECT_EQ(expected.dimensions[d].name, actual.dimensions[d].name);
    EXPECT_EQ(expected.dimensions[d].units, actual.dimensions[d].units);
    EXPECT_EQ(expected.dimensions[d].labels, actual.dimensions[d].labels);
    expect_same_doubles(expected.dimensions[d].values, actual.dimensions[d].values,
                        expected.dimensions[d].name);
  }
  EXPECT_EQ(expected.status, actual.status);
  expect_same_columns(expected.parameters, actual.parameters);
  expect_same_columns(expected.indicators, actual.indicators);
  ASSERT_EQ(expected.numeric_attributes.size(), actual.numeric_attributes.size());
  for (std::size_t i = 0; i < expected.numeric_attributes.size(); ++i) {
    EXPECT_EQ(expected.numeric_attributes[i].first, actual.numeric_attributes[i].first);
    expect_same_doubles({expected.numeric_attributes[i].second},
                        {actual.numeric_attributes[i].second},
                        expected.numeric_attributes[i].first);
  }
  EXPECT_EQ(expected.text_attributes, actual.text_attributes);
}

// The test's own folder, removed afterwards.
class ResultsFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("impactid_results_file_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path file(const std::string& name) const { return dir_ / name; }

  fs::path dir_;
};

// The message of the Hdf5Error that fn throws ("" and a failure if it throws none).
template <class Error = Hdf5Error, class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception thrown";
  return "";
}

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// --- round trips ---

TEST_F(ResultsFileTest, GridRoundTripKeepsEveryFieldAndNaN) {
  const StudyResults written = grid_results();
  write_results(file("grid.h5"), written);
  const StudyResults read = read_results(file("grid.h5"));
  expect_same_results(written, read);
  EXPECT_TRUE(std::isnan(read.find_column("p_max")->values[2]));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(-0.0),
            std::bit_cast<std::uint64_t>(read.find_column("eps_p")->values[3]));
}

TEST_F(ResultsFileTest, ListRoundTrip) {
  const StudyResults written = list_results();
  write_results(file("list.h5"), written);
  expect_same_results(written, read_results(file("list.h5")));
}

TEST_F(ResultsFileTest, EvaluationTableRoundTripIncludingAnEmptyOne) {
  for (const std::size_t rows : {7u, 1u, 0u}) {
    SCOPED_TRACE("rows = " + std::to_string(rows));
    const StudyResults written = evaluation_results(rows);
    write_results(file("evaluations.h5"), written);
    const StudyResults read = read_results(file("evaluations.h5"));
    expect_same_results(written, read);
    EXPECT_EQ(static_cast<long>(rows), read.points_total());
  }
}

TEST_F(ResultsFileTest, RewritingReplacesTheFile) {
  StudyResults r = grid_results();
  write_results(file("r.h5"), r);
  r.status.assign(r.status.size(), 0);
  r.wall_time_s = 99.0;
  r.text_attributes.clear();
  write_results(file("r.h5"), r);
  expect_same_results(r, read_results(file("r.h5")));
}

// --- status, points_done, find_column ---

TEST(StudyResults, PointsDoneCountsEveryStatusButNotDone) {
  const StudyResults r = grid_results();  // 12 points, 3 of them -1
  EXPECT_EQ(12, r.points_total());
  EXPECT_EQ(9, r.points_done());
  StudyResults none = list_results();
  none.status.assign(3, kStatusNotDone);
  EXPECT_EQ(0, none.points_done());
  EXPECT_EQ(0, evaluation_results(0).points_done());
}

TEST(StudyResults, FindColumnSearchesParametersThenIndicators) {
  const StudyResults r = grid_results();
  ASSERT_NE(nullptr, r.find_column("beta"));
  EXPECT_EQ(&r.parameters[1], r.find_column("beta"));
  EXPECT_EQ(&r.indicators[1], r.find_column("eps_p"));
  EXPECT_EQ(nullptr, r.find_column("alpha"));  // a dimension, not a column
  EXPECT_EQ(nullptr, r.find_column("status"));
  EXPECT_EQ(nullptr, r.find_column(""));
}

TEST_F(ResultsFileTest, StatusIsAnIntegerDatasetWithCfFlags) {
  const StudyResults r = grid_results();
  write_results(file("r.h5"), r);
  const Hdf5Reader h5(file("r.h5"));
  EXPECT_EQ((Hdf5Dims{4, 3}), h5.shape("status"));
  EXPECT_EQ(r.status, h5.ints("status"));
  EXPECT_EQ((std::vector<int>{-1, 0, 1, 2}), h5.attribute_ints("status", "flag_values"));
  EXPECT_EQ("not_done ok unstable failed", h5.attribute_string("status", "flag_meanings"));
  EXPECT_TRUE(h5.has_attribute("status", "long_name"));
  EXPECT_FALSE(h5.has_attribute("status", "_FillValue"));
  EXPECT_EQ(12, h5.attribute_long("/", "points_total"));
  EXPECT_EQ(9, h5.attribute_long("/", "points_done"));
  EXPECT_EQ("impactid-results-1", h5.attribute_string("/", "format"));
  EXPECT_EQ(8, h5.attribute_long("/", "threads"));
}

TEST_F(ResultsFileTest, ColumnsCarryUnitsNamesDefinitionsAndRoles) {
  write_results(file("r.h5"), grid_results());
  const Hdf5Reader h5(file("r.h5"));
  EXPECT_EQ((Hdf5Dims{4, 3}), h5.shape("p_max"));
  EXPECT_EQ("MPa", h5.attribute_string("p_max", "units"));
  EXPECT_EQ("largest sampled contact pressure", h5.attribute_string("p_max", "long_name"));
  EXPECT_FALSE(h5.has_attribute("p_max", "definition"));  // empty: not written
  EXPECT_EQ("eq. 15", h5.attribute_string("beta", "definition"));
  EXPECT_EQ("indicator", h5.attribute_string("eps_p", "role"));
  EXPECT_EQ("parameter", h5.attribute_string("gamma", "role"));
  EXPECT_EQ("s", h5.attribute_string("dt", "units"));
  EXPECT_EQ((std::vector<std::string>{"alpha", "dt", "status", "gamma", "beta", "p_max", "eps_p"}),
            h5.members("/"));
}

TEST_F(ResultsFileTest, AxesAreDimensionScalesAttachedToEveryGriddedDataset) {
  write_results(file("r.h5"), grid_results());
  const Hdf5Reader h5(file("r.h5"));
  for (const char* axis : {"alpha", "dt"}) {
    EXPECT_TRUE(h5.is_dimension_scale(axis)) << axis;
    EXPECT_EQ("DIMENSION_SCALE", h5.attribute_string(axis, "CLASS")) << axis;
    EXPECT_EQ(axis, h5.attribute_string(axis, "NAME")) << axis;
    EXPECT_TRUE(h5.has_attribute(axis, "REFERENCE_LIST")) << axis;
  }
  EXPECT_EQ((Hdf5Dims{4}), h5.shape("alpha"));
  EXPECT_EQ((Hdf5Dims{3}), h5.shape("dt"));
  for (const char* dataset : {"status", "gamma", "beta", "p_max", "eps_p"}) {
    EXPECT_FALSE(h5.is_dimension_scale(dataset)) << dataset;
    EXPECT_TRUE(h5.has_attribute(dataset, "DIMENSION_LIST")) << dataset;
    EXPECT_EQ((std::vector<std::string>{"/alpha"}), h5.attached_scales(dataset, 0)) << dataset;
    EXPECT_EQ((std::vector<std::string>{"/dt"}), h5.attached_scales(dataset, 1)) << dataset;
  }
  EXPECT_THROW(h5.attached_scales("eps_p", 2), Hdf5Error);
}

// --- invalid tables are refused before anything is written ---

TEST_F(ResultsFileTest, InconsistentTablesAreRefusedWithTheReason) {
  const auto refused = [&](StudyResults r) {
    return error_of([&] { write_results(file("bad.h5"), r); });
  };
  StudyResults r = grid_results();
  r.status[4] = 7;
  EXPECT_NE(std::string::npos, refused(r).find("status[4] = 7"));
  r = grid_results();
  r.indicators[0].values.pop_back();
  EXPECT_NE(std::string::npos, refused(r).find("p_max"));
  r = grid_results();
  r.numeric_attributes.emplace_back("threads", 3.0);
  EXPECT_NE(std::string::npos, refused(r).find("reserved"));
  r = grid_results();
  r.text_attributes.emplace_back("answer", "also numeric");
  EXPECT_NE(std::string::npos, refused(r).find("used twice"));
  r = grid_results();
  r.indicators[0].name = "alpha";
  EXPECT_NE(std::string::npos, refused(r).find("used twice"));
  r = grid_results();
  r.indicators[0].name = "a/b";
  EXPECT_NE(std::string::npos, refused(r).find("'/'"));
  r = grid_results();
  r.dimensions.clear();
  r.status = {0};
  EXPECT_NE(std::string::npos, refused(r).find("at least one dimension"));
  const std::string message = refused(r);
  EXPECT_NE(std::string::npos, message.find(file("bad.h5").string())) << message;
  EXPECT_FALSE(fs::exists(file("bad.h5")));
  EXPECT_FALSE(fs::exists(file("bad.h5.tmp")));
}

// --- atomic replacement ---

TEST_F(ResultsFileTest, WriteLeavesNoTemporaryFile) {
  write_results(file("r.h5"), grid_results());
  EXPECT_TRUE(fs::exists(file("r.h5")));
  EXPECT_FALSE(fs::exists(file("r.h5.tmp")));
  EXPECT_EQ((std::vector<fs::path>{file("r.h5")}),
            std::vector<fs::path>(fs::directory_iterator(dir_), fs::directory_iterator()));
}

TEST_F(ResultsFileTest, FailedWritesLeaveThePreviousFileIntact) {
  const StudyResults previous = grid_results();
  write_results(file("r.h5"), previous);
  const std::string bytes = contents(file("r.h5"));

  StudyResults bad = list_results();
  bad.status.push_back(0);  // one value too many
  EXPECT_THROW(write_results(file("r.h5"), bad), Hdf5Error);

  {  // a writer that fails (or is abandoned) half way through
    Hdf5Writer writer(file("r.h5"));
    writer.attribute("/", "format", std::string("half-written"));
    const std::vector<double> data{1.0, 2.0};
    EXPECT_THROW(writer.dataset("x", data, Hdf5Dims{3}), Hdf5Error);
    // The file is built in memory: nothing of it is on disk before commit().
    EXPECT_FALSE(fs::exists(file("r.h5.tmp")));
  }
  EXPECT_FALSE(fs::exists(file("r.h5.tmp")));
  EXPECT_EQ(bytes, contents(file("r.h5")));
  expect_same_results(previous, read_results(file("r.h5")));
}

TEST_F(ResultsFileTest, WriteIntoAnUnwritablePlaceThrowsNamingTheFile) {
  const fs::path impossible = "/proc/impactid/x.h5";
  const std::string message = error_of([&] { write_results(impossible, grid_results()); });
  EXPECT_NE(std::string::npos, message.find("/proc/impactid/x.h5")) << message;
  EXPECT_FALSE(fs::exists(impossible));
}

TEST_F(ResultsFileTest, FailedRenameRemovesTheTemporaryFile) {
  fs::create_directories(file("taken.h5") / "not-empty");  // a folder cannot be replaced
  const std::string message = error_of([&] { write_results(file("taken.h5"), grid_results()); });
  EXPECT_NE(std::string::npos, message.find(file("taken.h5").string())) << message;
  EXPECT_FALSE(fs::exists(file("taken.h5.tmp")));
  EXPECT_TRUE(fs::is_directory(file("taken.h5") / "not-empty"));
}

// --- damaged and foreign files ---

TEST_F(ResultsFileTest, MissingFileIsRejectedByName) {
  const std::string message = error_of([&] { read_results(file("nowhere.h5")); });
  EXPECT_NE(std::string::npos, message.find(file("nowhere.h5").string())) << message;
}

TEST_F(ResultsFileTest, TruncatedFileIsRejectedByName) {
  write_results(file("r.h5"), grid_results());
  fs::resize_file(file("r.h5"), fs::file_size(file("r.h5")) / 2);
  const std::string message = error_of([&] { read_results(file("r.h5")); });
  EXPECT_NE(std::string::npos, message.find(file("r.h5").string())) << message;
  EXPECT_NE(std::string::npos, message.find("truncated")) << message;
}

TEST_F(ResultsFileTest, NonHdf5FileIsRejectedByName) {
  std::ofstream(file("text.h5")) << "alpha,beta\n1,2\n";
  const std::string message = error_of([&] { read_results(file("text.h5")); });
  EXPECT_NE(std::string::npos, message.find(file("text.h5").string())) << message;
}

TEST_F(ResultsFileTest, ForeignHdf5FileIsRejectedByName) {
  {
    Hdf5Writer writer(file("foreign.h5"));
    const std::vector<double> data{1.0, 2.0, 3.0};
    writer.dataset("t", data, Hdf5Dims{3});
    writer.attribute("/", "method", std::string("hht"));
    writer.commit();
  }
  std::string message = error_of([&] { read_results(file("foreign.h5")); });
  EXPECT_NE(std::string::npos, message.find(file("foreign.h5").string())) << message;
  EXPECT_NE(std::string::npos, message.find("not an impactid results file")) << message;

  {
    Hdf5Writer writer(file("future.h5"));
    writer.attribute("/", "format", std::string("impactid-results-2"));
    writer.commit();
  }
  message = error_of([&] { read_results(file("future.h5")); });
  EXPECT_NE(std::string::npos, message.find(file("future.h5").string())) << message;
  EXPECT_NE(std::string::npos, message.find("impactid-results-2")) << message;
}

// --- checksums (issue 38: a flipped bit was read as a value) ---

// Flips `mask` in the byte `offset` bytes after the first occurrence of `pattern` in the file.
void flip_after(const fs::path& path, const std::string& pattern, std::size_t offset,
                unsigned char mask) {
  std::string bytes = contents(path);
  const std::size_t at = bytes.find(pattern);
  ASSERT_NE(std::string::npos, at) << "not in " << path;
  ASSERT_EQ(std::string::npos, bytes.find(pattern, at + 1)) << "found twice in " << path;
  bytes[at + offset] = static_cast<char>(bytes[at + offset] ^ mask);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string bytes_of(double value) {
  std::string out(sizeof value, '\0');
  std::memcpy(out.data(), &value, sizeof value);
  return out;
}

TEST_F(ResultsFileTest, EveryNumericDatasetIsStoredWithAFletcher32Checksum) {
  write_results(file("r.h5"), grid_results());
  H5::H5File f(file("r.h5").string(), H5F_ACC_RDONLY);
  for (const char* name : {"alpha", "dt", "status", "gamma", "beta", "p_max", "eps_p"}) {
    const H5::DSetCreatPropList plist = f.openDataSet(name).getCreatePlist();
    unsigned flags = 0;
    std::size_t values = 0;
    EXPECT_GE(H5Pget_filter_by_id2(plist.getId(), H5Z_FILTER_FLETCHER32, &flags, &values, nullptr,
                                   0, nullptr, nullptr),
              0)
        << name;
  }
  EXPECT_TRUE(f.openGroup("/").attrExists(kChecksumAttribute));
}

TEST_F(ResultsFileTest, AFlippedValueIsRefusedNamingFileAndDataset) {
  write_results(file("r.h5"), grid_results());
  // eps_p[9] = 6.02e23: one bit of its exponent would read as 1.2e24 without the checksum.
  flip_after(file("r.h5"), bytes_of(6.02e23), 7, 0x01);
  const std::string message = error_of([&] { read_results(file("r.h5")); });
  EXPECT_EQ(0u, message.find(file("r.h5").string() + ": eps_p: data corrupted")) << message;
}

TEST_F(ResultsFileTest, AFlippedValueOfACompressedDatasetIsRefused) {
  StudyResults r = list_results();
  const std::size_t n = 5000;  // above compress_large_datasets' 4096: chunked and deflated
  r.dimensions[0].values.resize(n);
  std::iota(r.dimensions[0].values.begin(), r.dimensions[0].values.end(), 0.0);
  r.status.assign(n, 0);
  for (ResultColumn& c : r.parameters) c.values.assign(n, 0.5);
  for (ResultColumn& c : r.indicators) {
    c.values.resize(n);
    for (std::size_t i = 0; i < n; ++i) c.values[i] = 1.0 / static_cast<double>(i + 1);
  }
  write_results_compressed(file("s.h5"), r);
  const std::string name = r.indicators.front().name;
  haddr_t address = 0;
  hsize_t size = 0;
  {
    H5::H5File f(file("s.h5").string(), H5F_ACC_RDONLY);
    const H5::DataSet d = f.openDataSet(name);
    unsigned filter_mask = 0;
    hsize_t offset[1] = {0};
    ASSERT_GE(H5Dget_chunk_info(d.getId(), d.getSpace().getId(), 0, offset, &filter_mask, &address,
                                &size),
              0);
    ASSERT_LT(size, n * sizeof(double));  // deflated
  }
  std::string bytes = contents(file("s.h5"));
  bytes[address + size / 2] = static_cast<char>(bytes[address + size / 2] ^ 0x04);
  std::ofstream(file("s.h5"), std::ios::binary | std::ios::trunc) << bytes;
  const std::string message = error_of([&] { read_results(file("s.h5")); });
  EXPECT_EQ(0u, message.find(file("s.h5").string() + ": " + name + ": data corrupted")) << message;
}

TEST_F(ResultsFileTest, DamagedTextIsRefusedByTheChecksumOfAttributesAndText) {
  write_results(file("r.h5"), grid_results());
  flip_after(file("r.h5"), "[grid]\nalpha", 1, 0x01);  // the plan's text: "[grid]" -> "[frid]"
  const std::string message = error_of([&] { read_results(file("r.h5")); });
  EXPECT_EQ(0u,
            message.find(file("r.h5").string() + ": the checksum of its attributes and text (/@" +
                         kChecksumAttribute + "): data corrupted"))
      << message;
}

TEST_F(ResultsFileTest, AFileWithoutChecksumsIsReadWithANote) {
  const StudyResults written = grid_results();
  write_results(file("r.h5"), written);
  {
    H5::H5File f(file("r.h5").string(), H5F_ACC_RDWR);
    f.openGroup("/").removeAttr(kChecksumAttribute);
  }
  testing::internal::CaptureStderr();
  const StudyResults read = read_results(file("r.h5"));
  const std::string err = testing::internal::GetCapturedStderr();
  expect_same_results(written, read);
  EXPECT_NE(std::string::npos, err.find(file("r.h5").string() + ": no checksums")) << err;
}

TEST_F(ResultsFileTest, TheChecksumAttributeIsNoStudyAttribute) {
  write_results(file("r.h5"), grid_results());
  const StudyResults read = read_results(file("r.h5"));
  for (const auto& [name, value] : read.numeric_attributes) EXPECT_NE(kChecksumAttribute, name);
  write_results(file("again.h5"), read);  // a resumed file: one checksum, not a copy of the old
  expect_same_results(read, read_results(file("again.h5")));
}

// --- CSV export ---

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream s(line);
  std::string field;
  while (std::getline(s, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) rows.push_back(split(line));
  return rows;
}

// The number a field holds, exactly: "nan" is the only spelling of NaN.
double number(const std::string& field) {
  if (field == "nan") return kNaN;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);  // subnormals too (std::stod throws)
  EXPECT_EQ(field.c_str() + field.size(), end) << field;
  return value;
}

void expect_same_number(double expected, const std::string& field, const std::string& what) {
  if (std::isnan(expected)) {
    EXPECT_EQ("nan", field) << what;
  } else {
    EXPECT_EQ(expected, number(field)) << what << ": " << field;  // exact
  }
}

// A choice axis keeps its words: CF flag_values/flag_meanings in the file, the word in CSV.
TEST_F(ResultsFileTest, ChoiceAxisWordsRoundTripAndReachTheCsv) {
  StudyResults r = grid_results();
  r.dimensions[0] = {"contact", "1", {0.0, 1.0, 2.0, 3.0}, {"a", "b-c", "d", "e"}};
  write_results(file("choice.h5"), r);
  expect_same_results(r, read_results(file("choice.h5")));
  export_csv(r, dir_ / "csv");
  const auto rows = read_csv(dir_ / "csv" / "points.csv");
  ASSERT_EQ(13u, rows.size());
  EXPECT_EQ("a", rows[1][0]);
  EXPECT_EQ("b-c", rows[4][0]);
  EXPECT_EQ("e", rows[12][0]);
  r.dimensions[0].labels.pop_back();
  EXPECT_THROW(write_results(file("bad.h5"), r), Hdf5Error);
  EXPECT_FALSE(fs::exists(file("bad.h5")));
}

TEST_F(ResultsFileTest, PointsCsvHasOneRowPerPointInFlatOrder) {
  const StudyResults r = grid_results();
  export_csv(r, dir_ / "csv");
  const auto rows = read_csv(dir_ / "csv" / "points.csv");
  ASSERT_EQ(1u + 12u, rows.size());
  EXPECT_EQ((std::vector<std::string>{"alpha", "dt[s]", "gamma", "beta", "status", "p_max[MPa]",
                                      "eps_p"}),
            rows[0]);
  for (std::size_t i = 0; i < 12; ++i) {
    const auto& row = rows[i + 1];
    ASSERT_EQ(7u, row.size()) << i;
    const std::string at = "point " + std::to_string(i);
    expect_same_number(r.dimensions[0].values[i / 3], row[0], at + " alpha");
    expect_same_number(r.dimensions[1].values[i % 3], row[1], at + " dt");
    expect_same_number(r.parameters[0].values[i], row[2], at + " gamma");
    expect_same_number(r.parameters[1].values[i], row[3], at + " beta");
    EXPECT_EQ(std::to_string(r.status[i]), row[4]) << at;
    expect_same_number(r.indicators[0].values[i], row[5], at + " p_max");
    expect_same_number(r.indicators[1].values[i], row[6], at + " eps_p");
  }
  // The shortest text that reads back as the exact double (expect_same_number checked that),
  // down to the smallest subnormal: 0.1, not 0.10000000000000001.
  EXPECT_EQ("0.1", rows[1][6]);
  EXPECT_EQ("0.3333333333333333", rows[2][6]);
  EXPECT_EQ("-0", rows[4][6]);
  EXPECT_EQ("5e-324", rows[9][6]);
  EXPECT_EQ("6.02e+23", rows[10][6]);
  EXPECT_EQ("1e-07", rows[1][1]);
  EXPECT_EQ("0.4225", rows[1][3]);
}

// A column with no number at any point (an indicator that does not apply to the scene, a
// parameter that no point has) is left out of points.csv and gets no matrix; export_csv names it.
// A column NaN at some points only stays.
TEST_F(ResultsFileTest, ColumnsThatAreNanAtEveryPointAreLeftOut) {
  StudyResults r = grid_results();
  r.parameters.push_back(
      {"penalty_stiffness", "N/mm", "penalty", "", std::vector<double>(12, kNaN)});
  r.indicators.insert(r.indicators.begin() + 1, {"impacts", "1", "impacts on the far wall", "",
                                                 std::vector<double>(12, kNaN)});
  const std::vector<std::string> skipped = export_csv(r, dir_ / "csv");
  EXPECT_EQ((std::vector<std::string>{"penalty_stiffness", "impacts"}), skipped);
  const auto rows = read_csv(dir_ / "csv" / "points.csv");
  ASSERT_EQ(13u, rows.size());
  EXPECT_EQ((std::vector<std::string>{"alpha", "dt[s]", "gamma", "beta", "status", "p_max[MPa]",
                                      "eps_p"}),
            rows[0]);
  for (const auto& row : rows) EXPECT_EQ(7u, row.size());
  EXPECT_FALSE(fs::exists(dir_ / "csv" / "impacts.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "csv" / "eps_p.csv"));
  EXPECT_TRUE(export_csv(grid_results(), dir_ / "all").empty());
}

TEST_F(ResultsFileTest, TwoDimensionalExportWritesOneMatrixPerIndicator) {
  const StudyResults r = grid_results();
  export_csv(r, dir_ / "csv");
  for (const ResultColumn& c : r.indicators) {
    const auto rows = read_csv(dir_ / "csv" / (c.name + ".csv"));
    ASSERT_EQ(1u + 4u, rows.size()) << c.name;
    ASSERT_EQ(1u + 3u, rows[0].size()) << c.name;
    EXPECT_EQ("alpha\\dt", rows[0][0]);
    for (std::size_t j = 0; j < 3; ++j) {
      expect_same_number(r.dimensions[1].values[j], rows[0][j + 1], "dt");
    }
    for (std::size_t i = 0; i < 4; ++i) {
      ASSERT_EQ(1u + 3u, rows[i + 1].size());
      expect_same_number(r.dimensions[0].values[i], rows[i + 1][0], "alpha");
      for (std::size_t j = 0; j < 3; ++j) {
        expect_same_number(c.values[i * 3 + j], rows[i + 1][j + 1],
                           c.name + "(" + std::to_string(i) + "," + std::to_string(j) + ")");
      }
    }
  }
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir_ / "csv")) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ((std::vector<std::string>{"eps_p.csv", "p_max.csv", "points.csv"}), names);
}

TEST_F(ResultsFileTest, OneDimensionalExportWritesOnlyThePointTable) {
  const StudyResults r = list_results();
  export_csv(r, dir_ / "a" / "b");  // folders are created
  std::vector<fs::path> files(fs::directory_iterator(dir_ / "a" / "b"), fs::directory_iterator());
  EXPECT_EQ((std::vector<fs::path>{dir_ / "a" / "b" / "points.csv"}), files);
  EXPECT_EQ("point,delta,status,nop_p\n0,0.5,0,3\n1,0.6,-1,nan\n2,0.7,1,nan\n",
            contents(dir_ / "a" / "b" / "points.csv"));
}

TEST_F(ResultsFileTest, ExportRoundTripsThroughTheHdf5File) {
  const StudyResults r = grid_results();
  write_results(file("r.h5"), r);
  export_csv(r, dir_ / "direct");
  export_csv(read_results(file("r.h5")), dir_ / "via-file");
  for (const char* name : {"points.csv", "p_max.csv", "eps_p.csv"}) {
    EXPECT_EQ(contents(dir_ / "direct" / name), contents(dir_ / "via-file" / name)) << name;
  }
}

TEST_F(ResultsFileTest, ExportFailuresNameTheFile) {
  std::string message =
      error_of<std::runtime_error>([&] { export_csv(grid_results(), "/proc/impactid/csv"); });
  EXPECT_NE(std::string::npos, message.find("/proc/impactid/csv")) << message;

  std::ofstream(file("plain")) << "x";
  message = error_of<std::runtime_error>([&] { export_csv(grid_results(), file("plain")); });
  EXPECT_NE(std::string::npos, message.find(file("plain").string())) << message;

  fs::create_directories(dir_ / "csv" / "points.csv" / "occupied");
  message = error_of<std::runtime_error>([&] { export_csv(list_results(), dir_ / "csv"); });
  EXPECT_NE(std::string::npos, message.find((dir_ / "csv" / "points.csv").string())) << message;
  EXPECT_FALSE(fs::exists(dir_ / "csv" / "points.csv.tmp"));

  StudyResults r = grid_results();
  r.indicators[0].name = "points";
  message = error_of<std::runtime_error>([&] { export_csv(r, dir_ / "other"); });
  EXPECT_NE(std::string::npos, message.find("points.csv")) << message;
}

// --- third-party readers ---

bool python_has_h5py() {
  return std::system("/usr/bin/python3 -c 'import h5py' >/dev/null 2>&1") == 0;
}

TEST_F(ResultsFileTest, H5pySeesTheDimensionScales) {
  if (!python_has_h5py()) GTEST_SKIP() << "/usr/bin/python3 cannot import h5py";
  write_results(file("r.h5"), grid_results());
  const fs::path script = file("check.py");
  std::ofstream(script) << R"(import sys, h5py, numpy as np
f = h5py.File(sys.argv[1], "r")
assert f.attrs["format"] == "impactid-results-1"
for name in ["status", "gamma", "beta", "p_max", "eps_p"]:
    d = f[name]
    assert d.shape == (4, 3), name
    assert d.dims[0][0].name == "/alpha", name
    assert d.dims[1][0].name == "/dt", name
assert f["status"].dtype == np.int32
assert list(f["status"].attrs["flag_values"]) == [-1, 0, 1, 2]
assert f["p_max"].attrs["units"] == "MPa"
assert np.isnan(f["p_max"][0, 2])
assert f["alpha"].attrs["CLASS"] == b"DIMENSION_SCALE"
assert sorted(f) == ["alpha", "beta", "dt", "eps_p", "gamma", "p_max", "status"], list(f)
try:
    import xarray
    import h5netcdf  # noqa: F401
except ImportError:
    sys.exit(0)
ds = xarray.open_dataset(sys.argv[1], engine="h5netcdf")
assert ds["eps_p"].dims == ("alpha", "dt"), ds["eps_p"].dims
assert float(ds["dt"][2]) == 5e-7
)";
  const std::string command = "/usr/bin/python3 " + script.string() + " " + file("r.h5").string();
  EXPECT_EQ(0, std::system(command.c_str())) << command;
}

}  // namespace
}  // namespace impactid
