// first_read (study/formats/first_read.hpp): the walk of some bytes runs in a child process,
// once, and its answers reach the caller; a crash or a loop there is a refusal naming the file,
// kept for the same bytes; bytes this process wrote are walked here; changed bytes are another
// file.
#include "study/formats/first_read.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <optional>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/formats/hdf5_error.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("first_read_test", name);
}

// A walk that leaves a mark where it ran: the number of walks is the file's length. Its answer
// says in which process it ran.
struct MarkingRead {
  fs::path marks;
  Hdf5Answers operator()() const {
    std::ofstream(marks, std::ios::app) << 'x';
    Hdf5Answers answers;
    answers.record("pid", {false, encode_answer(static_cast<long>(::getpid()))});
    return answers;
  }
  long children() const { return fs::exists(marks) ? static_cast<long>(fs::file_size(marks)) : 0; }
};

MarkingRead marking(const std::string& name) {
  MarkingRead read{scratch(name + ".marks")};
  fs::remove(read.marks);
  return read;
}

long walked_in(const Hdf5Answers& answers) {
  const std::optional<Hdf5Answers::Answer> pid = answers.find("pid");
  EXPECT_TRUE(pid.has_value());
  long value = 0;
  if (pid) decode_answer(pid->bytes, value);
  return value;
}

TEST(FirstRead, TheSameBytesAreReadInAChildOnce) {
  const fs::path file = testing::write_file(scratch("once.bin"), "the bytes of a file, once");
  const MarkingRead read = marking("once");
  EXPECT_NE(walked_in(*first_read(file, read)), static_cast<long>(::getpid()));
  first_read(file, read);
  EXPECT_EQ(read.children(), 1);
  // Other bytes under the same name are another file.
  testing::write_file(file, "the bytes of a file, twice");
  first_read(file, read);
  EXPECT_EQ(read.children(), 2);
}

TEST(FirstRead, ACrashIsARefusalNamingTheFileAndIsKept) {
  const fs::path file = testing::write_file(scratch("crash.bin"), "bytes that crash a reader");
  const auto crash = []() -> Hdf5Answers {
    std::raise(SIGSEGV);
    return {};
  };
  try {
    first_read(file, crash);
    FAIL() << "not refused";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ": damaged: reading it crashes HDF5"),
              std::string::npos)
        << e.what();
  }
  // The same bytes again: refused without a child, whatever the read would do now.
  const MarkingRead read = marking("crash");
  EXPECT_THROW(first_read(file, read), Hdf5Error);
  EXPECT_EQ(read.children(), 0);
}

// The answers are the child's: recorded there, handed over whole, equal here.
TEST(FirstRead, TheChildsAnswersReachTheCaller) {
  const fs::path file = testing::write_file(scratch("answers.bin"), "a file with answers");
  const std::vector<double> values{1.5, -0.0, 1e-300, 7};
  const auto walk = [&values] {
    Hdf5Answers answers;
    answers.record("pid", {false, encode_answer(static_cast<long>(::getpid()))});
    answers.record(hdf5_question("doubles", "/x"), {false, encode_answer(values)});
    answers.record(hdf5_question("strings", "/y"), {true, "FILE: /y: data corrupted"});
    return answers;
  };
  const std::shared_ptr<const Hdf5Answers> answers = first_read(file, walk);
  EXPECT_NE(walked_in(*answers), static_cast<long>(::getpid()));
  const std::optional<Hdf5Answers::Answer> x = answers->find(hdf5_question("doubles", "/x"));
  ASSERT_TRUE(x.has_value());
  std::vector<double> read;
  decode_answer(x->bytes, read);
  EXPECT_EQ(read, values);
  const std::optional<Hdf5Answers::Answer> y = answers->find(hdf5_question("strings", "/y"));
  ASSERT_TRUE(y.has_value());
  EXPECT_TRUE(y->failed);
  EXPECT_EQ(y->bytes, "FILE: /y: data corrupted");
}

