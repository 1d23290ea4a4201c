#include "study/hdf5_file.hpp"

#include <H5DSpublic.h>

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

template <class Fn>
auto guarded(const std::filesystem::path& file, const std::string& object, Fn&& fn) {
  try {
    return fn();
  } catch (const H5::Exception& e) {
    throw Hdf5Error(file.string() + ": " + object + ": " + e.getDetailMsg());
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

}  // namespace

Hdf5Writer::Hdf5Writer(std::filesystem::path path) : path_(std::move(path)) {
  temporary_ = path_;
  temporary_ += ".tmp";
  std::error_code ec;
  if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path(), ec);
  guarded(temporary_, "/", [&] { file_.emplace(temporary_.string(), H5F_ACC_TRUNC); });
}

Hdf5Writer::~Hdf5Writer() {
  if (file_) {
    try {
      file_->close();
    } catch (...) {
    }
    std::error_code ec;
    std::filesystem::remove(temporary_, ec);
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

void Hdf5Writer::group(const std::string& path) {
  guarded(path_, path, [&] { file_->createGroup(path); });
}

void Hdf5Writer::dataset(const std::string& path, std::span<const double> data,
                         const Hdf5Dims& dims) {
  if (element_count(dims) != data.size()) {
    throw Hdf5Error(path_.string() + ": " + path + ": data size does not match its shape");
  }
  guarded(path_, path, [&] {
    H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    file_->createDataSet(path, H5::PredType::NATIVE_DOUBLE, space)
        .write(data.data(), H5::PredType::NATIVE_DOUBLE);
  });
}

void Hdf5Writer::dataset(const std::string& path, std::span<const long> data,
                         const Hdf5Dims& dims) {
  if (element_count(dims) != data.size()) {
    throw Hdf5Error(path_.string() + ": " + path + ": data size does not match its shape");
  }
  guarded(path_, path, [&] {
    H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    file_->createDataSet(path, H5::PredType::NATIVE_LONG, space)
        .write(data.data(), H5::PredType::NATIVE_LONG);
  });
}

void Hdf5Writer::dataset(const std::string& path, const std::vector<std::string>& data) {
  guarded(path_, path, [&] {
    std::vector<const char*> pointers;
    pointers.reserve(data.size());
    for (const auto& s : data) pointers.push_back(s.c_str());
    const hsize_t n = data.size();
    const H5::StrType type = utf8_string_type();
    file_->createDataSet(path, type, H5::DataSpace(1, &n)).write(pointers.data(), type);
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
  guarded(temporary_, "/", [&] { file_->close(); });
  file_.reset();
  std::error_code ec;
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) {
    throw Hdf5Error("cannot move " + temporary_.string() + " to " + path_.string() + ": " +
                    ec.message());
  }
}

Hdf5Reader::Hdf5Reader(const std::filesystem::path& path) : path_(path) {
  if (!std::filesystem::exists(path)) throw Hdf5Error(path.string() + ": no such file");
  try {
    file_ = H5::H5File(path.string(), H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    throw Hdf5Error(path.string() + ": not a readable HDF5 file (truncated or corrupt?): " +
                    e.getDetailMsg());
  }
}

bool Hdf5Reader::exists(const std::string& path) const {
  return guarded(path_, path, [&] { return path == "/" || file_.nameExists(path); });
}

std::vector<std::string> Hdf5Reader::members(const std::string& group) const {
  return guarded(path_, group, [&] {
    H5::Group g = file_.openGroup(group);
    std::vector<std::string> names;
    for (hsize_t i = 0; i < g.getNumObjs(); ++i) names.push_back(g.getObjnameByIdx(i));
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
    H5::DataSet d = file_.openDataSet(dataset);
    std::vector<double> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
    d.read(out.data(), H5::PredType::NATIVE_DOUBLE);
    return out;
  });
}

std::vector<long> Hdf5Reader::longs(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    H5::DataSet d = file_.openDataSet(dataset);
    std::vector<long> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
    d.read(out.data(), H5::PredType::NATIVE_LONG);
    return out;
  });
}

std::vector<std::string> Hdf5Reader::strings(const std::string& dataset) const {
  return guarded(path_, dataset, [&] {
    H5::DataSet d = file_.openDataSet(dataset);
    const auto n = static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints());
    std::vector<char*> pointers(n, nullptr);
    const H5::StrType type = utf8_string_type();
    d.read(pointers.data(), type);
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
      o.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &v);
      return v;
    });
  });
}

long Hdf5Reader::attribute_long(const std::string& object, const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      long v = 0;
      o.openAttribute(name).read(H5::PredType::NATIVE_LONG, &v);
      return v;
    });
  });
}

std::string Hdf5Reader::attribute_string(const std::string& object,
                                         const std::string& name) const {
  return guarded(path_, object + "@" + name, [&] {
    H5::H5File& file = file_;
    return with_object(file, object, [&](H5::H5Object& o) {
      H5::Attribute a = o.openAttribute(name);
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

}  // namespace impactid
