#include <tripsitter/display/io.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <random>
#include <system_error>

namespace tripsitter::display {
namespace {

std::string errno_message(int e) { return std::generic_category().message(e); }

// Creates a new file "<path>.tmp-XXXXXXXX" that did not exist before ("x": exclusive). On failure returns
// nullptr with the errno of the last attempt in `err`.
std::FILE* create_temp_beside(const std::string& path, std::string& tmp_path, int& err) {
  std::random_device rd;
  std::mt19937 gen(rd());
  for (int attempt = 0; attempt < 16; ++attempt) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(gen()));
    tmp_path = path + ".tmp-" + suffix;
    errno = 0;
    if (std::FILE* f = std::fopen(tmp_path.c_str(), "wbx")) return f;
    err = errno;
    if (err != EEXIST) return nullptr;
  }
  return nullptr;
}

}  // namespace

core::Result<bool, IoError> write_file_beside_and_rename(const std::string& path, std::span<const char> bytes,
                                                         const std::string& what) {
  const auto error = [&](const std::string& reason) { return IoError{what + " '" + path + "': " + reason}; };
  std::string tmp_path;
  int err = 0;
  std::FILE* f = create_temp_beside(path, tmp_path, err);
  if (f == nullptr) return error("cannot create temporary file '" + tmp_path + "': " + errno_message(err));

  errno = 0;
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_errno = errno;
  const bool flushed = std::fflush(f) == 0 && std::ferror(f) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(f) == 0;
  const int close_errno = errno;

  std::string reason;
  if (!written) {
    reason = errno_message(write_errno);
  } else if (!flushed) {
    reason = errno_message(flush_errno);
  } else if (!closed) {
    reason = errno_message(close_errno);
  } else {
    std::error_code ec;
    std::filesystem::rename(tmp_path, path, ec);
    if (!ec) return true;
    reason = "cannot rename '" + tmp_path + "': " + ec.message();
  }
  std::error_code ignored;
  std::filesystem::remove(tmp_path, ignored);
  return error(reason);
}

}  // namespace tripsitter::display
