"""The C backend's two batch paths as the batch tests see them (tests/hpa/test_batch_paths.py and the per-path
modules): how to build a filter that takes the path, how to switch the path off, how to count the points it took."""

from dataclasses import dataclass, field

from support import assert_same_results

from wake import WakeFilter
from wake.hpa import c_batch


@dataclass(frozen=True)
class BatchPath:
    """One batch path: its filter settings, the ``c_batch`` rule that covers a channel, the batch class."""

    name: str
    settings: dict = field(default_factory=dict)
    covers: str = "covers"
    batch: type = c_batch.Batch
    counts_offered: bool = False   # the install batch may hand points back: count what it kept

    def filter(self, **settings):
        return WakeFilter(backend="c", **self.settings, **settings)

    def count_points(self, monkeypatch):
        """Patch the batch's flush to count the points it took; the count (a one-element list)."""
        count = [0]
        flush = self.batch.flush
        offered = self.counts_offered

        def counting(batch, y):
            handed = len(batch.points)
            result = flush(batch, y)
            count[0] += handed - len(result[1]) if offered else handed
            return result

        monkeypatch.setattr(self.batch, "flush", counting)
        return count


PATHS = {"install": BatchPath("install", covers="covers_installs", batch=c_batch.InstallBatch, counts_offered=True),
         "driver": BatchPath("driver", settings=dict(hpa_backend="c"))}


def without_path(path, run, monkeypatch):
    """``run()`` with the path switched off: every point on ``Channel.hpa``."""
    with monkeypatch.context() as m:
        m.setattr(c_batch, path.covers, lambda channel: False)
        return run()


def assert_same_run(path, x, monkeypatch, taken, **settings):
    """The path's run of ``x`` is the point-by-point run's, bit for bit; the points the path took."""
    run = lambda: path.filter(**settings).run(x)  # noqa: E731
    res = run()
    used = taken[0]
    ref = without_path(path, run, monkeypatch)
    assert taken[0] == used
    assert_same_results(res, ref)
    return used


def stop_after_first_point(monkeypatch, call, n_samples_at, status):
    """Make the C call ``call`` stop after its first point of each call, as a refusal leaves it, and return the
    refusal ``status``: its arguments from ``n_samples_at`` are (n_samples, n_points, stops)."""
    ffi, lib = c_batch._core()

    def first_point(*args):
        args = list(args)
        i = n_samples_at
        args[i], args[i + 1] = args[i + 2][0], min(args[i + 1], 1)   # to the first point, no tail
        getattr(lib, call)(*args)
        return getattr(lib, status)

    class FirstPointOnly:
        def __getattr__(self, name):
            return first_point if name == call else getattr(lib, name)

    monkeypatch.setattr(c_batch, "_core", lambda: (ffi, FirstPointOnly()))
