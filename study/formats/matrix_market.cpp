#include "study/formats/matrix_market.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace impactid {
namespace {

constexpr long kProgressEvery = 1L << 20;
// Dimensions beyond this are refused before anything is allocated: ten million DOFs is a
// hundred times the largest model issue 20 asks to measure, and the limit keeps a stray size
// line from asking for gigabytes.
constexpr long kMaxDimension = 10'000'000;
// Storage reserved ahead of the entries at most (a size line may announce more than follow).
constexpr long kMaxReserve = 1L << 22;

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// Whitespace-separated fields of a line.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > begin) out.push_back(line.substr(begin, i - begin));
  }
  return out;
}

// A file read line by line, each error naming the file and the line.
class MarketReader {
 public:
  MarketReader(std::istream& in, std::string name) : name_(std::move(name)), in_(in) {}

  [[noreturn]] void fail_file(const std::string& what) const {
    throw MatrixMarketError(name_ + ": " + what);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw MatrixMarketError(name_ + ":" + std::to_string(line_number_) + ": " + what);
  }

  // The next line that is neither blank nor a comment; nothing at the end of the file.
  std::optional<std::vector<std::string_view>> next_data_line() {
    while (std::getline(in_, line_)) {
      ++line_number_;
      const std::vector<std::string_view> f = fields(line_);
      if (f.empty() || f[0].front() == '%') continue;
      return f;
    }
    return std::nullopt;
  }
  // The banner, the file's first line.
  std::vector<std::string_view> first_line() {
    if (!std::getline(in_, line_))
      fail_file("is empty: a Matrix Market file starts with %%MatrixMarket");
    line_number_ = 1;
    return fields(line_);
  }

  long index(std::string_view text, long size, const char* what) const {
    long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size()) {
      fail(std::string(what) + " '" + std::string(text) + "' is not an integer");
    }
    if (value < 1 || value > size) {
      fail(std::string(what) + " " + std::string(text) + " is out of range 1.." +
           std::to_string(size));
    }
    return value - 1;
  }
  long count(std::string_view text, const char* what) const {
    long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size() || value < 0) {
      fail(std::string(what) + " '" + std::string(text) + "' is not a count (an integer >= 0)");
    }
    return value;
  }
  double number(std::string_view text) const {
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value)) {
      fail("the value '" + std::string(text) + "' is not a finite number");
    }
    return value;
  }

 private:
  std::string name_;
  std::istream& in_;
  std::string line_;
  long line_number_ = 0;
};

struct Header {
  bool coordinate = true;
  bool symmetric = false;
};

Header read_banner(MarketReader& r) {
  const std::vector<std::string_view> f = r.first_line();
  if (f.empty() || lower(f[0]) != "%%matrixmarket") {
    // Not a Matrix Market file: nothing of it is echoed, since a plan can name any file the user
    // may read (plans are trusted input, plans/README.md; but a message should not show a secret).
    r.fail(
        "is not a Matrix Market file: its first line must be the banner '%%MatrixMarket matrix "
        "<format> <field> <symmetry>'");
  }
  if (f.size() != 5 || lower(f[1]) != "matrix") {
    r.fail("the banner must read '%%MatrixMarket matrix <format> <field> <symmetry>'");
  }
  Header h;
  const std::string format = lower(f[2]), field = lower(f[3]), symmetry = lower(f[4]);
  if (format != "coordinate" && format != "array") {
    r.fail("format '" + std::string(f[2]) + "' is not coordinate or array");
  }
  h.coordinate = format == "coordinate";
  if (field != "real" && field != "integer") {
    r.fail("field '" + std::string(f[3]) +
           "' is not read: a model's matrices are real (real or integer)");
  }
  if (symmetry != "general" && symmetry != "symmetric") {
    r.fail("symmetry '" + std::string(f[4]) + "' is not read: general or symmetric");
  }
  h.symmetric = symmetry == "symmetric";
  return h;
}

}  // namespace

