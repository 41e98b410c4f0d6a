// A composite USB gadget made through configfs (libcomposite): device identity and strings, one
// configuration, its functions, and binding to a USB device controller (UDC). Unbinding is what
// unplugging the cable does to the host.
#pragma once

#include <cstdint>
#include <string>

namespace palpa::gadget {

struct GadgetIdentity {
  uint16_t vendor = 0x1209;  ///< pid.codes test id, as host::kUsbVendorId
  uint16_t product = 0x0001;
  uint16_t device_release = 0x0100;
  std::string manufacturer = "palpa";
  std::string product_name = "palpa actuator board";
  std::string serial = "0001";
  uint16_t max_power_ma = 100;
  std::string max_speed = "full-speed";  ///< as an MCU's USB: 64-byte bulk packets, 1 ms frames
};

class ConfigfsGadget {
 public:
  ConfigfsGadget() = default;
  ~ConfigfsGadget();  ///< unbinds and removes everything it made
  ConfigfsGadget(const ConfigfsGadget&) = delete;
  ConfigfsGadget& operator=(const ConfigfsGadget&) = delete;

  /// Makes /sys/kernel/config/usb_gadget/NAME with the identity and one configuration.
  bool Create(const std::string& name, const GadgetIdentity& identity, std::string* error);
  /// Makes functions/INSTANCE ("ffs.palpa_bulk", "acm.palpa") and links it into the configuration.
  bool AddFunction(const std::string& instance, std::string* error);
  /// Reads an attribute of a function (the ACM function's port_num).
  std::string FunctionAttribute(const std::string& instance, const std::string& attribute) const;
  /// Binds to `udc` (empty: the first one in /sys/class/udc).
  bool Bind(const std::string& udc, std::string* error);
  void Unbind();
  void Remove();

  const std::string& path() const { return path_; }
  const std::string& udc() const { return udc_; }

 private:
  std::string path_;
  std::string udc_;
};

/// /sys/kernel/config/usb_gadget/NAME.
std::string GadgetPath(const std::string& name);
/// Removes an unbound gadget's configfs tree, whatever configurations and functions it has (a
/// missing one is no error); false with *error (when not null) if the gadget is still there.
bool RemoveGadgetTree(const std::string& path, std::string* error);

/// Writes `text` to a sysfs or configfs attribute; false with *error naming it on failure.
bool WriteAttribute(const std::string& path, const std::string& text, std::string* error);

}  // namespace palpa::gadget
