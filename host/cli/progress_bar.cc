// A progress bar on stderr, in place on a terminal and a line per tenth elsewhere (progress_bar.h).
#include "progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace palpa::cli {

ProgressBar::ProgressBar() : terminal_(isatty(STDERR_FILENO) == 1) {}

void ProgressBar::Show(long done, long total, const std::string& text) {
  const int percent = total > 0 ? static_cast<int>(100 * done / total) : 100;
  const int mark = terminal_ ? percent : percent / 10;
  if (mark == shown_) return;
  shown_ = mark;
  const int width = 30, filled = percent * width / 100;
  std::fprintf(stderr, "%s[%s%s] %s%s", terminal_ ? "\r" : "",
               std::string(static_cast<size_t>(filled), '#').c_str(),
               std::string(static_cast<size_t>(width - filled), '.').c_str(), text.c_str(),
               terminal_ ? "" : "\n");
  std::fflush(stderr);
}

void ProgressBar::End() {
  if (terminal_ && shown_ >= 0) std::fputs("\n", stderr);
  shown_ = -1;
}

}  // namespace palpa::cli
