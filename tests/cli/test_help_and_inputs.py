"""Help texts keep every bracketed word; study files from Windows editors are read; solve prints
round-off as 0 (issue 20, "Smaller contract breaks", "Fail ... in the user's words")."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _commands():
    group = typer.main.get_command(app)
    return sorted(group.commands)


def _texts(command) -> list[str]:
    texts = [command.help or ""] + [getattr(p, "help", None) or "" for p in command.params]
    return [t.replace("\\[", "[") for t in texts]  # as written (the group escapes them for Rich)


@pytest.mark.parametrize("name", _commands())
def test_no_help_text_loses_a_bracketed_word(name):
    group = typer.main.get_command(app)
    words = sorted({w for t in _texts(group.commands[name]) for w in re.findall(r"\[[^\[\]]*\]", t)})
    res = runner.invoke(app, [name, "--help"], env={"COLUMNS": "400", "TERMINAL_WIDTH": "400"})
    assert res.exit_code == 0, res.output
    flat = re.sub(r"[\s│]+", "", res.stdout)
    missing = [w for w in words if re.sub(r"\s+", "", w) not in flat]
    assert not missing, f"{name} --help lost {missing}"


def test_the_issues_examples_keep_their_words():
    out = runner.invoke(app, ["analyse", "--help"], env={"COLUMNS": "400", "TERMINAL_WIDTH": "400"}).stdout
    assert "[columns]" in out and "[units]" in out and "[files]" in out and "(, , )" not in out
    for name in ("sweep", "design"):
        assert "[sweep]" in runner.invoke(app, [name, "--help"], env={"COLUMNS": "400"}).stdout


def test_a_study_file_with_a_byte_order_mark_is_read(tmp_path):
    text = (EXAMPLES / "study.toml").read_text(encoding="utf-8")
    plain, bom = tmp_path / "plain.toml", tmp_path / "bom.toml"
    plain.write_text(text, encoding="utf-8")
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    runs = [runner.invoke(app, ["predict", str(p), "--model", "hertz", "--loads", "1N", "--json", "-"]) for p in
            (plain, bom)]
    assert all(r.exit_code == 0 for r in runs), [r.output for r in runs]
    import json

    first, second = (json.loads(r.stdout) for r in runs)
    for payload in (first, second):
        payload["inputs"].pop("study_file")
        payload.pop("timings")
        payload["cell"].pop("seconds")
    assert first == second


@pytest.mark.parametrize("data, expect", [
    ("utf-16", "UTF-16"),
    (b"\x00\x01\x02binary", "binary"),
    (b'[texture]\nname = "caps\xe9"\n', "not UTF-8 text (byte 23, line 2"),
])
def test_an_undecodable_study_file_says_what_it_is(data, expect, tmp_path):
    path = tmp_path / "s.toml"
    if data == "utf-16":
        path.write_bytes((EXAMPLES / "study.toml").read_text(encoding="utf-8").encode("utf-16"))
    else:
        path.write_bytes(data)
    res = runner.invoke(app, ["predict", str(path)])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and expect in lines[0] and "save it as UTF-8" in lines[0], lines


def test_solve_prints_round_off_of_the_mean_gap_as_zero():
    from fingerpad.cli.solve import resolved

    res = runner.invoke(app, ["solve", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing",
                              "100um", "--grid", "32", "--pressure", "1MPa", "--pressure", "1kPa"],
                        env={"COLUMNS": "200"})
    assert res.exit_code == 0, res.output
    full = next(line for line in res.stdout.splitlines() if "full" in line)
    assert re.search(r"MPa\s+0 m\s+full", full), full  # the mean-gap column
    assert resolved(-2.01e-23, 1e-13) == 0.0 and resolved(3e-6, 1e-13) == 3e-6
