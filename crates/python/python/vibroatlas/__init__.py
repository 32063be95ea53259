"""vibroatlas in Python: the engine of the `vibroatlas` CLI (the same Rust code,
the same numbers) behind functions that return dicts and xarray DataTrees.

    import vibroatlas as va
    r = va.cell("configs/multi-stop.toml", omega=0.33, delta=0.6)    # like `cell --json`
    t = va.atlas("configs/multi-stop.toml", x=("omega", 0.1, 3.05, 60), y=("delta", 0.05, 2.0, 40),
                 sweep="both")                                      # xarray.DataTree, as the file
    va.plot.map(t["up"], mass="M1")

Every function takes the scene as a path, a TOML text or a dict; extra keyword
arguments are scene parameters (the CLI's `--set NAME=VALUE`, in the order
given). Errors are exceptions with the CLI's one-line messages, options named
as keyword arguments (`threads: must be >= 1`): SceneError (a
ValueError) for scenes, ValueError for arguments, OSError for files.
Reference: docs/python.md.
"""
import io
import os

import numpy as _np

from . import _native
from ._native import SceneError
from . import _run
from ._run import axis as _axis, common as _common, number as _number, params_arg as _params
from ._run import names as _names, text as _text, whole as _whole

try:
    from importlib.metadata import version as _version

    __version__ = _version("vibroatlas")
except Exception:  # not installed (run from the sources)
    __version__ = "unknown"

__all__ = ["cell", "sweep", "atlas", "zoom", "explore", "Explorer", "attractors", "basins", "curve", "open",
           "labels", "label_table", "plot", "SceneError"]


def __dir__():
    """The package's API only (not the modules and helpers it uses)."""
    return sorted(__all__ + ["__version__"])


def cell(scene=None, *, state=None, from_file=None, at=None, sweep=None, portrait=False, sections=False,
         section_periods=None, preset=None, integrator=None, accuracy=None, progress=None, params=None,
         **parameters):
    """Simulates one parameter point from the scene's initial state (or from
    `state`) and classifies its steady motion, like `vibroatlas cell SCENE
    --json`.

    scene: a path, a TOML text or a dict. preset: "fast", "standard" or
    "precise"; integrator: "exact" or "rk4"; accuracy: {knob: value} (the
    CLI's `--accuracy`). Extra keywords (and `params`, a dict, for names that
    clash with these keywords) are scene parameters (`--set`). state: the
    start [x1, x2, ..., v1, v2, ...] at the scene's forcing phase, instead of
    the scene's initial state (`--state`). progress is accepted for symmetry
    with the other functions and ignored (a cell is short: no bar).

    from_file, at, sweep: a cell of a stored atlas (or sweep file), run
    again from the state it started from, like `cell --from FILE --at
    omega=…,delta=… --sweep down`: at is {parameter: value} (the nearest
    stored cell is taken), sweep the file's sweep (default its first); the
    file's scene, preset, knobs and integrator are used unless given.
    `Explorer.selected` is the cell clicked in the page, as this returns it.

    Returns the dict `cell --json` prints: class, n, reason (and
    reason_detail, the reason with its numbers, for an unresolved cell), labels,
    symmetry, impacts, chatter, sticking, final_state, period_section,
    max_multiplier, lyapunov, scene, parameters, preset, integrator,
    periods_simulated, events (and friction_stick in scenes with friction).

    portrait=True adds "portrait", what `cell --portrait FILE` draws
    (va.plot.portrait): the classified window sampled 400 times a period,
    as title, masses, t [row], x and v [mass, row] (numpy arrays), events
    [(row, "impact A1"), ...] and the frame stops [(mass, position, name)].
    sections=True adds "sections", what `cell --section-png FILE` draws
    (va.plot.sections): over section_periods forcing periods from the final
    state (default 1000, as `--section-periods`), its title, periods and
    panels, each {"x": description, "y": description, "points": array
    [point, 2]}: the first labelled mass's (x, v) at t = kT, then each stop
    with impacts (phase in radians, normal speed just before).
    """
    options = _common({}, preset, integrator, accuracy)
    if state is not None:
        options["state"] = _run.floats("state", state)
    if from_file is not None:
        if state is not None:
            raise ValueError("state: give either state or from_file, not both")
        if at is None or not hasattr(at, "items"):
            raise TypeError(f"at: expected {{parameter: value}} with from_file, got {at!r}")
        values = [(_text("at", k), _number(f"at {k}", v)) for k, v in at.items()]
        options["stored"] = (_run.path("from_file", from_file), values, None if sweep is None else _text("sweep", sweep))
        if scene is None:
            scene = _run.Stored(from_file)
    elif at is not None or sweep is not None:
        raise ValueError("at, sweep: given without from_file")
    if scene is None:
        raise TypeError("cell: missing the scene (a path, a TOML text or a dict), or from_file")
    _run.flag("progress", progress)
    _run.flag("portrait", portrait)
    _run.flag("sections", sections)
    if portrait:
        options["portrait"] = True
    if sections:
        options["sections"] = True
    if section_periods is not None:
        if not sections:
            raise ValueError("section_periods: given without sections=True")
        options["section_periods"] = _whole("section_periods", section_periods)
    r = _run.run(_native.cell, scene, _params(params, parameters), options)
    if "portrait" in r:
        p = r["portrait"]
        for key in ("t", "x", "v"):
            p[key] = _np.asarray(p[key], dtype=float)
        p["events"] = [(int(i), str(what)) for i, what in p["events"]]
        p["stops"] = [(int(k), float(x), str(name)) for k, x, name in p["stops"]]
    if "sections" in r:
        for panel in r["sections"]["panels"]:
            panel["points"] = _np.asarray(panel["points"], dtype=float).reshape(-1, 2)
    return r


