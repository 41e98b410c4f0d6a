// The gadget name's lock and the teardown of a gadget whose owner died.
#include "gadget_claim.h"

#include <fcntl.h>
#include <mntent.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

#include "configfs_gadget.h"

namespace palpa::gadget {

bool GadgetClaim::Take(const std::string& lock_path, const std::string& name, std::string* error) {
  Release();
  fd_ = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    *error = lock_path + ": " + std::strerror(errno);
    return false;
  }
  // An flock belongs to the open file: the kernel drops it when the last descriptor closes, which
  // a process's death does too. So a held lock is a living owner, whatever its pid says.
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int saved = errno;
    char pid[16] = {};
    const ssize_t n = pread(fd_, pid, sizeof(pid) - 1, 0);
    *error = "gadget " + name + " is in use" +
             (n > 0 ? " by process " + std::string(pid, static_cast<size_t>(n)) : std::string()) +
             " (" + lock_path + " is locked" +
             (saved == EWOULDBLOCK ? "" : ": " + std::string(std::strerror(saved))) + ")";
    Release();
    return false;
  }
  const std::string pid = std::to_string(getpid());
  if (ftruncate(fd_, 0) != 0 || pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    *error = lock_path + ": " + std::strerror(errno);
    Release();
    return false;
  }
  return true;
}

void GadgetClaim::Release() {
  if (fd_ >= 0) close(fd_);  // drops the lock
  fd_ = -1;
}

bool RemoveStaleGadget(const std::string& name, bool* found, std::string* error) {
  const std::string path = GadgetPath(name);
  struct stat st;
  *found = stat(path.c_str(), &st) == 0;
  if (!*found) return true;
  // Its FunctionFS instances: functions/ffs.INSTANCE, each mounted with INSTANCE as its source.
  // A dead owner's mounts stay (the mount outlives the process); its files are closed.
  std::vector<std::pair<std::string, std::string>> mounts;  // instance, mount point
  if (FILE* table = setmntent("/proc/self/mounts", "r")) {
    while (mntent* m = getmntent(table)) {
      if (std::strcmp(m->mnt_type, "functionfs") == 0 &&
          stat((path + "/functions/ffs." + m->mnt_fsname).c_str(), &st) == 0)
        mounts.emplace_back(m->mnt_fsname, m->mnt_dir);
    }
    endmntent(table);
  }
  // Nothing is touched while a program still has one of them open: MNT_EXPIRE only asks
  // (EBUSY: in use; EAGAIN: idle, marked to go), and an open instance is a running server.
  for (const auto& [instance, dir] : mounts) {
    if (umount2(dir.c_str(), MNT_EXPIRE) != 0 && errno == EBUSY) {
      *error = "gadget " + name + ": its FunctionFS instance " + instance + " (" + dir +
               ") is open in a running program";
      return false;
    }
  }
  for (const auto& [instance, dir] : mounts) {
    if (umount(dir.c_str()) != 0) {
      *error = "gadget " + name + ": unmounting " + dir + ": " + std::strerror(errno);
      return false;
    }
  }
  WriteAttribute(path + "/UDC", "\n", nullptr);  // unbound already when its owner died, mostly
  return RemoveGadgetTree(path, error);
}

}  // namespace palpa::gadget
