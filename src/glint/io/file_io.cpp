// Whole-file reads and atomic writes (temp file in the target's folder, then
// rename), shared by the image writers and the render's resume files.
#include "glint/io/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <string>
#include <system_error>

#include "glint/error.h"

namespace glint {
namespace fs = std::filesystem;

void fail_write(const fs::path& path, const std::string& reason) {
  throw Error(SourceLocation{path.string(), 0, 0}, "cannot write: " + reason);
}
void fail_read(const fs::path& path, const std::string& reason) {
  throw Error(SourceLocation{path.string(), 0, 0}, "cannot read: " + reason);
}

namespace {

std::string errno_message(int error) { return std::generic_category().message(error); }

// --- the atomic write -------------------------------------------------------

// Owns the temp file until it has been renamed over the target.
class TempFile {
 public:
  TempFile() = default;
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd >= 0) ::close(fd);
    if (!committed && !path.empty()) {
      std::error_code ignored;
      fs::remove(path, ignored);
    }
  }
  fs::path path;
  int fd = -1;
  bool committed = false;
};

}  // namespace

void write_file_atomically(const fs::path& target, std::span<const unsigned char> bytes, Flush flush) {
  static std::atomic<unsigned long> counter{0};
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  // Appended piece by piece: `"." + std::string` trips GCC 12's bogus -Wrestrict at -O3.
  std::string prefix(1, '.');
  prefix += target.filename().string();
  prefix += ".glint-tmp-";
  prefix += std::to_string(::getpid());
  prefix += '-';

  TempFile temp;
  // O_EXCL: never reuse (and so never clobber) a file that already exists,
  // e.g. one left by a crashed run whose pid has been recycled.
  for (int attempt = 0; attempt < 100 && temp.fd < 0; ++attempt) {
    fs::path candidate = folder / (prefix + std::to_string(counter++));
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    const int error = errno;  // before any string building can disturb it
    if (fd >= 0) {
      temp.path = std::move(candidate);
      temp.fd = fd;
    } else if (error != EEXIST) {
      fail_write(target, "cannot create a temporary file in '" + folder.string() + "': " + errno_message(error));
    }
  }
  if (temp.fd < 0) fail_write(target, "cannot create a temporary file in '" + folder.string() + "'");

  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t chunk = std::min<std::size_t>(bytes.size() - done, std::size_t{1} << 30);
    const ssize_t n = ::write(temp.fd, bytes.data() + done, chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_write(target, errno_message(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  // Flush before the rename: otherwise a crash could leave a renamed but empty file.
  // EINVAL only means this file system cannot sync, which is not an error here.
  if (flush == Flush::to_disk && ::fsync(temp.fd) != 0 && errno != EINVAL) fail_write(target, errno_message(errno));
  const int fd = temp.fd;
  temp.fd = -1;
  if (::close(fd) != 0) fail_write(target, errno_message(errno));

  std::error_code ec;
  fs::rename(temp.path, target, ec);
  if (ec) fail_write(target, ec.message());
  temp.committed = true;
}

namespace {
thread_local FileReadLog* read_log = nullptr;  // the innermost on this thread
}  // namespace

std::vector<unsigned char> read_file(const fs::path& path) {
  struct FileDescriptor {
    int fd;
    ~FileDescriptor() {
      if (fd >= 0) ::close(fd);
    }
  } file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  const int fd = file.fd;
  if (fd < 0) fail_read(path, errno_message(errno));
  struct stat info {};
  if (::fstat(fd, &info) != 0) fail_read(path, errno_message(errno));
  if (S_ISDIR(info.st_mode)) fail_read(path, "it is a directory");
  std::vector<unsigned char> bytes;
  if (S_ISREG(info.st_mode)) bytes.reserve(static_cast<std::size_t>(info.st_size));
  unsigned char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_read(path, errno_message(errno));
    }
    if (n == 0) break;
    bytes.insert(bytes.end(), buffer, buffer + n);
  }
  for (FileReadLog* log = read_log; log; log = log->outer_) log->files_.push_back(path);
  return bytes;
}

FileReadLog::FileReadLog() : outer_(read_log) { read_log = this; }
FileReadLog::~FileReadLog() { read_log = outer_; }

}  // namespace glint