def sweep(scene, axis, *, direction=None, threads=None, section_cap=None, output=None, preset=None,
          integrator=None, accuracy=None, progress=True, params=None, **parameters):
    """Follows one motion along a parameter (each cell from the final state of
    the one before), like `vibroatlas sweep SCENE --axis ... --json`.

    axis: (name, start, stop, count), run in that order (start > stop sweeps
    down). direction: "up", "down", "both" (each from the scene's initial
    state), "down-up" or "up-down" (a hysteresis loop); default: the order of
    the axis. threads: worker threads; section_cap: section points kept per
    cell. output: also write the sweep's file there, as `sweep -o FILE`
    does (an atlas of one row: `va.open` and `render` read it). progress: a
    tqdm bar on long sweeps (False: never).

    Returns the dict `sweep --json` prints (the points of each leg, in run
    order, each with its labels, stability, reason, final state and period
    section, and the hysteresis values).
    """
    options = _common({"axis": _axis("axis", axis)}, preset, integrator, accuracy)
    if direction is not None:
        options["direction"] = _text("direction", direction)
    if threads is not None:
        options["threads"] = _whole("threads", threads)
    if section_cap is not None:
        options["section_cap"] = _whole("section_cap", section_cap)
    if output is not None:
        options["output"] = _run.path("output", output)
    return _run.run(_native.sweep, scene, _params(params, parameters), options, progress, unit="cell",
                    desc="sweep")


def atlas(scene, x, y, *, sweep=None, along=None, threads=None, section_cap=None, attractors=None,
          attractors_where=None, seed=None, quantities=None, output=None, force=None, resume=None, preset=None,
          integrator=None, accuracy=None, progress=True, params=None, **parameters):
    """Maps a plane of two parameters, like `vibroatlas atlas SCENE --x ... --y
    ... -o FILE`, and returns it as an xarray.DataTree with the file's groups
    (/up, /down or /fresh, /legend, /attractors; the root holds the axes and,
    with up and down, the `hysteresis` mask), variables,
    coordinates and attributes, loaded into memory.

    x, y: (name, start, stop, count). sweep: "fresh" (default), "up", "down"
    or "both"; along: "x" (rows, default) or "y" (columns); threads: worker
    threads (default: all cores); section_cap: raw section points kept per
    cell (16); attractors: K initial states sampled per cell (the
    /attractors group), attractors_where: "all" or "hysteresis", seed: their
    seed. quantities: the quantities of the steady motion stored per cell,
    "all" (default), "none", or a list of names (["max_abs_x_M1",
    "power_in"]). output: also keep the file, written by the Rust writer at that path
    (force: accepted and ignored, as `--force` is: an output that is a device
    or a pipe is always refused; resume: continue a run
    killed from outside from its journal beside `output`, or do nothing when
    `output` is already this run's finished file); without it the file is
    written in memory (nothing on disk) and read from there. Either way the
    tree returned is in memory (no file stays open) and the same, but for
    the run's time and provenance. progress: a tqdm
    bar (False: never). Ctrl-C stops the run within about a second and leaves
    no file, partial or whole, at `output`.
    """
    options = _common({"x": _axis("x", x), "y": _axis("y", y)}, preset, integrator, accuracy)
    for key, value in (("sweep", sweep), ("along", along), ("attractors_where", attractors_where)):
        if value is not None:
            options[key] = _text(key, value)
    for key, value in (("threads", threads), ("section_cap", section_cap), ("attractors", attractors),
                       ("seed", seed)):
        if value is not None:
            options[key] = _whole(key, value)
    if quantities is not None:
        options["quantities"] = _names("quantities", quantities)
    for key, value in (("force", force), ("resume", resume)):
        if value is not None and not isinstance(value, bool):
            raise TypeError(f"{key}: expected True or False, got {value!r}")
    if resume and output is None:
        raise ValueError("resume: continues the run of an output file; give output too")
    if resume is not None:
        options["resume"] = resume  # force is accepted and ignored, as `--force` is
    return _tree_of(lambda: _run.run(_native.atlas, scene, _params(params, parameters), options, progress,
                                     unit="cell", desc="atlas"), options, output)


