"""``fingerpad sweep STUDY.toml``: texture dimensions swept on Dask into a Zarr store."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from ..extras import require
from .common import (ADHESION_FIELDS, ADHESION_HELP, DEVICE_HELP, EXIT_INTERRUPTED, device_option, report_interrupt,
                     rich_console, say, stderr_console, user_errors, warnings_to)

_HELP = {
    "--out": "Zarr store of the results (default: the study file's name with .zarr). Rerunning the same sweep "
             "into it computes only the points not done.",
    "--workers": "Worker processes of the local Dask cluster (default: one per core), one thread each.",
    "--scheduler": "Address of an existing Dask scheduler (tcp://HOST:PORT) instead of a local cluster.",
    "--overwrite": "Replace a sweep store that holds another sweep (anything else at --out is never replaced).",
    "--population": "Predict a population of fingers at every point: a preset (adults) or a TOML file with a "
                    "[population] table (docs/population.md); the study file's own [population] table is used "
                    "without it. Stores quantile bands per point (docs/sweeps.md).",
    "--quantiles": "Quantiles of the population bands, comma-separated (default 0.05,0.25,0.5,0.75,0.95; "
                   "0.1, 0.5 and 0.9 are always stored for the design map).",
    "--device": DEVICE_HELP + " The workers of a local cluster inherit it; those of an existing scheduler "
                "use their own FINGERPAD_DEVICE.",
    "--repair": "Mend a damaged store of this sweep: its unreadable chunks are computed again and its "
                "metadata rewritten (a damaged store is refused without it).",
    **{k: v + " Overrides the study file's [finger] value at every point." for k, v in ADHESION_HELP.items()},
}


def sweep_command(
    study: Annotated[str, typer.Argument(metavar="STUDY.toml", help="A predict study file with a [sweep] table.",
                                         show_default=False)],
    out: Annotated[str | None, typer.Option("--out", "-o", metavar="RESULTS.zarr", help=_HELP["--out"])] = None,
    workers: Annotated[str | None, typer.Option("--workers", metavar="N", help=_HELP["--workers"])] = None,
    scheduler: Annotated[str | None, typer.Option("--scheduler", metavar="tcp://HOST:PORT",
                                                  help=_HELP["--scheduler"])] = None,
    overwrite: Annotated[bool, typer.Option("--overwrite", help=_HELP["--overwrite"])] = False,
    repair: Annotated[bool, typer.Option("--repair", help=_HELP["--repair"])] = False,
    population: Annotated[str | None, typer.Option("--population", metavar="NAME|FILE",
                                                   help=_HELP["--population"])] = None,
    quantiles: Annotated[str | None, typer.Option("--quantiles", metavar="Q,Q,...", help=_HELP["--quantiles"])] = None,
    device: Annotated[str | None, typer.Option("--device", metavar="cpu|cupy|torch", help=_HELP["--device"])] = None,
    work_of_adhesion: Annotated[str | None, typer.Option("--work-of-adhesion", metavar="W",
                                                         help=_HELP["--work-of-adhesion"])] = None,
    adhesion_range: Annotated[str | None, typer.Option("--adhesion-range", metavar="RHO",
                                                       help=_HELP["--adhesion-range"])] = None,
    adhesion_law: Annotated[str | None, typer.Option("--adhesion-law", metavar="exponential|maugis",
                                                     help=_HELP["--adhesion-law"])] = None,
) -> None:
    """Sweep texture, material or finger values of a study on Dask; results in a Zarr store.

    The study file is a predict study plus [sweep] (see docs/sweeps.md): a grid of axes
    (lists or START:STOP:COUNT ranges), a Latin hypercube (lhs) or explicit points. Per point:
    critical loads, full-contact load, the cell's state pressures, psi(p), and at the
    exploration loads the contact state, A_re/A_fr, mu, mu_ref and mu/mu_ref. With a population
    (--population or a [population] table), also their quantiles over the fingers, those of the
    critical and full-contact loads, and the probability of each contact state.
    """
    from pathlib import Path

    from ..design.engine import check_workers, eta, run_sweep
    from ..design.store import check_store_path, points_done
    from ..io import check_output_location
    from ..design.spec import read_sweep_file, sweep_from_dict

    with user_errors(), device_option(device):
        require("sweep")  # before any work: the same line as run_sweep's
        err = stderr_console()
        if workers is not None and scheduler is not None:
            raise_error("give --workers (a local cluster) or --scheduler (an existing one), not both")
        n = check_workers(workers)
        with warnings_to(err):
            data = read_sweep_file(study)
            given = {"--work-of-adhesion": work_of_adhesion, "--adhesion-range": adhesion_range,
                     "--adhesion-law": adhesion_law}
            if any(v is not None for v in given.values()):
                from ..finger import finger_param

                for option, value in given.items():
                    if value is not None:  # checked by the finger's declaration, named by the option
                        field = ADHESION_FIELDS[option]
                        data.setdefault("finger", {})[field] = finger_param(field).parse(value, option)
            spec = sweep_from_dict(data, population=population, quantiles=quantiles)
        store = out if out is not None else str(Path(study).with_suffix(".zarr"))
        where = str(check_output_location(store, "--out"))  # before any work; a link is written through
        check_store_path(store, spec, overwrite, repair)  # only a sweep store is ever replaced
        bar = _Progress(err, spec.size,
                        f"sweep: {spec.size} points ({spec.design}: {', '.join(a.name for a in spec.axes)}) into {store}"
                        + (f"; {spec.population_text()} at every point" if spec.population is not None else ""))
        try:
            report = run_sweep(spec, where, workers=n, scheduler=scheduler, overwrite=overwrite, repair=repair,
                               progress=bar, notice=bar.notice)
        except KeyboardInterrupt:
            bar.close()
            done = points_done(where)
            report_interrupt(None if done is None else
                             f"{done} of {spec.size} points kept in {store} (rerun the same command to finish)")
            raise typer.Exit(EXIT_INTERRUPTED) from None
        finally:
            bar.close()
        _summary(err, report, store, eta)
    if report.failures:
        raise typer.Exit(1)


def raise_error(message: str) -> None:
    from ..errors import FingerpadError

    raise FingerpadError(message)


class _Progress:
    """Points done with ETA, cells solved, cache hits and failures, on stderr (plain lines where
    stderr is not a terminal, :class:`~.common.PlainProgress`: a bar there is left frozen in the log)."""

    def __init__(self, console: Any, total: int, headline: str) -> None:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        from .common import PlainProgress

        self.plain = None if console.is_terminal else PlainProgress(console)
        self.total = total
        self.bar = Progress(TextColumn("points"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                            TextColumn("{task.fields[info]}"), console=rich_console(console))
        self.task = self.bar.add_task("sweep", total=total, info="")
        self.headline = headline
        self.started = False
        self.started_headline = False
        self.announced = False

    def __call__(self, report: Any) -> None:
        if not self.started:
            if not self.started_headline:
                self.bar.console.print(self.headline, markup=False)
            if report.damage:
                self.bar.console.print(f"repairing ({report.damage}): {report.repaired} points computed again",
                                       markup=False)
            if report.done_before:
                self.bar.console.print(f"resuming: {report.done_before} points done before", markup=False)
            if self.plain is None:
                self.bar.start()
            self.started = True
        if not self.announced and report.dashboard:
            self.bar.console.print(f"Dask dashboard: {report.dashboard}", markup=False)
            self.announced = True
        info = (f"cells {report.cells_solved} solved, {report.cache_hits} cached; "
                f"{report.invalid} invalid, {len(report.failures)} failed")
        if self.plain is not None:
            self.plain.line(f"points: {report.done_before + report.computed}/{self.total}, {info}")
            return
        self.bar.update(self.task, completed=report.done_before + report.computed, info=info)

    def notice(self, message: str) -> None:
        """A line while the sweep waits (no worker yet on the scheduler)."""
        if not self.started and not self.started_headline:
            self.bar.console.print(self.headline, markup=False)
            self.started_headline = True
        self.bar.console.print(message, markup=False)

    def close(self) -> None:
        if self.started and self.plain is None:
            self.bar.stop()


def _summary(err: Any, report: Any, store: str, eta: Any) -> None:
    if report.damage and not report.computed:
        say(err, f"repaired: {report.damage}")
    if report.done_before == report.points and not report.computed:
        say(err, f"sweep: all {report.points} points of {store} were done before: nothing to compute "
                 f"(fingerpad design-map {store} --x AXIS --y AXIS)")
        return
    minutes = report.seconds / 60
    rate = f"{report.computed / minutes:.3g} points/min, " if minutes > 0 and report.computed else ""
    lines = [
        f"sweep: {report.points} points, {report.done_before} done before, {report.computed} computed now "
        f"in {report.seconds:.1f} s ({rate}{report.workers} worker{'' if report.workers == 1 else 's'})",
        f"cells: {report.cells} distinct, {report.cells_solved} solved, {report.cache_hits} from the cache",
        f"points: {report.invalid} invalid (stored with their reason), {report.unconverged} with unconverged cells",
    ]
    if report.failures:
        lines.append(f"failed chunks: {len(report.failures)} (rerun the same command to retry them): "
                     + "; ".join(report.failures[:3]))
    lines.append(f"results: {store} (fingerpad design-map {store} --x AXIS --y AXIS)")
    for line in lines:
        say(err, line)


def register(app: typer.Typer) -> None:
    app.command("sweep")(sweep_command)
