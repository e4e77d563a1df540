"""What a sweep computes, in which tasks and in which order: its plan, apart from any executor.

A sweep's store is cut into chunks (:func:`~.store.chunk_slices`); the points of a chunk not yet
done are computed by one task. Points that share a unit cell (the same texture shape and
numerics: :func:`~.evaluate.cell_key`) read it from the on-disk cache, and the cell is solved once
per sweep by a task of its own, for its first point, over what every point that shares it asks
for (in the order of their indices, done points included): every point then reads the cell as it
is in the end, whatever order the chunks run in, and a resumed sweep stores what a sweep run at
once would. So the plan holds

* the cell tasks, one per distinct cell, in the order their first points come (chunks in store
  order, points in index order within a chunk);
* the chunk tasks, each with the cells it waits for; a chunk whose every point is its cell's
  first point needs no task: it is written from those cells' results (``from_cells``).

:func:`plan_sweep` builds it from the study alone (no cluster, no store): it can be tested and
timed on its own, and any executor (:mod:`.executor`) runs it.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .evaluate import cell_key
from .spec import SweepSpec
from .store import chunk_slices

__all__ = ["CellTask", "ChunkTask", "SweepPlan", "plan_sweep"]

#: A point: its index in the sweep's grid and its study data.
Point = tuple[tuple[int, ...], dict[str, Any]]


@dataclass(frozen=True)
class CellTask:
    """The task that solves one unit cell by predicting its first point.

    Attributes
    ----------
    key
        The cell's key (:func:`~.evaluate.cell_key`).
    index, data
        The first point that uses it (its index and study data); the task returns that point's
        result, which its chunk then takes as it is.
    sharing
        The study data of every point of the sweep that uses the cell, done ones included, in
        the order of their indices: the cell is prepared for all of them before any is predicted.
    """

    key: str
    index: tuple[int, ...]
    data: dict[str, Any]
    sharing: tuple[dict[str, Any], ...]

    @property
    def name(self) -> str:
        """The task's name (an executor's key): ``cell-`` and the key's first 16 characters."""
        return f"cell-{self.key[:16]}"


@dataclass(frozen=True)
class ChunkTask:
    """One chunk of the store to compute.

    Attributes
    ----------
    region
        The chunk's slices, one per dimension of the sweep.
    items
        Its points not yet done, in index order.
    cells
        The keys of the cells its points use (sorted): the cell tasks it waits for.
    from_cells
        Every point is the first point of its cell: the chunk needs no task of its own and is
        written from those cells' results as they come in.
    """

    region: tuple[slice, ...]
    items: tuple[Point, ...]
    cells: tuple[str, ...]
    from_cells: bool

    @property
    def label(self) -> str:
        """``[i:j, k:l]``: the chunk as failures and logs name it."""
        return "[" + ", ".join(f"{s.start}:{s.stop}" for s in self.region) + "]"


@dataclass
class SweepPlan:
    """The tasks of a sweep (see the module doc); :func:`plan_sweep` makes it.

    Attributes
    ----------
    cells
        Cell key -> :class:`CellTask`, in submission order.
    chunks
        The chunks with points left to compute, in store order.
    points, done_before
        Points of the sweep, and those already done before it ran.
    """

    cells: dict[str, CellTask] = field(default_factory=dict)
    chunks: list[ChunkTask] = field(default_factory=list)
    points: int = 0
    done_before: int = 0

    @property
    def to_compute(self) -> int:
        """Points the plan computes."""
        return sum(len(c.items) for c in self.chunks)

    def chunk_tasks(self) -> Iterator[tuple[int, ChunkTask]]:
        """The chunks that need a task of their own, with their numbers (positions in ``chunks``)."""
        return ((n, c) for n, c in enumerate(self.chunks) if not c.from_cells)

    def written_from_cells(self) -> dict[str, list[int]]:
        """Cell key -> the numbers of the chunks written from cell results that wait for it."""
        waiting: dict[str, list[int]] = {}
        for n, chunk in enumerate(self.chunks):
            if chunk.from_cells:
                for key in chunk.cells:
                    waiting.setdefault(key, []).append(n)
        return waiting

    def first_points(self) -> dict[tuple[int, ...], str]:
        """Index of each cell's first point -> the cell's key."""
        return {task.index: key for key, task in self.cells.items()}


def plan_sweep(spec: SweepSpec, done: np.ndarray | None = None) -> SweepPlan:
    """The plan of ``spec``'s points not ``done`` (a boolean array of the sweep's shape; ``None``:
    none done). Builds every point's study data and cell key, nothing more: no cell is solved,
    nothing is read or written."""
    done = np.zeros(spec.shape, bool) if done is None else np.asarray(done, bool)
    plan = SweepPlan(points=spec.size, done_before=int(done.sum()))
    todo = [region for region in chunk_slices(spec.shape, spec.chunk) if not done[region].all()]
    first_of: dict[str, Point] = {}
    keyed: dict[str, list[Point]] = {}
    raw: list[tuple[tuple[slice, ...], list[Point], set[str]]] = []
    for region in todo:
        items: list[Point] = []
        keys: set[str] = set()
        for offset in np.ndindex(*(s.stop - s.start for s in region)):
            idx = tuple(i + s.start for i, s in zip(offset, region, strict=True))
            if done[idx]:
                continue
            data = spec.study_data(spec.assignment(idx))
            key = cell_key(data)
            if key is not None:
                keys.add(key)
                first_of.setdefault(key, (idx, data))
                keyed.setdefault(key, []).append((idx, data))
            items.append((idx, data))
        raw.append((region, items, keys))
    sharing = _sharing(spec, keyed, done)
    plan.cells = {key: CellTask(key, idx, data, tuple(sharing[key])) for key, (idx, data) in first_of.items()}
    firsts = {idx for idx, _ in first_of.values()}
    plan.chunks = [ChunkTask(region, tuple(items), tuple(sorted(keys)),
                             bool(items) and all(idx in firsts for idx, _ in items))
                   for region, items, keys in raw]
    return plan


def _sharing(spec: SweepSpec, keyed: dict[str, list[Point]], done: np.ndarray) -> dict[str, list[dict[str, Any]]]:
    """The study data of the points that share each cell to compute (``keyed``: the points left
    to compute, by cell), in the order of their indices, with the points of those cells already
    done: a resumed sweep prepares each curve over the same points as a sweep run at once."""
    found = {key: list(items) for key, items in keyed.items()}
    for idx in zip(*np.nonzero(done), strict=True):
        index = tuple(int(i) for i in idx)
        data = spec.study_data(spec.assignment(index))
        key = cell_key(data)
        if key in found:
            found[key].append((index, data))
    return {key: [data for _, data in sorted(items, key=lambda t: t[0])] for key, items in found.items()}
