#include "aar_geometry/load_error.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace aar_geometry {

void CheckReadableFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw LoadError(path, std::strerror(errno));
  if (S_ISDIR(info.st_mode)) throw LoadError(path, "is a directory, not a file");
  if (!S_ISREG(info.st_mode)) throw LoadError(path, "is not a regular file");
  if (info.st_size == 0) throw LoadError(path, "file is empty");
  std::ifstream probe(path);
  if (!probe) throw LoadError(path, "cannot be opened for reading");
}

}  // namespace aar_geometry
