// The teardown of a gadget whose owner died.
#include "gadget_claim.h"

#include <mntent.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

#include "configfs_gadget.h"

namespace palpa::gadget {

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
