// The simulated board's flash in a file: a header naming the board, then the flash's bytes.
#include "flash_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace palpa::sim {
namespace {

/// "palpa-sim flash 1\n", the configuration's name (NUL-padded), the flash size (LE), zeros.
constexpr size_t kHeaderSize = 64;
constexpr char kMagic[] = "palpa-sim flash 1\n";
constexpr size_t kNameAt = 24, kNameSize = 24, kSizeAt = 48;

std::vector<uint8_t> Header(const std::string& config, uint32_t size) {
  std::vector<uint8_t> h(kHeaderSize, 0);
  std::memcpy(h.data(), kMagic, sizeof(kMagic) - 1);
  std::memcpy(h.data() + kNameAt, config.data(), std::min(config.size(), kNameSize - 1));
  for (int i = 0; i < 4; ++i) h[kSizeAt + i] = static_cast<uint8_t>(size >> (8 * i));
  return h;
}

bool WriteAll(int fd, const uint8_t* data, size_t size, off_t at) {
  while (size > 0) {
    const ssize_t n = pwrite(fd, data, size, at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
    at += n;
  }
  return true;
}

}  // namespace

FlashFile::~FlashFile() {
  if (fd_ >= 0) close(fd_);
}

hal::Done FlashFile::Open(const std::string& path, const std::string& config) {
  const std::string where = "--flash " + path + ": ";
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) return {Status::kIoError, where + std::strerror(errno)};
  struct stat st {};
  fstat(fd_, &st);
  const std::vector<uint8_t> expected = Header(config, flash_.size());
  existed_ = st.st_size > 0;
  if (!existed_) {  // a new board: the flash as the factory left it
    if (!WriteAll(fd_, expected.data(), expected.size(), 0) ||
        !WriteAll(fd_, flash_.contents().data(), flash_.size(), kHeaderSize) || fsync(fd_) != 0) {
      return {Status::kIoError, where + "cannot write: " + std::strerror(errno)};
    }
    return {};
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(st.st_size));
  if (pread(fd_, bytes.data(), bytes.size(), 0) != static_cast<ssize_t>(bytes.size()) ||
      bytes.size() < kHeaderSize || std::memcmp(bytes.data(), kMagic, sizeof(kMagic) - 1) != 0) {
    return {Status::kBadValue, where + "not a palpa-sim flash file"};
  }
  const std::string owner(
      reinterpret_cast<const char*>(bytes.data() + kNameAt),
      strnlen(reinterpret_cast<const char*>(bytes.data() + kNameAt), kNameSize));
  if (owner != config) {
    return {Status::kBadValue, where + "the flash of a " + owner + " board, not of a " + config +
                                   " one (start it with --config " + owner +
                                   ", or give another file)"};
  }
  if (std::memcmp(bytes.data(), expected.data(), kHeaderSize) != 0 ||
      !flash_.Restore(bytes.data() + kHeaderSize, bytes.size() - kHeaderSize)) {
    return {Status::kBadValue, where + std::to_string(bytes.size() - kHeaderSize) +
                                   " bytes of flash, where this board has " +
                                   std::to_string(flash_.size())};
  }
  return {};
}

Status FlashFile::Persist(uint32_t offset, size_t size) {
  if (offset > flash_.size() || size > flash_.size() - offset) return Status::kOutOfRange;
  return WriteAll(fd_, flash_.contents().data() + offset, size, kHeaderSize + offset)
             ? Status::kOk
             : Status::kIoError;
}

Status FlashFile::DoErase(uint32_t offset) {
  const Status s = flash_.Erase(offset);
  const Status kept = Persist(offset, flash_.sector_size());  // a torn erase is kept torn
  return s != Status::kOk ? s : kept;
}

Status FlashFile::DoProgram(uint32_t offset, const uint8_t* data, size_t size) {
  const Status s = flash_.Program(offset, data, size);
  const Status kept = Persist(offset, size);
  return s != Status::kOk ? s : kept;
}

Status FlashFile::DoRead(uint32_t offset, uint8_t* out, size_t size) {
  return flash_.Read(offset, out, size);
}

}  // namespace palpa::sim
