#include "cobra/bridges/shared_memory.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace cobra::bridges {

namespace {
[[noreturn]] void fail(const std::string& name, const std::string& what, int error) {
  throw std::runtime_error("shared memory '" + name + "': " + what + ": " + std::strerror(error));
}
}  // namespace

SharedSegment::SharedSegment(const std::string& name, std::size_t size) : name_(name), size_(size) {
  if (name.size() < 2 || name.front() != '/' || name.find('/', 1) != std::string::npos)
    throw std::runtime_error("shared memory '" + name + "': a name is '/' followed by at least one character and no "
                             "other '/', e.g. '/cobra_isur'");
  const int fd = ::shm_open(name.c_str(), O_RDWR | O_CREAT, 0600);
  if (fd < 0) fail(name, "shm_open", errno);
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    fail(name, "fstat", e);
  }
  if (st.st_size == 0) {
    if (::ftruncate(fd, static_cast<off_t>(size)) != 0) {
      const int e = errno;
      ::close(fd);
      fail(name, "ftruncate to " + std::to_string(size) + " bytes", e);
    }
  } else if (static_cast<std::size_t>(st.st_size) != size) {
    ::close(fd);
    throw std::runtime_error("shared memory '" + name + "' has " + std::to_string(st.st_size) + " bytes, expected " +
                             std::to_string(size) + ": another program uses this name");
  }
  void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int e = errno;
  ::close(fd);
  if (p == MAP_FAILED) fail(name, "mmap", e);
  data_ = p;
}

SharedSegment::~SharedSegment() {
  if (data_ != nullptr) ::munmap(data_, size_);
}

bool SharedSegment::unlink(const std::string& name) noexcept { return ::shm_unlink(name.c_str()) == 0; }

}  // namespace cobra::bridges
