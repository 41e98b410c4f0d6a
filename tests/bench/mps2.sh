#!/bin/sh
# Control tick on the Cortex-M4F image under QEMU: exact instructions per tick (worst and mean),
# split by stage, counted by the qemu_insn_count TCG plugin. Prints figures; asserts nothing.
# Usage: tests/bench/mps2.sh [IMAGE...]   (default: the two benchmark images of the mps2 preset)
set -eu
for image in "$@"; do  # images named relative to the caller
  case "$image" in /*) ;; *) image="$PWD/$image" ;; esac
  set -- "$@" "$image"; shift
done
cd "$(dirname "$0")/../.."
PLUGIN=${PALPA_INSN_PLUGIN:-build/default/tests/bench/libpalpa_qemu_insn_count.so}
IMAGES=${PALPA_MPS2_IMAGES:-build/mps2/firmware/boards/mps2}
QEMU=${QEMU:-qemu-system-arm}
[ -f "$PLUGIN" ] || { echo "mps2.sh: $PLUGIN is missing (build the default preset)" >&2; exit 1; }
[ $# -gt 0 ] || set -- "$IMAGES/palpa-mps2-bench-5finger.elf" "$IMAGES/palpa-mps2-bench-full8.elf" \
  "$IMAGES/palpa-mps2-bench-5finger-pi16.elf" "$IMAGES/palpa-mps2-bench-5finger-pi16-shaped.elf" \
  "$IMAGES/palpa-mps2-bench-5finger-pi16-calibrated.elf"

. tests/bench/qemu_spans.inc

echo "== firmware on Cortex-M4F (QEMU mps2-an386, -Os, exact instruction counts; 1 ms tick) =="
log=$(mktemp)
trap 'rm -f "$log" "$log.err"' EXIT
for image in "$@"; do
  args="$(span tick palpa::core::Board::Tick "$image")"
  args="$args,$(span sensors palpa::core::BoardLines::Sense "$image")"
  args="$args,$(span config_check palpa::core::ConfigCheck::Step "$image")"
  args="$args,$(span supervisor palpa::core::Supervise "$image")"
  args="$args,$(span fingers palpa::core::BoardFingers::Step "$image")"
  case "$image" in *-pi16.elf|*-pi16-shaped.elf|*-pi16-calibrated.elf) pi16=1 ;; *) pi16= ;; esac
  if [ -n "$pi16" ]; then  # the images with a PI(16) compensator on every finger
    args="$args,$(span play_passes palpa_play_pairs_v7em "$image")"
  fi
  args="$args,$(span lines palpa::core::BoardLines::Step "$image")"  # line steps inlined
  args="$args,$(span outputs palpa::core::Board::WriteOutputs "$image")"
  args="$args,$(span telemetry palpa::core::TelemetryBatch::Sample "$image")"
  args="$args,$(span framing palpa::protocol::EncodeFrameInPlace "$image")"
  args="$args,$(span link_poll palpa::core::Board::Poll "$image")"
  # The control tick: sensors to outputs, without telemetry and the configuration check. The
  # level-1 plant behind the converters runs in the main loop between ticks (plant_io.h): the
  # tick copies the ADC's scan buffer and writes the DAC's registers, as on a board with DMA.
  args="$args,exclude=telemetry,exclude=config_check"
  rc=0
  "$QEMU" -M mps2-an386 -nographic -monitor none -serial null -semihosting-config enable=on,target=native \
    -icount shift=3,sleep=off -plugin "$PLUGIN,$args" -d plugin -D "$log" -kernel "$image" 2>"$log.err" || rc=$?
  [ "$rc" -eq 0 ] || { cat "$log.err" >&2; echo "mps2.sh: $image exited $rc (0 = ran 3 s with the session live)" >&2; exit 1; }
  echo "  $(basename "$image" .elf):"
  awk '/^insn-count: executed/ { printf "    %s ticks, %s instructions in all\n", $5, $3 }
       /^insn-count: control/ { printf "    %-13s worst/tick %7s  mean/tick %9s  (the tick without telemetry and the configuration check)\n", "control", $6, $4; next }
       /^insn-count: span link_poll/ { printf "    %-13s worst/call %7s  mean/call %9s  (calls %s: the main loop polls between ticks)\n", $3, $9, $7, $5; next }
       /^insn-count: span/ { printf "    %-13s worst/tick %7s  mean/tick %9s  (calls %s, worst/call %s)\n", $3, $13, $11, $5, $9 }' "$log"
done
