// Matrix Market files, the exchange format of NIST's Matrix Market
// (https://math.nist.gov/MatrixMarket/formats.html): the input of a user's own model (issue 20:
// M, K and C of a finite element model, its initial displacement and velocity), as
// scipy.io.mmwrite, Eigen's saveMarket and the common FE codes write them.
//
//   %%MatrixMarket matrix coordinate real symmetric      <- the banner: format, field, symmetry
//   % comments                                           <- any number, and blank lines
//   3 3 4                                                <- rows, columns, stored entries
//   1 1 2.0                                              <- row, column (1-based), value
//   2 1 -1.0                                             <- symmetric: the lower triangle only
//   ...
//
// Read: format coordinate or array, field real or integer, symmetry general or symmetric (the
// stored triangle is mirrored). Not read, with an error saying so: pattern and complex fields,
// skew-symmetric and hermitian symmetry. Repeated coordinate entries are summed, as
// scipy.io.mmread and Eigen's loadMarket do. At most 10^7 rows and columns. Why not Eigen's
// loadMarket (unsupported/SparseExtra, installed): it reports a bad file as `false`, where a user
// needs the line and the value.
//
// Thread safety: free functions.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <filesystem>
#include <functional>
#include <istream>
#include <stdexcept>
#include <string>

namespace impactid {

/// A file that cannot be read as a matrix: what() says "FILE:LINE: " (or "FILE: " when no line
/// is to blame), what is wrong and the bad value.
struct MatrixMarketError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Progress of a long read: entries read so far, of the total the size line announces. Called
/// every 2^20 entries and once at the end.
using MatrixMarketProgress = std::function<void(long read, long total)>;

/// The matrix of a Matrix Market file (coordinate or array format); a symmetric file's triangle
/// is mirrored, so the matrix returned is whole. Throws MatrixMarketError.
Eigen::SparseMatrix<double> read_matrix_market(const std::filesystem::path& path,
                                               const MatrixMarketProgress& progress = {});
/// The same from a stream; errors name it `name` (the fuzzer's entry: fuzz/).
Eigen::SparseMatrix<double> read_matrix_market(std::istream& in, const std::string& name,
                                               const MatrixMarketProgress& progress = {});

/// A vector: a Matrix Market matrix of one column (array format as scipy writes a 1-D array, or
/// coordinate format with absent entries zero). Throws MatrixMarketError, also when the file has
/// more than one column.
Eigen::VectorXd read_matrix_market_vector(const std::filesystem::path& path);

}  // namespace impactid
