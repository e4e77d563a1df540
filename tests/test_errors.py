"""Messages for users: one line, control characters shown escaped, never megabytes long
(issue 30, items 12, 13 and 17)."""

from __future__ import annotations

from fingerpad.errors import MAX_LINE, one_line, printable


def test_control_characters_are_shown_escaped():
    assert printable("P01\x1b[2J\x07\u202e\tx") == "P01\\x1b[2J\\x07\\u202e\\tx"
    assert printable("µm, 0.3 MPa, Ø, ψ(p)") == "µm, 0.3 MPa, Ø, ψ(p)"  # printable text is left as it is
    assert printable("a\nb") == "a\nb"
    assert one_line("bad label 'x\x1b[31m'\n  second line") == "bad label 'x\\x1b[31m' second line"


def test_a_long_message_keeps_its_ends():
    value = "9" * 5000
    line = one_line(f"--grid: expected an integer, got '{value}' (the end says why)")
    assert len(line) < MAX_LINE + 60
    assert line.startswith("--grid: expected an integer, got '999") and line.endswith("(the end says why)")
    assert "characters left out" in line
    assert one_line("x" * MAX_LINE) == "x" * MAX_LINE