def _tree_of(run, options, output):
    """Runs `run()` and returns the atlas as a DataTree in memory: read from
    the file written at `output` (options["output"]), or, without one, from
    the file's bytes that the run wrote in memory (no file on disk)."""
    if output is not None:
        options["output"] = _run.path("output", output)
        result = run()
        return _loaded(result.get("output", options["output"]))
    return _loaded(io.BytesIO(run()["image"]))


def _loaded(source):
    """The file at the path `source`, or in the file object `source`, read
    as va.open reads a file into a DataTree in memory (no file left open)."""
    import xarray as xr

    tree = xr.open_datatree(source, **_READING)
    try:
        tree.load()
    finally:
        tree.close()
    return tree


def zoom(parent, x, y, *, sweep=None, threads=None, output=None, progress=True, params=None, **parameters):
    """Computes a box of a stored atlas again, like `vibroatlas zoom PARENT
    --x ... --y ... -o FILE`, and returns it as an xarray.DataTree like
    `atlas`: with the parent's scene, parameter values, preset, accuracy and
    sweeps, its continuation chains entering the box from the parent's final
    states at the box's edge. A box aligned with the parent's grid at the
    parent's spacing reproduces the parent's cells bit for bit.

    parent: the parent atlas's file, or a DataTree that `va.open` or
    `va.atlas(..., output=...)` made from one (its file is used). x, y:
    (name, start, stop, count), the parent's axes' parameters, within its
    plane. sweep: narrows the parent's sweeps ("up", "down", "fresh" or
    "both"). threads, output, progress: as for `atlas` (without output the
    file is written in memory, nothing on disk). params / keyword
    parameters: scene parameters that are not axes, set to other values
    than the parent's (`zoom --set`): the box is then a slice beside the
    parent's plane (`va.zoom(p, x, y, zeta=0.07)`).
    """
    parent = _file_of(parent, "parent")
    options = {"x": _axis("x", x), "y": _axis("y", y)}
    if sweep is not None:
        options["sweep"] = _text("sweep", sweep)
    given = _params(params, parameters)
    if given:
        options["set"] = given
    if threads is not None:
        options["threads"] = _whole("threads", threads)
    _run.flag("progress", progress)
    return _tree_of(lambda: _run.wait(lambda: _native.zoom(parent, **options), progress, "cell", "zoom"),
                    options, output)


def _file_of(source, what):
    """The path of an atlas given as a path or as a DataTree read from a file."""
    if isinstance(source, (str, bytes, os.PathLike)):
        return _run.path(what, source)
    encoding = getattr(source, "encoding", None) or {}
    path = encoding.get("source")
    if path is None:
        raise TypeError(f"{what}: expected an atlas file's path, or a DataTree opened from one "
                        f"(va.open, or va.atlas with output=), got {type(source).__name__}")
    return path


