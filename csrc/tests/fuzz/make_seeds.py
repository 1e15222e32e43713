"""Write the libFuzzer seed corpus (csrc/tests/fuzz/seeds/{rtp,hpa,rtp_split,hpa_ahead}/) in the harnesses'
input encoding.

Each seed is a readable scenario the fuzzer mutates from: a valid configuration followed by a
realistic call sequence (see the decoders in fuzz_rtp.c, fuzz_hpa.c and fuzz_rtp_split.c; fuzz_hpa_ahead is
fuzz_hpa.c built with the tremor-ahead fit and reads the hpa seeds too). Run from anywhere:
``python csrc/tests/fuzz/make_seeds.py``; the files are committed, so this only runs when the encoding
changes.
"""

import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
RTP_OPS = dict(step=0, missing=1, run=2, set_weights=3, reset=4, load_state=5, get_state=6, corrupt=7)
HPA_OPS = dict(push=0, burst=1, missing=2, slice=3, run=4, start=5, take=6, to_rtp=7, apply=8, corrupt=9,
               scribble=10)
#: fuzz_hpa.c built with WAKE_HPA_AHEAD (fuzz_hpa_ahead): one more call before corrupt
HPA_AHEAD_OPS = dict(HPA_OPS, ahead_to_rtp=9, corrupt=10, scribble=11)
SPLIT_OPS = dict(sample=0, missing=1, prepare=2, unprepared=3, set_weights=4, reset=5, load_state=6, run=7,
                 set_ahead=8, set_ahead_ramp=9, load_ahead=10, corrupt=11)
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


def scribbled_run(ops, n=128):
    """A caller's window (a tremor about an offset) started, then zeroed (a contract violation) after the
    pass that sums it and before the lag sums: the noise comes out negative (fuzz_hpa.c, check_result)."""
    start = bytes([ops["start"]]) + struct.pack("<H", n) + b"".join(i16(16000 + tone(k) / 4) for k in range(n))
    zero = bytes([ops["scribble"]]) + struct.pack("<H", 0) + bytes([n - 1]) + bytes(2 * n)
    return start + i32(n) + bytes([ops["slice"], 0]) + zero + bytes([ops["run"], ops["take"], ops["apply"]])


def hpa_seeds():
    small = bytes([3]) + struct.pack("<H", 200) + bytes([8])      # level 3, window 200, order 8
    start = bytes([HPA_OPS["start"]]) + struct.pack("<H", 128) + b"".join(i16(tone(k)) for k in range(128)) + i32(128)
    return {
        "defaults": hpa_seed(),
        "long_gap": hpa_seed(missing=120),
        "level3_window200": hpa_seed(small, mask=1 | 2 | 4),
        "start_window": hpa_seed() + start + bytes([HPA_OPS["run"], HPA_OPS["take"]]),
        "scribbled_window": hpa_seed() + scribbled_run(HPA_OPS),
    }


def split_seed(level, mode, body):
    """fuzz_rtp_split.c: the RTP's init (as rtp_seed), the mode word (bit 0: rate; bit 1: D = 1 + (mode >> 2) % 16,
    else 1 + (mode >> 2) % 1000), then the calls."""
    return rtp_seed(level, 0) + struct.pack("<H", mode) + body


def split_seeds():
    ops = SPLIT_OPS
    ahead = bytes([ops["set_ahead"], 0]) + b"".join(i32(v << 26) for v in (3, -2, 1, 0, 0, 0, 0, 1)) + i32(1 << 29)
    direct = b"".join(bytes([ops["sample"], k % 3]) + i16(tone(k)) for k in range(60))
    direct += bytes([ops["missing"], 0, ops["missing"], 1])
    direct += bytes([ops["prepare"], ops["set_weights"], 0]) + b"".join(i32(1 << 22) for _ in range(RTP_MAX_LEVEL))
    direct += bytes([0]) + i32(1 << 15) + bytes([0]) + i32(1 << 9)
    direct += bytes([ops["sample"], 0]) + i16(tone(60)) + ahead
    direct += b"".join(bytes([ops["sample"], k % 2]) + i16(tone(k)) for k in range(61, 120))
    direct += bytes([ops["unprepared"], 0]) + i16(7) + bytes([ops["run"], 8]) + b"".join(i16(tone(k)) for k in range(8))
    direct += bytes([ops["prepare"], ops["set_ahead_ramp"]]) + i32(1 << 25) + bytes([ops["sample"], 0]) + i16(99)
    direct += bytes([ops["reset"]]) + b"".join(bytes([ops["sample"], 0]) + i16(tone(k)) for k in range(20))

    def rate(factor, n=200):
        body = b""
        for k in range(n):
            body += bytes([ops["missing"]]) if k % 17 == 5 else bytes([ops["sample"]]) + i16(tone(k))
            if k == n // 2:
                body += ahead
        return split_seed(5, 1 | 2 | ((factor - 1) << 2), body)

    return {"direct_level5": split_seed(5, 0, direct), "direct_level3": split_seed(3, 2, direct),
            "rate_d2": rate(2), "rate_d3": rate(3), "rate_d10": rate(10, 400), "rate_d1_refused": rate(1, 20)}


def hpa_ahead_seeds():
    """The hpa seeds' stream with the tremor ahead at horizons 1, 5 and 32 (config bit 16: clean_below and
    horizon), each result converted for the RTP and applied; one window clipped at full scale."""
    ops = HPA_AHEAD_OPS
    seeds = {}
    for h in (1, 5, 32):
        seeds[f"horizon{h}"] = (hpa_seed(struct.pack("<H", 200) + bytes([h]), mask=16)
                                + bytes([ops["ahead_to_rtp"], ops["apply"]]))
    clipped = b"".join(i16(max(-32768, min(32767, 4 * tone(k)))) for k in range(500))
    start = bytes([ops["start"]]) + struct.pack("<H", 500) + clipped + i32(1000)
    seeds["clipped_window"] = (hpa_seed(struct.pack("<H", 200) + bytes([1]), mask=16) + start
                               + bytes([ops["run"], ops["ahead_to_rtp"], ops["apply"], ops["take"]]))
    seeds["scribbled_window"] = hpa_seed(struct.pack("<H", 200) + bytes([5]), mask=16) + scribbled_run(ops)
    return seeds


def main():
    for name, seeds in (("rtp", rtp_seeds()), ("hpa", hpa_seeds()), ("rtp_split", split_seeds()),
                        ("hpa_ahead", hpa_ahead_seeds())):
        folder = os.path.join(HERE, "seeds", name)
        os.makedirs(folder, exist_ok=True)
        for stem, data in seeds.items():
            with open(os.path.join(folder, stem), "wb") as f:
                f.write(data)
        print(f"{folder}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
