"""Recordings for the reader tests: a gyroscope and an accelerometer with gravity, at any rate, in any layout.

Both carry a 6 Hz tremor over slow voluntary motion.  The gyroscope (deg/s) has no offset; the accelerometer
(m/s^2) carries gravity, 9.81 on z and a slowly turning share of it on x and y, as a wrist does.
"""

import numpy as np

#: Kinds of recording every reader test runs on.
KINDS = ("gyro", "acc")
#: Rates every reader test runs at, Hz.
RATES = (100.0, 1000.0)


def signals(kind, fs, seconds=12.0, seed=0):
    """``(names, units, samples (n, 3))`` of a 3-axis recording of ``kind`` at ``fs``."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * fs))) / fs
    tremor = np.sin(2 * np.pi * 6.0 * t)[:, None] * np.array([1.0, 0.6, 0.3])
    voluntary = np.column_stack([np.sin(2 * np.pi * f * t + p) for f, p in ((0.3, 0.0), (0.5, 1.0), (0.2, 2.0))])
    noise = 0.01 * rng.standard_normal((t.size, 3))
    if kind == "gyro":
        return ("gx", "gy", "gz"), ("deg/s",) * 3, 40.0 * voluntary + 8.0 * tremor + noise
    tilt = 0.3 * np.sin(2 * np.pi * 0.1 * t)
    gravity = 9.81 * np.column_stack([np.sin(tilt), np.sin(tilt) * 0.5, np.cos(tilt)])
    return ("ax", "ay", "az"), ("m/s^2",) * 3, gravity + 0.5 * voluntary + 0.3 * tremor + noise


def cell(v) -> str:
    return repr(float(v))


def write(path, header, rows, sep=","):
    """Write ``rows`` (lists of cells, str or numbers) under ``header`` (a list of cells, or None)."""
    lines = [] if header is None else [sep.join(header)]
    lines += [sep.join(c if isinstance(c, str) else cell(c) for c in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def _jittered(n, fs, seed=3):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs + rng.uniform(-0.2, 0.2, n) / fs
    return np.sort(t)


def _text_layouts():
    """Every delimited-text layout the reader tests (tests/io) read, as a builder of that layout for any
    recording: ``name -> (builder(path, names, units, t, x) -> None, options both commands need, regular)``.

    ``regular``: the time column (if any) steps evenly, so ``wake run`` does not resample and its rows are
    the file's rows.  (MATLAB files are read by ``wake run`` only: a stream is text.)
    """

    def header_units(path, names, units, t, x):  # test_readers: round trip with names and units
        write(path, ["time [s]", *(f"{n} [{u}]" for n, u in zip(names, units))], [[a, *r] for a, r in zip(t, x)])

    def headerless_jittered(path, names, units, t, x):  # test_readers: irregular timestamps, time by its shape
        write(path, None, [[a, *r] for a, r in zip(_jittered(len(t), 1 / (t[1] - t[0])), x)])

    def ms_semicolons(path, names, units, t, x):  # test_readers: "t [ms];x"
        write(path, ["t [ms]", *names], [[1e3 * a, *r] for a, r in zip(t, x)], sep=";")

    def comment_tabs_counter(path, names, units, t, x):  # test_readers: a comment line, tabs, a row counter
        path.write_text("# exported by a logger\n" + "".join(
            f"{i}\t" + "\t".join(cell(v) for v in r) + "\n" for i, r in enumerate(x)))

    def pads_shape(path, names, units, t, x):  # test_readers: 7 headerless columns, time first
        write(path, None, [[a, *r, *(-r)] for a, r in zip(_jittered(len(t), 1 / (t[1] - t[0])), x)])

    def text_columns(path, names, units, t, x):  # test_text_and_decimal: subject, time, a label between
        write(path, ["subject", "time", names[0], "label", *names[1:]],
              [["S01", a, r[0], "rest" if i % 2 else "move", *r[1:]] for i, (a, r) in enumerate(zip(t, x))])

    def subject_no_time(path, names, units, t, x):  # test_text_and_decimal: subject, then signals, no time
        write(path, ["subject", *names], [["S01", *r] for r in x])

    def headerless_text(path, names, units, t, x):  # test_text_and_decimal: "S01,0.5", no header
        write(path, None, [["S01", *r] for r in x])

    def decimal_comma(path, names, units, t, x):  # test_text_and_decimal: "0,01;1,5"
        path.write_text(";".join(["time", *names]) + "\n" + "".join(
            ";".join(f"{v:.6f}".replace(".", ",") for v in (a, *r)) + "\n" for a, r in zip(t, x)))

    def headerless_values(path, names, units, t, x):  # test_text_and_decimal: --units on a headerless file
        write(path, None, x.tolist())

    def named_time_ms(path, names, units, t, x):  # test_time_units: "timestamp_ms,gyro_x"
        write(path, ["timestamp_ms", *names], [[1e3 * a, *r] for a, r in zip(t, x)])

    def headerless_ms_clock(path, names, units, t, x):  # test_time_units: an unlabelled clock in ms
        # it starts at 0.5 ms: at 1 kHz whole milliseconds would step by 1, as a row counter does (read so)
        write(path, None, [[round(1e3 * a + 0.5, 3), *r] for a, r in zip(t, x)])

    def zeit(path, names, units, t, x):  # test_time_detection: "Zeit [s]"
        write(path, ["Zeit [s]", *names], [[a, *r] for a, r in zip(t, x)])

    def phone(path, names, units, t, x):  # test_time_detection: timestamp_ms after a subject column
        write(path, ["subject", "timestamp_ms", *names], [["P01", repr(float(1.7e12 + 1e3 * a)), *r] for a, r in zip(t, x)])

    def headerless_text_then_clock(path, names, units, t, x):  # test_time_detection
        write(path, None, [["S1", a, *r] for a, r in zip(t, x)])

    fs_opt = ["--fs", "{fs}"]
    return {
        "header_units": (header_units, [], True),
        "headerless_jittered": (headerless_jittered, [], False),
        "ms_semicolons": (ms_semicolons, [], True),
        "comment_tabs_counter": (comment_tabs_counter, fs_opt, True),
        "pads_shape": (pads_shape, [], False),
        "text_columns": (text_columns, [], True),
        "subject_no_time": (subject_no_time, fs_opt, True),
        "headerless_text": (headerless_text, fs_opt, True),
        "decimal_comma": (decimal_comma, [], True),
        "headerless_values": (headerless_values, fs_opt + ["--units", "u"], True),
        "named_time_ms": (named_time_ms, [], True),
        "headerless_ms_clock": (headerless_ms_clock, [], True),
        "zeit": (zeit, [], True),
        "phone": (phone, [], True),
        "headerless_text_then_clock": (headerless_text_then_clock, [], True),
    }


#: name -> (builder, options, regular): every delimited-text layout of the reader tests (:func:`_text_layouts`).
TEXT_LAYOUTS = _text_layouts()


def make_layout(folder, layout, kind, fs, seconds=6.0):
    """Write ``kind`` at ``fs`` in ``layout`` (a key of :data:`TEXT_LAYOUTS`) into ``folder``: ``(path, options)``."""
    build, options, _ = TEXT_LAYOUTS[layout]
    names, units, x = signals(kind, fs, seconds=seconds)
    x = np.round(x, 6)
    t = np.round(np.arange(x.shape[0]) / fs, 6)
    path = folder / f"{layout}_{kind}_{fs:g}.csv"
    build(path, names, units, t, x)
    return path, [o.format(fs=f"{fs:g}") for o in options]