class Explorer:
    """The interactive atlas of a file (`vibroatlas explore`), served from a
    thread of this process on 127.0.0.1: `.url`, `.stop()`; in Jupyter it
    shows the page inline."""

    def __init__(self, path, port=0, threads=None, height=900):
        if not isinstance(port, int) or isinstance(port, bool) or not 0 <= port <= 65535:
            raise ValueError(f"port: expected 0 to 65535, got {port!r}")
        if threads is not None:
            threads = _whole("threads", threads)
        # Absolute: the page reads the file while the process's folder may change.
        path = os.path.abspath(_run.path("path", path))
        self._native = _native.Explorer(path, port, threads)
        self.path = path
        self.height = height

    @property
    def url(self):
        """The page's address."""
        return self._native.url

    def stop(self):
        """Stops serving (running zooms are cancelled; their files removed)."""
        self._native.stop()

    @property
    def clicked(self):
        """Where the cell last clicked in the page is stored, as va.cell's
        keywords: {"from_file": FILE, "at": {name: value}, "sweep": S} (a
        zoom's child is a file of the explorer, removed when it stops), or
        None before a click."""
        chosen = self._native.selected
        if chosen is None:
            return None
        file, sweep, at = chosen
        return {"from_file": file, "at": dict(at), "sweep": sweep}

    @property
    def selected(self):
        """The cell last clicked in the page, as `va.cell` returns it
        (`va.cell(**explorer.clicked)`), or None before a click."""
        clicked = self.clicked
        return None if clicked is None else cell(**clicked)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

    def __repr__(self):
        state = "serving" if self._native.running else "stopped"
        return f"<vibroatlas.Explorer of {self.path} at {self.url} ({state})>"

    def _repr_html_(self):
        return (f'<iframe src="{self.url}" width="100%" height="{int(self.height)}" '
                f'style="border:1px solid #ccc"></iframe>')


def explore(source, *, port=0, threads=None):
    """Starts the interactive atlas of `source` (an atlas file, or a DataTree
    with a file behind it) in a background thread and returns an `Explorer`:
    its `.url` opens in a browser, `.stop()` ends it, and in Jupyter the
    object displays the page inline. port: on 127.0.0.1 (0: a free one)."""
    return Explorer(_file_of(source, "source"), port, threads)


def attractors(scene, *, samples=None, seed=None, box=None, threads=None, preset=None, integrator=None,
               accuracy=None, progress=True, params=None, **parameters):
    """Finds the coexisting attractors of one parameter point from sampled
    initial states, like `vibroatlas attractors SCENE --json`.

    samples: initial states (64); seed: of the deterministic sampling (1);
    box: (x, v) half-widths of the box of initial positions and velocities
    ((2, 2)); threads: worker threads (any count gives the same result).

    Returns the dict `attractors --json` prints: each attractor with its
    label, class, state and basin fraction.
    """
    options = _common({}, preset, integrator, accuracy)
    if samples is not None:
        options["samples"] = _whole("samples", samples)
    if seed is not None:
        options["seed"] = _whole("seed", seed)
    if box is not None:
        try:
            bx, bv = box
        except (TypeError, ValueError):
            raise TypeError(f"box: expected (x, v), got {box!r}") from None
        options["box"] = (_number("box x", bx), _number("box v", bv))
    if threads is not None:
        options["threads"] = _whole("threads", threads)
    return _run.run(_native.attractors, scene, _params(params, parameters), options, progress,
                    unit="sample", desc="attractors")


def basins(scene, x, y, *, state=None, phase=None, early_stop=None, threads=None, output=None, preset=None,
           integrator=None, accuracy=None, progress=True, params=None, **parameters):
    """Maps the basins of attraction of one parameter point over a grid of
    two state components, like `vibroatlas basins SCENE --x ... --y ... -o
    FILE`, and returns the file as an xarray.Dataset loaded into memory.

    x, y: (component, start, stop, count), the component `x_<mass>` or
    `v_<mass>` (("x_M2", -1, 1, 200)); state: the state outside the two axes
    (x of every mass, then v; default: the scene's initial state); phase:
    the forcing phase omega t + tau at the start, in radians (default: the
    scene's tau); early_stop: stop a start once it reaches a stable periodic
    attractor already found (`--early-stop`); threads: worker threads (any
    count gives the same file);
    output: also keep the file at that path (else it is written to a
    temporary folder and removed once read).

    The Dataset holds `basin` (y, x): the attractor each start reaches (-1:
    the start penetrates a stop), `periods` (y, x), per attractor its class,
    `labels_<mass>`, `fraction`, `count`, stability and period-section
    points, and the boundary measures as attributes (`basin_entropy`,
    `boundary_basin_entropy`, `uncertainty_exponent`, `fractal`);
    docs/basins.md gives every variable.
    """
    import tempfile
    import xarray as xr

    options = _common({"x": _axis("x", x), "y": _axis("y", y)}, preset, integrator, accuracy)
    if state is not None:
        options["state"] = _run.floats("state", state)
    if phase is not None:
        options["phase"] = _number("phase", phase)
    if threads is not None:
        options["threads"] = _whole("threads", threads)
    _run.flag("early_stop", early_stop)
    if early_stop is not None:
        options["early_stop"] = early_stop
    with tempfile.TemporaryDirectory(prefix="vibroatlas-basins-") as scratch:
        path = _run.path("output", output) if output is not None else os.path.join(scratch, "basins.h5")
        options["output"] = path
        _run.run(_native.basins, scene, _params(params, parameters), options, progress, unit="start",
                 desc="basins")
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return ds.load()


