"""Long calls: progress reported to a callable or a tqdm-like bar, an exception raised in the
callback stops the call and comes out of it, Ctrl-C (SIGINT) stops it with KeyboardInterrupt,
and the GIL is released while the library computes (another thread runs meanwhile)."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import motionmap


@pytest.fixture(scope="module")
def X():
    return np.random.default_rng(7).normal(size=(1500, 40))


def test_progress_callable(golf):
    seen = []
    motionmap.Isomap().fit(golf, progress=lambda f, stage: seen.append((f, stage)))
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    stages = {s for _, s in seen}
    assert "features" in stages and "shortest paths" in stages


class FakeBar:
    """What the module uses of a tqdm bar: total, n, update(), set_description()."""

    def __init__(self):
        self.total, self.n, self.descriptions = 100, 0.0, []

    def update(self, k):
        self.n += k

    def set_description(self, text):
        self.descriptions.append(text)


def test_progress_bar(golf):
    bar = FakeBar()
    motionmap.features(golf, return_distances=True, progress=bar)
    assert bar.n == pytest.approx(100.0) and bar.descriptions


def test_progress_with_a_real_tqdm_bar(golf):
    tqdm = pytest.importorskip("tqdm")  # Debian's python3-tqdm (scripts/install-deps.sh)
    import io

    out = io.StringIO()
    with tqdm.tqdm(total=100, file=out, mininterval=0) as bar:
        motionmap.Isomap().fit(golf, progress=bar)
        assert bar.n == pytest.approx(100.0)
    text = out.getvalue()
    # Whole steps: 47/100, never 47.956…/100.
    assert "100/100" in text and "shortest paths" in text and ".0/100" not in text, text


def test_callback_exception_stops_the_call(X):
    class Stop(Exception):
        pass

    def progress(fraction, stage):
        if fraction > 0.1:
            raise Stop(stage)

    with pytest.raises(Stop):
        motionmap.Isomap().fit(X, progress=progress)


def test_ctrl_c_stops_the_call(X):
    timer = threading.Timer(0.1, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            motionmap.Isomap().fit(X)  # about 1.5 s on this machine when not stopped
    finally:
        timer.cancel()
    assert time.monotonic() - start < 1.0


def test_gil_released(X):
    times = {}

    def work():
        times["start"] = time.monotonic()
        motionmap.MDS().fit(X)
        times["end"] = time.monotonic()

    ticks = []
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks.append(time.monotonic())
        time.sleep(0.001)
    worker.join()
    during = [t for t in ticks if times["start"] < t < times["end"]]
    # The main thread ran throughout the fit (it could not while a call held the GIL).
    assert len(during) >= 20, (len(during), times["end"] - times["start"])
