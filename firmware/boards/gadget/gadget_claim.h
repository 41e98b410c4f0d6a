// A gadget a killed program left behind, taken down: its name's claim (hosted::ProcessClaim, a
// lock the kernel drops when its holder dies) tells it apart from one a running program serves.
#pragma once

#include <string>

namespace palpa::gadget {

/// With the claim held: takes down what a dead owner left of gadget NAME — its FunctionFS
/// instances unmounted, the gadget unbound, its configfs tree removed. *found says whether there
/// was one. False, with nothing touched, when a FunctionFS instance of it is still open (a running
/// program that does not take the claim serves it), or when it could not be removed.
bool RemoveStaleGadget(const std::string& name, bool* found, std::string* error);

}  // namespace palpa::gadget
