#include "study/formats/hdf5_file.hpp"

#include <H5DSpublic.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <optional>

#include "study/formats/first_read.hpp"
#include "study/formats/hdf5_answers.hpp"
#include "study/formats/hdf5_support.hpp"

namespace impactid {
namespace {

using namespace hdf5_support;

// Objects as the walk records them: from the root ("t" is "/t").
std::string absolute(const std::string& object) {
  return object.empty() || object.front() != '/' ? "/" + object : object;
}

std::string parent_of(const std::string& object) {
  const std::size_t slash = object.rfind('/');
  return slash == 0 || slash == std::string::npos ? "/" : object.substr(0, slash);
}

// A recorded error names the object as the walk did ("FILE: /t: …"); the caller's error names it
// as the caller did ("FILE: t: …").
std::string as_asked(const std::string& message, const std::string& asked,
                     const std::string& recorded) {
  const std::size_t at = message.find(": " + recorded);
  if (asked == recorded || at == std::string::npos) return message;
  return message.substr(0, at + 2) + asked + message.substr(at + 2 + recorded.size());
}

std::string child_of(const std::string& group, const std::string& member) {
  return group == "/" ? "/" + member : group + "/" + member;
}

template <class T>
std::vector<T> read_numeric_dataset(H5::H5File& file, const std::string& name,
                                    const H5::PredType& type) {
  H5::DataSet d = file.openDataSet(name);
  std::vector<T> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
  if (!out.empty()) checked_read([&] { d.read(out.data(), type); });
  return out;
}

// One file read by HDF5: each of Hdf5Reader's questions asked of the library, its failures as
// Hdf5Error naming the file and the object. Only the walk below uses it.
class LiveFile {
 public:
  explicit LiveFile(std::filesystem::path path) : path_(std::move(path)) {}

  // An object's attributes, read through the group or dataset the path names.
  template <class Fn>
  auto with_attributes_of(const std::string& object, const std::string& named, Fn&& fn) {
    return guarded(path_, named, [&] { return with_object(file_, object, fn); });
  }


  // Opens the file and checks the checksum of its attributes and text; true when it has one.
  bool open() {
    try {
      file_.openFile(path_.string(), H5F_ACC_RDONLY);
    } catch (const H5::Exception& e) {
      if (checksum_failed()) throw Hdf5Error(corrupted(path_, "/"));
      throw Hdf5Error(path_.string() +
                      ": not a readable HDF5 file (truncated or corrupt?): " + failure_text(e));
    }
    const std::string what =
        std::string("the checksum of its attributes and text (/@") + kChecksumAttribute + ")";
    const bool checksummed = guarded(path_, "/", [&] {
      H5::Group root = file_.openGroup("/");
      return root.attrExists(kChecksumAttribute);
    });
    if (!checksummed) return false;
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
    return true;
  }

  void close() { file_.close(); }

  bool is_group(const std::string& path) {
    return path == "/" ||
           guarded(path_, path, [&] { return file_.childObjType(path) == H5O_TYPE_GROUP; });
  }

  H5T_class_t type_class(const std::string& dataset) {
    return guarded(path_, dataset, [&] { return file_.openDataSet(dataset).getTypeClass(); });
  }

  std::vector<std::string> members(const std::string& group) {
    return guarded(path_, group, [&] {
      H5::Group g = file_.openGroup(group);
      const H5_index_t index = (creation_order_flags(g.getId(), false) & H5P_CRT_ORDER_TRACKED)
                                   ? H5_INDEX_CRT_ORDER
                                   : H5_INDEX_NAME;
      return link_names(g.getId(), index);
    });
  }

  Hdf5Dims shape(const std::string& dataset) {
    return guarded(path_, dataset, [&] {
      const H5::DataSpace space = file_.openDataSet(dataset).getSpace();
      Hdf5Dims dims(static_cast<std::size_t>(space.getSimpleExtentNdims()));
      space.getSimpleExtentDims(dims.data());
      return dims;
    });
  }

  template <class T>
  std::vector<T> numbers(const std::string& dataset, const H5::PredType& type) {
    return guarded(path_, dataset, [&] { return read_numeric_dataset<T>(file_, dataset, type); });
  }

