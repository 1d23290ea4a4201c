// check_first_read (study/formats/first_read.hpp): the first read of some bytes runs in a child
// process, once; a crash or a loop there is a refusal naming the file, kept for the same bytes;
// bytes this process wrote, or changed bytes, are told apart by their digest.
#include "study/formats/first_read.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdint>
#include <cstdlib>
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
  check_first_read(file, read).keep();
  check_first_read(file, read).keep();
  EXPECT_EQ(read.children(), 1);
  // Other bytes under the same name are another file.
  testing::write_file(file, "the bytes of a file, twice");
  check_first_read(file, read).keep();
  EXPECT_EQ(read.children(), 2);
}

TEST(FirstRead, ACrashIsARefusalNamingTheFileAndIsKept) {
  const fs::path file = testing::write_file(scratch("crash.bin"), "bytes that crash a reader");
  const auto crash = [] { std::raise(SIGSEGV); };
  try {
    check_first_read(file, crash).keep();
    FAIL() << "not refused";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ": damaged: reading it crashes HDF5"),
              std::string::npos)
        << e.what();
  }
  // The same bytes again: refused without a child, whatever the read would do now.
  const MarkingRead read = marking("crash");
  EXPECT_THROW(check_first_read(file, read).keep(), Hdf5Error);
  EXPECT_EQ(read.children(), 0);
}

// From the child's start to the caller's own read this process takes and gives back no memory,
// so that the caller's read meets the heap the child met (first_read.cpp says why: HDF5 reads
// memory it never set on some damaged files): the first block the child takes is the block
// this process takes first after the check, and an outcome is kept only when the caller says.
TEST(FirstRead, TheCallerMeetsTheHeapTheChildMet) {
  const fs::path file =
      testing::write_file(scratch("heap.bin"), "a file whose reader takes memory");
  const fs::path where = scratch("heap.address");
  const int fd = ::open(where.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  constexpr std::size_t kBytes = 40;  // the size of the blocks a kept outcome takes
  constexpr int kBlocks = 4;
  using Addresses = std::array<std::uintptr_t, kBlocks>;
  // The addresses of kBlocks blocks taken one after the other, then given back.
  const auto take_blocks = [] {
    std::array<void*, kBlocks> blocks{};
    Addresses addresses{};
    for (int k = 0; k < kBlocks; ++k) {
      blocks[k] = std::malloc(kBytes);
      addresses[k] = reinterpret_cast<std::uintptr_t>(blocks[k]);
    }
    for (void* block : blocks) std::free(block);
    return addresses;
  };
  const auto take = [fd, &take_blocks] {
    const Addresses addresses = take_blocks();
    if (::write(fd, addresses.data(), sizeof addresses) != sizeof addresses) _exit(3);
  };
  for (int round = 0; round < 3; ++round) {
    ASSERT_EQ(::lseek(fd, 0, SEEK_SET), 0);
    testing::write_file(file, "a file whose reader takes memory, round " + std::to_string(round));
    const FirstRead first = check_first_read(file, take);
    const Addresses mine = take_blocks();
    first.keep();
    Addresses childs{};
    std::ifstream in(where, std::ios::binary);
    in.read(reinterpret_cast<char*>(childs.data()), sizeof childs);
    ASSERT_TRUE(in) << "the child wrote no addresses";
    EXPECT_EQ(mine, childs) << "round " << round;
  }
  ::close(fd);
}

TEST(FirstRead, BytesThisProcessWroteNeedNoChild) {
  const std::string bytes = "bytes an Hdf5Writer committed";
  remember_readable(bytes);
  const fs::path file = testing::write_file(scratch("written.bin"), bytes);
  const MarkingRead read = marking("written");
  check_first_read(file, read).keep();
  EXPECT_EQ(read.children(), 0);
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
  check_first_read(file, read).keep();
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
      check_first_read(file, read).keep();
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
  const auto loop = [] {
    for (volatile bool forever = true; forever;) {
    }
  };
  try {
    check_first_read(file, loop).keep();
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
