// A progress bar on stderr: redrawn in place on a terminal; to a pipe or a log file, a line at
// each tenth of the way (and the last), so what is kept holds no carriage returns.
#pragma once

#include <string>

namespace palpa::cli {

class ProgressBar {
 public:
  ProgressBar();
  /// `done` of `total` with `text` after the bar. A terminal's bar is redrawn when a whole per
  /// cent has passed; elsewhere a line is written when a tenth has.
  void Show(long done, long total, const std::string& text);
  /// Ends the terminal's line the bar is on (elsewhere every line is ended already); the next
  /// Show starts a new bar.
  void End();

 private:
  bool terminal_;
  int shown_ = -1;  ///< the per cent (terminal) or tenth (elsewhere) last shown; -1: none yet
};

}  // namespace palpa::cli
