// Shared by the fuzz targets: scratch files, the source tree, invariant checks, and ROS message
// deserialization that cannot be made to allocate gigabytes.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <string>

#include <ros/serialization.h>

#ifndef AAR_SOURCE_DIR
#error "AAR_SOURCE_DIR (the repository's src/) must be defined"
#endif

// A property of the code under test that does not hold: reported and the run ends (libFuzzer
// keeps the input as a crash; the corpus test fails).
#define FUZZ_CHECK(condition, message)                                                             \
  do {                                                                                             \
    if (!(condition)) {                                                                            \
      std::fprintf(stderr, "FUZZ_CHECK failed at %s:%d: %s: %s\n", __FILE__, __LINE__, #condition, \
                   std::string(message).c_str());                                                  \
      std::abort();                                                                                \
    }                                                                                              \
  } while (0)

namespace aar_fuzz {

inline std::string SourceDir() { return AAR_SOURCE_DIR; }

// A folder of this process's own (libFuzzer's -jobs run several), in memory where possible,
// removed at exit.
inline const std::string& ScratchDir() {
  static const std::string dir = [] {
    namespace fs = std::filesystem;
    const fs::path base = fs::is_directory("/dev/shm") ? "/dev/shm" : fs::temp_directory_path();
    const fs::path path = base / ("aar_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(path);
    static const struct Remover {
      fs::path path;
      ~Remover() {
        std::error_code ec;
        fs::remove_all(path, ec);
      }
    } remover{path};
    return path.string();
  }();
  return dir;
}

// Writes the bytes to ScratchDir()/name and returns the path.
inline std::string WriteScratch(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = ScratchDir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  return path;
}

// roscpp_serialization resizes a vector to its 4-byte length prefix before it checks that the
// buffer holds that much, so a few bytes can ask for 4 GB (ROS's transport bounds a message at
// 1 GB, not its fields). Messages are first read with this allocator, which refuses more elements
// than there are bytes left to read (every element takes at least one), and only then for real.
inline size_t& MaxElements() {
  static thread_local size_t max = 0;
  return max;
}
template <typename T>
struct CappedAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {  // the generated messages use the C++03 form
    using other = CappedAllocator<U>;
  };
  CappedAllocator() = default;
  template <typename U>
  CappedAllocator(const CappedAllocator<U>&) {}  // NOLINT: allocators convert implicitly
  T* allocate(size_t n) {
    if (n > MaxElements()) throw std::bad_alloc();
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, size_t n) { std::allocator<T>().deallocate(p, n); }
};
template <typename T, typename U>
bool operator==(const CappedAllocator<T>&, const CappedAllocator<U>&) {
  return true;
}
template <typename T, typename U>
bool operator!=(const CappedAllocator<T>&, const CappedAllocator<U>&) {
  return false;
}

// The next message of type Msg (e.g. sensor_msgs::PointCloud2_) from `stream`; false, with the
// stream where it was, when the bytes left do not hold one.
template <template <typename> class Msg>
bool NextMessage(ros::serialization::IStream& stream, Msg<std::allocator<void>>& out) {
  try {
    ros::serialization::IStream probe(stream.getData(), stream.getLength());
    MaxElements() = stream.getLength();
    Msg<CappedAllocator<void>> capped;
    ros::serialization::deserialize(probe, capped);
  } catch (const ros::serialization::StreamOverrunException&) {
    return false;
  } catch (const std::bad_alloc&) {
    return false;
  }
  ros::serialization::deserialize(stream, out);  // the same bytes: they fit
  return true;
}

}  // namespace aar_fuzz
