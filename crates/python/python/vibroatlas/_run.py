"""Arguments for the native engine, and the loop that runs one of its jobs.

The native module (`vibroatlas._native`, Rust) starts every computation on a
thread of its own and hands back a Job; this module turns Python arguments
into the job's (scene, params, options), waits for it in slices of 0.1 s
(so that Ctrl-C is seen within a slice), draws a tqdm bar for long work, and
cancels the job on KeyboardInterrupt.
"""
import difflib
import json
import math
import numbers
import os
import sys
import time
from collections.abc import Mapping

from . import _native

#: A bar is shown for work of more than this many units (cells, samples) ...
BAR_UNITS = 300
#: ... or that has run longer than this many seconds.
BAR_SECONDS = 1.0
#: How long one wait for the job lasts, seconds (the latency of Ctrl-C).
SLICE = 0.1
#: How long Ctrl-C waits for a cancelled job to stop, seconds.
CANCEL_WAIT = 1.0


class Stored:
    """The scene stored in an atlas or sweep file (`cell --from FILE` without a scene)."""

    def __init__(self, path):
        self.path = os.fspath(path)


def scene_arg(scene):
    """The native scene argument: ("path", p) for a path (str or os.PathLike),
    ("toml", text) for a str holding a TOML text (one with a newline), ("json",
    text) for a dict (a parsed scene table)."""
    if isinstance(scene, Stored):
        return ("stored", scene.path)
    if isinstance(scene, Mapping):
        try:
            table = _table(scene, "")
        except RecursionError:
            raise _native.SceneError("scene: a table nested deeper than Python can follow, "
                                     "or one that contains itself") from None
        return ("json", json.dumps(table, allow_nan=False))
    if isinstance(scene, os.PathLike):
        return ("path", os.fspath(scene))
    if isinstance(scene, str):
        if "\n" not in scene:
            return ("path", scene)
        try:
            scene.encode("utf-8")
        except UnicodeEncodeError as e:
            raise _native.SceneError(f"scene: not text that UTF-8 can hold ({e.reason} at character {e.start})") from None
        return ("toml", scene)
    if isinstance(scene, bytes):
        raise TypeError("scene: give a path (str or pathlib.Path), a TOML text (str) or a dict, not bytes")
    raise TypeError(f"scene: give a path (str or pathlib.Path), a TOML text (str) or a dict, "
                    f"not {type(scene).__name__}")


