#!/bin/sh
# The host library, its calibration and its command line report failure in one shape: an Outcome
# or a Result<T> (palpa/host/outcome.h) carrying the status and its message; the HAL below them and
# the board programs above it (palpa-sim, palpa-linux-board) the same shape, Opened<T> or Done
# (palpa/hal/linux/opened.h). Never a bool, a pointer or an optional beside a std::string* error
# out-parameter.
set -eu
cd "$(dirname "$0")/.."
pattern='std::string[[:space:]]*\*[[:space:]]*(const[[:space:]]+)?(err|error|errors|why|reason|problem|failure|message|msg)[[:space:]]*[,)=]'
if grep -rnE "$pattern" --include='*.h' --include='*.cc' host calibration hal \
    firmware/boards/linux firmware/boards/sim; then
  echo "error_shape_check: a std::string* error out-parameter (return host::Outcome or host::Result<T>; in hal/, firmware/boards/linux and firmware/boards/sim, hal::Opened<T> or hal::Done)"
  exit 1
fi
echo "error_shape_check: host/ and calibration/ report failure as Outcome or Result<T>; hal/, firmware/boards/linux and firmware/boards/sim as Opened<T> or Done"
