#include "study/formats/hdf5_support.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <numeric>

namespace impactid::hdf5_support {
namespace {

// HDF5's C++ API throws; its default is also to print a stack to stderr. We report errors
// ourselves, once, with the file named.
struct QuietHdf5 {
  QuietHdf5() { H5::Exception::dontPrint(); }
};
const QuietHdf5 quiet_hdf5;

}  // namespace

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

namespace {

// The names of a group's links or an object's attributes, ordered as `index` orders them (by
// name, or by creation order), read by iterating in HDF5's native order and sorted here. Not by
// index (H5Lget_name_by_idx, H5Aget_name_by_idx): for each name HDF5 1.10 builds a table of
// every link or attribute, and when one of a damaged group's fails to decode it frees the
// table's entries it never set (H5G__link_release_table), a crash that depends on what the heap
// held (a results_fuzzer finding: one reading of the file survived it, the next did not).
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

}  // namespace

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

// --- the checksum of attributes and text ------------------------------------------------------

namespace {

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

}  // namespace

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

}  // namespace impactid::hdf5_support
