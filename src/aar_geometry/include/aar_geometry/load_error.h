#pragma once

#include <stdexcept>
#include <string>

namespace aar_geometry {

// A model or data file could not be used. what() reads "<path>: <reason>" so that the message
// alone tells a user which file to fix and why.
class LoadError : public std::runtime_error {
 public:
  LoadError(const std::string& path, const std::string& reason)
      : std::runtime_error(path + ": " + reason), path_(path), reason_(reason) {}

  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string path_;
  std::string reason_;
};

// Throws LoadError unless `path` names a readable, non-empty regular file.
void CheckReadableFile(const std::string& path);

}  // namespace aar_geometry
