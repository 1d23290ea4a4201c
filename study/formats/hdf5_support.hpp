// What the HDF5 writer and reader (study/formats/hdf5_file.hpp) share: HDF5's failures turned
// into Hdf5Error naming the file and the object, the names of links and attributes, and the
// checksum of attributes and text. Used only inside study/formats/.
#pragma once

#include <H5Cpp.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "study/formats/hdf5_error.hpp"
#include "study/formats/hdf5_file.hpp"

namespace impactid::hdf5_support {

H5::StrType utf8_string_type();

hsize_t element_count(const Hdf5Dims& dims);

/// HDF5's message for a failed call, with the most specific reason on its error stack.
std::string failure_text(const H5::Exception& e);

/// True when HDF5's error stack reports a checksum that does not match its data.
bool checksum_failed();

/// "FILE: OBJECT: data corrupted: …".
std::string corrupted(const std::filesystem::path& file, const std::string& object);

// A read refused by a checksum. HDF5's error stack, which says so, is cleared by the next HDF5
// call, such as closing the dataset as the exception leaves its scope: the read is checked
// where it fails (checked_read, inside the scope of the objects it reads through) and carried
// out as this.
struct ChecksumMismatch : H5::Exception {
  ChecksumMismatch() : H5::Exception("read", "checksum mismatch") {}
};

template <class Fn>
auto checked_read(Fn&& read) {
  try {
    return read();
  } catch (const H5::Exception&) {
    if (checksum_failed()) throw ChecksumMismatch();
    throw;
  }
}

template <class Fn>
auto guarded(const std::filesystem::path& file, const std::string& object, Fn&& fn) {
  try {
    return fn();
  } catch (const ChecksumMismatch&) {
    throw Hdf5Error(corrupted(file, object));
  } catch (const H5::Exception& e) {
    if (checksum_failed()) throw Hdf5Error(corrupted(file, object));
    throw Hdf5Error(file.string() + ": " + object + ": " + failure_text(e));
  }
}

// Opens a group or a dataset, whichever the path names, as the common H5Object.
template <class Fn>
auto with_object(H5::H5File& file, const std::string& path, Fn&& fn) {
  if (path == "/") {
    H5::Group root = file.openGroup("/");
    return checked_read([&] { return fn(static_cast<H5::H5Object&>(root)); });
  }
  if (file.childObjType(path) == H5O_TYPE_GROUP) {
    H5::Group group = file.openGroup(path);
    return checked_read([&] { return fn(static_cast<H5::H5Object&>(group)); });
  }
  H5::DataSet dataset = file.openDataSet(path);
  return checked_read([&] { return fn(static_cast<H5::H5Object&>(dataset)); });
}

// The C API (H5P, H5L, H5A, H5DS) reports failure by a negative return; turn it into the C++
// API's exception so guarded() names the file.
template <class T>
T checked(T result, const char* function) {
  if (result < 0) throw H5::Exception(function, std::string(function) + " failed");
  return result;
}

/// Link or attribute creation-order flags of a group or dataset (0 when not tracked).
unsigned creation_order_flags(hid_t object, bool attributes);

/// The names of a group's links, or of an object's attributes, ordered by `index` (hdf5_support.cpp
/// says why they are read by native iteration).
std::vector<std::string> link_names(hid_t group, H5_index_t index);
std::vector<std::string> attribute_names_of(hid_t object, H5_index_t index);

/// Opens an attribute that must hold one value (an array attribute would overrun the one read).
H5::Attribute open_scalar_attribute(H5::H5Object& object, const std::string& name);

/// The CRC-32 of everything in a file that HDF5's own checksums miss (hdf5_file.hpp says what).
std::uint32_t metadata_checksum(H5::H5File& file);

}  // namespace impactid::hdf5_support
