"""``fingerpad textures``: the texture families, their parameters with units and meanings."""

from __future__ import annotations

import typer

from .common import say_wrapped, stdout_console, user_errors


def textures_command() -> None:
    """List the texture families and their parameters (give them as --NAME VALUE)."""
    from rich.markup import escape
    from rich.table import Table

    from ..textures import registry

    with user_errors():
        families = registry()
    # one row per parameter (a family's rows closed by a line): a parameter's meaning, wrapped
    # over several lines, stays beside that parameter; cells of many lines drifted apart
    table = Table(title="textures: fingerpad solve|predict --texture NAME --PARAM VALUE ...")
    table.add_column("texture", max_width=28)
    table.add_column("parameter", no_wrap=True)
    table.add_column("unit", no_wrap=True)
    table.add_column("default", no_wrap=True)
    table.add_column("meaning")
    for name, fam in families.items():
        for i, p in enumerate(fam.params):
            doc = p.doc + (f" ({' | '.join(p.choices)})" if p.choices else "")
            table.add_row(f"{name}\n{fam.summary}" if i == 0 else "", escape(f"{p.option} {p.metavar}"), p.unit,
                          p.default_text(), escape(doc), end_section=i == len(fam.params) - 1)
    console = stdout_console(140)
    if console.width >= 120:
        console.print(table)
    else:  # a narrow terminal: one block per family, one line per parameter
        for name, fam in families.items():
            say_wrapped(console, f"{name}: {fam.summary}")
            for p in fam.params:
                default = p.default_text()
                unit = f" [{p.unit}]" if p.unit else ""
                choices = f" ({' | '.join(p.choices)})" if p.choices else ""
                say_wrapped(console, f"  {p.option} {p.metavar}{unit}, {default}: {p.doc}{choices}")
    say_wrapped(console, "Lengths take unit suffixes (50um, 0.2mm) or metres; angles are in degrees unless suffixed "
                 "(30deg, 0.5rad); the grid is given as --grid N.")


def register(app: typer.Typer) -> None:
    app.command("textures")(textures_command)
