"""Long calls release the GIL: Python code runs while they compute, and two
threads' calls overlap in time. Measured as progress and overlap, not as
speed: a call that held the GIL would show one gap as long as the call and
two calls one after the other."""

import _thread
import os
import threading
import time

import numpy as np
import pytest

import cmr
from conftest import ROOT

FIG8 = str(ROOT / "examples/figures/fig8.json")

# 200 seeded points that a kappa-curve does not converge on: it iterates
# max_iterations times (about 0.8 ms each on the 2-core VM), then refuses.
_rng = np.random.default_rng(38)
POINTS = np.cumsum(_rng.uniform(0.5, 1.5, (200, 2)), axis=0) * [1, 0] + _rng.uniform(-3, 3, (200, 2)) * [0, 1]


def slow_kcurve(iterations=1500):
    try:
        cmr.kcurve(POINTS, max_iterations=iterations)
    except cmr.InputError as e:
        assert "did not converge" in str(e)


def big_region():
    # 8192 x 8192 labels of Fig. 8's P3 on the CPU backend (every core).
    return cmr.region(FIG8, point=3, size=(8192, 8192), backend="cpu")


@pytest.mark.parametrize("call", [slow_kcurve, big_region], ids=["kcurve", "region"])
def test_python_runs_during_a_call(call):
    done = threading.Event()
    span = {}

    def worker():
        span["start"] = time.perf_counter()
        call()
        span["end"] = time.perf_counter()
        done.set()

    t = threading.Thread(target=worker)
    t.start()
    stamps = []
    while not done.is_set():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    t.join()
    inside = [s for s in stamps if span["start"] <= s <= span["end"]]
    duration = span["end"] - span["start"]
    assert duration > 0.05, f"the call took only {duration:.3f} s: too short to tell"
    gaps = [b - a for a, b in zip([span["start"]] + inside, inside + [span["end"]])]
    # With the GIL held through the call, this thread could not run at all
    # until it returned: one gap as long as the call.
    assert max(gaps) < 0.5 * duration, f"longest pause {max(gaps):.3f} s of a {duration:.3f} s call"
    assert len(inside) >= 5


def test_two_threads_overlap():
    spans = [None, None]

    def worker(i):
        start = time.perf_counter()
        slow_kcurve()
        spans[i] = (start, time.perf_counter())

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    (a0, a1), (b0, b1) = spans
    overlap = min(a1, b1) - max(a0, b0)
    shorter = min(a1 - a0, b1 - b0)
    # Serialised by the GIL the two would not overlap at all.
    assert overlap > 0.5 * shorter, f"overlap {overlap:.3f} s of {shorter:.3f} s"


def _threads():
    return len(os.listdir("/proc/self/task"))


def long_analysis():
    # 60,000 cubic spans of a random walk: more than 256 spans run on the
    # worker, on every core in chunks of 256.
    rng = np.random.default_rng(42)
    m = 60000
    points = np.cumsum(rng.uniform(-1, 1, (m, 2)), axis=0)
    cmr.analyze(cmr.Spline(3, points, knots=list(range(m + 2))))


@pytest.mark.parametrize("call", [long_analysis, big_region, slow_kcurve], ids=["analyze", "region", "kcurve"])
def test_keyboard_interrupt_cancels_the_computation(call):
    # The call is cancelled, not abandoned: when the KeyboardInterrupt
    # arrives (0.1 s in), the computation has stopped and its thread is
    # gone. Without the cancel flag it would go on until it ended: on its
    # own thread (one more thread in /proc/self/task, CPU time rising), or
    # with the caller waiting for it. (That a region's render stops between
    # blocks, not only after it, is Region.ASetCancelFlagStopsTheCpuRender-
    # BeforeItsBlocks: a render is too fast to time from here.)
    start = time.perf_counter()
    call()
    full = time.perf_counter() - start
    assert full > 0.3, f"the call took only {full:.3f} s: too short to tell"
    before = _threads()  # after a first run: the region's worker pool is up
    timer = threading.Timer(0.1, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        call()
    interrupted = time.perf_counter() - start
    timer.join()
    left = _threads() - before
    cpu0 = time.process_time()
    time.sleep(0.5)
    after = time.process_time() - cpu0
    # A region's render allocates and converts its labels in passes that a
    # flag does not cut short, and under load they are most of the call:
    # only its threads and CPU time are checked here.
    if call is not big_region:
        assert interrupted < 0.1 + 0.5 * full, f"interrupted after {interrupted:.3f} s of a {full:.3f} s call"
    assert left <= 0, f"{left} more threads after the interrupt: the computation went on"
    assert after < 0.05, f"{after:.3f} s of CPU time in the 0.5 s after the interrupt: the computation went on"
