// One FunctionFS function: its file system mounted, descriptors and strings written to ep0, the
// events read from ep0 (bind, enable, disable, setup requests) and its endpoint files.
#pragma once

#include <linux/usb/ch9.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace palpa::gadget {

class FfsFunction {
 public:
  /// Answers a setup request addressed to the function's interface: the data for an IN request,
  /// or false to stall it. An OUT request without data is acknowledged when this returns true.
  using SetupHandler = std::function<bool(const usb_ctrlrequest&, std::vector<uint8_t>* reply)>;

  FfsFunction() = default;
  ~FfsFunction();
  FfsFunction(const FfsFunction&) = delete;
  FfsFunction& operator=(const FfsFunction&) = delete;

  /// Mounts the instance NAME (configfs functions/ffs.NAME) at `mount_dir`, writes descriptors
  /// and strings, and opens the `endpoints` endpoint files (ep1, ep2, ... in descriptor order).
  bool Open(const std::string& name, const std::string& mount_dir,
            const std::vector<uint8_t>& descriptors, const std::vector<uint8_t>& strings,
            int endpoints, std::string* error);
  void Close();
  void set_setup_handler(SetupHandler handler) { setup_ = std::move(handler); }

  /// Reads what ep0 has (never blocks) and answers setup requests. Returns true when the
  /// function was enabled or disabled (the host configured it, or it went away).
  bool ServiceEp0();
  bool enabled() const { return enabled_; }
  int ep0_fd() const { return ep0_; }
  int endpoint_fd(int index) const { return endpoints_[static_cast<size_t>(index)]; }
  const std::string& name() const { return name_; }

 private:
  void AnswerSetup(const usb_ctrlrequest& request);

  std::string name_;
  std::string mount_dir_;
  bool mounted_ = false;
  int ep0_ = -1;
  std::vector<int> endpoints_;
  bool enabled_ = false;
  SetupHandler setup_;
};

}  // namespace palpa::gadget