def curve(scene, kind, start, free, to=None, *, steps=None, window=None, bounds=None, n=None, state=None, output=None,
          preset=None, integrator=None, accuracy=None, progress=None, params=None, **parameters):
    """Follows a bifurcation in a plane of two parameters, like `vibroatlas
    curve SCENE --kind ... --json`.

    kind: "pd", "sn", "pf", "ns" or "grazing"; start: {A: value, B: value}
    (or a sequence of two (name, value) pairs) where the bifurcation is
    located near A's value; free: (A, B), A located and B stepped; to: the
    last value of B (None: the curve is followed both ways from the start,
    within the scene's range of B, until it ends); steps (20), window (0.05): the search half-width in A;
    bounds: (lo, hi), the range of A the curve may take (default: the
    scene's range of A; `--bounds A=LO:HI`); n: the orbit's period (default: the cell's); state: the
    state (x of every mass, then v) the first cell, at start, is simulated from
    (default: the scene's initial state; where orbits coexist, the curve of
    the one it reaches); output: also write the curve
    file (for `vibroatlas render --curves`). progress: accepted and ignored
    (no bar).

    Returns the dict `curve --json` prints: the points, the codimension-two
    points and why the curve ended.
    """
    try:
        pairs = list(start.items()) if isinstance(start, dict) else list(start)
    except TypeError:
        raise TypeError(f"start: expected two parameters, e.g. {{'omega': 6.845, 'fk': 0.01}}, got {start!r}") from None
    if len(pairs) != 2:
        raise ValueError(f"start: expected two parameters, e.g. {{'omega': 6.845, 'fk': 0.01}}, got {start!r}")
    if not all(isinstance(p, (tuple, list)) and len(p) == 2 for p in pairs):
        raise TypeError(f"start: expected two (name, value) pairs, got {start!r}")
    options = {"kind": _text("kind", kind),
               "start": [(_text("start name", a), _number(f"start {a}", v)) for a, v in pairs],
               }
    if to is not None:
        options["to"] = _number("to", to)
    try:
        fa, fb = free
    except (TypeError, ValueError):
        raise TypeError(f"free: expected (A, B), got {free!r}") from None
    options["free"] = (_text("free", fa), _text("free", fb))
    options = _common(options, preset, integrator, accuracy)
    if steps is not None:
        options["steps"] = _whole("steps", steps)
    if window is not None:
        options["window"] = _number("window", window)
    if bounds is not None:
        options["bounds"] = tuple(_run.floats("bounds", bounds, length=2))
    if n is not None:
        options["n"] = _whole("n", n)
    if state is not None:
        options["state"] = _run.floats("state", state)
    if output is not None:
        options["output"] = _run.path("output", output)
    _run.flag("progress", progress)
    return _run.run(_native.curve, scene, _params(params, parameters), options)


# How va.open reads a file with xarray: its h5netcdf engine, unnamed dimensions
# named as netCDF-C names them (none in layout 2).
_READING = {"engine": "h5netcdf", "phony_dims": "sort"}


def open(path, **kwargs):  # noqa: A001 (va.open, as the issue names it)
    """Opens a vibroatlas file (atlas, sweep or curve) as an xarray.DataTree
    with xarray's own reader (engine h5netcdf): the groups /up, /down,
    /fresh, /attractors, /curves... as stored. Lazy: close it (or use `with`)
    when done, or call .load() to read it all. kwargs go to
    xarray.open_datatree (e.g. mask_and_scale=False keeps `class` as u8)."""
    import xarray as xr

    path = _run.path("path", path)
    if os.path.isdir(path):
        raise IsADirectoryError(f"{path}: is a folder, not a vibroatlas file")
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no such file")
    if not os.path.isfile(path):
        # a pipe would block the reader for ever, a device has no file in it
        raise OSError(f"{path}: not a regular file (a pipe, a device, ...)")
    kwargs.setdefault("engine", _READING["engine"])
    if kwargs["engine"] == _READING["engine"]:
        kwargs.setdefault("phony_dims", _READING["phony_dims"])
    try:
        return xr.open_datatree(path, **kwargs)
    except (OSError, KeyError) as e:
        # h5py says a damaged object's metadata with a KeyError
        # h5py's message runs over several lines; its first says why
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise OSError(f"{path}: not a file that HDF5 reads ({first})") from e


