#!/bin/sh
# Ed25519 verification on the Cortex-M4F image under QEMU: exact instructions per verification
# (RFC 8032's five vectors, each also with its message changed), counted by the qemu_insn_count
# TCG plugin; and the flash the verifier and SHA-512 take in the bootloader. Prints figures;
# asserts nothing.
set -eu
cd "$(dirname "$0")/../.."
PLUGIN=${PALPA_INSN_PLUGIN:-build/default/tests/bench/libpalpa_qemu_insn_count.so}
IMAGE=${PALPA_ED25519_IMAGE:-build/mps2/firmware/boards/mps2/palpa-mps2-ed25519-check.elf}
BOOT=${PALPA_MPS2_BOOT:-build/mps2/firmware/boot}/palpa-mps2-boot.elf
QEMU=${QEMU:-qemu-system-arm}
[ -f "$PLUGIN" ] || { echo "signature.sh: $PLUGIN is missing (build the default preset)" >&2; exit 1; }
[ -f "$IMAGE" ] || { echo "signature.sh: $IMAGE is missing (build the mps2 preset)" >&2; exit 1; }

. tests/bench/qemu_spans.inc

echo "== Ed25519 verification on Cortex-M4F (QEMU mps2-an386, exact instruction counts) =="
log=$(mktemp)
trap 'rm -f "$log" "$log.err"' EXIT
args="$(span verify palpa::protocol::Ed25519Verify "$IMAGE")"
"$QEMU" -M mps2-an386 -nographic -monitor none -serial null -semihosting-config enable=on,target=native \
  -icount shift=3,sleep=off -plugin "$PLUGIN,$args" -d plugin -D "$log" -kernel "$IMAGE" 2>"$log.err" ||
  { cat "$log.err" >&2; echo "signature.sh: $IMAGE failed its check" >&2; exit 1; }
awk '/^insn-count: span verify/ {
       printf "  Ed25519Verify: %s calls, mean %.0f, worst %s instructions a verification\n", $5, $7, $9
       printf "  at one cycle an instruction (a lower bound): %.1f ms at 25 MHz (the MPS2), %.1f ms at 64 MHz, %.1f ms at 168 MHz\n",
              $9 / 25e3, $9 / 64e3, $9 / 168e3 }' "$log"
MAP=${PALPA_BOOT_MAP:-build/mps2/palpa-mps2-boot.map}
if [ -f "$BOOT" ] && [ -f "$MAP" ]; then
  # The verifier's objects in the bootloader's link map: code, constants and the key table.
  flash=$(/usr/bin/python3 - "$MAP" <<'PY'
import re, sys
total = 0
pending = False
for line in open(sys.argv[1]):
    m = re.match(r"^ \.(text|rodata)\S*\s+(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+(\S+)", line)
    if m is None and pending:
        m = re.match(r"^\s+(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+(\S+)", line)
        if m: m = (None, None, m.group(1), m.group(2), m.group(3))
    else:
        m = m and (None,) + m.groups()
    pending = re.match(r"^ \.(text|rodata)\S*\s*$", line) is not None
    if m and re.search(r"(ed25519|sha512|trusted_keys)", m[4]):
        total += int(m[3], 16)
print(total)
PY
)
  used=$(arm-none-eabi-size "$BOOT" | awk 'NR == 2 { print $1 + $2 }')
  echo "  bootloader: $used bytes of flash in its 32768-byte region; of them the verifier, SHA-512 and the trusted keys $flash bytes"
fi
