#include "study/formats/hdf5_file.hpp"

#include <H5DSpublic.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <numeric>
#include <system_error>

#include "study/formats/first_read.hpp"

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

// True when HDF5's error stack reports a checksum that does not match its data: a dataset's
// Fletcher32 ("data error detected by Fletcher32 checksum") or an object header's or index's
// metadata checksum ("incorrect metadata checksum after all read attempts").
bool checksum_failed() {
  bool failed = false;
  const H5E_walk2_t visit = [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
    if (error->desc && std::strstr(error->desc, "checksum")) *static_cast<bool*>(data) = true;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, visit, &failed);
  return failed;
}

std::string corrupted(const std::filesystem::path& file, const std::string& object) {
  return file.string() + ": " + object +
         ": data corrupted: its stored checksum does not match the bytes read (the file is "
         "damaged; use a backup or run it again)";
}

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

H5::Attribute replace_attribute(H5::H5Object& object, const std::string& name,
                                const H5::DataType& type, const H5::DataSpace& space) {
  if (object.attrExists(name)) object.removeAttr(name);
  return object.createAttribute(name, type, space);
}

// The C API (H5P, H5L, H5A, H5DS) reports failure by a negative return; turn it into the C++
// API's exception so guarded() names the file.
template <class T>
T checked(T result, const char* function) {
  if (result < 0) throw H5::Exception(function, std::string(function) + " failed");
  return result;
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

template <class T>
std::vector<T> read_numeric_dataset(H5::H5File& file, const std::string& name,
                                    const H5::PredType& type) {
  H5::DataSet d = file.openDataSet(name);
  std::vector<T> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
  if (!out.empty()) checked_read([&] { d.read(out.data(), type); });
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

// The names of a group's links or an object's attributes, ordered as `index` orders them (by
// name, or by creation order), read by iterating in HDF5's native order and sorted here. Not by
// index (H5Lget_name_by_idx, H5Aget_name_by_idx): for each name HDF5 1.10 builds a table of
// every link or attribute, and when one of a damaged group's fails to decode it frees the
// table's entries it never set (H5G__link_release_table), a crash that depends on what the heap
// held (a results_fuzzer finding: the first-read child survived the file, the parent did not).
// Native iteration over dense storage reads them one at a time without that table.
struct NamedEntry {
  std::string name;
  std::int64_t creation_order;
};

std::vector<std::string> names_in_index_order(std::vector<NamedEntry> entries, H5_index_t index) {
  if (index == H5_INDEX_CRT_ORDER) {
    std::stable_sort(entries.begin(), entries.end(), [](const NamedEntry& a, const NamedEntry& b) {
      return a.creation_order < b.creation_order;
    });
  } else {
    std::sort(entries.begin(), entries.end(),
              [](const NamedEntry& a, const NamedEntry& b) { return a.name < b.name; });
  }
  std::vector<std::string> names;
  names.reserve(entries.size());
  for (NamedEntry& e : entries) names.push_back(std::move(e.name));
  return names;
}

// An iteration callback's entry, kept from throwing into HDF5's C frames.
herr_t add_entry(const char* name, std::int64_t creation_order, void* entries) {
  try {
    static_cast<std::vector<NamedEntry>*>(entries)->push_back({name, creation_order});
    return 0;
  } catch (...) {
    return -1;
  }
}

std::vector<std::string> link_names(hid_t group, H5_index_t index) {
  std::vector<NamedEntry> entries;
  const H5L_iterate_t add = [](hid_t, const char* name, const H5L_info_t* info, void* data) {
    return add_entry(name, info->corder_valid ? info->corder : 0, data);
  };
  checked(H5Literate(group, index, H5_ITER_NATIVE, nullptr, add, &entries), "H5Literate");
  return names_in_index_order(std::move(entries), index);
}

std::vector<std::string> attribute_names_of(hid_t object, H5_index_t index) {
  std::vector<NamedEntry> entries;
  const H5A_operator2_t add = [](hid_t, const char* name, const H5A_info_t* info, void* data) {
    return add_entry(name, info->corder_valid ? info->corder : 0, data);
  };
  checked(H5Aiterate2(object, index, H5_ITER_NATIVE, nullptr, add, &entries), "H5Aiterate2");
  return names_in_index_order(std::move(entries), index);
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

// --- the checksum of attributes and text ------------------------------------------------------

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320: zlib's crc32 and Python's
// zlib.crc32), bit by bit: it runs once per file over a few kilobytes of text.
std::uint32_t crc32_update(std::uint32_t crc, const void* bytes, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(bytes);
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= p[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// The checksum's input is a sequence of fields, each its length (8 bytes, little-endian: the
// only byte order impactid runs on) then its bytes, so that no two different files give one
// sequence.
struct Digest {
  std::uint32_t crc = 0;
  void field(const void* bytes, std::size_t size) {
    const std::uint64_t length = size;
    crc = crc32_update(crc, &length, sizeof length);
    crc = crc32_update(crc, bytes, size);
  }
  void field(const std::string& text) { field(text.data(), text.size()); }
};

// HDF5's dimension-scale bookkeeping (H5DS): object references (addresses in the file, which a
// repacked file changes) and fixed names that H5DS writes; not results, so not covered.
bool is_dimension_scale_attribute(const std::string& name) {
  return name == "CLASS" || name == "NAME" || name == "DIMENSION_LIST" || name == "REFERENCE_LIST";
}

std::vector<std::string> sorted_attribute_names(H5::H5Object& object) {
  return attribute_names_of(object.getId(), H5_INDEX_NAME);
}

// An attribute's value as the checksum reads it: text as its UTF-8 bytes, numbers as 8-byte
// little-endian doubles or integers; other types (references) are not covered.
void add_attribute(Digest& digest, H5::H5Object& object, const std::string& name) {
  H5::Attribute a = object.openAttribute(name);
  const auto n = static_cast<std::size_t>(a.getSpace().getSimpleExtentNpoints());
  const H5T_class_t type = a.getTypeClass();
  if (type == H5T_STRING && n == 1) {  // impactid writes scalar text only
    std::string text;
    a.read(a.getStrType(), text);
    digest.field(name);
    digest.field(text);
  } else if (type == H5T_FLOAT) {
    std::vector<double> v(n);
    if (n > 0) a.read(H5::PredType::NATIVE_DOUBLE, v.data());
    digest.field(name);
    digest.field(v.data(), v.size() * sizeof(double));
  } else if (type == H5T_INTEGER) {
    std::vector<std::int64_t> v(n);
    if (n > 0) a.read(H5::PredType::NATIVE_INT64, v.data());
    digest.field(name);
    digest.field(v.data(), v.size() * sizeof(std::int64_t));
  }
}

// The checksum of everything in a file that HDF5's own checksums miss: every attribute (the
// plan's text is kept in the file's global heap, which has no checksum) and the text datasets
// (variable-length strings, also in the global heap, which Fletcher32 cannot cover: it would
// check only their heap addresses). Objects by path ("/", then the root's members by name,
// recursively), attributes by name; kChecksumAttribute and H5DS's bookkeeping left out.
std::uint32_t metadata_checksum(H5::H5File& file) {
  Digest digest;
  std::function<void(const std::string&)> visit;
  const auto visit_object = [&](const std::string& path) {
    digest.field(path);
    const auto add_attributes = [&](H5::H5Object& o) {
      for (const std::string& name : sorted_attribute_names(o)) {
        if (name == kChecksumAttribute || is_dimension_scale_attribute(name)) continue;
        add_attribute(digest, o, name);
      }
    };
    if (path == "/" || file.childObjType(path) == H5O_TYPE_GROUP) {
      H5::Group g = file.openGroup(path);
      add_attributes(g);
      for (const std::string& m : link_names(g.getId(), H5_INDEX_NAME)) {
        visit(path == "/" ? "/" + m : path + "/" + m);
      }
      return;
    }
    H5::DataSet d = file.openDataSet(path);
    add_attributes(d);
    if (d.getTypeClass() != H5T_STRING) return;  // numbers: Fletcher32
    const auto n = static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints());
    std::vector<char*> pointers(n, nullptr);
    const H5::StrType type = utf8_string_type();
    if (n > 0) d.read(pointers.data(), type);
    for (char*& p : pointers) {
      digest.field(p ? std::string(p) : std::string());
      std::free(p);
      p = nullptr;
    }
  };
  visit = [&](const std::string& path) { checked_read([&] { visit_object(path); }); };
  visit("/");
  return digest.crc;
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

Hdf5Reader::Hdf5Reader(const std::filesystem::path& path, UncheckedFile unchecked) : path_(path) {
  if (!std::filesystem::exists(path)) throw Hdf5Error(path.string() + ": no such file");
  // The child makes this object's own calls, and this process makes them next, before anything
  // else takes or gives back memory (study/formats/first_read.cpp says why). The child also
  // closes the file, as this object's end does (a damaged file's object headers have crashed
  // HDF5 at the close, H5O__free), and reads it a second time, as a later reader of the same
  // bytes does without a child of its own (HDF5's free lists, damaged by the first read, have
  // crashed the next one).
  const FirstRead first = check_first_read(path, [this, unchecked] {
    for (int pass = 0; pass < 2; ++pass) {
      try {
        open(unchecked);
        read_everything();
      } catch (const std::exception&) {  // the parent meets it again, and reports it
      }
      try {
        file_.close();
      } catch (const H5::Exception&) {
      }
    }
  });
  open(unchecked);
  first.keep();
}

void Hdf5Reader::read_everything() const {
  const auto attempt = [](auto&& read) {
    try {
      read();
    } catch (const std::exception&) {  // the parent meets it again, and reports it
    }
  };
  std::function<void(const std::string&)> visit = [&](const std::string& path) {
    attempt([&] {
      for (const std::string& name : attribute_names(path)) {
        attempt([&] {
          if (attribute_is_text(path, name)) {
            attribute_string(path, name);
          } else {
            attribute_doubles(path, name);
            attribute_ints(path, name);
          }
        });
      }
    });
    const bool group = path == "/" || guarded(path_, path, [&] {
                         return file_.childObjType(path) == H5O_TYPE_GROUP;
                       });
    if (group) {
      for (const std::string& member : members(path)) {
        attempt([&] { visit(path == "/" ? "/" + member : path + "/" + member); });
      }
      return;
    }
    // Each read on its own, as the parent's readers call them: one that fails does not keep
    // the walk from the others (a dataset's scales are read even if its values are damaged).
    attempt([&] {
      const H5T_class_t type =
          guarded(path_, path, [&] { return file_.openDataSet(path).getTypeClass(); });
      if (type == H5T_STRING) {
        strings(path);
      } else if (type == H5T_INTEGER) {
        longs(path);
      } else {
        doubles(path);
      }
    });
    attempt([&] { is_dimension_scale(path); });
    attempt([&] {
      const auto rank = static_cast<unsigned>(shape(path).size());
      for (unsigned i = 0; i < rank; ++i) attempt([&] { attached_scales(path, i); });
    });
  };
  attempt([&] { visit("/"); });
}

void Hdf5Reader::open(UncheckedFile unchecked) {
  const std::filesystem::path& path = path_;
  try {
    file_.openFile(path.string(), H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    if (checksum_failed()) throw Hdf5Error(corrupted(path, "/"));
    throw Hdf5Error(path.string() +
                    ": not a readable HDF5 file (truncated or corrupt?): " + failure_text(e));
  }
  const std::string what =
      std::string("the checksum of its attributes and text (/@") + kChecksumAttribute + ")";
  checksummed_ = guarded(path_, "/", [&] {
    H5::Group root = file_.openGroup("/");
    return root.attrExists(kChecksumAttribute);
  });
  if (!checksummed_) {
    if (unchecked == UncheckedFile::note) {
      std::cerr << "impactid: note: " << path_.string()
                << ": no checksums (written by an impactid before they were added, or by "
                   "another program): its data are read unverified\n";
    }
    return;
  }
  guarded(path_, what, [&] {
    H5::Group root = file_.openGroup("/");
    long stored = 0;
    open_scalar_attribute(root, kChecksumAttribute).read(H5::PredType::NATIVE_LONG, &stored);
    const long computed = metadata_checksum(file_);
    if (stored != computed) {
      throw Hdf5Error(path_.string() + ": " + what +
                      ": data corrupted: the stored checksum does not match the attributes and "
                      "text read (the file is damaged; use a backup or run it again)");
    }
  });
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
    return link_names(g.getId(), index);
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
    if (n > 0) checked_read([&] { d.read(pointers.data(), type); });
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
      std::vector<std::string> names = attribute_names_of(o.getId(), index);
      if (object == "/") {  // the checksum: storage, not content
        names.erase(std::remove(names.begin(), names.end(), kChecksumAttribute), names.end());
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
