// Who owns a gadget name: a lock the kernel drops when its holder dies, so that a gadget a killed
// program left in configfs is told apart from one a running program serves, and only the first
// is taken down.
#pragma once

#include <string>

namespace palpa::gadget {

class GadgetClaim {
 public:
  GadgetClaim() = default;
  ~GadgetClaim() { Release(); }
  GadgetClaim(const GadgetClaim&) = delete;
  GadgetClaim& operator=(const GadgetClaim&) = delete;

  /// Takes `lock_path` (made if missing; flock, exclusive) for gadget NAME and writes this
  /// process's id into it. False when a running process holds it, *error naming that process.
  bool Take(const std::string& lock_path, const std::string& name, std::string* error);
  void Release();

 private:
  int fd_ = -1;
};

/// With the claim held: takes down what a dead owner left of gadget NAME — its FunctionFS
/// instances unmounted, the gadget unbound, its configfs tree removed. *found says whether there
/// was one. False, with nothing touched, when a FunctionFS instance of it is still open (a running
/// program that does not take the claim serves it), or when it could not be removed.
bool RemoveStaleGadget(const std::string& name, bool* found, std::string* error);

}  // namespace palpa::gadget
