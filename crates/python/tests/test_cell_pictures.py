"""va.cell(portrait=True, sections=True) and va.plot.portrait / va.plot.sections:
what `cell --portrait` and `cell --section-png` draw, as data and as matplotlib
figures. The portrait is the classified window sampled 400 times a period:
it equals the CLI's trace of that window (`cell --trace --trace-samples 400`)
row for row. The sections of a periodic cell return to its final state every
period, and a stop's impact panel holds the cell's impacts per period times
the periods."""
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import vibroatlas as va  # noqa: E402

from conftest import DRY, MULTI, cli, cli_error, cli_json  # noqa: E402

POINT = {"omega": 0.33, "delta": 0.6}  # 1-4-4 / 1-0-4: four impacts a period at A1 and at A12, none at A2


def sets(point):
    return [a for k, v in point.items() for a in ("--set", f"{k}={v!r}")]


def without(r, *keys):
    return {k: v for k, v in r.items() if k not in keys}


@pytest.mark.parametrize("scene, point", [(MULTI, POINT), (DRY, {"omega": 6.9, "fk": 0.01})])
def test_portrait_is_the_clis_trace_of_the_window(tmp_path, scene, point):
    r = va.cell(scene, portrait=True, **point)
    assert without(r, "portrait") == cli_json("cell", scene, *sets(point))
    p = r["portrait"]
    path = tmp_path / "trace.csv"
    cli("cell", scene, *sets(point), "--trace", path, "--trace-samples", "400")
    with open(path) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    masses = p["masses"]
    assert head == ["t"] + [f"x_{m}" for m in masses] + [f"v_{m}" for m in masses] + ["event"]
    values = np.array([[float(c) for c in row[:-1]] for row in body])
    m = len(masses)
    assert p["t"].shape == (len(body),) and p["x"].shape == p["v"].shape == (m, len(body))
    # the CSV prints 16 significant digits
    np.testing.assert_allclose(p["t"], values[:, 0], rtol=1e-15, atol=0)
    np.testing.assert_allclose(p["x"], values[:, 1:1 + m].T, rtol=1e-14, atol=1e-300)
    np.testing.assert_allclose(p["v"], values[:, 1 + m:].T, rtol=1e-14, atol=1e-300)
    assert p["events"] == [(i, row[-1]) for i, row in enumerate(body) if row[-1]]
    assert p["events"], "the window of an impacting cell has events"
    assert all(isinstance(s[2], str) for s in p["stops"])


def test_sections_of_a_periodic_cell(tmp_path):
    periods = 40
    r = va.cell(MULTI, sections=True, section_periods=periods, **POINT)
    assert without(r, "sections") == cli_json("cell", MULTI, *sets(POINT))
    assert r["n"] == 1 and r["labels"] == {"M1": "1-4-4", "M2": "1-0-4"}
    s = r["sections"]
    assert s["periods"] == periods
    assert "Poincaré sections over 40 periods; no impacts at\u00a0A2" in s["title"]
    names = [(q["x"], q["y"]) for q in s["panels"]]
    assert names == [("x_M1 at t = kT", "v_M1"), ("phase at A1 (rad)", "impact speed"),
                     ("phase at A12 (rad)", "impact speed")]
    # a period-1 orbit: every return is the final state (x_M1, v_M1) = (y[0], y[2]), to the
    # tolerance the classification converged to
    first = s["panels"][0]["points"]
    assert first.shape == (periods, 2)
    final = r["final_state"]
    np.testing.assert_allclose(first, np.tile([final[0], final[2]], (periods, 1)), rtol=0, atol=1e-7)
    for panel, stop in zip(s["panels"][1:], ("A1", "A12")):
        assert panel["points"].shape == (r["impacts"][stop] * periods, 2)
        assert (panel["points"][:, 1] > 0).all(), "impact speeds are speeds of approach"
        assert ((0 <= panel["points"][:, 0]) & (panel["points"][:, 0] < 2 * np.pi)).all()


