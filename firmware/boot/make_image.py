#!/usr/bin/env python3
"""The build step from a slot's binary to a firmware image (docs/flashing.md): header, body,
protected TLVs (board kind, load slot, anti-rollback counter), TLVs (SHA-256; the signer's Ed25519
public key and its signature of the SHA-256, made with Python's cryptography package). A second,
independent writer of the format the C++ parser in protocol/image.h checks.

    make_image.py --kind mps2-an386 --slot 0 --load-address 0x8000 --version 0.1.0 \
                  --counter 1 --key KEY_FILE [--header-size 256] BODY.bin OUT.img
    make_image.py --package SLOT0.img SLOT1.img OUT.palpa    (the update package: both slots)
"""
import argparse
import hashlib
import struct
import sys

from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

IMAGE_MAGIC = 0x96F3B83D
TLV_INFO_MAGIC, PROTECTED_TLV_INFO_MAGIC = 0x6907, 0x6908
TLV_PUBKEY, TLV_SHA256, TLV_ED25519 = 0x02, 0x10, 0x24
TLV_SECURITY_COUNTER, TLV_BOARD_KIND, TLV_LOAD_SLOT = 0x50, 0xA0, 0xA1
BOARD_KINDS = ["sim", "mps2-an386", "stm32f4", "linux"]


def tlv(kind, value):
    return struct.pack("<HH", kind, len(value)) + value


def read_key(path):
    """A palpa key file: '#' comment lines, then one line of 64 hexadecimal digits (the seed)."""
    with open(path) as f:
        lines = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    try:
        if len(lines) != 1 or len(lines[0]) != 64:
            raise ValueError
        return Ed25519PrivateKey.from_private_bytes(bytes.fromhex(lines[0]))
    except ValueError:
        sys.exit(f"make_image.py: {path}: expected one line of 64 hexadecimal digits (a private key)")


def build(body, kind, slot, load_address, version, counter, header_size, key):
    major, minor, patch = version
    protected = (tlv(TLV_BOARD_KIND, bytes([BOARD_KINDS.index(kind)])) +
                 tlv(TLV_LOAD_SLOT, bytes([slot])) +
                 tlv(TLV_SECURITY_COUNTER, struct.pack("<I", counter)))
    protected = struct.pack("<HH", PROTECTED_TLV_INFO_MAGIC, 4 + len(protected)) + protected
    header = struct.pack("<IIHHIIBBHII", IMAGE_MAGIC, load_address, header_size, len(protected),
                         len(body), 0, major, minor, patch, 0, 0)
    header += bytes(header_size - len(header))
    covered = header + body + protected
    digest = hashlib.sha256(covered).digest()
    public = key.public_key().public_bytes(serialization.Encoding.Raw, serialization.PublicFormat.Raw)
    tlvs = tlv(TLV_SHA256, digest) + tlv(TLV_PUBKEY, public) + tlv(TLV_ED25519, key.sign(digest))
    return covered + struct.pack("<HH", TLV_INFO_MAGIC, 4 + len(tlvs)) + tlvs


def package(slot0, slot1, out):
    """PALPAPKG, version 1, two entries: slot (u8), size (u32 LE), the image."""
    data = b"PALPAPKG" + bytes([1, 2])
    for slot, path in enumerate((slot0, slot1)):
        with open(path, "rb") as f:
            image = f.read()
        data += struct.pack("<BI", slot, len(image)) + image
    with open(out, "wb") as f:
        f.write(data)


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--package":
        package(*sys.argv[2:])
        return
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--kind", required=True, choices=BOARD_KINDS)
    p.add_argument("--slot", required=True, type=int, choices=[0, 1])
    p.add_argument("--load-address", required=True, type=lambda s: int(s, 0))
    p.add_argument("--version", required=True)
    p.add_argument("--counter", required=True, type=int)
    p.add_argument("--header-size", type=int, default=32)
    p.add_argument("--key", required=True, help="the private key file to sign with")
    p.add_argument("body")
    p.add_argument("out")
    a = p.parse_args()
    try:
        version = tuple(int(x) for x in a.version.split("."))
        if len(version) != 3 or not (0 <= version[0] < 256 and 0 <= version[1] < 256 and 0 <= version[2] < 65536):
            raise ValueError
    except ValueError:
        sys.exit(f"make_image.py: --version {a.version}: expected MAJOR.MINOR.PATCH")
    if a.header_size < 32 or a.header_size > 1024 or a.header_size % 4:
        sys.exit(f"make_image.py: --header-size {a.header_size}: expected 32 to 1024, a multiple of 4")
    with open(a.body, "rb") as f:
        body = f.read()
    image = build(body, a.kind, a.slot, a.load_address, version, a.counter, a.header_size,
                  read_key(a.key))
    with open(a.out, "wb") as f:
        f.write(image)


if __name__ == "__main__":
    main()
