#!/bin/sh
# Hysteresis compensation: Cortex-M4F instructions per step for every method and size (QEMU,
# exact counts), then the accuracy benchmark on the simulated rig with those costs on its chart.
# Then the pressure loop's robustness map. Writes docs/hysteresis.svg and the two table blocks of
# docs/hysteresis.md.
set -eu
cd "$(dirname "$0")/../.."
PLUGIN=${PALPA_INSN_PLUGIN:-build/default/tests/bench/libpalpa_qemu_insn_count.so}
IMAGE=${PALPA_MPS2_IMAGES:-build/mps2/firmware/boards/mps2}/palpa-mps2-compensators.elf
QEMU=${QEMU:-qemu-system-arm}
. tests/bench/qemu_spans.inc

args=""
for method in None Branch4 Branch8 Branch12 Branch16 Pi4 Pi8 Pi16 Pi32 Api4 Api8 Api16 Api32; do
  args="$args${args:+,}$(span "$method" "Step$method" "$IMAGE")"
done
log=$(mktemp)
trap 'rm -f "$log"' EXIT
"$QEMU" -M mps2-an386 -nographic -monitor none -serial null -semihosting-config enable=on,target=native \
  -icount shift=3,sleep=off -plugin "$PLUGIN,$args" -d plugin -D "$log" -kernel "$IMAGE"
echo "== compensators on Cortex-M4F (QEMU mps2-an386, exact instructions per step, 2 000 steps each) =="
awk '/^insn-count: span/ { printf "  %-9s worst/step %5s  mean/step %8s\n", $3, $9, $7 }' "$log"
costs=$(awk '/^insn-count: span/ { name = tolower($3);
  if (name ~ /^(branch|pi|api)[0-9]+$/) { match(name, /[0-9]+/); name = substr(name, 1, RSTART - 1) "(" substr(name, RSTART) ")" }
  printf " --cost %s=%s", name, $9 }' "$log")
# shellcheck disable=SC2086
[ -n "${PALPA_COSTS_ONLY:-}" ] && exit 0
build/default/tests/bench/palpa_hysteresis_bench $costs docs
build/default/tests/bench/palpa_loop_bench docs
