#include "study/formats/hdf5_file.hpp"

#include <H5DSpublic.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <numeric>
#include <system_error>

namespace impactid {
namespace {

// HDF5's C++ API throws; its default is also to print a stack to stderr. We report errors
// ourselves, once, with the file named.
struct QuietHdf5 {
  QuietHdf5() { H5::Exception::dontPrint(); }
};
const QuietHdf5 quiet_hdf5;

H5::StrType utf8_string_type() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

hsize_t element_count(const Hdf5Dims& dims) {
  return std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
}

// The C++ API's message names only the failed call ("H5Fopen failed"); HDF5's error stack still
// holds the most specific reason ("truncated file: eof = …", "… errno = 13, error message =
// 'Permission denied' …"), which is added when there is one.
std::string failure_text(const H5::Exception& e) {
  std::string innermost;
  const H5E_walk2_t first = [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
    if (n == 0 && error->desc) *static_cast<std::string*>(data) = error->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, first, &innermost);
  const std::string detail = e.getDetailMsg();
  return innermost.empty() || innermost == detail ? detail : detail + " (" + innermost + ")";
}

template <class Fn>
auto guarded(const std::filesystem::path& file, const std::string& object, Fn&& fn) {
  try {
    return fn();
  } catch (const H5::Exception& e) {
    throw Hdf5Error(file.string() + ": " + object + ": " + failure_text(e));
  }
}

// Opens a group or a dataset, whichever the path names, as the common H5Object.
template <class Fn>
auto with_object(H5::H5File& file, const std::string& path, Fn&& fn) {
  if (path == "/") {
    H5::Group root = file.openGroup("/");
    return fn(static_cast<H5::H5Object&>(root));
  }
  if (file.childObjType(path) == H5O_TYPE_GROUP) {
    H5::Group group = file.openGroup(path);
    return fn(static_cast<H5::H5Object&>(group));
  }
  H5::DataSet dataset = file.openDataSet(path);
  return fn(static_cast<H5::H5Object&>(dataset));
}

H5::Attribute replace_attribute(H5::H5Object& object, const std::string& name,
                                const H5::DataType& type, const H5::DataSpace& space) {
  if (object.attrExists(name)) object.removeAttr(name);
  return object.createAttribute(name, type, space);
}

// The C API (H5P, H5L, H5A, H5DS) reports failure by a negative return; turn it into the C++
// API's exception so guarded() names the file.
template <class T>
T checked(T result, const char* function) {
  if (result < 0) throw H5::Exception(function, "failed");
  return result;
}

constexpr unsigned kCreationOrder = H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED;

// Every dataset tracks its attributes' creation order, as netCDF-4 does.
H5::DSetCreatPropList dataset_properties() {
  H5::DSetCreatPropList properties;
  properties.setAttrCrtOrder(kCreationOrder);
  return properties;
}

// Chunks of at most 2^16 elements (512 KB of doubles, inside HDF5's default 1 MB chunk cache),
// whole along the last dimensions first, so that a row-major table is cut into runs of
// consecutive points.
Hdf5Dims chunk_shape(const Hdf5Dims& dims) {
  Hdf5Dims chunk(dims.size(), 1);
  hsize_t budget = hsize_t{1} << 16;
  for (std::size_t d = dims.size(); d-- > 0 && budget > 1;) {
    chunk[d] = std::min(dims[d], budget);
    budget /= chunk[d];
  }
  return chunk;
}

template <class T>
void write_numeric_dataset(H5::H5File& file, const std::filesystem::path& path,
                           const std::string& name, std::span<const T> data, const Hdf5Dims& dims,
                           const H5::PredType& type, bool compressed) {
  if (element_count(dims) != data.size()) {
    throw Hdf5Error(path.string() + ": " + name + ": data size does not match its shape");
  }
  guarded(path, name, [&] {
    H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    H5::DSetCreatPropList properties = dataset_properties();
    if (compressed && !dims.empty() && data.size() >= 4096) {
      const Hdf5Dims chunk = chunk_shape(dims);
      properties.setChunk(static_cast<int>(chunk.size()), chunk.data());
      properties.setShuffle();
      properties.setDeflate(1);
    }
    H5::DataSet d = file.createDataSet(name, type, space, properties);
    if (!data.empty()) d.write(data.data(), type);  // a zero-size dataset has nothing to write
  });
}

template <class T>
std::vector<T> read_numeric_dataset(H5::H5File& file, const std::string& name,
                                    const H5::PredType& type) {
  H5::DataSet d = file.openDataSet(name);
  std::vector<T> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
  if (!out.empty()) d.read(out.data(), type);
  return out;
}

// Link or attribute creation-order flags of a group or dataset (0 when not tracked).
unsigned creation_order_flags(hid_t object, bool attributes) {
  hid_t properties = H5I_INVALID_HID;
  switch (H5Iget_type(object)) {
    case H5I_GROUP:
      properties = H5Gget_create_plist(object);
      break;
    case H5I_DATASET:
      properties = H5Dget_create_plist(object);
      break;
    default:
      return 0;
  }
  checked(properties, "H5Xget_create_plist");
  unsigned flags = 0;
  const herr_t status = attributes ? H5Pget_attr_creation_order(properties, &flags)
                                   : H5Pget_link_creation_order(properties, &flags);
  H5Pclose(properties);
  checked(status, "H5Pget_creation_order");
  return flags;
}

// Reads a name with the C API's two-call protocol (size first, then the text).
template <class Fn>
std::string c_name(Fn&& get, const char* function) {
  const auto size = checked(get(static_cast<char*>(nullptr), std::size_t{0}), function);
  std::string name(static_cast<std::size_t>(size), '\0');
  checked(get(name.data(), name.size() + 1), function);
  return name;
}

// Grows the in-memory file in steps of 1 MB (HDF5's suggestion for the core driver).
constexpr std::size_t kMemoryIncrement = std::size_t{1} << 20;

// Writes `bytes` as the file `path` (created or truncated) and forces them to disk, so the
// rename that follows cannot outlive them. Every failure (no space left, a read-only file
// system, a quota, an interrupted write) comes back as the error, with the file left to the
// caller to remove.
std::error_code write_to_disk(const std::filesystem::path& path, const std::vector<char>& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return {errno, std::generic_category()};
  std::error_code ec;
  std::size_t done = 0;
  while (done < bytes.size() && !ec) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
    } else if (n < 0 && errno != EINTR) {
      ec = {errno, std::generic_category()};
    } else if (n == 0) {
      ec = std::make_error_code(std::errc::io_error);
    }
  }
  if (!ec && ::fsync(fd) != 0) ec = {errno, std::generic_category()};
  if (::close(fd) != 0 && !ec) ec = {errno, std::generic_category()};
  return ec;
}

