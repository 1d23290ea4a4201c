#include "study/formats/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

namespace impactid {

void write_text_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  // A stream reports only that it failed; errno, cleared before and read right after, holds the
  // system's reason for the write or close that failed.
  const auto fail = [&](const std::string& what) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "the stream failed";
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw TextFileError(path.string() + ": " + what + ": " + reason);
  };
  try {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail("cannot create " + temporary.string());
    write(out);
    errno = 0;
    out.close();  // the last buffered bytes are written here, and may fail here
    if (!out) fail("cannot write " + temporary.string());
  } catch (const TextFileError&) {
    throw;
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw TextFileError(path.string() + ": cannot replace it with " + temporary.string() + ": " +
                        ec.message());
  }
}

}  // namespace impactid
