"""The HTML report of a measurement study: one self-contained page a person reads.

Numbers are shown as a person wants them: E_s in MPa, each estimate with its interval in
brackets, p-values as numbers (``< 0.001`` at the resolution of the test), and plain words
where the data do not determine something. Wide tables scroll inside their own box (with the
first column and the header kept in view), so the page itself never scrolls sideways.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..plotting.measure import condition_label
from .study import StudyResult
from .study import study_info as default_study_info
from .study import study_references
from .breakpoint import format_p

CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0 auto;padding:1em 1.5em;
max-width:1400px;color:#222;line-height:1.4;box-sizing:border-box}
h1{font-size:1.6em;margin:.2em 0 .4em}h2{border-bottom:1px solid #ccc;font-size:1.25em;margin-top:1.6em}
h3{font-size:1.05em;margin:1em 0 .3em}
.facts{font-size:13px;max-width:70em}
.warn{background:#fff4d6;border:1px solid #e0b84f;padding:.5em 1em;font-size:13px;max-width:70em}
.scroll{overflow-x:auto;max-width:100%;border:1px solid #ddd;margin:.5em 0 1.2em;max-height:32em;overflow-y:auto}
table{border-collapse:collapse;font-size:12.5px;font-variant-numeric:tabular-nums}
td,th{border-bottom:1px solid #e4e4e4;padding:3px 8px;text-align:right;white-space:nowrap}
th{background:#f0f0f0;position:sticky;top:0;z-index:1;text-align:center;font-weight:600}
td:first-child,th:first-child{position:sticky;left:0;background:#fafafa;text-align:left;z-index:2}
th:first-child{z-index:3;background:#e8e8e8}
td.text{text-align:left;white-space:normal;min-width:16em;max-width:34em}
tr:nth-child(even) td{background:#fcfcfc}
.no{color:#a33}.muted{color:#777}
img{max-width:100%;height:auto;border:1px solid #ddd;margin:.3em 0}
ul.qc{columns:3 16em;font-size:13px}
"""


def _num(value: Any, digits: int = 3) -> str:
    if value is None or (isinstance(value, (float, np.floating)) and not math.isfinite(value)):
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{value:.{digits}g}"
    return str(value)


def _with_ci(value: Any, lo: Any, hi: Any, scale: float = 1.0, digits: int = 3) -> str:
    """``0.52 [0.48, 0.57]``; empty without a value."""
    def ok(x: Any) -> bool:
        return isinstance(x, (int, float, np.floating, np.integer)) and math.isfinite(float(x))

    if not ok(value):
        return ""
    text = f"{float(value) / scale:.{digits}g}"
    if ok(lo) and ok(hi):
        text += f" [{float(lo) / scale:.{digits}g}, {float(hi) / scale:.{digits}g}]"
    return text


def _get(row: Mapping[str, Any], key: str) -> Any:
    value = row.get(key)
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def _table(header: list[str], rows: list[list[str]], text_columns: tuple[int, ...] = ()) -> str:
    head = "".join(f"<th>{h}</th>" for h in header)
    body = []
    for r in rows:
        cells = "".join(f"<td{' class=text' if j in text_columns else ''}>{c}</td>" for j, c in enumerate(r))
        body.append(f"<tr>{cells}</tr>")
    return f"<div class='scroll'><table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table></div>"


def _esc(text: Any) -> str:
    return html.escape("" if text is None else str(text))


def _modulus_cells(row: Mapping[str, Any], level: float) -> list[str]:
    """E_s (MPa) [accepted set], micro-model, the other model's E_s, the friction-parameter range."""
    e = _get(row, "skin_modulus")
    if e is None:
        return ["", "", "", "", ""]
    interval = _esc(_get(row, "skin_modulus_interval") or "")
    best = f"{e / 1e6:.3g}"
    if not _get(row, "skin_modulus_determined"):
        best = f"<span class='no'>not determined</span> (best {best})"
    other = _get(row, "skin_modulus_other")
    other_text = f"{other / 1e6:.3g} ({_esc(_get(row, 'skin_modulus_other_model'))})" if other else ""
    lo, hi = _get(row, "skin_modulus_sens_low"), _get(row, "skin_modulus_sens_high")
    sens = f"{lo / 1e6:.3g}-{hi / 1e6:.3g}" if lo and hi else ""
    return [best, interval, _esc(_get(row, "skin_modulus_model") or ""), other_text, sens]


