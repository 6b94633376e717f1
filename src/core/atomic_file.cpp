#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/error.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace pcl {
namespace patchdict {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void failWrite(const std::string& path, const std::string& what)
{
  throw Error("cannot write '" + path + "': " + what);
}

[[noreturn]] void failRead(const std::string& path, const std::string& what)
{
  throw Error("cannot read '" + path + "': " + what);
}

// O_EXCL: never write through a file (or symlink) someone else put at the temporary name.
void writeNewFile(const std::string& target, const std::string& file_path, const std::string& bytes)
{
  const int fd = ::open(file_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0)
    failWrite(target, std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (written < 0 && errno == EINTR)
      continue;
    if (written <= 0) {
      const int saved = errno;
      ::close(fd);
      failWrite(target, written < 0 ? std::strerror(saved) : "short write");
    }
    done += static_cast<std::size_t>(written);
  }
  if (::fsync(fd) != 0) {
    const int saved = errno;
    ::close(fd);
    failWrite(target, std::strerror(saved));
  }
  if (::close(fd) != 0)
    failWrite(target, std::strerror(errno));
}

// Temporary files being written, for the signal handler: fixed slots of atomic pointers (no
// allocation or lock in the handler; unlink() is async-signal-safe).
constexpr int kSlots = 64;
std::atomic<const char*> g_temporaries[kSlots];

/** Registers a temporary file for the lifetime of the object (no slot free: not registered). */
class TemporaryRegistration {
public:
  explicit TemporaryRegistration(const std::string& path) : path_(path)
  {
    for (int i = 0; i < kSlots; ++i) {
      const char* expected = nullptr;
      if (g_temporaries[i].compare_exchange_strong(expected, path_.c_str())) {
        slot_ = i;
        return;
      }
    }
  }
  ~TemporaryRegistration()
  {
    if (slot_ >= 0)
      g_temporaries[slot_].store(nullptr);
  }
  TemporaryRegistration(const TemporaryRegistration&) = delete;
  TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;

private:
  std::string path_;
  int slot_ = -1;
};

extern "C" void removeTemporariesAndReraise(int signal_number)
{
  for (auto& slot : g_temporaries) {
    const char* path = slot.exchange(nullptr);
    if (path)
      ::unlink(path);
  }
  std::raise(signal_number);  // SA_RESETHAND restored the default action: the process ends as it would have
}

}  // namespace

void removeTemporaryFilesOnInterrupt()
{
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action {};
    action.sa_handler = removeTemporariesAndReraise;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    ::sigaction(signal_number, &action, nullptr);
  }
}

void checkWritableFile(const std::string& path)
{
  const fs::path target(path);
  if (target.filename().empty())
    failWrite(path, "not a file name");
  std::error_code ec;
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(directory, ec))
    failWrite(path, "directory '" + directory.string() + "' does not exist");
  if (fs::is_directory(target, ec))
    failWrite(path, "it is a directory");
}

void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write_temporary)
{
  checkWritableFile(path);
  const fs::path target(path);
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  // Same directory as the target, so the rename cannot cross file systems; pid and counter keep
  // concurrent writers (threads or processes) apart.
  static std::atomic<unsigned long> counter{0};
  const fs::path temporary = directory / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) +
                                          "." + std::to_string(counter++));
  const TemporaryRegistration registration(temporary.string());
  try {
    write_temporary(temporary.string());
    fs::rename(temporary, target, ec);
    if (ec)
      failWrite(path, ec.message());
  } catch (const Error&) {
    fs::remove(temporary, ec);
    throw;
  } catch (const std::exception& e) {
    fs::remove(temporary, ec);
    failWrite(path, e.what());
  }
}

void writeFileAtomically(const std::string& path, const std::string& bytes)
{
  writeFileAtomically(path, [&](const std::string& temporary) { writeNewFile(path, temporary, bytes); });
}

std::string readWholeFile(const std::string& path)
{
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status))
    failRead(path, "no such file");
  if (fs::is_directory(status))
    failRead(path, "is a directory");
  // A FIFO or a device could block forever or never end.
  if (!fs::is_regular_file(status))
    failRead(path, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    failRead(path, std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size < 0 || !in)
    failRead(path, "cannot determine the file size");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(bytes.data(), size))
    failRead(path, "read error");
  return bytes;
}

}  // namespace patchdict
}  // namespace pcl