def labels(ds, mass=None):
    """The label text of one mass, a DataArray of str with the dims and
    coordinates of `label_code_<mass>` ((y, x) in a sweep group; (y, x,
    attractor) in /attractors, where an empty slot, code -1, is "").

    ds: a sweep group (a Dataset, or a DataTree node such as t["up"]); mass:
    a labelled mass ("M1"; default: the first). Decoded through the group's
    `label` table, else the CF `flag_meanings` of the code variable."""
    import numpy as np
    import xarray as xr

    ds = _dataset(ds)
    mass = _first_mass(ds) if mass is None else _text("mass", mass)
    code, c, table = _codes(ds, mass)
    out = np.where(c >= 0, table[np.clip(c, 0, len(table) - 1)], "")
    return xr.DataArray(out, dims=code.dims, coords=code.coords, name=f"label_text_{mass}",
                        attrs={"long_name": f"{mass} label n-p-q", "mass": mass})


def _codes(ds, mass):
    """The label codes of `mass` in the Dataset `ds`: its variable, its codes
    as int64 (-1 for none) and the label table, every code checked to lie in
    the table (a damaged or changed file is refused, never indexed out of
    range or drawn in another label's colour)."""
    import numpy as np

    name = f"label_code_{mass}"
    if name not in ds:
        have = sorted(str(v)[len("label_code_"):] for v in ds.data_vars if str(v).startswith("label_code_"))
        raise ValueError(f"mass {mass!r}: this group labels {', '.join(have) or 'no mass'}")
    code = ds[name]
    table = label_table(ds, code)
    c = np.asarray(code.values)
    if c.dtype.kind not in "iuf":
        raise ValueError(f"{name}: codes of type {c.dtype}, not numbers: the file is damaged or was changed")
    if c.dtype.kind == "f":  # a masked fill decoded as NaN
        c = np.where(np.isnan(c), -1, c)
        if (c != np.floor(c)).any():
            raise ValueError(f"{name}: codes that are not whole numbers: the file is damaged or was changed")
    c = c.astype(np.int64)
    outside = (c < -1) | (c >= len(table))
    if outside.any():
        at = tuple(int(i) for i in np.argwhere(outside)[0])
        raise ValueError(f"{name}: code {int(c[at])} at {dict(zip(code.dims, at))} is outside the label table "
                         f"(0 to {len(table) - 1}, -1 for none): the file is damaged or was changed")
    return code, c, table


def label_table(ds, code=None):
    """The label table of a group as an array of str (its `label` coordinate,
    else the code variable's flag_meanings)."""
    import numpy as np

    if "label" in ds.variables:
        return np.asarray(ds["label"].values).astype(str)
    if code is not None and "flag_meanings" in code.attrs:
        return np.asarray(str(code.attrs["flag_meanings"]).split(" "), dtype=str)
    raise ValueError("this group has no label table (an older file? see docs/file-format.md, section 12)")


def _dataset(ds):
    """A Dataset from a Dataset or a DataTree node; anything else is a
    TypeError saying what it takes."""
    import xarray as xr

    if isinstance(ds, xr.DataTree):
        return ds.to_dataset()
    if isinstance(ds, xr.Dataset):
        return ds
    raise TypeError(f"expected a sweep group of an atlas (an xarray Dataset, or a DataTree node such as "
                    f"t['up']), got {type(ds).__name__}")


def _first_mass(ds):
    if "mass" in ds.variables and ds["mass"].size:
        return str(ds["mass"].values.astype(str)[0])
    for v in ds.data_vars:
        if str(v).startswith("label_code_"):
            return str(v)[len("label_code_"):]
    raise ValueError("this group has no label_code_<mass> variable")


from . import plot  # noqa: E402  (va.plot.map, va.plot.hysteresis)