def _table(value, field):
    """A scene given as a dict, as plain JSON values: numpy numbers become
    Python ones; a value TOML cannot hold (None, NaN, infinity, an object) is
    a SceneError naming its field (`masses[0].mass`)."""
    where = field or "scene"
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise _native.SceneError(f"{where}: keys must be text, got {k!r}")
            out[k] = _table(v, f"{field}.{k}" if field else k)
        return out
    if isinstance(value, (list, tuple)):
        return [_table(v, f"{field}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, (str, bool)):
        return value
    if isinstance(value, numbers.Integral):
        # a TOML integer is 64 bits; beyond, the number as a float, if one holds it
        n = int(value)
        if -2**63 <= n < 2**63:
            return n
        try:
            return float(n)
        except OverflowError:
            raise _native.SceneError(f"{where}: not a finite number, got an integer of {len(str(abs(n)))} digits") from None
    if isinstance(value, numbers.Real):
        v = float(value)
        if not math.isfinite(v):
            raise _native.SceneError(f"{where}: not a finite number, got {v}")
        return v
    raise _native.SceneError(f"{where}: a scene holds numbers, text, tables and lists, not {type(value).__name__}")


def number(what, v):
    """v as a float (ints and numpy scalars too; not bools or strings)."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(f"{what}: expected a number, got {v!r}")
    try:
        return float(v)
    except OverflowError:
        raise ValueError(f"{what}: not a finite number, got {v!r}") from None


# The largest count the library takes (a 64-bit one); each is bounded far
# below it, with its own message, once it gets there.
WHOLE_MAX = 2**63 - 1


def whole(what, v, least=0):
    """v as an int (a whole number; an integral float too), at least `least`
    (no count, seed or cap is negative)."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(f"{what}: expected a whole number, got {v!r}")
    if isinstance(v, numbers.Integral):
        n = int(v)
    else:
        f = float(v)
        if not math.isfinite(f) or f != int(f):
            raise ValueError(f"{what}: expected a whole number, got {v!r}")
        n = int(f)
    if least is not None and n < least:
        raise ValueError(f"{what}: must be >= {least}, got {n}")
    if n > WHOLE_MAX:
        raise ValueError(f"{what}: must be at most {WHOLE_MAX}, got {n}")
    return n


def flag(what, v):
    """Refuses a flag that is neither True, False nor None (`"yes"`)."""
    if v is not None and not isinstance(v, bool):
        raise TypeError(f"{what}: expected True or False, got {v!r}")


def floats(what, v, length=None):
    """v, a sequence of numbers, as a list of floats (of `length` when given)."""
    if isinstance(v, (str, bytes, dict)) or not hasattr(v, "__iter__"):
        raise TypeError(f"{what}: expected a sequence of numbers, got {v!r}")
    out = [number(f"{what}[{i}]", x) for i, x in enumerate(v)]
    if length is not None and len(out) != length:
        raise ValueError(f"{what}: expected {length} numbers, got {len(out)}")
    return out


def path(what, v):
    """v, a path (str, bytes or os.PathLike), as the str the library takes."""
    try:
        p = os.fsdecode(os.fspath(v))
    except TypeError:
        raise TypeError(f"{what}: expected a path (str or pathlib.Path), got {type(v).__name__}") from None
    if "\0" in p:
        raise ValueError(f"{what}: a path cannot hold a NUL character, got {p!r}")
    return p


def text(what, v):
    """v, a str, or a TypeError naming `what`."""
    if not isinstance(v, str):
        raise TypeError(f"{what}: expected a str, got {v!r}")
    return v


def names(what, v):
    """A text the engine reads as a list of names: "all", "none", or names
    separated by commas, given as that text or as a list of names."""
    if isinstance(v, str):
        return v
    if isinstance(v, (list, tuple)) and all(isinstance(n, str) for n in v):
        bad = next((n for n in v if not n.strip() or "," in n or n.strip() in ("all", "none")), None)
        if bad is not None:
            raise ValueError(f"{what}: {bad[:80]!r} is not a name (give \"all\", \"none\" or a list of names)")
        return ",".join(v) if v else "none"
    raise TypeError(f"{what}: expected \"all\", \"none\" or a list of names, got {v!r:.80}")


def axis(what, v):
    """(name, start, stop, count) of an axis given as a 4-sequence."""
    try:
        name, start, stop, count = v
    except (TypeError, ValueError):
        raise TypeError(f"{what}: expected (name, start, stop, count), e.g. ('omega', 0.1, 3.05, 60); "
                        f"got {v!r}") from None
    return (text(f"{what} name", name), number(f"{what} start", start), number(f"{what} stop", stop),
            whole(f"{what} count", count))


def keywords():
    """The named parameters of the package's functions that take a scene's
    parameters as extra keywords (`**parameters`): an extra keyword close to
    one of them is a misspelt keyword, not a scene parameter."""
    import inspect

    import vibroatlas

    names = set()
    for f in vars(vibroatlas).values():
        if inspect.isfunction(f):
            params = inspect.signature(f).parameters.values()
            if any(p.kind is p.VAR_KEYWORD and p.name == "parameters" for p in params):
                names |= {p.name for p in params if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)}
    return sorted(names)


def params_arg(params, extra):
    """The --set list [(name, float)] in the order given: `params` (a dict, for
    names that clash with a keyword of the function) then the extra keywords.
    An extra keyword that is not a number and is spelt like a keyword of the
    package (`presett`) is a TypeError naming the keyword meant."""
    if params is not None and not hasattr(params, "items"):
        raise TypeError(f"params: expected a dict of parameter values, got {type(params).__name__}")
    for name, v in extra.items():
        close = difflib.get_close_matches(name, keywords(), n=1, cutoff=0.8)
        if close == [name] and not isinstance(v, numbers.Real):
            raise TypeError(f"unexpected keyword {name!r}: this function does not take it (its other keywords "
                            f"are scene parameters, which take numbers)")
        if close and (isinstance(v, (str, bool, dict, list, tuple)) or v is None):
            raise TypeError(f"unexpected keyword {name!r}: did you mean {close[0]!r}? (other keywords are "
                            f"scene parameters, which take numbers)")
    out = []
    for source in (params or {}), extra:
        for name, v in source.items():
            out.append((text("parameter name", name), number(f"parameter {name}", v)))
    return out


#: The simulation options (`common`) that the native functions take with the
#: scene and its parameters, apart from their own keywords.
SIM_KEYWORDS = ("preset", "integrator", "accuracy")


def common(options, preset, integrator, accuracy):
    """Adds the simulation options every command takes (only those given)."""
    if preset is not None:
        options["preset"] = text("preset", preset)
    if integrator is not None:
        options["integrator"] = text("integrator", integrator)
    if accuracy is not None:
        if not isinstance(accuracy, Mapping):
            raise TypeError(f"accuracy: expected a dict of knob -> value, got {accuracy!r}")
        options["accuracy"] = {text("accuracy knob", k): number(f"accuracy {k}", v) for k, v in accuracy.items()}
    return options


def run(start, scene, params, options, progress=False, unit="cell", desc=None):
    """`_job` with its arguments checked; a dict scene's errors name it as
    the scene, not as the TOML text it is sent as."""
    flag("progress", progress)
    try:
        return _job(start, scene, params, options, progress, unit, desc)
    except _native.SceneError as e:
        said = str(e)
        if isinstance(scene, Mapping) and said.startswith("scene text: "):
            raise _native.SceneError("scene: " + said[len("scene text: "):]) from None
        raise


def _job(start, scene, params, options, progress, unit, desc):
    """Starts a native job and waits for it; returns its result (the value of
    the CLI's `--json`, as dicts, lists, numbers and text). With `progress`, a tqdm bar (tqdm.auto: a widget in a notebook)
    appears once the work is known to be long (more than BAR_UNITS units, or
    running for more than BAR_SECONDS). Ctrl-C cancels the job, waits for it
    to end (it removes its partial output) at most CANCEL_WAIT seconds, and
    re-raises KeyboardInterrupt. A job that cannot stop at once (one cell's
    simulation, a curve's steps) ends on its own thread and writes nothing."""
    sim = {"scene": scene_arg(scene), "params": params}
    sim.update({key: options.pop(key) for key in SIM_KEYWORDS if key in options})
    return wait(lambda: start(sim, **options), progress, unit, desc)


def wait(start, progress, unit, desc):
    """Starts the native job `start()` returns and waits for it (see
    `_job`); returns its result as Python objects."""
    job = start()
    bar = None
    # no standard error (pythonw, a closed stream set to None): no bar to draw
    progress = progress and sys.stderr is not None
    t0 = time.monotonic()
    try:
        while not job.wait(SLICE):
            if not progress:
                continue
            done, total = job.progress()
            if bar is None and (total > BAR_UNITS or time.monotonic() - t0 > BAR_SECONDS):
                from tqdm.auto import tqdm
                bar = tqdm(total=total or None, unit=unit, desc=desc, dynamic_ncols=True)
            if bar is not None:
                if total and bar.total != total:
                    bar.total = total
                bar.update(done - bar.n)
        if bar is not None:
            done, total = job.progress()
            if total and bar.total != total:
                bar.total = total
            bar.update(done - bar.n)
    except BaseException:
        # Ctrl-C, or a bar that cannot draw (stderr closed, None or full):
        # nothing may go on writing after the call has raised.
        job.cancel()
        bar = _close(bar)
        # wait for the work to stop (it cleans up its partial output); past
        # CANCEL_WAIT, or at a second Ctrl-C, the job ends on its own thread
        # and, cancelled, writes nothing
        try:
            job.wait(CANCEL_WAIT)
        except KeyboardInterrupt:
            pass
        raise
    finally:
        _close(bar)
    return job.result()


def _close(bar):
    """Closes a tqdm bar, if any, ignoring a stream that no longer takes its
    last line; returns None."""
    if bar is not None:
        try:
            bar.close()
        except (OSError, ValueError, AttributeError):
            pass
    return None
