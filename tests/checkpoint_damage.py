"""Damages one named section of a Quarry checkpoint and writes the header's CRC-32 again, so that
the section's own checks (not the checksum) must find the damage. Used by the CLI restart tests.

checkpoint_damage.py IN OUT SECTION OFFSET FORMAT VALUE
  OFFSET: bytes from the start of the section's payload, an integer or an expression of
          u64(k), the little-endian uint64 at payload byte k (e.g. "4 + 3 * (8 + 8 * u64(4)) + 8");
  FORMAT: a struct format ("<I", "<d"); VALUE: a number, or nan.
Layout (src/sim/checkpoint.cpp): a 32-byte header whose bytes 24-27 are the CRC-32 of the rest;
each section is its name's length (uint64), the name, its payload's length (uint64), the payload.
"""
import math
import struct
import sys
import zlib

HEADER = 32


def main(source, target, section, offset, fmt, value):
    data = bytearray(open(source, "rb").read())
    name = section.encode()
    start = data.index(struct.pack("<Q", len(name)) + name, HEADER) + 8 + len(name) + 8

    def u64(k):
        return struct.unpack_from("<Q", data, start + k)[0]

    at = start + int(eval(offset, {"u64": u64}))  # the test's own expression, not user input
    number = math.nan if value == "nan" else (float(value) if "d" in fmt or "f" in fmt else int(value))
    struct.pack_into(fmt, data, at, number)
    struct.pack_into("<I", data, 24, zlib.crc32(bytes(data[HEADER:])) & 0xFFFFFFFF)
    open(target, "wb").write(data)


if __name__ == "__main__":
    main(*sys.argv[1:7])
