// check_first_read (study/formats/first_read.hpp): the first read of some bytes runs in a child
// process, once; a crash or a loop there is a refusal naming the file, kept for the same bytes;
// bytes this process wrote, or changed bytes, are told apart by their digest.
#include "study/formats/first_read.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <iterator>
#include <string>

#include "study/formats/hdf5_error.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("first_read_test", name);
}

// A read whose child leaves a mark: the number of children that ran is the file's length.
struct MarkingRead {
  fs::path marks;
  void operator()() const { std::ofstream(marks, std::ios::app) << 'x'; }
  long children() const { return fs::exists(marks) ? static_cast<long>(fs::file_size(marks)) : 0; }
};

MarkingRead marking(const std::string& name) {
  MarkingRead read{scratch(name + ".marks")};
  fs::remove(read.marks);
  return read;
}

TEST(FirstRead, TheSameBytesAreReadInAChildOnce) {
  const fs::path file = testing::write_file(scratch("once.bin"), "the bytes of a file, once");
  const MarkingRead read = marking("once");
  check_first_read(file, read);
  check_first_read(file, read);
  EXPECT_EQ(read.children(), 1);
  // Other bytes under the same name are another file.
  testing::write_file(file, "the bytes of a file, twice");
  check_first_read(file, read);
  EXPECT_EQ(read.children(), 2);
}

TEST(FirstRead, ACrashIsARefusalNamingTheFileAndIsKept) {
  const fs::path file = testing::write_file(scratch("crash.bin"), "bytes that crash a reader");
  const auto crash = [] { std::raise(SIGSEGV); };
  try {
    check_first_read(file, crash);
    FAIL() << "not refused";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ": damaged: reading it crashes HDF5"),
              std::string::npos)
        << e.what();
  }
  // The same bytes again: refused without a child, whatever the read would do now.
  const MarkingRead read = marking("crash");
  EXPECT_THROW(check_first_read(file, read), Hdf5Error);
  EXPECT_EQ(read.children(), 0);
}

TEST(FirstRead, BytesThisProcessWroteNeedNoChild) {
  const std::string bytes = "bytes an Hdf5Writer committed";
  remember_readable(bytes);
  const fs::path file = testing::write_file(scratch("written.bin"), bytes);
  const MarkingRead read = marking("written");
  check_first_read(file, read);
  EXPECT_EQ(read.children(), 0);
}

TEST(FirstRead, ALoopIsRefusedAtTheBound) {
  const fs::path file = testing::write_file(scratch("loop.bin"), "bytes that loop a reader");
  const auto loop = [] {
    for (volatile bool forever = true; forever;) {
    }
  };
  try {
    check_first_read(file, loop);
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