  std::vector<std::string> strings(const std::string& dataset) {
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

  std::vector<std::string> attribute_names(const std::string& object) {
    return with_attributes_of(object, object, [&](H5::H5Object& o) {
      const H5_index_t index = (creation_order_flags(o.getId(), true) & H5P_CRT_ORDER_TRACKED)
                                   ? H5_INDEX_CRT_ORDER
                                   : H5_INDEX_NAME;
      std::vector<std::string> names = attribute_names_of(o.getId(), index);
      if (object == "/") {  // the checksum: storage, not content
        names.erase(std::remove(names.begin(), names.end(), kChecksumAttribute), names.end());
      }
      return names;
    });
  }

  bool attribute_is_text(const std::string& object, const std::string& name) {
    return with_attributes_of(object, object + "@" + name, [&](H5::H5Object& o) {
      return o.openAttribute(name).getTypeClass() == H5T_STRING;
    });
  }

  std::string attribute_string(const std::string& object, const std::string& name) {
    return with_attributes_of(object, object + "@" + name, [&](H5::H5Object& o) {
      H5::Attribute a = open_scalar_attribute(o, name);
      std::string v;
      a.read(a.getStrType(), v);
      return v;
    });
  }

  template <class T>
  T attribute_number(const std::string& object, const std::string& name, const H5::PredType& type) {
    return with_attributes_of(object, object + "@" + name, [&](H5::H5Object& o) {
      T v = 0;
      open_scalar_attribute(o, name).read(type, &v);
      return v;
    });
  }

  template <class T>
  std::vector<T> attribute_numbers(const std::string& object, const std::string& name,
                                   const H5::PredType& type) {
    return with_attributes_of(object, object + "@" + name, [&](H5::H5Object& o) {
      H5::Attribute a = o.openAttribute(name);
      std::vector<T> v(static_cast<std::size_t>(a.getSpace().getSimpleExtentNpoints()));
      if (!v.empty()) a.read(type, v.data());
      return v;
    });
  }

  bool is_dimension_scale(const std::string& dataset) {
    return guarded(path_, dataset, [&] {
      H5::DataSet d = file_.openDataSet(dataset);
      return checked(H5DSis_scale(d.getId()), "H5DSis_scale") > 0;
    });
  }

  std::vector<std::string> attached_scales(const std::string& dataset, unsigned index) {
    return guarded(path_, dataset, [&] {
      H5::DataSet d = file_.openDataSet(dataset);
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
        checked(H5DSiterate_scales(d.getId(), index, nullptr, visitor, &visit),
                "H5DSiterate_scales");
      }
      if (visit.failed) throw H5::Exception("H5Iget_name", "cannot name a dimension scale");
      return visit.names;
    });
  }

 private:
  std::filesystem::path path_;
  H5::H5File file_;
};

// The walk of a whole file: every question a reader may ask of each object, asked of HDF5 and
// recorded with its answer or its error, going on past errors (a dataset's scales are asked even
// if its values are damaged). The questions' names are Hdf5Reader's functions.
class Walk {
 public:
  explicit Walk(const std::filesystem::path& path) : live_(path) {}

  Hdf5Answers run() && {
    const std::optional<bool> opened = ask("open", "/", {}, [&] { return live_.open(); });
    if (!opened) return std::move(answers_);
    visit("/");
    try {
      live_.close();
    } catch (const H5::Exception&) {  // the close is part of the reading: a crash is the child's
    }
    return std::move(answers_);
  }

 private:
  template <class Fn>
  auto ask(std::string_view what, const std::string& object, const std::string& argument,
           Fn&& read) -> std::optional<decltype(read())> {
    std::string question = hdf5_question(what, object, argument);
    try {
      auto value = read();
      answers_.record(question, {false, encode_answer(value)});
      return value;
    } catch (const std::exception& e) {
      answers_.record(question, {true, e.what()});
      return std::nullopt;
    }
  }

