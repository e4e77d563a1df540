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
    table = Table(title="textures: fingerpad solve|predict --texture NAME --PARAM VALUE ...", show_lines=True)
    table.add_column("texture", no_wrap=True)
    table.add_column("parameter", no_wrap=True)
    table.add_column("unit", no_wrap=True)
    table.add_column("default", no_wrap=True)
    table.add_column("meaning")
    for name, fam in families.items():
        opts, units, defaults, docs = [], [], [], []
        for p in fam.params:
            opts.append(f"{p.option} {p.metavar}")
            units.append(p.unit)
            defaults.append(p.default_text())
            doc = p.doc + (f" ({' | '.join(p.choices)})" if p.choices else "")
            docs.append(doc)
        table.add_row(f"{name}\n{fam.summary}", escape("\n".join(opts)), "\n".join(units), "\n".join(defaults),
                      escape("\n".join(docs)))
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
