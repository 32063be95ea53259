"""The interpreter is released while the engine computes: another Python
thread keeps running at full speed during a long call."""
import threading
import time

import vibroatlas as va

from conftest import MULTI


def test_other_threads_run_during_an_atlas():
    done = threading.Event()
    ticks = []

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    th = threading.Thread(target=tick)
    th.start()
    t0 = time.monotonic()
    try:
        va.atlas(MULTI, x=("omega", 0.1, 3.05, 60), y=("delta", 0.05, 2.0, 40), sweep="both", threads=1,
                 progress=False)
    finally:
        done.set()
        th.join()
    seconds = time.monotonic() - t0
    # Held through each 0.1 s wait, the interpreter would let the other thread
    # tick about 10 times a second; released, it ticks every few milliseconds.
    assert len(ticks) / seconds > 50, f"{len(ticks)} ticks in {seconds:.2f} s"