def participants_table(result: StudyResult) -> str:
    lv = result.options.level
    header = ["participant", "strokes", "reference k [CI]", "reference n [CI]", "recordings",
              "E<sub>s</sub> (MPa)", f"E<sub>s</sub> {100 * lv:.0f} % set", "micro-model",
              "E<sub>s</sub> other model (MPa)", "E<sub>s</sub> range over friction parameters (MPa)", "note"]
    rows = []
    for row in result.participants.to_dict("records"):
        rows.append([
            _esc(row["participant"]), _num(row.get("n_strokes")),
            _with_ci(row.get("ref_k"), row.get("ref_k_ci_low"), row.get("ref_k_ci_high")),
            _with_ci(row.get("ref_n"), row.get("ref_n_ci_low"), row.get("ref_n_ci_high")),
            _num(row.get("ref_n_recordings")), *_modulus_cells(row, lv),
            _esc(_get(row, "skin_modulus_note") or _get(row, "note") or ""),
        ])
    return _table(header, rows, text_columns=(10,))


def conditions_table(result: StudyResult) -> str:
    lv = result.options.level
    header = ["participant", "sample", "strokes (outliers)", "k [CI]", "n [CI]", "sense ratio +/- [CI]",
              "mu_norm mean", "transition load (N) [CI]", "breakpoint p", "E<sub>s</sub> closed form, Eq. 3.6 (MPa)",
              "E<sub>s</sub> model fit (MPa)", f"E<sub>s</sub> {100 * lv:.0f} % set", "micro-model",
              "E<sub>s</sub> other model (MPa)", "E<sub>s</sub> range over friction parameters (MPa)", "note"]
    rows = []
    for row in result.conditions.to_dict("records"):
        ref = bool(row.get("is_reference"))
        notes_extra: list[str] = []
        if ref:
            transition = "<span class='muted'>reference</span>"
            p = ""
        elif _get(row, "breakpoint_detected"):
            transition = _with_ci(row.get("breakpoint_load"), row.get("breakpoint_ci_low"), row.get("breakpoint_ci_high"))
            p = format_p(float(row["breakpoint_p"]), result.options.n_null)
        elif _get(row, "breakpoint_outside"):
            transition = "none reported: the best change lies at the edge of the load range (see note)"
            p = format_p(float(row["breakpoint_p"]), result.options.n_null)
            notes_extra = [str(row.get("transition") or "")]
        elif _get(row, "breakpoint_p") is not None:
            transition = (f"none detected in {row['breakpoint_search_low']:.2g}-{row['breakpoint_search_high']:.2g} N")
            p = format_p(float(row["breakpoint_p"]), result.options.n_null)
        else:
            transition, p = "", ""
        closed = _with_ci(row.get("skin_modulus_closed_form"), row.get("skin_modulus_closed_form_ci_low"),
                          row.get("skin_modulus_closed_form_ci_high"), scale=1e6)
        notes = [n for n in (*notes_extra, _get(row, "skin_modulus_note"), _get(row, "note")) if n]
        rows.append([
            _esc(row["participant"]), _esc(condition_label(row["sample"], row.get("direction") or "")),
            f"{_num(row.get('n_strokes'))} ({_num(row.get('n_outliers'))})",
            _with_ci(row.get("k"), row.get("k_ci_low"), row.get("k_ci_high")),
            _with_ci(row.get("n"), row.get("n_ci_low"), row.get("n_ci_high")),
            _with_ci(row.get("sense_ratio"), row.get("sense_ratio_ci_low"), row.get("sense_ratio_ci_high")),
            "" if ref else _num(row.get("mu_norm_mean")), transition, p, closed,
            *_modulus_cells(row, lv), _esc("; ".join(notes)),
        ])
    return _table(header, rows, text_columns=(15,))


def population_table(result: StudyResult) -> str:
    pf = result.population_fits
    if pf is None or pf.empty:
        return "<p class='facts'>No population fits (fewer than three participants, or switched off).</p>"
    header = ["sample", "quantity", "participants", "recordings", "k [CI]", "n [CI]", "numbers from",
              "sd between persons: ln k", "sd between persons: n", "sd between recordings (ln)",
              "sd between strokes (ln)", "mixed model: k, n (se)", "two-stage: k, n (se)", "model", "note"]
    rows = []
    for row in pf.to_dict("records"):
        rows.append([
            _esc(condition_label(row["sample"], row.get("direction") or "")), _esc(row["quantity"]),
            _num(row.get("n_participants")), _num(row.get("n_recordings")),
            _with_ci(row.get("k"), row.get("k_ci_low"), row.get("k_ci_high")),
            _with_ci(row.get("n"), row.get("n_ci_low"), row.get("n_ci_high")),
            _esc(row.get("source") if isinstance(row.get("source"), str) else ""),
            _num(row.get("sd_participant_level")), _num(row.get("sd_participant_slope")),
            _num(row.get("sd_recording")), _num(row.get("sd_stroke")),
            _pair(row, "mixed"), _pair(row, "two_stage"),
            _esc(row.get("model") if isinstance(row.get("model"), str) else ""),
            _esc(row.get("note") if isinstance(row.get("note"), str) else ""),
        ])
    return _table(header, rows, text_columns=(6, 13, 14))


