"""A tqdm bar on stderr for long work; progress=False prints nothing at all
(captured at the file descriptor, so the native side is silent too); short
work (a cell) shows no bar."""
import re

import vibroatlas as va

from conftest import MULTI

# 4800 cells (both sweeps of 60 x 40): long enough for a bar.
LONG = dict(x=("omega", 0.1, 3.05, 60), y=("delta", 0.05, 2.0, 40), sweep="both", threads=2)


def test_bar_on_a_long_atlas(capfd):
    va.atlas(MULTI, **LONG)
    err = capfd.readouterr().err
    assert re.search(r"atlas: +\d+%\|", err), err
    assert "100%" in err and "4800/4800" in err, err


def test_progress_false_is_silent(capfd):
    va.atlas(MULTI, progress=False, **LONG)
    va.sweep(MULTI, axis=("omega", 0.2, 0.4, 21), progress=False)
    va.attractors(MULTI, omega=0.3149, delta=0.7, samples=16, progress=False)
    out, err = capfd.readouterr()
    assert err == "" and out == ""


def test_no_bar_on_short_work(capfd):
    va.cell(MULTI)
    va.sweep(MULTI, axis=("omega", 0.2, 0.4, 11))
    va.attractors(MULTI, omega=0.3149, delta=0.7, samples=8)
    out, err = capfd.readouterr()
    assert err == "" and out == ""
