#!/bin/sh
# The instruction-count benchmark works and is exact: two runs of the 5-finger benchmark image
# print identical figures, every tick of 3 s is counted, no stage exceeds the tick it is in, and the
# control tick (the tick without telemetry and the configuration check) holds its stages.
# Usage: insn_count_test.sh BENCH_SCRIPT IMAGE   (PALPA_INSN_PLUGIN names the plugin)
set -eu
first=$(sh "$1" "$2")
second=$(sh "$1" "$2")
[ "$first" = "$second" ] || { printf 'counts differ between runs:\n%s\n---\n%s\n' "$first" "$second"; exit 1; }
echo "$first"
echo "$first" | awk '
  / ticks, / { ticks = $1 }
  $1 == "tick" { tick = $3; tick_mean = $5 }
  $2 == "worst/tick" && $1 != "tick" { stage[$1] = $3; mean[$1] = $5 }
  END {
    if (ticks != 3000) { print "expected 3000 ticks, got " ticks; exit 1 }
    if (tick < 1000) { print "tick count implausibly small: " tick; exit 1 }
    n = 0
    for (s in stage) { n++; if (stage[s] + 0 <= 0 || stage[s] + 0 > tick + 0) { print s " out of range: " stage[s]; exit 1 } }
    if (n != 9) { print "expected 8 stages and the control tick, got " n; exit 1 }
    inside = mean["sensors"] + mean["supervisor"] + mean["fingers"] + mean["lines"] + mean["outputs"]
    parts = mean["control"] + mean["telemetry"] + mean["config_check"]
    if (mean["control"] + 0 < inside || parts - tick_mean > 0.5 || tick_mean - parts > 0.5) {
      print "control tick " mean["control"] " does not hold its stages (" inside ") or with telemetry and the configuration check is not the tick (" parts " against " tick_mean ")"; exit 1
    }
  }'
