// FunctionFS: ep0 carries the descriptors in and the host's events out; endpoints are files.
#include "ffs_function.h"

#include <fcntl.h>
#include <linux/usb/functionfs.h>
#include <poll.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::gadget {
namespace {

bool WriteAll(int fd, const std::vector<uint8_t>& data) {
  return write(fd, data.data(), data.size()) == static_cast<ssize_t>(data.size());
}

}  // namespace

FfsFunction::~FfsFunction() { Close(); }

bool FfsFunction::Open(const std::string& name, const std::string& mount_dir,
                       const std::vector<uint8_t>& descriptors, const std::vector<uint8_t>& strings,
                       int endpoints, std::string* error) {
  name_ = name;
  mount_dir_ = mount_dir;
  mkdir(mount_dir.c_str(), 0755);
  if (mount(name.c_str(), mount_dir.c_str(), "functionfs", 0, nullptr) != 0) {
    *error = "mount functionfs " + name + " at " + mount_dir + ": " + std::strerror(errno);
    return false;
  }
  mounted_ = true;
  ep0_ = open((mount_dir + "/ep0").c_str(), O_RDWR | O_CLOEXEC);
  if (ep0_ < 0 || !WriteAll(ep0_, descriptors) || !WriteAll(ep0_, strings)) {
    *error = mount_dir + "/ep0: the kernel refused the descriptors: " + std::strerror(errno);
    return false;
  }
  for (int i = 1; i <= endpoints; ++i) {
    // Non-blocking: a transfer queued while the host has not configured the function is refused
    // at once instead of waiting for it.
    const std::string path = mount_dir + "/ep" + std::to_string(i);
    const int fd = open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      *error = path + ": " + std::strerror(errno);
      return false;
    }
    endpoints_.push_back(fd);
  }
  return true;
}

void FfsFunction::Close() {
  for (int fd : endpoints_) close(fd);
  endpoints_.clear();
  if (ep0_ >= 0) close(ep0_);
  ep0_ = -1;
  if (mounted_) umount(mount_dir_.c_str());
  mounted_ = false;
  enabled_ = false;
}

bool FfsFunction::ServiceEp0() {
  bool changed = false;
  for (;;) {
    pollfd p{ep0_, POLLIN, 0};
    if (ep0_ < 0 || poll(&p, 1, 0) <= 0 || (p.revents & POLLIN) == 0) return changed;
    usb_functionfs_event events[4];
    const ssize_t n = read(ep0_, events, sizeof(events));
    if (n <= 0) return changed;
    for (ssize_t i = 0; i < n / static_cast<ssize_t>(sizeof(events[0])); ++i) {
      switch (events[i].type) {
        case FUNCTIONFS_ENABLE:
          changed |= !enabled_;
          enabled_ = true;
          break;
        case FUNCTIONFS_DISABLE:
        case FUNCTIONFS_UNBIND:
          changed |= enabled_;
          enabled_ = false;
          break;
        case FUNCTIONFS_SETUP:
          AnswerSetup(events[i].u.setup);
          break;
        default:  // bind, suspend, resume: nothing to do
          break;
      }
    }
  }
}

void FfsFunction::AnswerSetup(const usb_ctrlrequest& request) {
  std::vector<uint8_t> reply;
  const bool answered = setup_ && setup_(request, &reply);
  // FunctionFS: the data stage goes the request's way, and a transfer against it stalls. The
  // result is not needed: a stall reports an error by design, and so does a host that gave up.
  ssize_t moved = 0;
  if ((request.bRequestType & USB_DIR_IN) != 0) {
    if (reply.size() > request.wLength) reply.resize(request.wLength);
    moved = answered ? write(ep0_, reply.data(), reply.size()) : read(ep0_, reply.data(), 0);
  } else {
    std::vector<uint8_t> data(request.wLength);
    moved = answered ? read(ep0_, data.data(), data.size()) : write(ep0_, data.data(), 0);
  }
  (void)moved;
}

}  // namespace palpa::gadget
