#include <pcl_patchdict/atomic_file.h>
#include <pcl_patchdict/error.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace pcl {
namespace patchdict {

void writeFileAtomically(const std::string& path, const std::string& bytes)
{
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.filename().empty())
    throw Error("cannot write '" + path + "': not a file name");
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(directory, ec))
    throw Error("cannot write '" + path + "': directory '" + directory.string() + "' does not exist");
  if (fs::is_directory(target, ec))
    throw Error("cannot write '" + path + "': it is a directory");

  static std::atomic<unsigned> counter{0};
  const fs::path temporary = directory / ("." + target.filename().string() + ".tmp." +
                                          std::to_string(::getpid()) + "." + std::to_string(counter++));
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw Error("cannot write '" + path + "': " + std::strerror(errno));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      out.close();
      fs::remove(temporary, ec);
      throw Error("cannot write '" + path + "': write failed (disk full?)");
    }
  }
  if (std::rename(temporary.c_str(), target.c_str()) != 0) {
    const int error = errno;
    fs::remove(temporary, ec);
    throw Error("cannot write '" + path + "': " + std::strerror(error));
  }
}

std::string readWholeFile(const std::string& path)
{
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read '" + path + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error("cannot open '" + path + "': " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0)
    throw Error("cannot read '" + path + "'");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  in.read(bytes.data(), size);
  if (!in)
    throw Error("cannot read '" + path + "': read failed");
  return bytes;
}

}  // namespace patchdict
}  // namespace pcl