  void visit_attributes(const std::string& object) {
    const auto names = ask("attribute_names", object, {}, [&] {
      return live_.attribute_names(object);
    });
    if (!names) return;
    for (const std::string& name : *names) {
      const auto text = ask("attribute_is_text", object, name, [&] {
        return live_.attribute_is_text(object, name);
      });
      if (!text) continue;
      if (*text) {
        ask("attribute_string", object, name, [&] { return live_.attribute_string(object, name); });
        continue;
      }
      ask("attribute_double", object, name, [&] {
        return live_.attribute_number<double>(object, name, H5::PredType::NATIVE_DOUBLE);
      });
      ask("attribute_long", object, name, [&] {
        return live_.attribute_number<long>(object, name, H5::PredType::NATIVE_LONG);
      });
      ask("attribute_doubles", object, name, [&] {
        return live_.attribute_numbers<double>(object, name, H5::PredType::NATIVE_DOUBLE);
      });
      ask("attribute_ints", object, name, [&] {
        return live_.attribute_numbers<int>(object, name, H5::PredType::NATIVE_INT);
      });
    }
  }

  void visit(const std::string& object) {
    visit_attributes(object);
    const auto group = ask("is_group", object, {}, [&] { return live_.is_group(object); });
    if (!group) return;
    if (*group) {
      const auto members = ask("members", object, {}, [&] { return live_.members(object); });
      if (members) {
        for (const std::string& member : *members) visit(child_of(object, member));
      }
      return;
    }
    const auto type = ask("type_class", object, {}, [&] {
      return static_cast<long>(live_.type_class(object));
    });
    if (type && *type == H5T_STRING) {
      ask("strings", object, {}, [&] { return live_.strings(object); });
    } else if (type) {
      ask("doubles", object, {}, [&] {
        return live_.numbers<double>(object, H5::PredType::NATIVE_DOUBLE);
      });
      if (*type == H5T_INTEGER) {
        ask("longs", object, {}, [&] {
          return live_.numbers<long>(object, H5::PredType::NATIVE_LONG);
        });
        ask("ints", object, {}, [&] { return live_.numbers<int>(object, H5::PredType::NATIVE_INT); });
      }
    }
    ask("is_dimension_scale", object, {}, [&] { return live_.is_dimension_scale(object); });
    const auto shape = ask("shape", object, {}, [&] { return live_.shape(object); });
    if (!shape) return;
    for (unsigned i = 0; i < shape->size(); ++i) {
      ask("attached_scales", object, std::to_string(i), [&] {
        return live_.attached_scales(object, i);
      });
    }
  }

