#include "study/formats/hdf5_answers.hpp"

#include <cstring>

namespace impactid {
namespace {

// Serialized answers: a count, then each answer as its question, a failed flag and its bytes;
// every length is 8 bytes in native order (the bytes never leave the machine).
void put_count(std::string& out, std::uint64_t n) {
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
}

void put_text(std::string& out, std::string_view text) {
  put_count(out, text.size());
  out.append(text);
}

// Reads serialized bytes front to back; anything cut short is an error, never a read past them.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : rest_(bytes) {}
  std::uint64_t count() {
    std::uint64_t n = 0;
    std::memcpy(&n, take(sizeof n).data(), sizeof n);
    return n;
  }
  std::string_view text() { return take(count()); }
  std::string_view take(std::uint64_t n) {
    if (n > rest_.size()) throw std::runtime_error("HDF5 answers cut short");
    const std::string_view taken = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return taken;
  }
  bool done() const { return rest_.empty(); }

 private:
  std::string_view rest_;
};

template <class T>
std::string encode_numbers(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <class T>
std::vector<T> decode_numbers(std::string_view bytes) {
  if (bytes.size() % sizeof(T) != 0) throw std::runtime_error("HDF5 answer of the wrong size");
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

template <class T>
T decode_number(std::string_view bytes) {
  if (bytes.size() != sizeof(T)) throw std::runtime_error("HDF5 answer of the wrong size");
  T value{};
  std::memcpy(&value, bytes.data(), sizeof(T));
  return value;
}

}  // namespace

void Hdf5Answers::record(std::string_view question, Answer answer) {
  put_text(records_, question);
  records_ += answer.failed ? '\1' : '\0';
  put_count(records_, answer.bytes.size());
  places_.insert_or_assign(std::string(question),
                           Place{answer.failed, records_.size(), answer.bytes.size()});
  records_.append(answer.bytes);
}

std::optional<Hdf5Answers::Answer> Hdf5Answers::find(const std::string& question) const {
  const auto at = places_.find(question);
  if (at == places_.end()) return std::nullopt;
  const Place& p = at->second;
  return Answer{p.failed, std::string_view(records_).substr(p.offset, p.length)};
}

Hdf5Answers Hdf5Answers::parse(std::string bytes) {
  Hdf5Answers answers;
  if (!std::string_view(bytes).starts_with(kMagic)) {
    throw std::runtime_error("HDF5 answers without their header");
  }
  answers.records_ = std::move(bytes);
  const std::string_view all(answers.records_);
  Cursor in(all.substr(kMagic.size()));
  while (!in.done()) {
    std::string question(in.text());
    const bool failed = in.take(1)[0] != '\0';
    const std::string_view value = in.text();
    const auto offset = static_cast<std::size_t>(value.data() - all.data());
    answers.places_.insert_or_assign(std::move(question), Place{failed, offset, value.size()});
  }
  return answers;
}

std::string hdf5_question(std::string_view what, std::string_view object,
                          std::string_view argument) {
  std::string question;
  put_text(question, what);
  put_text(question, object);
  put_text(question, argument);
  return question;
}

std::string encode_answer(bool value) { return std::string(1, value ? '\1' : '\0'); }
std::string encode_answer(double value) { return encode_numbers(std::vector<double>{value}); }
std::string encode_answer(long value) { return encode_numbers(std::vector<long>{value}); }
std::string encode_answer(const std::string& value) { return value; }
std::string encode_answer(const std::vector<double>& values) { return encode_numbers(values); }
std::string encode_answer(const std::vector<long>& values) { return encode_numbers(values); }
std::string encode_answer(const std::vector<int>& values) { return encode_numbers(values); }
std::string encode_answer(const std::vector<unsigned long long>& values) {
  return encode_numbers(values);
}
std::string encode_answer(const std::vector<std::string>& values) {
  std::string out;
  for (const std::string& v : values) put_text(out, v);
  return out;
}

void decode_answer(std::string_view bytes, bool& value) {
  if (bytes.size() != 1) throw std::runtime_error("HDF5 answer of the wrong size");
  value = bytes[0] != '\0';
}
void decode_answer(std::string_view bytes, double& value) { value = decode_number<double>(bytes); }
void decode_answer(std::string_view bytes, long& value) { value = decode_number<long>(bytes); }
void decode_answer(std::string_view bytes, std::string& value) { value = std::string(bytes); }
void decode_answer(std::string_view bytes, std::vector<double>& values) {
  values = decode_numbers<double>(bytes);
}
void decode_answer(std::string_view bytes, std::vector<long>& values) {
  values = decode_numbers<long>(bytes);
}
void decode_answer(std::string_view bytes, std::vector<int>& values) {
  values = decode_numbers<int>(bytes);
}
void decode_answer(std::string_view bytes, std::vector<unsigned long long>& values) {
  values = decode_numbers<unsigned long long>(bytes);
}
void decode_answer(std::string_view bytes, std::vector<std::string>& values) {
  Cursor in(bytes);
  values.clear();
  while (!in.done()) values.emplace_back(in.text());
}

}  // namespace impactid