// Forces a closed file's data to disk, so the rename that follows cannot outlive it.
std::error_code sync_to_disk(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return {errno, std::generic_category()};
  std::error_code ec;
  if (::fsync(fd) != 0) ec = {errno, std::generic_category()};
  ::close(fd);
  return ec;
}

// Reading a scalar into one value: an array attribute (a foreign or edited file) would
// overrun it, so it is rejected instead.
H5::Attribute open_scalar_attribute(H5::H5Object& object, const std::string& name) {
  H5::Attribute a = object.openAttribute(name);
  if (a.getSpace().getSimpleExtentNpoints() != 1) {
    throw H5::Exception(
        "openAttribute",
        "holds " + std::to_string(a.getSpace().getSimpleExtentNpoints()) + " values, expected one");
  }
  return a;
}

}  // namespace

Hdf5Writer::Hdf5Writer(std::filesystem::path path) : path_(std::move(path)) {
  temporary_ = path_;
  temporary_ += ".tmp";
  std::error_code ec;
  if (path_.has_parent_path()) {
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) {
      throw Hdf5Error(path_.string() + ": cannot create the folder " +
                      path_.parent_path().string() + ": " + ec.message());
    }
  }
  guarded(path_, "creating the file in memory", [&] {
    // Tracked creation order keeps the root group's datasets and attributes in written order.
    H5::FileCreatPropList properties;
    checked(H5Pset_link_creation_order(properties.getId(), kCreationOrder),
            "H5Pset_link_creation_order");
    checked(H5Pset_attr_creation_order(properties.getId(), kCreationOrder),
            "H5Pset_attr_creation_order");
    // The core driver without a backing store: the file lives in memory until commit() writes
    // its image (see the header: HDF5 never writes to the disk itself).
    H5::FileAccPropList access;
    access.setCore(kMemoryIncrement, false);
    file_.emplace(temporary_.string(), H5F_ACC_TRUNC, properties, access);
  });
}

