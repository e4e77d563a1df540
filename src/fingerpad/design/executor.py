"""Who runs a sweep's tasks: a small interface, with Dask distributed as its implementation.

A sweep's plan (:mod:`.plan`) says which tasks there are and what each waits for; an executor
runs them. The engine (:func:`~.engine.execute_plan`) needs four things of it, in the manner of
xarray's chunk managers: send a value to every worker once (:meth:`Executor.broadcast`), submit a
function with the results of earlier tasks as its first argument (:meth:`Executor.submit`), hand
back tasks as they finish (:meth:`Executor.as_completed`), and close. Two implementations:

* :class:`DaskExecutor`: a Dask distributed client (a LocalCluster the sweep started, or an
  existing scheduler), the one ``fingerpad sweep`` uses;
* :class:`InProcessExecutor`: the tasks run in this process when their results are asked for,
  in submission order or any order their dependencies allow (``order``): to test a plan and the
  engine without a cluster, and to time them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

__all__ = ["DaskExecutor", "Done", "Executor", "InProcessExecutor"]


@dataclass
class Done:
    """A finished task: its handle, and its result or the exception it raised."""

    handle: Any
    result: Any = None
    error: BaseException | None = None


class Executor(Protocol):
    """What the sweep engine asks of an executor (see the module doc)."""

    #: Workers running tasks (0 where unknown).
    workers: int
    #: A page showing the tasks, or ``None``.
    dashboard: str | None

    def broadcast(self, value: Any) -> Any:
        """``value`` sent to every worker once; what is returned is passed to tasks in its stead."""

    def submit(self, fn: Callable[..., Any], *args: Any, after: Sequence[Any] | None = None,
               name: str | None = None) -> Any:
        """Run ``fn(*args)``, or with ``after`` (handles of earlier tasks) ``fn(results, *args)``
        once they finished, ``results`` their results in that order; returns a handle."""

    def as_completed(self, handles: Iterable[Any]) -> Iterator[Done]:
        """The tasks of ``handles`` as they finish."""

    def close(self) -> None:
        """Release the workers (and stop a cluster this executor started)."""


@dataclass
class _Task:
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    after: tuple[_Task, ...] | None
    name: str
    done: Done | None = None


@dataclass
class InProcessExecutor:
    """Tasks run in this process, one at a time, when :meth:`as_completed` asks for them.

    ``order(ready)`` picks the next task among those whose dependencies are done (default: the
    first submitted); a task whose dependency failed fails with that dependency's exception, as a
    Dask task does. ``ran`` lists the tasks' names in the order they ran.
    """

    order: Callable[[list[Any]], Any] | None = None
    workers: int = 1
    dashboard: str | None = None
    ran: list[str] = field(default_factory=list)
    submitted: int = 0

    def broadcast(self, value: Any) -> Any:
        return value

    def submit(self, fn: Callable[..., Any], *args: Any, after: Sequence[Any] | None = None,
               name: str | None = None) -> Any:
        self.submitted += 1
        return _Task(fn, args, None if after is None else tuple(after), name or f"task-{self.submitted}")

    def as_completed(self, handles: Iterable[Any]) -> Iterator[Done]:
        pending = list(handles)
        while pending:
            ready = [t for t in pending if all(d.done is not None for d in (t.after or ()))]
            if not ready:  # each waits on a task not asked for here: run one of those first
                self._run(next(d for t in pending for d in (t.after or ()) if d.done is None))
                continue
            task = self.order(ready) if self.order is not None else ready[0]
            self._run(task)
            pending.remove(task)
            yield task.done  # type: ignore[misc]

    def _run(self, task: _Task) -> None:
        if task.done is not None:
            return
        self.ran.append(task.name)
        deps = [d.done for d in (task.after or ())]
        failed = next((d.error for d in deps if d is not None and d.error is not None), None)
        if failed is not None:
            task.done = Done(task, error=failed)
            return
        try:
            args = task.args if task.after is None else ([d.result for d in deps if d is not None], *task.args)
            task.done = Done(task, result=task.fn(*args))
        except Exception as exc:  # noqa: BLE001 - a task's failure is its result, as on a cluster
            task.done = Done(task, error=exc)

    def close(self) -> None:
        pass


class DaskExecutor:
    """Tasks run by a Dask distributed ``client`` (and a ``cluster`` it owns, closed with it).

    Tasks are submitted impure (each runs once, even with equal arguments); a task's dependencies
    are its first argument, a list of futures, which Dask replaces by their results on the worker.
    """

    def __init__(self, client: Any, cluster: Any = None) -> None:
        self.client = client
        self.cluster = cluster

    @property
    def workers(self) -> int:
        return len(self.client.scheduler_info().get("workers", {}))

    @property
    def dashboard(self) -> str | None:
        return getattr(self.client, "dashboard_link", None)

    def broadcast(self, value: Any) -> Any:
        return self.client.scatter([value], broadcast=True)[0]  # a list: a dict would be scattered by keys

    def submit(self, fn: Callable[..., Any], *args: Any, after: Sequence[Any] | None = None,
               name: str | None = None) -> Any:
        extra = {} if name is None else {"key": name}
        if after is None:
            return self.client.submit(fn, *args, pure=False, **extra)
        return self.client.submit(fn, list(after), *args, pure=False, **extra)

    def as_completed(self, handles: Iterable[Any]) -> Iterator[Done]:
        from distributed import as_completed

        given = {future.key: future for future in handles}  # each handed back as it was given
        for future in as_completed(list(given.values()), loop=self.client.loop):
            if future.status == "finished":
                yield Done(given[future.key], result=future.result())
            else:
                yield Done(given[future.key], error=future.exception())

    def close(self) -> None:
        _close_quietly(self.client)
        if self.cluster is not None:
            self.cluster.close()


def _close_quietly(client: Any) -> None:
    """Close a Client whose constructor failed, so that its ``__del__`` has nothing left to do."""
    import contextlib

    with contextlib.suppress(Exception):
        client.close(timeout=2)
    with contextlib.suppress(Exception):
        client.status = "closed"
