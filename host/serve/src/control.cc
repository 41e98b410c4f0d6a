// One controller, watchers, and what each change of control does to the board.
#include "palpa/serve/control.h"

namespace palpa::serve {

host::Result<Control::Change> Control::Take(ClientId id, bool force,
                                            const std::string& holder_name) {
  Change change;
  if (controller_ == id) return change;
  if (controller_.has_value()) {
    if (!force) {
      return host::Outcome::Fail(
          host::Status::kBusy,
          holder_name +
              " controls the board; taking control from it needs force (a person's "
              "choice): the board is then released first");
    }
    change.release_board = true;
    change.previous = controller_;
  }
  controller_ = id;
  return change;
}

Control::Change Control::Leave(ClientId id) {
  Change change;
  if (controller_ != id) return change;
  change.release_board = true;
  change.previous = controller_;
  controller_.reset();
  return change;
}

}  // namespace palpa::serve
