// What one HDF5 file answered to Hdf5Reader's questions (a group's members, a dataset's shape
// and numbers, an attribute's text…), each answer a value or the message of the error its
// reading raised. A walk of the whole file records them where HDF5 may be harmed by the bytes
// (a child process, study/formats/first_read.hpp), and hands them over as one string of bytes;
// the reader then answers from them, and HDF5 never parses those bytes in the reader's process
// (study/formats/hdf5_file.hpp says why).
//
// A value type: copies are independent; const access is safe from several threads.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace impactid {

class Hdf5Answers {
 public:
  /// A recorded answer: the value's bytes (encode_answer), or the error's message.
  struct Answer {
    bool failed = false;
    std::string_view bytes;
  };

  /// Adds an answer (a question asked again replaces the earlier answer).
  void record(std::string_view question, Answer answer);
  /// The answer to `question` (its bytes a view into this object), or none when the walk did
  /// not ask it.
  std::optional<Answer> find(const std::string& question) const;

  /// Every answer in one string of bytes, and back: parse() keeps the string it is given and
  /// answers from it (no copy of the values: a results file's are most of its size). It throws
  /// std::runtime_error for bytes that are not such a string (cut short, a length past its end).
  const std::string& serialized() const { return records_; }
  static Hdf5Answers parse(std::string bytes);

  /// The bytes the answers hold (for a bounded cache).
  std::size_t size_in_bytes() const { return records_.size(); }

 private:
  struct Place {
    bool failed;
    std::size_t offset, length;  // of the answer's bytes in records_
  };
  // The records in order, each its question, a failed flag and its bytes (lengths 8 bytes, in
  // native order: the bytes never leave the machine), and where each question's answer lies.
  // records_ starts with kMagic, so that no bytes at all (a child that wrote nothing) are not
  // taken for a file without answers.
  static constexpr std::string_view kMagic = "impactid HDF5 answers 1\n";
  std::string records_{kMagic};
  std::unordered_map<std::string, Place> places_;
};

/// A question's key: what is asked (the reader's function name), of which object, and its
/// argument (an attribute's name, a dimension's index).
std::string hdf5_question(std::string_view what, std::string_view object,
                          std::string_view argument = {});

// Values as answer bytes: numbers in their native representation, texts each after its length.
std::string encode_answer(bool value);
std::string encode_answer(double value);
std::string encode_answer(long value);
std::string encode_answer(const std::string& value);
std::string encode_answer(const std::vector<double>& values);
std::string encode_answer(const std::vector<long>& values);
std::string encode_answer(const std::vector<int>& values);
std::string encode_answer(const std::vector<unsigned long long>& values);
std::string encode_answer(const std::vector<std::string>& values);

/// The value of answer bytes; throws std::runtime_error when they do not hold one.
void decode_answer(std::string_view bytes, bool& value);
void decode_answer(std::string_view bytes, double& value);
void decode_answer(std::string_view bytes, long& value);
void decode_answer(std::string_view bytes, std::string& value);
void decode_answer(std::string_view bytes, std::vector<double>& values);
void decode_answer(std::string_view bytes, std::vector<long>& values);
void decode_answer(std::string_view bytes, std::vector<int>& values);
void decode_answer(std::string_view bytes, std::vector<unsigned long long>& values);
void decode_answer(std::string_view bytes, std::vector<std::string>& values);

}  // namespace impactid
