# Type hints of vibroatlas.plot (docs/python.md).
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import xarray
from matplotlib.axes import Axes
from matplotlib.figure import Figure

# A sweep group: a DataTree node or a Dataset (a DataArray is accepted by
# type, as xarray types a tree's item, and refused when called).
Group = xarray.DataTree | xarray.Dataset | xarray.DataArray

def edges(v: Sequence[float] | np.ndarray[Any, Any]) -> np.ndarray[Any, Any]: ...
def colours(ds: Group) -> dict[str, tuple[int, int, int]]: ...
def axis_label(coord: xarray.DataArray) -> str: ...
def map(
    ds: Group,
    mass: str | None = ...,
    ax: Axes | None = ...,
    *,
    legend: bool = ...,
    title: str | None = ...,
    max_legend: int = ...,
    view: Literal["labels", "multiplier", "lyapunov"] = ...,
) -> Axes: ...
def basins(
    ds: xarray.Dataset,
    ax: Axes | None = ...,
    *,
    legend: bool = ...,
    title: str | None = ...,
) -> Axes: ...
def hysteresis_mask(tree: xarray.DataTree | str, masses: Sequence[str] | None = ...) -> xarray.DataArray: ...
def hysteresis(
    tree: xarray.DataTree | str,
    mass: str | None = ...,
    fig: Figure | None = ...,
    *,
    legend: bool = ...,
    max_legend: int = ...,
) -> list[Axes]: ...
def scalar(
    ds: Group,
    quantity: Literal["multiplier", "lyapunov"] = ...,
    ax: Axes | None = ...,
    *,
    colorbar: bool = ...,
    title: str | None = ...,
) -> Axes: ...
def quantity(
    ds: Group,
    name: str,
    ax: Axes | None = ...,
    *,
    colorbar: bool = ...,
    title: str | None = ...,
) -> Axes: ...
def difference(
    tree: xarray.DataTree | str,
    name: str,
    ax: Axes | None = ...,
    *,
    colorbar: bool = ...,
    title: str | None = ...,
) -> Axes: ...
def row(
    tree: xarray.DataTree | str,
    at: float | None = ...,
    variable: str | None = ...,
    fig: Figure | None = ...,
) -> list[Axes]: ...
def portrait(result: dict[str, Any], fig: Figure | None = ...) -> list[Axes]: ...
def sections(result: dict[str, Any], fig: Figure | None = ...) -> list[Axes]: ...