// A child that ends without handing answers over (its walk threw) read nothing usable.
TEST(FirstRead, AChildWithoutAnswersIsARefusal) {
  const fs::path file = testing::write_file(scratch("silent.bin"), "a file whose walk throws");
  const auto throwing = []() -> Hdf5Answers { throw std::runtime_error("no answers"); };
  try {
    first_read(file, throwing);
    FAIL() << "not refused";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ": damaged: its reader's answers"),
              std::string::npos)
        << e.what();
  }
}

TEST(FirstRead, BytesThisProcessWroteAreWalkedHere) {
  const std::string bytes = "bytes an Hdf5Writer committed";
  remember_readable(bytes);
  const fs::path file = testing::write_file(scratch("written.bin"), bytes);
  const MarkingRead read = marking("written");
  EXPECT_EQ(walked_in(*first_read(file, read)), static_cast<long>(::getpid()));
  EXPECT_EQ(read.children(), 1);  // walked here
}

// A global heap collection as HDF5 writes one (its header, then objects of a 16-byte header
// and data padded to 8 bytes, then the free space), 64 bytes in all, after some other bytes.
std::string collection(std::uint64_t first_length, std::uint64_t free_length) {
  const auto put = [](std::string& s, std::uint64_t v, int bytes) {
    for (int k = 0; k < bytes; ++k) s += static_cast<char>((v >> (8 * k)) & 0xff);
  };
  std::string s = "other bytes before it";
  s += std::string("GCOL\x01\x00\x00\x00", 8);
  put(s, 64, 8);  // the collection's size
  put(s, 1, 2), put(s, 1, 2), put(s, 0, 4), put(s, first_length, 8);
  s += std::string("text\0\0\0\0", 8);  // 5 bytes of data, padded to 8
  put(s, 0, 2), put(s, 0, 2), put(s, 0, 4), put(s, free_length, 8);
  s += std::string(8, '\0');  // the free space's own bytes: 16 + 8 = 24 in all
  return s;
}

TEST(FirstRead, AConsistentGlobalHeapIsRead) {
  const fs::path file = testing::write_file(scratch("heap.bin"), collection(5, 24));
  const MarkingRead read = marking("heap");
  first_read(file, read);
  EXPECT_EQ(read.children(), 1);
}

// What HDF5 1.10.8 does not check, found before any child reads the file.
TEST(FirstRead, AGlobalHeapObjectPastItsCollectionIsRefusedUnread) {
  struct Case {
    std::string bytes, words;
  };
  for (const Case& c :
       {Case{collection(1ull << 40, 24), "holds an object (index 1) of 1099511627776 bytes"},
        Case{collection(5, 0), "holds an object (index 0) of 0 bytes"},
        Case{collection(5, 25), "holds an object (index 0) of 25 bytes"},
        Case{collection(5, 24).substr(0, 60), "claims 64 bytes, past the file's end"}}) {
    SCOPED_TRACE(c.words);
    const fs::path file = testing::write_file(scratch("bad-heap.bin"), c.bytes);
    const MarkingRead read = marking("bad-heap");
    try {
      first_read(file, read);
      FAIL() << "not refused";
    } catch (const Hdf5Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string() + ": damaged: its global heap collection at byte 21 "),
                std::string::npos)
          << what;
      EXPECT_NE(what.find(c.words), std::string::npos) << what;
    }
    EXPECT_EQ(read.children(), 0);
  }
}

TEST(FirstRead, ALoopIsRefusedAtTheBound) {
  const fs::path file = testing::write_file(scratch("loop.bin"), "bytes that loop a reader");
  const auto loop = []() -> Hdf5Answers {
    for (volatile bool forever = true; forever;) {
    }
    return {};
  };
  try {
    first_read(file, loop);
    FAIL() << "not refused";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(
        std::string(e.what()).find(file.string() + ": damaged: reading it did not end within " +
                                   std::to_string(static_cast<int>(kFirstReadSeconds)) + " s"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace impactid