def _pair(row: Mapping[str, Any], prefix: str) -> str:
    """``k, n (se of n)`` of one of the two population estimates, for comparison."""
    k, n, se = (_get(row, f"{prefix}_{name}") for name in ("k", "n", "n_se"))
    if k is None or n is None:
        return ""
    return f"{_num(k)}, {_num(n)} ({_num(se)})" if se is not None else f"{_num(k)}, {_num(n)}"


def spread_table_html(result: StudyResult) -> str:
    header = ["sample", "reference", "load bins", "CV raw mu (%)", "CV mu_tex/mu_ref (%)", "reduction (%)"]
    rows = []
    for row in result.spread_summary.to_dict("records"):
        rows.append([
            _esc(condition_label(row["sample"], row.get("direction") or "")), "yes" if row["is_reference"] else "",
            _num(row.get("n_bins")), _num(100 * row["cv_raw"]) if math.isfinite(row["cv_raw"]) else "",
            _num(100 * row["cv_norm"]) if math.isfinite(row["cv_norm"]) else "",
            _num(100 * row["reduction"]) if math.isfinite(row["reduction"]) else "",
        ])
    return _table(header, rows)


def sensitivity_table(result: StudyResult) -> str:
    sens = result.sensitivity
    if sens is None or sens.empty:
        return "<p class='facts'>No sensitivity refits (no texture model, or switched off).</p>"
    sens = sens.assign(key=sens["parameter"] + " " + sens["value"])
    keys = list(dict.fromkeys(sens["key"]))
    header = ["participant", "sample"] + [_esc(k) for k in keys]
    rows = []
    for (participant, sample, direction), g in sens.groupby(["participant", "sample", "direction"], sort=True):
        by = dict(zip(g["key"], g.to_dict("records")))
        cells = []
        for k in keys:
            r = by.get(k)
            if r is None or not math.isfinite(r["skin_modulus"]):
                cells.append("")
            elif not r["determined"]:
                cells.append(f"<span class='no'>n.d.</span> ({r['skin_modulus'] / 1e6:.2g})")
            else:
                cells.append(f"{r['skin_modulus'] / 1e6:.3g} (x{r['ratio']:.2f})")
        rows.append([_esc(participant), _esc(condition_label(sample, direction or ""))] + cells)
    return _table(header, rows)


def _clipped_facts(info: Mapping[str, Any]) -> str:
    n = int(info.get("n_clipped_strokes") or 0)
    if not n:
        return ""
    return (f"; {n} more left out because a force sensor was saturated (clipped) during them "
            f"({len(info.get('clipping') or {})} recordings, see the warnings)")


