// The error every reader and writer of HDF5 files throws (study/formats/hdf5_file.hpp,
// study/formats/first_read.hpp): a message naming the file and the object.
#pragma once

#include <stdexcept>

namespace impactid {

struct Hdf5Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace impactid
