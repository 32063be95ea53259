"""Ctrl-C (SIGINT, sent from a thread) stops a long atlas within about a
second: KeyboardInterrupt is raised, and no file, whole or partial, is left
at the output."""
import os
import signal
import tempfile
import threading
import time

import pytest
import vibroatlas as va

from conftest import DRY, MULTI

# The README's main job: about 20 s on two cores, so it is still running when the signal comes.
BIG = dict(x=("omega", 0.1, 3.05, 296), y=("delta", 0.05, 2.0, 196), sweep="both", threads=2)


@pytest.fixture(autouse=True)
def python_handles_sigint():
    """Python's own SIGINT handler for each test: a shell starts a background job with
    SIGINT ignored, and Python then keeps it ignored (the signal would never arrive)."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def sigint_after(delay):
    """Sends SIGINT to the main thread after `delay` s; returns a list that
    receives the time it was sent."""
    sent = []
    main = threading.main_thread().ident

    def fire():
        time.sleep(delay)
        sent.append(time.monotonic())
        signal.pthread_kill(main, signal.SIGINT)

    threading.Thread(target=fire, daemon=True).start()
    return sent


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs signal.pthread_kill")
def test_ctrl_c_stops_a_long_atlas(tmp_path):
    out = tmp_path / "big.h5"
    sent = sigint_after(1.0)
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        va.atlas(MULTI, output=out, progress=False, **BIG)
    raised = time.monotonic()
    assert sent, f"the atlas ended before the signal ({raised - t0:.1f} s): make the grid larger"
    assert raised - sent[0] < 2.0, f"KeyboardInterrupt {raised - sent[0]:.2f} s after SIGINT"
    assert not out.exists()
    assert not (tmp_path / ".big.partial.h5").exists()
    assert os.listdir(tmp_path) == [], f"left behind: {os.listdir(tmp_path)}"  # no journal or lock either
    # the output is free again: a small atlas writes it
    va.atlas(MULTI, x=("omega", 0.3, 0.4, 3), y=("delta", 0.5, 0.6, 2), output=out, progress=False)
    assert out.is_file()


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs signal.pthread_kill")
def test_ctrl_c_of_an_atlas_without_output_leaves_nothing(monkeypatch):
    """An atlas without output is written in memory: interrupted, it has
    made no temporary folder and left no file in the temporary directory."""
    made = []
    real = tempfile.mkdtemp

    def spy(*a, **k):
        made.append(real(*a, **k))
        return made[-1]

    monkeypatch.setattr(tempfile, "mkdtemp", spy)
    tmp = tempfile.gettempdir()
    before = {n for n in os.listdir(tmp) if n.startswith("vibroatlas")}
    sent = sigint_after(0.5)
    with pytest.raises(KeyboardInterrupt):
        va.atlas(MULTI, progress=False, **BIG)
    assert sent and not made
    assert {n for n in os.listdir(tmp) if n.startswith("vibroatlas")} <= before


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs signal.pthread_kill")
def test_ctrl_c_stops_the_attractor_sampling_and_keeps_the_old_file(tmp_path):
    """During an atlas's attractor phase and during va.attractors, Ctrl-C stops
    the sampling; an output that held another atlas is left as it was."""
    out = tmp_path / "a.h5"
    va.atlas(MULTI, x=("omega", 0.3, 0.4, 3), y=("delta", 0.5, 0.6, 2), output=out, progress=False)
    before = out.read_bytes()
    grid = dict(x=("omega", 0.1, 3.05, 30), y=("delta", 0.05, 2.0, 30), threads=2)
    for call in (lambda: va.atlas(MULTI, attractors=200, output=out, force=False, progress=False, **grid),
                 lambda: va.attractors(MULTI, samples=60000, omega=0.3149, delta=0.7, progress=False)):
        sent = sigint_after(1.0)
        t0 = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            call()
        raised = time.monotonic()
        assert sent, f"ended before the signal ({raised - t0:.1f} s): make it longer"
        assert raised - sent[0] < 2.0, f"KeyboardInterrupt {raised - sent[0]:.2f} s after SIGINT"
    time.sleep(1.0)  # nothing written late either
    assert out.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["a.h5"], f"left behind: {os.listdir(tmp_path)}"


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs signal.pthread_kill")
def test_ctrl_c_on_a_curve_raises_at_once_and_writes_no_file(tmp_path):
    """A curve's steps cannot be interrupted: Ctrl-C raises within about a
    second all the same, and the curve file is never written."""
    out = tmp_path / "c.h5"
    sent = sigint_after(0.5)
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        va.curve(DRY, kind="pf", start={"omega": 6.845, "fk": 0.01}, free=("omega", "fk"), to=0.3, steps=1000,
                 output=out)
    raised = time.monotonic()
    assert sent, f"the curve ended before the signal ({raised - t0:.1f} s): make it longer"
    assert raised - sent[0] < 2.0, f"KeyboardInterrupt {raised - sent[0]:.2f} s after SIGINT"
    # The same curve uninterrupted takes about 7 s here: its steps end on
    # their own thread meanwhile, and then write nothing.
    time.sleep(max(0.0, 15.0 - (time.monotonic() - t0)))
    assert not out.exists()
