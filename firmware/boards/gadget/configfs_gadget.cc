// The gadget's configfs tree, made in the order the kernel wants and removed in reverse.
#include "configfs_gadget.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

namespace palpa::gadget {
namespace {

constexpr char kGadgetRoot[] = "/sys/kernel/config/usb_gadget";

bool MakeDirectory(const std::string& path, std::string* error) {
  if (mkdir(path.c_str(), 0755) == 0 || errno == EEXIST) return true;
  *error = path + ": " + std::strerror(errno) +
           (errno == ENOENT ? " (is configfs mounted and libcomposite loaded?)" : "");
  return false;
}

std::string Hex(uint16_t value) {
  char text[8];
  std::snprintf(text, sizeof(text), "0x%04x", value);
  return text;
}

/// The names in a directory, without "." and "..".
std::vector<std::string> Entries(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0)
        names.push_back(e->d_name);
    }
    closedir(d);
  }
  return names;
}

std::string FirstUdc() {
  std::string first;
  if (DIR* dir = opendir("/sys/class/udc")) {
    while (dirent* e = readdir(dir)) {
      if (e->d_name[0] != '.' && (first.empty() || first > e->d_name)) first = e->d_name;
    }
    closedir(dir);
  }
  return first;
}

}  // namespace

std::string GadgetPath(const std::string& name) { return std::string(kGadgetRoot) + "/" + name; }

bool RemoveGadgetTree(const std::string& path, std::string* error) {
  // configfs takes a gadget apart only in this order: the configurations' links to functions and
  // their strings, the configurations, the functions, the strings, then the gadget itself (the
  // kernel removes the attribute files and the groups it made along with their directory).
  for (const std::string& c : Entries(path + "/configs")) {
    const std::string config = path + "/configs/" + c;
    for (const std::string& e : Entries(config)) {
      struct stat st;
      if (lstat((config + "/" + e).c_str(), &st) == 0 && S_ISLNK(st.st_mode))
        unlink((config + "/" + e).c_str());
    }
    for (const std::string& lang : Entries(config + "/strings"))
      rmdir((config + "/strings/" + lang).c_str());
    rmdir(config.c_str());
  }
  for (const std::string& f : Entries(path + "/functions"))
    rmdir((path + "/functions/" + f).c_str());
  for (const std::string& lang : Entries(path + "/strings"))
    rmdir((path + "/strings/" + lang).c_str());
  if (rmdir(path.c_str()) == 0 || errno == ENOENT) return true;
  if (error != nullptr) *error = path + ": cannot be removed: " + std::strerror(errno);
  return false;
}

bool WriteAttribute(const std::string& path, const std::string& text, std::string* error) {
  const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
  const bool ok =
      fd >= 0 && write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const int saved = errno;
  if (fd >= 0) close(fd);
  if (!ok && error != nullptr) *error = path + ": " + std::strerror(saved);
  return ok;
}

ConfigfsGadget::~ConfigfsGadget() { Remove(); }

bool ConfigfsGadget::Create(const std::string& name, const GadgetIdentity& id, std::string* error) {
  path_ = GadgetPath(name);
  const std::string strings = path_ + "/strings/0x409", config = path_ + "/configs/c.1";
  return MakeDirectory(path_, error) &&
         WriteAttribute(path_ + "/idVendor", Hex(id.vendor), error) &&
         WriteAttribute(path_ + "/idProduct", Hex(id.product), error) &&
         WriteAttribute(path_ + "/bcdDevice", Hex(id.device_release), error) &&
         WriteAttribute(path_ + "/bcdUSB", "0x0200", error) &&
         WriteAttribute(path_ + "/max_speed", id.max_speed, error) &&
         MakeDirectory(strings, error) &&
         WriteAttribute(strings + "/manufacturer", id.manufacturer, error) &&
         WriteAttribute(strings + "/product", id.product_name, error) &&
         WriteAttribute(strings + "/serialnumber", id.serial, error) &&
         MakeDirectory(config, error) &&
         WriteAttribute(config + "/MaxPower", std::to_string(id.max_power_ma), error) &&
         MakeDirectory(config + "/strings/0x409", error) &&
         WriteAttribute(config + "/strings/0x409/configuration", "palpa link", error);
}

bool ConfigfsGadget::AddFunction(const std::string& instance, std::string* error) {
  const std::string function = path_ + "/functions/" + instance;
  if (!MakeDirectory(function, error)) return false;
  const std::string link = path_ + "/configs/c.1/" + instance;
  if (symlink(function.c_str(), link.c_str()) != 0 && errno != EEXIST) {
    *error = link + ": " + std::strerror(errno);
    return false;
  }
  return true;
}

std::string ConfigfsGadget::FunctionAttribute(const std::string& instance,
                                              const std::string& attribute) const {
  std::ifstream in(path_ + "/functions/" + instance + "/" + attribute);
  std::string value;
  std::getline(in, value);
  return value;
}

bool ConfigfsGadget::Bind(const std::string& udc, std::string* error) {
  const std::string chosen = udc.empty() ? FirstUdc() : udc;
  if (chosen.empty()) {
    *error = "no USB device controller in /sys/class/udc (load dummy_hcd, or a real UDC driver)";
    return false;
  }
  if (!WriteAttribute(path_ + "/UDC", chosen, error)) return false;
  udc_ = chosen;
  return true;
}

void ConfigfsGadget::Unbind() {
  if (!path_.empty()) WriteAttribute(path_ + "/UDC", "\n", nullptr);
}

void ConfigfsGadget::Remove() {
  if (path_.empty()) return;
  Unbind();
  RemoveGadgetTree(path_, nullptr);
  path_.clear();
}

}  // namespace palpa::gadget
