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
    std::string bytes;
  };

  void record(std::string question, Answer answer);
  /// The answer to `question`, or null when the walk did not ask it.
  const Answer* find(const std::string& question) const;

  /// Every answer in one string of bytes, and back. parse() throws std::runtime_error for bytes
  /// that are not such a string (cut short, or a count past its end).
  std::string serialized() const;
  static Hdf5Answers parse(std::string_view bytes);

  /// The bytes the answers hold (for a bounded cache).
  std::size_t size_in_bytes() const { return bytes_; }

 private:
  std::unordered_map<std::string, Answer> answers_;
  std::size_t bytes_ = 0;
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
