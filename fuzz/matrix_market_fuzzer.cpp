// libFuzzer target: any bytes as a Matrix Market file (study/formats/matrix_market.hpp, issue 20's
// model input).
//
// The contract under test: read_matrix_market() either returns a matrix or throws
// MatrixMarketError, whose message names the input. A crash, a sanitizer report, a hang, an
// out-of-memory, or an exception of any other type (std::bad_alloc from a size line taken at its
// word, std::length_error…) is a finding. Promises of a returned matrix, checked here: its
// dimensions are within the reader's limit, every stored value is finite, and a file with
// "symmetric" in its banner gives a symmetric matrix.
//
// Run it with scripts/fuzz; seeds: fuzz/corpus/matrix_market/, dictionary fuzz/mtx.dict.
#include <Eigen/SparseCore>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <typeinfo>

#include "study/formats/matrix_market.hpp"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "matrix_market_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  try {
    const Eigen::SparseMatrix<double> m = impactid::read_matrix_market(in, "input.mtx");
    if (m.rows() > 10'000'000 || m.cols() > 10'000'000) finding("dimensions beyond the limit");
    for (int k = 0; k < m.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(m, k); it; ++it) {
        if (!std::isfinite(it.value())) finding("a stored value is not finite");
      }
    }
    const std::string banner = text.substr(0, text.find('\n'));
    const bool symmetric = banner.find("symmetric") != std::string::npos ||
                           banner.find("Symmetric") != std::string::npos ||
                           banner.find("SYMMETRIC") != std::string::npos;
    if (symmetric) {
      const Eigen::SparseMatrix<double> t = m.transpose();
      if ((m - t).norm() != 0.0) finding("a symmetric file gave an unsymmetric matrix");
    }
  } catch (const impactid::MatrixMarketError& e) {
    if (std::string(e.what()).rfind("input.mtx:", 0) != 0) {
      finding(std::string("an error that does not name the input: ") + e.what());
    }
  } catch (const std::exception& e) {
    finding(std::string("an exception other than MatrixMarketError: ") + typeid(e).name() + ": " +
            e.what());
  }
  return 0;
}