  LiveFile live_;
  Hdf5Answers answers_;
};

}  // namespace

Hdf5Reader::Hdf5Reader(const std::filesystem::path& path, UncheckedFile unchecked) : path_(path) {
  if (!std::filesystem::exists(path)) throw Hdf5Error(path.string() + ": no such file");
  answers_ = first_read(path, [&path] { return Walk(path).run(); });
  checksummed_ = answer<bool>("open", "/");
  if (!checksummed_ && unchecked == UncheckedFile::note) {
    std::cerr << "impactid: note: " << path_.string()
              << ": no checksums (written by an impactid before they were added, or by "
                 "another program): its data are read unverified\n";
  }
}

template <class T>
T Hdf5Reader::answer(std::string_view what, const std::string& object,
                     const std::string& argument) const {
  const std::string at = absolute(object);
  const std::optional<Hdf5Answers::Answer> recorded = answers_->find(hdf5_question(what, at, argument));
  if (!recorded) throw unanswered(what, at, argument);
  if (recorded->failed) throw Hdf5Error(as_asked(std::string(recorded->bytes), object, at));
  T value{};
  try {
    decode_answer(recorded->bytes, value);
  } catch (const std::runtime_error& e) {
    throw Hdf5Error(path_.string() + ": " + at + ": " + e.what());
  }
  return value;
}

// A question the walk did not ask: of an object it could not tell (its error), of one that is
// not in the file, or one the object cannot answer (the integers of a dataset of floating-point
// numbers, the text of a numeric attribute, a dimension past the dataset's rank).
Hdf5Error Hdf5Reader::unanswered(std::string_view what, const std::string& object,
                                 const std::string& argument) const {
  for (const char* kind : {"is_group", "type_class"}) {
    const std::optional<Hdf5Answers::Answer> a = answers_->find(hdf5_question(kind, object));
    if (a && a->failed) return Hdf5Error(std::string(a->bytes));
  }
  const std::string named = path_.string() + ": " + object;
  if (!exists(object)) return Hdf5Error(named + ": no such object in the file");
  const std::string_view question = what;
  if (question.starts_with("attribute_")) {
    if (!has_attribute(object, argument)) return Hdf5Error(named + ": no attribute " + argument);
    const std::string wanted = question == "attribute_string"   ? "one text"
                               : question == "attribute_double" ? "one number"
                               : question == "attribute_long"   ? "one number"
                                                                : "numbers";
    return Hdf5Error(named + "@" + argument + ": does not hold " + wanted);
  }
  if (question == "attached_scales") {
    return Hdf5Error(named + ": dimension " + argument + " out of range");
  }
  const std::string wanted = question == "members"   ? "a group"
                             : question == "strings" ? "a dataset of text"
                             : question == "doubles" ? "a dataset of numbers"
                             : question == "longs" || question == "ints"
                                 ? "a dataset of integers"
                                 : "a dataset";
  return Hdf5Error(named + ": not " + wanted);
}

bool Hdf5Reader::exists(const std::string& path) const {
  const std::string object = absolute(path);
  if (object == "/") return true;
  const std::string group = parent_of(object);
  if (const auto members = answers_->find(hdf5_question("members", group))) {
    if (members->failed) throw Hdf5Error(std::string(members->bytes));
    std::vector<std::string> names;
    decode_answer(members->bytes, names);
    const std::string name = object.substr(group == "/" ? 1 : group.size() + 1);
    return std::find(names.begin(), names.end(), name) != names.end();
  }
  if (const auto a = answers_->find(hdf5_question("is_group", group))) {
    if (a->failed) throw Hdf5Error(std::string(a->bytes));
  }
  return false;  // inside a dataset, or inside an object that is not in the file
}

std::vector<std::string> Hdf5Reader::members(const std::string& group) const {
  return answer<std::vector<std::string>>("members", group);
}

Hdf5Dims Hdf5Reader::shape(const std::string& dataset) const {
  return answer<Hdf5Dims>("shape", dataset);
}

std::vector<double> Hdf5Reader::doubles(const std::string& dataset) const {
  return answer<std::vector<double>>("doubles", dataset);
}

std::vector<long> Hdf5Reader::longs(const std::string& dataset) const {
  return answer<std::vector<long>>("longs", dataset);
}

std::vector<int> Hdf5Reader::ints(const std::string& dataset) const {
  return answer<std::vector<int>>("ints", dataset);
}

std::vector<std::string> Hdf5Reader::strings(const std::string& dataset) const {
  return answer<std::vector<std::string>>("strings", dataset);
}

bool Hdf5Reader::has_attribute(const std::string& object, const std::string& name) const {
  const std::string at = absolute(object);
  if (at == "/" && name == kChecksumAttribute) return checksummed_;
  if (!answers_->find(hdf5_question("attribute_names", at)) && !exists(at)) {
    throw Hdf5Error(path_.string() + ": " + at + ": no such object in the file");
  }
  const std::vector<std::string> names = attribute_names(at);
  return std::find(names.begin(), names.end(), name) != names.end();
}

double Hdf5Reader::attribute_double(const std::string& object, const std::string& name) const {
  return answer<double>("attribute_double", object, name);
}

long Hdf5Reader::attribute_long(const std::string& object, const std::string& name) const {
  return answer<long>("attribute_long", object, name);
}

std::string Hdf5Reader::attribute_string(const std::string& object, const std::string& name) const {
  return answer<std::string>("attribute_string", object, name);
}

std::vector<double> Hdf5Reader::attribute_doubles(const std::string& object,
                                                  const std::string& name) const {
  return answer<std::vector<double>>("attribute_doubles", object, name);
}

std::vector<int> Hdf5Reader::attribute_ints(const std::string& object,
                                            const std::string& name) const {
  return answer<std::vector<int>>("attribute_ints", object, name);
}

std::vector<std::string> Hdf5Reader::attribute_names(const std::string& object) const {
  return answer<std::vector<std::string>>("attribute_names", object);
}

bool Hdf5Reader::attribute_is_text(const std::string& object, const std::string& name) const {
  return answer<bool>("attribute_is_text", object, name);
}

bool Hdf5Reader::is_dimension_scale(const std::string& dataset) const {
  return answer<bool>("is_dimension_scale", dataset);
}

std::vector<std::string> Hdf5Reader::attached_scales(const std::string& dataset,
                                                     unsigned index) const {
  return answer<std::vector<std::string>>("attached_scales", dataset, std::to_string(index));
}

}  // namespace impactid
