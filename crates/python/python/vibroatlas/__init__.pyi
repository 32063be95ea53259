# Type hints of the vibroatlas package (docs/python.md). Checked with
# `mypy --strict` on the README's and docs/python.md's examples
# (scripts/test-python.sh).
import os
from collections.abc import Mapping, Sequence
from typing import Any, Literal, Union

import xarray

from . import plot as plot

__version__: str

Scene = Union[str, os.PathLike[str], Mapping[str, Any]]
Path = Union[str, os.PathLike[str]]
Axis = tuple[str, float, float, int]
Preset = Literal["fast", "standard", "precise"]
Integrator = Literal["exact", "rk4"]
Sweep = Literal["fresh", "up", "down", "both"]

class SceneError(ValueError): ...

def cell(
    scene: Scene | None = ...,
    *,
    state: Sequence[float] | None = ...,
    from_file: Path | None = ...,
    at: Mapping[str, float] | None = ...,
    sweep: Literal["fresh", "up", "down"] | None = ...,
    portrait: bool = ...,
    sections: bool = ...,
    section_periods: int | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool | None = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> dict[str, Any]: ...
def sweep(
    scene: Scene,
    axis: Axis,
    *,
    direction: Literal["up", "down", "both", "down-up", "up-down"] | None = ...,
    threads: int | None = ...,
    section_cap: int | None = ...,
    output: Path | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> dict[str, Any]: ...
def atlas(
    scene: Scene,
    x: Axis,
    y: Axis,
    *,
    sweep: Sweep | None = ...,
    along: Literal["x", "y"] | None = ...,
    threads: int | None = ...,
    section_cap: int | None = ...,
    attractors: int | None = ...,
    attractors_where: Literal["all", "hysteresis"] | None = ...,
    seed: int | None = ...,
    quantities: str | Sequence[str] | None = ...,
    output: Path | None = ...,
    force: bool | None = ...,
    resume: bool | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> xarray.DataTree: ...
def zoom(
    parent: Path | xarray.DataTree,
    x: Axis,
    y: Axis,
    *,
    sweep: Sweep | None = ...,
    threads: int | None = ...,
    output: Path | None = ...,
    progress: bool = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> xarray.DataTree: ...

class Explorer:
    path: str
    height: int
    def __init__(self, path: str, port: int = ..., threads: int | None = ..., height: int = ...) -> None: ...
    @property
    def url(self) -> str: ...
    @property
    def clicked(self) -> dict[str, Any] | None: ...
    @property
    def selected(self) -> dict[str, Any] | None: ...
    def stop(self) -> None: ...
    def __enter__(self) -> Explorer: ...
    def __exit__(self, *exc: object) -> None: ...
    def _repr_html_(self) -> str: ...

def explore(source: Path | xarray.DataTree, *, port: int = ..., threads: int | None = ...) -> Explorer: ...
def attractors(
    scene: Scene,
    *,
    samples: int | None = ...,
    seed: int | None = ...,
    box: tuple[float, float] | None = ...,
    threads: int | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> dict[str, Any]: ...
def basins(
    scene: Scene,
    x: tuple[str, float, float, int],
    y: tuple[str, float, float, int],
    *,
    state: Sequence[float] | None = ...,
    phase: float | None = ...,
    early_stop: bool | None = ...,
    threads: int | None = ...,
    output: Path | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> xarray.Dataset: ...
def curve(
    scene: Scene,
    kind: Literal["pd", "sn", "pf", "ns", "grazing"],
    start: Mapping[str, float] | Sequence[tuple[str, float]],
    free: tuple[str, str],
    to: float | None = ...,
    *,
    steps: int | None = ...,
    window: float | None = ...,
    bounds: tuple[float, float] | None = ...,
    n: int | None = ...,
    state: Sequence[float] | None = ...,
    output: Path | None = ...,
    preset: Preset | None = ...,
    integrator: Integrator | None = ...,
    accuracy: Mapping[str, float] | None = ...,
    progress: bool | None = ...,
    params: Mapping[str, float] | None = ...,
    **parameters: float,
) -> dict[str, Any]: ...
def open(path: Path, **kwargs: Any) -> xarray.DataTree: ...
# A sweep group: a DataTree node or a Dataset (a DataArray is accepted by
# type, as xarray types a tree's item, and refused when called).
Group = Union[xarray.DataTree, xarray.Dataset, xarray.DataArray]

def labels(ds: Group, mass: str | None = ...) -> xarray.DataArray: ...
def label_table(ds: Group, code: xarray.DataArray | None = ...) -> Any: ...
