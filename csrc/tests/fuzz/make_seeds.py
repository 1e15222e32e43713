"""Write the libFuzzer seed corpus (csrc/tests/fuzz/seeds/{rtp,hpa}/) in the harnesses' input encoding.

Each seed is a readable scenario the fuzzer mutates from: a valid configuration followed by a
realistic call sequence (see the decoders in fuzz_rtp.c and fuzz_hpa.c). Run from anywhere:
``python csrc/tests/fuzz/make_seeds.py``; the files are committed, so this only runs when the encoding
changes.
"""

import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
RTP_OPS = dict(step=0, missing=1, run=2, set_weights=3, reset=4, load_state=5, get_state=6, corrupt=7)
HPA_OPS = dict(push=0, burst=1, missing=2, slice=3, run=4, start=5, take=6, to_rtp=7, apply=8, corrupt=9)
RTP_MAX_LEVEL = 6
RTP_MAX_TAPS = 1 << RTP_MAX_LEVEL


def i16(v):
    return struct.pack("<h", int(v))


def i32(v):
    return struct.pack("<i", int(v))


def tone(k, amplitude=8000.0):
    """A slow voluntary movement plus a 6 Hz tremor at 100 Hz, int16."""
    return amplitude * math.sin(2 * math.pi * 0.5 * k / 100) + 0.3 * amplitude * math.sin(2 * math.pi * 6 * k / 100)


def rtp_seed(level, steps, extra=b""):
    n = 1 << level
    out = bytes([level, level + 1])                 # level, taps scaled by 2^-(J+1): always accepted
    for j in range(level):                          # row j: the mean of the newest n >> j samples
        width = n >> j
        out += b"".join(i16(32767 if i >= n - width else 0) for i in range(n))
    out += bytes([0]) + b"".join(i32(2 * (1 << 24) // level) for _ in range(level))  # w = 1/J (scaled: /2)
    out += bytes([0]) + i32(1 << 16) + bytes([0]) + i32(1 << 10) + bytes([0]) + i32(1 << 12)  # R, q, p0
    out += bytes([1])                               # Kalman on
    for k in range(steps):
        out += bytes([RTP_OPS["step"]]) + i16(tone(k))
    return out + extra


def rtp_seeds():
    tail = bytes([RTP_OPS["missing"], RTP_OPS["missing"]])
    tail += bytes([RTP_OPS["set_weights"], 0]) + b"".join(i32(1 << 22) for _ in range(RTP_MAX_LEVEL))
    tail += bytes([0]) + i32(1 << 15) + bytes([0]) + i32(1 << 9)
    tail += bytes([RTP_OPS["run"], 16]) + b"".join(i16(tone(k)) for k in range(16))
    tail += bytes([RTP_OPS["get_state"], RTP_OPS["load_state"]])
    tail += b"".join(i16(tone(k)) for k in range(RTP_MAX_TAPS))
    tail += b"".join(i32(0) for _ in range(RTP_MAX_LEVEL))
    tail += b"".join(i32(1 << 12 if i % (RTP_MAX_LEVEL + 1) == 0 else 0) for i in range(RTP_MAX_LEVEL ** 2))
    tail += i32(0) + bytes([RTP_OPS["step"]]) + i16(100) + bytes([RTP_OPS["reset"]])
    tail += bytes([RTP_OPS["corrupt"]]) + struct.pack("<H", 6) + bytes([1, 7])   # level := 7: refused
    tail += bytes([RTP_OPS["step"]]) + i16(5)
    return {f"level{J}": rtp_seed(J, 40, tail) for J in (1, 3, 5, 6)}


def hpa_seed(mask_fields=b"", mask=0, missing=0):
    out = struct.pack("<H", mask) + mask_fields
    level = 5 if not (mask & 1) else mask_fields[0] % 7
    n = 1 << level
    out += bytes([level + 1])                       # taps scaled by 2^-(J+1)
    for j in range(level):
        width = n >> j
        out += b"".join(i16(32767 if i >= n - width else 0) for i in range(n))
    out += b"".join(bytes([0]) + i16(256) for _ in range(RTP_MAX_LEVEL))     # start weights 0.25
    for _ in range(3):                              # 3 x 200 samples of a square-ish tremor
        out += bytes([HPA_OPS["burst"], 199]) + struct.pack("<H", 7) + bytes([40])
        if missing:
            out += bytes([HPA_OPS["missing"], missing - 1])
        out += bytes([HPA_OPS["slice"], 255, HPA_OPS["slice"], 255])
    out += bytes([HPA_OPS["run"], HPA_OPS["take"], HPA_OPS["apply"]]) + bytes([HPA_OPS["to_rtp"]]) + struct.pack("<f", 0.01)
    return out


def hpa_seeds():
    small = bytes([3]) + struct.pack("<H", 200) + bytes([8])      # level 3, window 200, order 8
    start = bytes([HPA_OPS["start"]]) + struct.pack("<H", 128) + b"".join(i16(tone(k)) for k in range(128)) + i32(128)
    return {
        "defaults": hpa_seed(),
        "long_gap": hpa_seed(missing=120),
        "level3_window200": hpa_seed(small, mask=1 | 2 | 4),
        "start_window": hpa_seed() + start + bytes([HPA_OPS["run"], HPA_OPS["take"]]),
    }


def main():
    for name, seeds in (("rtp", rtp_seeds()), ("hpa", hpa_seeds())):
        folder = os.path.join(HERE, "seeds", name)
        os.makedirs(folder, exist_ok=True)
        for stem, data in seeds.items():
            with open(os.path.join(folder, stem), "wb") as f:
                f.write(data)
        print(f"{folder}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