def test_default_section_periods_are_the_clis():
    r = va.cell(MULTI, sections=True, **POINT)
    assert r["sections"]["periods"] == 1000
    assert len(r["sections"]["panels"][0]["points"]) == 1000


def test_plot_portrait_draws_the_data():
    r = va.cell(MULTI, portrait=True, **POINT)
    p = r["portrait"]
    fig = plt.figure()
    axes = va.plot.portrait(r, fig=fig)
    assert len(axes) == len(p["masses"]) + 1
    for k, ax in enumerate(axes[:-1]):
        np.testing.assert_array_equal(ax.lines[0].get_xydata(), np.column_stack([p["x"][k], p["v"][k]]))
        assert ax.get_xlabel() == f"x$_{{\\mathrm{{{p['masses'][k]}}}}}$"
    # the frame stops of M1 as vertical lines at their positions
    lines = [ln.get_xdata()[0] for ln in axes[0].lines[1:] if len(set(ln.get_xdata())) == 1
             and len(ln.get_xdata()) == 2]
    assert sorted(lines) == sorted(pos for mass, pos, _ in p["stops"] if mass == 0)
    np.testing.assert_array_equal(axes[-1].lines[0].get_xydata(), np.column_stack([p["t"], p["x"][0]]))
    fig.canvas.draw()
    plt.close(fig)


def test_plot_sections_draws_the_points():
    r = va.cell(MULTI, sections=True, section_periods=25, **POINT)
    fig = plt.figure()
    axes = va.plot.sections(r, fig=fig)
    assert len(axes) == 3
    for ax, panel in zip(axes, r["sections"]["panels"]):
        np.testing.assert_array_equal(ax.lines[0].get_xydata(), panel["points"])
    assert axes[0].get_xlabel() == "x$_{\\mathrm{M1}}$ at t = kT"
    # a period's few distinct points are drawn large, amid readable ticks, not over a range of
    # round-off (render's axis range: at least 5 % of the values' magnitude on each side)
    assert axes[0].lines[0].get_markersize() > 3
    final = r["final_state"]
    for (lo, hi), centre in ((axes[0].get_xlim(), final[0]), (axes[0].get_ylim(), final[2])):
        assert hi - lo >= 0.1 * abs(centre) and lo < centre < hi, (lo, hi, centre)
    fig.canvas.draw()
    img = np.asarray(fig.canvas.buffer_rgba())[:, :, :3]
    px, py = axes[1].transData.transform(r["sections"]["panels"][1]["points"][0])
    assert tuple(img[img.shape[0] - 1 - int(py), int(px)]) == (0, 114, 178)
    plt.close(fig)


def test_pictures_that_were_not_computed_are_refused():
    r = va.cell(MULTI, **POINT)
    with pytest.raises(ValueError, match=r"no portrait: compute it with va.cell\(\.\.\., portrait=True\)"):
        va.plot.portrait(r)
    with pytest.raises(ValueError, match=r"no sections: compute it with va.cell\(\.\.\., sections=True\)"):
        va.plot.sections(r)
    with pytest.raises(TypeError, match="expected the dict of va.cell"):
        va.plot.sections("r.h5")


def test_bad_section_periods():
    with pytest.raises(ValueError, match="section_periods: given without sections=True"):
        va.cell(MULTI, section_periods=10)
    with pytest.raises(ValueError) as e:
        va.cell(MULTI, sections=True, section_periods=0, **POINT)
    cli_says = cli_error("cell", MULTI, "--section-png", "/tmp/never.png", "--section-periods", "0")
    assert str(e.value) == cli_says.replace("--section-periods", "section_periods")
    with pytest.raises(ValueError, match="section_periods: must be >= 0, got -3"):
        va.cell(MULTI, sections=True, section_periods=-3)
    with pytest.raises(TypeError, match="portrait: expected True or False"):
        va.cell(MULTI, portrait="yes")