Hdf5Writer::~Hdf5Writer() {
  if (file_) {
    try {
      file_->close();  // in memory: nothing reaches the disk
    } catch (...) {
    }
  }
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, double value) {
  guarded(path_, object + "@" + name, [&] {
    with_object(*file_, object, [&](H5::H5Object& o) {
      replace_attribute(o, name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR))
          .write(H5::PredType::NATIVE_DOUBLE, &value);
    });
  });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, long value) {
  guarded(path_, object + "@" + name, [&] {
    with_object(*file_, object, [&](H5::H5Object& o) {
      replace_attribute(o, name, H5::PredType::NATIVE_LONG, H5::DataSpace(H5S_SCALAR))
          .write(H5::PredType::NATIVE_LONG, &value);
    });
  });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           const std::string& value) {
  guarded(path_, object + "@" + name, [&] {
    with_object(*file_, object, [&](H5::H5Object& o) {
      const H5::StrType type = utf8_string_type();
      replace_attribute(o, name, type, H5::DataSpace(H5S_SCALAR)).write(type, value);
    });
  });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           std::span<const double> values) {
  guarded(path_, object + "@" + name, [&] {
    with_object(*file_, object, [&](H5::H5Object& o) {
      const hsize_t n = values.size();
      replace_attribute(o, name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n))
          .write(H5::PredType::NATIVE_DOUBLE, values.data());
    });
  });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           std::span<const int> values) {
  guarded(path_, object + "@" + name, [&] {
    with_object(*file_, object, [&](H5::H5Object& o) {
      const hsize_t n = values.size();
      H5::Attribute a = replace_attribute(o, name, H5::PredType::NATIVE_INT, H5::DataSpace(1, &n));
      if (n > 0) a.write(H5::PredType::NATIVE_INT, values.data());
    });
  });
}

void Hdf5Writer::group(const std::string& path) {
  guarded(path_, path, [&] { file_->createGroup(path); });
}

void Hdf5Writer::dataset(const std::string& path, std::span<const double> data,
                         const Hdf5Dims& dims) {
  write_numeric_dataset(*file_, path_, path, data, dims, H5::PredType::NATIVE_DOUBLE, compressed_);
}

void Hdf5Writer::dataset(const std::string& path, std::span<const long> data,
                         const Hdf5Dims& dims) {
  write_numeric_dataset(*file_, path_, path, data, dims, H5::PredType::NATIVE_LONG, compressed_);
}

void Hdf5Writer::dataset(const std::string& path, std::span<const int> data, const Hdf5Dims& dims) {
  write_numeric_dataset(*file_, path_, path, data, dims, H5::PredType::NATIVE_INT, compressed_);
}

void Hdf5Writer::dataset(const std::string& path, const std::vector<std::string>& data) {
  guarded(path_, path, [&] {
    std::vector<const char*> pointers;
    pointers.reserve(data.size());
    for (const auto& s : data) pointers.push_back(s.c_str());
    const hsize_t n = data.size();
    const H5::StrType type = utf8_string_type();
    H5::DataSet d = file_->createDataSet(path, type, H5::DataSpace(1, &n), dataset_properties());
    if (n > 0) d.write(pointers.data(), type);
  });
}

void Hdf5Writer::dimension_scale(const std::string& scale, const std::string& dimension) {
  guarded(path_, scale, [&] {
    H5::DataSet d = file_->openDataSet(scale);
    if (H5DSset_scale(d.getId(), dimension.c_str()) < 0) {
      throw H5::Exception("H5DSset_scale", "cannot mark as a dimension scale");
    }
  });
}