Eigen::SparseMatrix<double> read_matrix_market(const std::filesystem::path& path,
                                               const MatrixMarketProgress& progress) {
  std::ifstream in(path);
  if (!in) throw MatrixMarketError(path.string() + ": cannot open the file");
  return read_matrix_market(in, path.string(), progress);
}

Eigen::SparseMatrix<double> read_matrix_market(std::istream& in, const std::string& name,
                                               const MatrixMarketProgress& progress) {
  MarketReader r(in, name);
  const Header h = read_banner(r);
  const auto size = r.next_data_line();
  if (!size) r.fail_file("ends before its size line");
  if (size->size() != (h.coordinate ? 3u : 2u)) {
    r.fail(h.coordinate ? "the size line must read '<rows> <columns> <entries>'"
                        : "the size line must read '<rows> <columns>'");
  }
  const long rows = r.count((*size)[0], "the row count");
  const long cols = r.count((*size)[1], "the column count");
  // A model's matrix has at least one unknown; an empty one is a truncated or mistaken file.
  if (rows == 0 || cols == 0) {
    r.fail("a matrix of " + std::to_string(rows) + " x " + std::to_string(cols) +
           " has no entries; a model's matrix needs at least one row and one column");
  }
  if (rows > kMaxDimension || cols > kMaxDimension) {
    r.fail("a matrix of " + std::to_string(rows) + " x " + std::to_string(cols) +
           " is beyond the " + std::to_string(kMaxDimension) + " rows and columns read here");
  }
  if (h.symmetric && rows != cols) {
    r.fail("a symmetric matrix must be square, not " + std::to_string(rows) + " x " +
           std::to_string(cols));
  }
  // Array format: every entry, column by column (a symmetric file: the lower triangle).
  const long entries = h.coordinate  ? r.count((*size)[2], "the entry count")
                       : h.symmetric ? rows * (rows + 1) / 2
                                     : rows * cols;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(
      static_cast<std::size_t>(std::min(entries, kMaxReserve) * (h.symmetric ? 2 : 1)));
  long row = 0, col = 0;  // the next array entry
  for (long k = 0; k < entries; ++k) {
    const auto f = r.next_data_line();
    if (!f) {
      r.fail_file("ends after " + std::to_string(k) + " of the " + std::to_string(entries) +
                  " entries its size line announces");
    }
    long i = row, j = col;
    double value = 0.0;
    if (h.coordinate) {
      if (f->size() != 3) r.fail("an entry must read '<row> <column> <value>'");
      i = r.index((*f)[0], rows, "the row");
      j = r.index((*f)[1], cols, "the column");
      value = r.number((*f)[2]);
    } else {
      if (f->size() != 1) r.fail("an array entry is one value per line");
      value = r.number((*f)[0]);
      if (++row == rows) col += 1, row = h.symmetric ? col : 0;
    }
    if (h.symmetric && i < j) {
      r.fail("entry (" + std::to_string(i + 1) + ", " + std::to_string(j + 1) +
             ") lies above the diagonal: a symmetric file stores the lower triangle");
    }
    if (h.coordinate || value != 0.0) {  // an array's zeros are not entries of the sparse matrix
      triplets.emplace_back(i, j, value);
      if (h.symmetric && i != j) triplets.emplace_back(j, i, value);
    }
    if (progress && (k + 1) % kProgressEvery == 0) progress(k + 1, entries);
  }
  if (r.next_data_line()) {
    r.fail("an entry beyond the " + std::to_string(entries) + " its size line announces");
  }
  if (progress) progress(entries, entries);
  Eigen::SparseMatrix<double> m(rows, cols);
  m.setFromTriplets(triplets.begin(), triplets.end());  // repeated entries are summed
  return m;
}

Eigen::VectorXd read_matrix_market_vector(const std::filesystem::path& path) {
  const Eigen::SparseMatrix<double> m = read_matrix_market(path);
  if (m.cols() != 1) {
    throw MatrixMarketError(path.string() + ": a vector is a matrix of one column, not " +
                            std::to_string(m.rows()) + " x " + std::to_string(m.cols()));
  }
  return Eigen::VectorXd(m.col(0));
}

}  // namespace impactid
