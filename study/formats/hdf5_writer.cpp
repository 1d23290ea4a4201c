#include "study/formats/hdf5_file.hpp"

#include <H5DSpublic.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <system_error>

#include "study/formats/first_read.hpp"
#include "study/formats/hdf5_support.hpp"

namespace impactid {
namespace {

using namespace hdf5_support;

H5::Attribute replace_attribute(H5::H5Object& object, const std::string& name,
                                const H5::DataType& type, const H5::DataSpace& space) {
  if (object.attrExists(name)) object.removeAttr(name);
  return object.createAttribute(name, type, space);
}

constexpr unsigned kCreationOrder = H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED;

// A text dataset of at most this many strings keeps their heap places (16 bytes each) in its
// object header: HDF5's compact storage, under its 64 KiB limit with room to spare.
constexpr hsize_t kCompactTextElements = 3000;

// Every dataset tracks its attributes' creation order, as netCDF-4 does.
H5::DSetCreatPropList dataset_properties() {
  H5::DSetCreatPropList properties;
  properties.setAttrCrtOrder(kCreationOrder);
  return properties;
}

// Chunks of at most 2^16 elements (512 KB of doubles, inside HDF5's default 1 MB chunk cache),
// whole along the last dimensions first, so that a row-major table is cut into runs of
// consecutive points. Every dataset is chunked (Fletcher32 needs it) and HDF5 stores edge chunks
// whole, so the dimension that is cut is cut into equal pieces: 1000 rows of 1000 points go in
// 16 chunks of 63 rows (8 rows of padding), not 65 (40 rows, 320 KB of padding a dataset).
Hdf5Dims chunk_shape(const Hdf5Dims& dims) {
  Hdf5Dims chunk(dims.size(), 1);
  hsize_t budget = hsize_t{1} << 16;
  for (std::size_t d = dims.size(); d-- > 0 && budget > 1;) {
    const hsize_t pieces = std::max<hsize_t>(1, (dims[d] + budget - 1) / budget);
    chunk[d] = std::max<hsize_t>(1, (dims[d] + pieces - 1) / pieces);
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
    // Fletcher32 needs chunked storage; a dataset of no elements has no bytes to check, and a
    // scalar one cannot be chunked (no dataset written here is scalar).
    if (!dims.empty() && !data.empty()) {
      const Hdf5Dims chunk = chunk_shape(dims);
      properties.setChunk(static_cast<int>(chunk.size()), chunk.data());
      if (compressed && data.size() >= 4096) {
        properties.setShuffle();
        properties.setDeflate(1);
      }
      // Added last, so it checks the stored (compressed) bytes and runs first on read, before
      // zlib sees them.
      properties.setFletcher32();
    }
    H5::DataSet d = file.createDataSet(name, type, space, properties);
    if (!data.empty()) d.write(data.data(), type);  // a zero-size dataset has nothing to write
  });
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

// Bob Jenkins' lookup3 hashlittle (public domain), byte by byte as HDF5's
// H5_checksum_lookup3 reads it: HDF5's checksum of its metadata (initial value 0).
std::uint32_t lookup3(const unsigned char* key, std::size_t length) {
  const auto rot = [](std::uint32_t x, int k) { return (x << k) | (x >> (32 - k)); };
  std::uint32_t a = 0xdeadbeefu + static_cast<std::uint32_t>(length);
  std::uint32_t b = a;
  std::uint32_t c = a;
  const auto word = [](const unsigned char* p) {
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
           std::uint32_t{p[3]} << 24;
  };
  for (; length > 12; length -= 12, key += 12) {
    a += word(key);
    b += word(key + 4);
    c += word(key + 8);
    a -= c;
    a ^= rot(c, 4);
    c += b;
    b -= a;
    b ^= rot(a, 6);
    a += c;
    c -= b;
    c ^= rot(b, 8);
    b += a;
    a -= c;
    a ^= rot(c, 16);
    c += b;
    b -= a;
    b ^= rot(a, 19);
    a += c;
    c -= b;
    c ^= rot(b, 4);
    b += a;
  }
  if (length == 0) return c;
  std::array<std::uint32_t*, 3> words{&a, &b, &c};
  for (std::size_t i = 0; i < length; ++i) *words[i / 4] += std::uint32_t{key[i]} << (8 * (i % 4));
  c ^= b;
  c -= rot(b, 14);
  a ^= c;
  a -= rot(c, 11);
  b ^= a;
  b -= rot(a, 25);
  c ^= b;
  c -= rot(b, 16);
  a ^= c;
  a -= rot(c, 4);
  b ^= a;
  b -= rot(a, 14);
  c ^= b;
  c -= rot(b, 24);
  return c;
}

// HDF5 1.10.8's H5Fget_file_image clears the superblock's status flags in the image (the
// in-memory file is open for writing; the image is a closed file) but leaves the superblock's
// checksum as computed with them set, so every reader refuses the image ("incorrect metadata
// checksum"). The superblock of versions 2 and 3 (the 1.10 format asked for above) is 12 bytes,
// four addresses, then the lookup3 checksum of all that: recomputed here.
void repair_superblock_checksum(std::vector<char>& image) {
  auto* bytes = reinterpret_cast<unsigned char*>(image.data());
  if (image.size() < 12 || bytes[8] < 2) return;  // versions 0 and 1 have no checksum
  const std::size_t checked_size = 12 + 4 * std::size_t{bytes[9]};  // bytes[9]: address size
  if (image.size() < checked_size + 4) return;
  const std::uint32_t checksum = lookup3(bytes, checked_size);
  for (std::size_t i = 0; i < 4; ++i) {
    bytes[checked_size + i] = static_cast<unsigned char>(checksum >> (8 * i));
  }
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
    // HDF5 1.10's file format: a dataset of one chunk (every one under 2^16 elements) is indexed
    // in its own layout message; the 1.8 format's B-tree per chunked dataset would double a
    // history file of small datasets. Also gives every object header a checksum.
    access.setLibverBounds(H5F_LIBVER_V110, H5F_LIBVER_V110);
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
    // The stored elements are the strings' places in the global heap (collection and index);
    // HDF5 1.10.8 follows an index without checking it against the collection, so a damaged
    // one would be a read anywhere. HDF5 allows no filter (Fletcher32) on variable-length
    // data, so the places are kept in the dataset's object header, which carries a checksum
    // (compact storage, up to kCompactTextElements strings of 16-byte places; the strings
    // themselves are covered by kChecksumAttribute).
    H5::DSetCreatPropList properties = dataset_properties();
    if (n > 0 && n <= kCompactTextElements) properties.setLayout(H5D_COMPACT);
    H5::DataSet d = file_->createDataSet(path, type, H5::DataSpace(1, &n), properties);
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
  guarded(path_, std::string("/@") + kChecksumAttribute, [&] {
    const long checksum = metadata_checksum(*file_);
    H5::Group root = file_->openGroup("/");
    replace_attribute(root, kChecksumAttribute, H5::PredType::NATIVE_LONG,
                      H5::DataSpace(H5S_SCALAR))
        .write(H5::PredType::NATIVE_LONG, &checksum);
  });
  const std::vector<char> image = guarded(path_, "/", [&] {
    file_->flush(H5F_SCOPE_GLOBAL);
    const ssize_t size =
        checked(H5Fget_file_image(file_->getId(), nullptr, 0), "H5Fget_file_image");
    std::vector<char> bytes(static_cast<std::size_t>(size));
    checked(H5Fget_file_image(file_->getId(), bytes.data(), bytes.size()), "H5Fget_file_image");
    repair_superblock_checksum(bytes);
    return bytes;
  });
  guarded(path_, "/", [&] { file_->close(); });
  file_.reset();
  remember_readable(image);
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

}  // namespace impactid
