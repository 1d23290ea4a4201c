// The Matrix Market reader (issue 20's input) against hand-written files: symmetric and general
// storage, coordinate and array format, comments and blank lines; and the error of every bad
// file names the file, the line and the value.
#include "study/formats/matrix_market.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <string>
#include <utility>
#include <vector>

#include "test_files.hpp"

namespace impactid {
namespace {

using testing::scratch_path;
using testing::write_file;

std::filesystem::path file(const std::string& name, const std::string& text) {
  return write_file(scratch_path("matrix_market", name), text);
}

// The message of the MatrixMarketError that reading `text` throws.
std::string error_of(const std::string& text) {
  try {
    read_matrix_market(file("bad.mtx", text));
  } catch (const MatrixMarketError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MatrixMarket, SymmetricCoordinateWithCommentsAndBlankLines) {
  // The paper rod's lumped stiffness pattern on 3 nodes, lower triangle, as scipy.io.mmwrite
  // writes a symmetric matrix (comment lines, then the size line).
  const auto path = file("k.mtx",
                         "%%MatrixMarket matrix coordinate real symmetric\n"
                         "%\n"
                         "% stiffness [N/mm]\n"
                         "\n"
                         "3 3 5\n"
                         "1 1 4.5\n"
                         "2 1 -4.5\n"
                         "2 2 9.0\n"
                         "3 2 -4.5\n"
                         "   3 3   4.5e0  \n"
                         "\n");
  const Eigen::MatrixXd k(read_matrix_market(path));
  Eigen::MatrixXd expected(3, 3);
  expected << 4.5, -4.5, 0.0, -4.5, 9.0, -4.5, 0.0, -4.5, 4.5;
  EXPECT_EQ(k, expected);
}

TEST(MatrixMarket, GeneralCoordinateSumsRepeatedEntries) {
  const auto path = file("g.mtx",
                         "%%MatrixMarket matrix coordinate real general\n"
                         "2 3 4\n"
                         "1 3 1.5\n"
                         "2 1 -2\n"
                         "1 3 0.25\n"
                         "2 2 1e-3\n");
  const Eigen::MatrixXd g(read_matrix_market(path));
  Eigen::MatrixXd expected(2, 3);
  expected << 0.0, 0.0, 1.75, -2.0, 0.001, 0.0;
  EXPECT_EQ(g, expected);
}

TEST(MatrixMarket, ArrayFormatIsColumnMajorAndASymmetricArrayItsLowerTriangle) {
  const Eigen::MatrixXd a(read_matrix_market(file("a.mtx",
                                                  "%%MatrixMarket matrix array real general\n"
                                                  "2 2\n1\n2\n3\n4\n")));
  Eigen::MatrixXd expected(2, 2);
  expected << 1, 3, 2, 4;
  EXPECT_EQ(a, expected);
  const Eigen::MatrixXd s(read_matrix_market(file("s.mtx",
                                                  "%%MatrixMarket matrix array integer symmetric\n"
                                                  "3 3\n1\n2\n3\n4\n5\n6\n")));
  Eigen::MatrixXd lower(3, 3);
  lower << 1, 2, 3, 2, 4, 5, 3, 5, 6;
  EXPECT_EQ(s, lower);
}

TEST(MatrixMarket, VectorsInEitherFormat) {
  EXPECT_EQ(read_matrix_market_vector(file("v.mtx",
                                           "%%MatrixMarket matrix array real general\n"
                                           "% initial velocity [mm/s]\n3 1\n1000\n1000\n0\n")),
            Eigen::Vector3d(1000.0, 1000.0, 0.0));
  EXPECT_EQ(read_matrix_market_vector(file("c.mtx",
                                           "%%MatrixMarket matrix coordinate real general\n"
                                           "4 1 1\n3 1 -2.5\n")),
            Eigen::Vector4d(0.0, 0.0, -2.5, 0.0));
  try {
    read_matrix_market_vector(
        file("m.mtx", "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n4\n"));
    ADD_FAILURE() << "a 2 x 2 matrix was read as a vector";
  } catch (const MatrixMarketError& e) {
    EXPECT_NE(std::string(e.what()).find("not 2 x 2"), std::string::npos) << e.what();
  }
}

// Issue 38: a plan naming /etc/passwd as a matrix made the message show its first line. A file
// that is not a Matrix Market file is refused without a word of its content.
TEST(MatrixMarket, AFileThatIsNotOneIsNotEchoed) {
  const std::string message = error_of("root:secret-token:0:0:root:/root:/bin/bash\n");
  EXPECT_NE(message.find("is not a Matrix Market file"), std::string::npos) << message;
  EXPECT_EQ(message.find("secret-token"), std::string::npos) << message;
}

TEST(MatrixMarket, BadFilesNameTheFileTheLineAndTheValue) {
  const std::string banner = "%%MatrixMarket matrix coordinate real general\n";
  const std::string path = scratch_path("matrix_market", "bad.mtx").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", path + ": is empty"},
      {"3 3 1\n1 1 1\n", path + ":1: is not a Matrix Market file"},
      {"%%MatrixMarket matrix coordinate complex general\n",
       path + ":1: field 'complex' is not read"},
      {"%%MatrixMarket matrix coordinate pattern general\n",
       path + ":1: field 'pattern' is not read"},
      {"%%MatrixMarket matrix coordinate real hermitian\n",
       path + ":1: symmetry 'hermitian' is not read"},
      {"%%MatrixMarket matrix dense real general\n",
       path + ":1: format 'dense' is not coordinate or array"},
      {"%%MatrixMarket matrix coordinate real symmetric\n2 3 1\n",
       path + ":2: a symmetric matrix must be square, not 2 x 3"},
      {banner + "% c\n2 2\n", path + ":3: the size line must read '<rows> <columns> <entries>'"},
      {banner + "2 2 x\n", path + ":2: the entry count 'x' is not a count"},
      {banner + "2 2 2\n1 1 1.0\n2 2 abc\n", path + ":4: the value 'abc' is not a finite number"},
      {banner + "2 2 1\n1 1 inf\n", path + ":3: the value 'inf' is not a finite number"},
      {banner + "2 2 1\n3 1 1.0\n", path + ":3: the row 3 is out of range 1..2"},
      {banner + "2 2 1\n1 0 1.0\n", path + ":3: the column 0 is out of range 1..2"},
      {banner + "2 2 1\n1 1.5 1.0\n", path + ":3: the column '1.5' is not an integer"},
      {banner + "2 2 1\n1 1\n", path + ":3: an entry must read '<row> <column> <value>'"},
      {banner + "2 2 3\n1 1 1\n2 2 1\n", path + ": ends after 2 of the 3 entries"},
      {banner + "2 2 1\n1 1 1\n2 2 1\n",
       path + ":4: an entry beyond the 1 its size line announces"},
      {banner + "1 20000000 0\n", path + ":2: a matrix of 1 x 20000000 is beyond the 10000000"},
      {"%%MatrixMarket matrix array integer symmetric\n0000 \v000\n",
       path + ":2: a matrix of 0 x 0 has no entries"},
      {banner + "3 0 0\n", path + ":2: a matrix of 3 x 0 has no entries"},
      {"%%MatrixMarket matrix array real general\n9223372036854775807 2\n",
       path + ":2: a matrix of 9223372036854775807 x 2 is beyond"},
      {"%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 2 1.0\n",
       path + ":3: entry (1, 2) lies above the diagonal"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = error_of(text);
    EXPECT_EQ(message.rfind(expected, 0), 0u) << "got: " << message << "\nexpected: " << expected;
  }
  try {
    read_matrix_market(scratch_path("matrix_market", "missing.mtx"));
    ADD_FAILURE() << "a missing file was read";
  } catch (const MatrixMarketError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.mtx: cannot open the file"), std::string::npos);
  }
}

TEST(MatrixMarket, ProgressReachesTheTotal) {
  long last_read = -1, last_total = -1;
  read_matrix_market(
      file("p.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n2 2 1\n"),
      [&](long read, long total) {
        last_read = read;
        last_total = total;
      });
  EXPECT_EQ(last_read, 2);
  EXPECT_EQ(last_total, 2);
}

}  // namespace
}  // namespace impactid
