// Native AIO through the raw system calls (no libaio needed).
#include "aio.h"

#include <sys/eventfd.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::gadget {

AioContext::~AioContext() {
  if (context_ != 0) syscall(SYS_io_destroy, context_);  // waits for what is still in flight
  if (event_fd_ >= 0) close(event_fd_);
}

bool AioContext::Open(unsigned max_in_flight, std::string* error) {
  event_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (event_fd_ < 0 || syscall(SYS_io_setup, max_in_flight, &context_) != 0) {
    *error = std::string("native AIO: ") + std::strerror(errno);
    return false;
  }
  return true;
}

bool AioContext::Submit(int fd, bool write, void* buffer, size_t size, uint64_t tag) {
  iocb cb{};
  cb.aio_fildes = static_cast<uint32_t>(fd);
  cb.aio_lio_opcode = write ? IOCB_CMD_PWRITE : IOCB_CMD_PREAD;
  cb.aio_buf = reinterpret_cast<uint64_t>(buffer);
  cb.aio_nbytes = size;
  cb.aio_flags = IOCB_FLAG_RESFD;
  cb.aio_resfd = static_cast<uint32_t>(event_fd_);
  cb.aio_data = tag;
  iocb* list[1] = {&cb};  // the kernel copies the control block during the call
  return syscall(SYS_io_submit, context_, 1, list) == 1;
}

void AioContext::Reap(const std::function<void(uint64_t, int64_t)>& done) {
  uint64_t ready = 0;
  if (read(event_fd_, &ready, sizeof(ready)) != sizeof(ready)) return;
  io_event events[32];
  for (;;) {
    timespec no_wait{0, 0};
    const long n = syscall(SYS_io_getevents, context_, 0, 32, events, &no_wait);
    if (n <= 0) return;
    for (long i = 0; i < n; ++i) done(events[i].data, events[i].res);
    if (n < 32) return;
  }
}

}  // namespace palpa::gadget