def html_report(
    result: StudyResult,
    figures: Mapping[str, bytes],
    title: str = "Finger friction study",
    *,
    qc_links: Mapping[str, str] | None = None,
    study_info: Callable[[StudyResult], dict[str, Any]] | None = None,
    qc_sheets: Mapping[str, bytes] | None = None,
) -> str:
    """One self-contained HTML page: study facts, warnings, tables, figures (base64 PNG), the
    QC sheets (``qc_sheets``: title -> PNG, embedded) and links to the per-recording QC
    figures (``qc_links``: recording -> file)."""
    info = (study_info or default_study_info)(result)
    lv = 100 * info["confidence_level"]
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        f"<title>{_esc(title)}</title><style>{CSS}</style></head><body>",
        f"<h1>{_esc(title)}</h1>",
        "<p class='facts'>",
        f"{len(info['participants'])} participants, {len(info['samples'])} samples "
        f"({', '.join(map(_esc, info['samples']))}), reference <b>{_esc(info['reference_sample'])}</b>; "
        f"{info['n_files']} recordings, {info['n_strokes']} strokes, {info['n_outliers']} flagged as outliers "
        f"(robust |z| &gt; {info['outlier_z']}){_clipped_facts(info)}. Friction per stroke: mean |F<sub>t</sub>|/F<sub>n</sub> over the "
        f"steady part ({100 * info['stroke_trim']:.0f} % trimmed at each end). Power law mu = k F<sup>n-1</sup> "
        f"(k = mu at 1 N); normalised friction mu<sub>tex</sub>/mu<sub>ref</sub> with the participant's fitted "
        f"reference curve. Intervals at {lv:.0f} % treat the strokes of one recording as one cluster "
        f"(random intercept per recording; Student t with recordings minus one degrees of freedom for levels). "
        f"Loads in N, E<sub>s</sub> in MPa. fingerpad {__version__}.</p>",
    ]
    if result.warnings:
        items = "".join(f"<li>{_esc(w)}</li>" for w in result.warnings)
        parts.append(f"<div class='warn'><b>Check the data:</b><ul>{items}</ul></div>")
    parts += [
        "<h2>Skin micro-modulus per participant</h2>",
        "<p class='facts'>E<sub>s</sub> fitted with the micro-model named, jointly to all textures: the "
        f"best value and the {lv:.0f} % set of E<sub>s</sub> the data allow (it may be several ranges; one that "
        "reaches the search range means the data do not determine E<sub>s</sub>). The fit rests on the level of "
        "mu/mu<sub>ref</sub>, hence on the assumed friction parameters: the last columns refit it with the "
        "other micro-model and with tau0, alpha, beta (x0.5, x2) and the ridge fraction (0.3, 0.7).</p>",
        participants_table(result),
        "<h2>Summary per participant and sample</h2>",
        "<p class='facts'>Transition: a change of trend of mu<sub>tex</sub>/mu<sub>ref</sub> is reported only "
        f"when the sup-likelihood-ratio test (which accounts for searching its location; {result.options.n_null} "
        "simulations of a straight line with the recordings' scatter) gives p &lt; "
        f"{1 - info['confidence_level']:.2g} and its location leaves at least "
        f"{100 * result.options.breakpoint_edge:.0f} % of the load range (log scale) and of the strokes on each side "
        "(nearer the edge one segment rests on a few strokes, and any curvature passes for a break); "
        "the closed-form E<sub>s</sub> (Eq. 3.6) is given beside the model "
        "fit only then. Sense ratio: mu sliding + over mu sliding -, at equal load.</p>",
        conditions_table(result),
        "<h2>Population per sample</h2>",
        "<p class='facts'>Power law across participants, two ways: a mixed-effects model (random level and "
        "exponent per participant, variance component per recording) and a two-stage estimate (each "
        "participant's own power law, then the mean and spread of ln k and n over participants). The numbers "
        "come from the mixed model where its variance components are estimable (converged, positive-definite "
        "covariance, invertible Hessian), else from the two-stage estimate: 'numbers from' says which, and the "
        "two are shown side by side. Intervals with participants minus one degrees of freedom. The "
        "sample figures show the mean curve over participants with its between-person interval.</p>",
        population_table(result),
        "<h2>Spread between participants</h2>",
        "<p class='facts'>Mean coefficient of variation across load bins; reduction = 1 - CV_norm / CV_raw.</p>",
        spread_table_html(result),
        "<h2>Sensitivity of E<sub>s</sub> (MPa; ratio to the main fit)</h2>",
        sensitivity_table(result),
        "<h2>Figures</h2>",
    ]
    for name, png in figures.items():
        data = base64.b64encode(png).decode("ascii")
        parts.append(f"<h3>{_esc(name)}</h3><img alt='{_esc(name)}' src='data:image/png;base64,{data}'>")
    if qc_sheets:
        parts.append("<h2>Recordings: stroke detection (QC sheets)</h2><p class='facts'>Every recording's "
                     "normal force (black) and friction force (green) against time, one panel per recording, a "
                     "row per sample: strokes shaded by sense (steady window darker), outliers outlined in red, "
                     "dropped strokes hatched grey, strokes with a saturated sensor cross-hatched magenta, the "
                     "lift-off threshold dotted red.</p>")
        for name, png in qc_sheets.items():
            data = base64.b64encode(png).decode("ascii")
            parts.append(f"<h3>{_esc(name)}</h3><img alt='{_esc(name)}' src='data:image/png;base64,{data}'>")
    if qc_links:
        parts.append("<h2>Recordings: stroke detection (QC figures)</h2><p class='facts'>Forces and position "
                     "against time with every stroke shaded (steady window darker, outliers outlined in red, "
                     "dropped strokes hatched), and mu against stroke number.</p><ul class='qc'>")
        for label, link in qc_links.items():
            parts.append(f"<li><a href='{_esc(link)}'>{_esc(Path(label).name)}</a></li>")
        parts.append("</ul>")
    parts.append(references_html(study_references(result)))
    parts.append("</body></html>")
    return "\n".join(parts)


def references_html(keys: Any) -> str:
    """The report's last section: the publications of the methods the analysis used, each with
    what it is used for (:mod:`fingerpad.references`)."""
    from ..references import citation, ordered

    items = "".join(f"<li>{_esc(citation(ref))} <span class='facts'>({_esc(ref.used_for)})</span></li>"
                    for ref in ordered(keys))
    return ("<h2>References</h2><p class='facts'>The publications of the methods this analysis used "
            "(<code>fingerpad cite --bibtex</code> gives BibTeX of the package and the thesis).</p>"
            f"<ol class='references'>{items}</ol>")