void Hdf5Writer::attach_scale(const std::string& dataset, const std::string& scale,
                              unsigned index) {
  guarded(path_, dataset, [&] {
    H5::DataSet d = file_->openDataSet(dataset);
    H5::DataSet s = file_->openDataSet(scale);
    if (H5DSattach_scale(d.getId(), s.getId(), index) < 0) {
      throw H5::Exception("H5DSattach_scale", "cannot attach " + scale);
    }
  });
}

void Hdf5Writer::commit() {
  const std::vector<char> image = guarded(path_, "/", [&] {
    file_->flush(H5F_SCOPE_GLOBAL);
    const ssize_t size = checked(H5Fget_file_image(file_->getId(), nullptr, 0), "H5Fget_file_image");
    std::vector<char> bytes(static_cast<std::size_t>(size));
    checked(H5Fget_file_image(file_->getId(), bytes.data(), bytes.size()), "H5Fget_file_image");
    return bytes;
  });
  guarded(path_, "/", [&] { file_->close(); });
  file_.reset();
  std::error_code ec;
  const auto fail = [&](const std::string& message) {
    std::filesystem::remove(temporary_, ec);
    throw Hdf5Error(message);
  };
  if (const std::error_code written = write_to_disk(temporary_, image)) {
    fail(path_.string() + ": cannot write " + temporary_.string() + ": " + written.message());
  }
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) {
    fail("cannot move " + temporary_.string() + " to " + path_.string() + ": " + ec.message());
  }
  // Best effort: makes the rename itself durable; the new file is complete either way.
  const std::filesystem::path folder = path_.has_parent_path() ? path_.parent_path() : ".";
  sync_to_disk(folder, O_RDONLY | O_DIRECTORY);
}

Hdf5Reader::Hdf5Reader(const std::filesystem::path& path) : path_(path) {
  if (!std::filesystem::exists(path)) throw Hdf5Error(path.string() + ": no such file");
  try {
    file_.openFile(path.string(), H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    throw Hdf5Error(path.string() +
                    ": not a readable HDF5 file (truncated or corrupt?): " + failure_text(e));
  }
}

bool Hdf5Reader::exists(const std::string& path) const {
  return guarded(path_, path, [&] { return path == "/" || file_.nameExists(path); });
}

std::vector<std::string> Hdf5Reader::members(const std::string& group) const {
  return guarded(path_, group, [&] {
    H5::Group g = file_.openGroup(group);
    const H5_index_t index = (creation_order_flags(g.getId(), false) & H5P_CRT_ORDER_TRACKED)
                                 ? H5_INDEX_CRT_ORDER
                                 : H5_INDEX_NAME;
    std::vector<std::string> names;
    for (hsize_t i = 0; i < g.getNumObjs(); ++i) {
      names.push_back(c_name(
          [&](char* buffer, std::size_t size) {
            return H5Lget_name_by_idx(g.getId(), ".", index, H5_ITER_INC, i, buffer, size,
                                      H5P_DEFAULT);
          },
          "H5Lget_name_by_idx"));
    }
    return names;
  });
}

Hdf5Dims Hdf5Reader::shape(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    const H5::DataSpace space = file_.openDataSet(dataset).getSpace();
    Hdf5Dims dims(static_cast<std::size_t>(space.getSimpleExtentNdims()));
    space.getSimpleExtentDims(dims.data());
    return dims;
  });
}

std::vector<double> Hdf5Reader::doubles(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    return read_numeric_dataset<double>(file_, dataset, H5::PredType::NATIVE_DOUBLE);
  });
}

std::vector<long> Hdf5Reader::longs(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    return read_numeric_dataset<long>(file_, dataset, H5::PredType::NATIVE_LONG);
  });
}

std::vector<int> Hdf5Reader::ints(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    return read_numeric_dataset<int>(file_, dataset, H5::PredType::NATIVE_INT);
  });
}

std::vector<std::string> Hdf5Reader::strings(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    H5::DataSet d = file_.openDataSet(dataset);
    const auto n = static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints());
    std::vector<char*> pointers(n, nullptr);
    const H5::StrType type = utf8_string_type();
    if (n > 0) d.read(pointers.data(), type);
    std::vector<std::string> out;
    for (char* p : pointers) {
      out.emplace_back(p ? p : "");
      std::free(p);
    }
    return out;
  });
}

