"""Ctrl-C (SIGINT) stops a render within a dispatch and raises KeyboardInterrupt, leaving
nothing corrupt: the device renders again at once, and an interrupted `Renderer` keeps exactly
the samples it finished, so that adding the rest gives the uninterrupted image bit for bit.
Renders release the GIL: other Python threads run during one."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import pathlab
from conftest import STUDY

# Long enough to be running when the signal comes (lavapipe renders ~10^7 samples/s), short
# enough that a render which ignores the signal ends in seconds and fails the test, not hangs.
LONG = dict(width=128, height=64)


@pytest.fixture(autouse=True)
def sigint_raises_keyboard_interrupt():
    """Python's own SIGINT handler for each test, whatever the suite was started from: a shell
    job started with `cmd &` in a script ignores SIGINT, and Python then installs no handler
    (the signal would be ignored, not raised). The disposition found is restored afterwards."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def interrupt_after(seconds):
    """Sends SIGINT to this process from another thread; returns when it was sent."""
    sent = {}

    def fire():
        sent["at"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(seconds, fire)
    timer.start()
    return timer, sent


def test_sigint_stops_a_render_within_a_second():
    scene = pathlab.load_scene(STUDY, **LONG)
    timer, sent = interrupt_after(1.0)
    start = time.perf_counter()
    try:
        pathlab.render(scene, "best", time=6.0)
    except KeyboardInterrupt:
        raised = time.perf_counter()
    else:
        raise AssertionError("the render finished: it was not long enough to interrupt")
    finally:
        timer.cancel()
    latency = raised - sent["at"]
    print(f"KeyboardInterrupt {latency * 1e3:.0f} ms after SIGINT (render ran {raised - start:.2f} s)")
    assert latency < 1.0
    # Nothing left broken: the same device renders at once, and the same image as ever.
    small = scene.with_(width=32, height=16)
    assert np.array_equal(pathlab.render(small, "mis", spp=4).image, pathlab.render(small, "mis", spp=4).image)


def test_interrupted_renderer_continues_bit_for_bit():
    scene = pathlab.load_scene(STUDY, **LONG)
    r = pathlab.Renderer(scene, "mis", seed=9)
    timer, sent = interrupt_after(0.8)
    try:
        r.add(20_000)
    except KeyboardInterrupt:
        latency = time.perf_counter() - sent["at"]
    else:
        raise AssertionError("add finished: it was not long enough to interrupt")
    finally:
        timer.cancel()
    assert latency < 1.0
    done = r.spp
    assert 0 < done < 20_000
    r.add(7)
    small_total = done + 7
    assert np.array_equal(r.image, pathlab.render(scene, "mis", spp=small_total, seed=9).image)


def test_a_render_releases_the_gil():
    scene = pathlab.load_scene(STUDY, width=128, height=64)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=count)
    start = time.perf_counter()
    t.start()
    try:
        r = pathlab.render(scene, "best", time=0.5)
    finally:
        stop.set()
        t.join()
    during = [x for x in ticks if start + 0.1 < x < start + r.seconds]
    print(f"{len(during)} ticks of the other thread during a {r.seconds:.2f} s render")
    # Holding the GIL, the render would let none through; released, ~100 per second.
    assert len(during) >= 10