bool Hdf5Reader::has_attribute(const std::string& object, const std::string& name) const {
  return guarded(path_, object, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) { return o.attrExists(name); });
  });
}

double Hdf5Reader::attribute_double(const std::string& object, const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      double v = 0;
      open_scalar_attribute(o, name).read(H5::PredType::NATIVE_DOUBLE, &v);
      return v;
    });
  });
}

long Hdf5Reader::attribute_long(const std::string& object, const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      long v = 0;
      open_scalar_attribute(o, name).read(H5::PredType::NATIVE_LONG, &v);
      return v;
    });
  });
}

std::string Hdf5Reader::attribute_string(const std::string& object, const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      H5::Attribute a = open_scalar_attribute(o, name);
      std::string v;
      a.read(a.getStrType(), v);
      return v;
    });
  });
}

std::vector<double> Hdf5Reader::attribute_doubles(const std::string& object,
                                                  const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      H5::Attribute a = o.openAttribute(name);
      std::vector<double> v(static_cast<std::size_t>(a.getSpace().getSimpleExtentNpoints()));
      a.read(H5::PredType::NATIVE_DOUBLE, v.data());
      return v;
    });
  });
}

std::vector<int> Hdf5Reader::attribute_ints(const std::string& object,
                                            const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      H5::Attribute a = o.openAttribute(name);
      std::vector<int> v(static_cast<std::size_t>(a.getSpace().getSimpleExtentNpoints()));
      if (!v.empty()) a.read(H5::PredType::NATIVE_INT, v.data());
      return v;
    });
  });
}

std::vector<std::string> Hdf5Reader::attribute_names(const std::string& object) const {
  return guarded(path_, object, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      const H5_index_t index = (creation_order_flags(o.getId(), true) & H5P_CRT_ORDER_TRACKED)
                                   ? H5_INDEX_CRT_ORDER
                                   : H5_INDEX_NAME;
      std::vector<std::string> names;
      const int count = o.getNumAttrs();
      for (int i = 0; i < count; ++i) {
        names.push_back(c_name(
            [&](char* buffer, std::size_t size) {
              return H5Aget_name_by_idx(o.getId(), ".", index, H5_ITER_INC, static_cast<hsize_t>(i),
                                        buffer, size, H5P_DEFAULT);
            },
            "H5Aget_name_by_idx"));
      }
      return names;
    });
  });
}

bool Hdf5Reader::attribute_is_text(const std::string& object, const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      return o.openAttribute(name).getTypeClass() == H5T_STRING;
    });
  });
}

bool Hdf5Reader::is_dimension_scale(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    H5::DataSet d = file_.openDataSet(dataset);
    return checked(H5DSis_scale(d.getId()), "H5DSis_scale") > 0;
  });
}

std::vector<std::string> Hdf5Reader::attached_scales(const std::string& dataset,
                                                     unsigned index) const {
  return guarded(path_, dataset, [&] {
    H5::DataSet d = file_.openDataSet(dataset);
    if (static_cast<int>(index) >= d.getSpace().getSimpleExtentNdims()) {
      throw H5::Exception("attached_scales",
                          "dimension " + std::to_string(index) + " out of range");
    }
    struct Visit {
      std::vector<std::string> names;
      bool failed = false;
    } visit;
    const H5DS_iterate_t visitor = [](hid_t, unsigned, hid_t scale, void* data) -> herr_t {
      auto* v = static_cast<Visit*>(data);
      const ssize_t size = H5Iget_name(scale, nullptr, 0);
      if (size < 0) {
        v->failed = true;
        return -1;
      }
      std::string name(static_cast<std::size_t>(size), '\0');
      H5Iget_name(scale, name.data(), name.size() + 1);
      v->names.push_back(std::move(name));
      return 0;
    };
    if (checked(H5DSget_num_scales(d.getId(), index), "H5DSget_num_scales") > 0) {
      checked(H5DSiterate_scales(d.getId(), index, nullptr, visitor, &visit), "H5DSiterate_scales");
    }
    if (visit.failed) throw H5::Exception("H5Iget_name", "cannot name a dimension scale");
    return visit.names;
  });
}

}  // namespace impactid
