"""Write the outputs of ``springcad fit``: ``fit.json``, a readable report and PNG plots.

Plots (matplotlib, Agg backend, imported here only):

* ``torque_deflection.png``: measured torque against deflection with the
  linear, deadband, logit and final loop models;
* ``crossover.png``: the same around zero torque (as the paper's Fig. 6);
* ``residual_step_<k>_<effect>.png``: the residual against deflection and
  against time before and after each step of the loop;
* ``energy_by_cycle.png``: energy loss of each loading–unloading cycle.

The report is Markdown (``report.md``) or HTML (``report.html``), built from the
same blocks. Units: N·m, rad, s.
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path

import numpy as np

from springcad.fit.analysis import FitResult
from springcad.fit.loop import State

#: at most this many points are drawn per scatter (evenly decimated)
_MAX_POINTS = 6000


def write_fit_outputs(result: FitResult, out_dir: Path | str, fmt: str = "md",
                      plots: bool = True) -> list[Path]:
    """Write ``fit.json``, the report and the plots into ``out_dir``.

    Args:
        result: the fit result.
        out_dir: an existing, empty folder (use ``atomic_output_dir``).
        fmt: ``"md"`` or ``"html"``.
        plots: draw the PNG plots.

    Returns:
        The files written.
    """
    if fmt not in ("md", "html"):
        raise ValueError(f"report format {fmt!r} is not 'md' or 'html'")
    from springcad.report.jsonio import write_json

    out_dir = Path(out_dir)
    written = [out_dir / "fit.json"]
    write_json(written[0], result.to_dict())
    data = json.loads(written[0].read_text(encoding="utf-8"))  # exactly what the file says
    images = _plot_all(result, out_dir) if plots else {}
    written += list(images.values())
    blocks = report_blocks(result, data, {k: p.name for k, p in images.items()})
    report = out_dir / f"report.{fmt}"
    report.write_text(render_markdown(blocks) if fmt == "md" else render_html(blocks),
                      encoding="utf-8")
    written.append(report)
    return written


# --- report text ---------------------------------------------------------------

def _f(v, digits=4) -> str:
    if v is None:
        return "n/a"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return str(v)
    return f"{v:.{digits}g}"


def report_blocks(result: FitResult, data: dict, images: dict[str, str]) -> list[tuple]:
    """The report as blocks: ``("h1"|"h2"|"p", text)``, ``("ul", items)``,
    ``("table", header, rows)``, ``("img", file, alt)``."""
    b: list[tuple] = []
    final = data["final"]
    b.append(("h1", f"Bench fit: {data['input']['source']}"))
    verdict = ("Structure remains in the residual that no effect of the library explains "
               "(see *Unexplained structure*)." if final["unexplained"] else
               "The final residual is consistent with white noise.")
    b.append(("p", f"Baseline `{data['baseline']['model']}` NRMSE {_f(data['baseline']['nrmse_pct'])} % "
                   f"→ final `{final['model']}` NRMSE {_f(final['nrmse_pct'])} % "
                   f"(noise floor {_f(final['noise_floor_nrmse_pct'])} %). {verdict}"))
    inp, seg = data["input"], data["segmentation"]
    b.append(("h2", "Data"))
    b.append(("table", ["quantity", "value"], [
        ["samples", _f(inp["n_samples"])], ["duration (s)", _f(inp["duration_s"])],
        ["sample rate (Hz)", _f(inp["sample_rate_hz"])],
        ["loading–unloading cycles", _f(seg["n_cycles"])],
        ["cycle amplitudes (rad)", ", ".join(_f(a, 3) for a in seg["cycle_amplitudes_rad"])],
        ["half torque range (N·m, NRMSE normaliser)", _f(inp["torque_half_range_Nm"])],
        ["residual noise level (N·m)", _f(final["noise_Nm"])],
        ["encoder channel", _f(inp["has_encoder"])]]))
    if data["warnings"]:
        b.append(("p", "Warnings:"))
        b.append(("ul", data["warnings"]))

    b.append(("h2", "Paper models (Section II-B)"))
    rows = []
    for name, m in data["paper_models"].items():
        rows.append([name, _f(m["stiffness_Nm_per_rad"]), _f(m["backlash_rad"]),
                     _f(m.get("transition_rad")), _f(m["rmse_Nm"]), _f(m["nrmse_pct"]),
                     _f(m.get("stiffness_error_pct"))])
    b.append(("table", ["model", "K (N·m/rad)", "backlash b (rad)", "transition l (rad)",
                        "RMSE (N·m)", "NRMSE (%)", "stiffness error (%)"], rows))
    b.append(("p", "Deadband fitted as in the paper (backlash centred on zero, one K, least "
                   "absolute error); logit K, h and l fitted together from it. NRMSE is the RMSE "
                   "over half the measured torque range (Table I)."))
    text = (f"Energy loss at the largest amplitude: {_f(data['energy_loss_pct'])} % "
            "(loop area over energy stored on loading, from the measured data).")
    if data.get("energy_loss_corrected_pct") is not None:
        text += (f" With the measurement effects found by the loop removed "
                 f"({', '.join(data['energy_loss_corrections'])}): "
                 f"{_f(data['energy_loss_corrected_pct'])} %.")
    b.append(("p", text))
    b.append(("table", ["cycle", "amplitude (rad)", "stored (J)", "returned (J)", "loss (%)"],
              [[str(i + 1), _f(c["sign"] * c["amplitude_rad"], 3), _f(c["stored_J"]),
                _f(c["returned_J"]), _f(c["loss_pct"], 3)]
               for i, c in enumerate(data["energy_by_cycle"])]))
    for key, alt in (("torque_deflection", "torque against deflection with each model"),
                     ("crossover", "crossover region"), ("energy", "energy loss per cycle")):
        if key in images:
            b.append(("img", images[key], alt))

    b.append(("h2", "Residual loop"))
    b.append(("p", "From `τ = K·θ`, each round tests every effect of the library: its detector "
                   "looks for the effect's signature in the residual (score test, z), then the "
                   "model with the effect is fitted on half of the cycles and scored on the "
                   "others (and vice versa). An effect is added when the held-out criterion "
                   f"N·ln(SSE/N) + k·ln(N) drops by more than {_f(data['loop_settings']['gain_threshold'])}."))
    if data["steps"]:
        rows = []
        for i, s in enumerate(data["steps"]):
            ev = s["evidence"]
            gain = ev.get("heldout_gain", ev.get("heldout_loss_when_removed"))
            z = (ev.get("detector") or {}).get("value")
            rows.append([str(i + 1), s["action"], s["effect"], _f(z, 3), _f(gain, 4),
                         _f(s["nrmse_before_pct"]), _f(s["nrmse_after_pct"])])
        b.append(("table", ["step", "action", "effect", "detector", "held-out gain",
                            "NRMSE before (%)", "NRMSE after (%)"], rows))
        for i, s in enumerate(data["steps"]):
            b.append(("p", f"**Step {i + 1}: {s['action']} `{s['effect']}`.** "
                           f"{_sentence(s['evidence'].get('meaning', ''))} "
                           + ("Parameters right after this step (later steps refit them): " + ", ".join(f"{k} = {_f(v)}" for k, v in s["params"].items())
                              if s["params"] else "")))
            if f"step{i}" in images:
                b.append(("img", images[f"step{i}"], f"residual before and after step {i + 1}"))
    else:
        b.append(("p", "No effect was added: the linear model leaves nothing any effect explains "
                       "better on held-out cycles."))
        if "step_none" in images:
            b.append(("img", images["step_none"], "residual of the linear model"))
    if data["last_round_candidates"]:
        b.append(("p", "Candidates in the last round (none cleared the threshold):"))
        b.append(("table", ["effect", "detector", "fitted", "held-out gain"],
                  [[c["effect"], _f(c["detector"], 3), _f(c["fitted"]), _f(c["heldout_gain"])]
                   for c in data["last_round_candidates"]]))

    b.append(("h2", "Final model"))
    b.append(("p", f"`{final['model']}`, NRMSE {_f(final['nrmse_pct'])} %, RMSE {_f(final['rmse_Nm'])} N·m."))
    b.append(("table", ["parameter", "value"], [[k, _f(v, 5)] for k, v in final["params"].items()]))
    b.append(("h2", "Unexplained structure"))
    ev = final["unexplained_evidence"]
    rows = [[name, _f(t["p_value"], 3), _f(t["structure_rms_over_noise"], 3),
             _f(t["largest_bin_mean_Nm"], 3), _f(t["significant"])]
            for name, t in ev["tests"].items()]
    b.append(("p", ("**Unexplained**: " if final["unexplained"] else "None found: ")
              + f"residual RMS is {_f(ev['residual_rms_over_noise'], 3)} × the noise level "
                f"({_f(ev['noise_Nm'])} N·m); binned residual means:"))
    b.append(("table", ["bins", "p-value", "structure RMS / noise", "largest bin mean (N·m)",
                        "significant"], rows))

    comp = data.get("design_comparison")
    target = data.get("target_stiffness_Nm_per_rad")
    if comp or target:
        b.append(("h2", "Comparison with the design"))
    if target and data.get("stiffness_error_pct"):
        err = data["stiffness_error_pct"]
        b.append(("p", f"Target stiffness {_f(target)} N·m/rad: deadband K is off by "
                       f"{_f(err['deadband'], 3)} %, final loop K by {_f(err['final'], 3)} %."))
    if comp:
        for label, c in (("deadband (paper method)", comp), ("residual loop", comp.get("residual_loop"))):
            if not c:
                continue
            st = c["stiffness"]
            b.append(("p", f"**{label}**: K = {_f(c['measured']['stiffness_Nm_per_rad'])} N·m/rad, "
                           f"b = {_f(c['measured']['backlash_rad'])} rad."))
            b.append(("table", ["reference", "K (N·m/rad)", "fitted error (%)"], [
                ["target", _f(st["target_Nm_per_rad"]), _f(st["error_vs_target_pct"], 3)],
                ["beam theory", _f(st["beam_Nm_per_rad"]), _f(st["error_vs_beam_pct"], 3)],
                ["FEA", _f(st["fea_Nm_per_rad"]), _f(st["error_vs_fea_pct"], 3)]]))
            bl = c["backlash"]
            b.append(("table", ["backlash range", "min (rad)", "max (rad)", "measurement inside"],
                      [[k, _f(r["min_rad"]), _f(r["max_rad"]), _f(r["inside"])]
                       for k, r in bl["ranges"].items()]))
            b.append(("p", bl["statement"].capitalize() + "."))
    return b


def render_markdown(blocks: list[tuple]) -> str:
    """Report blocks as Markdown text."""
    out = []
    for blk in blocks:
        kind = blk[0]
        if kind in ("h1", "h2", "h3"):
            out.append("#" * int(kind[1]) + " " + blk[1])
        elif kind == "p":
            out.append(blk[1])
        elif kind == "ul":
            out.append("\n".join(f"- {item}" for item in blk[1]))
        elif kind == "table":
            header, rows = blk[1], blk[2]
            lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            lines += ["| " + " | ".join(r) + " |" for r in rows]
            out.append("\n".join(lines))
        elif kind == "img":
            out.append(f"![{blk[2]}]({blk[1]})")
    return "\n\n".join(out) + "\n"


def render_html(blocks: list[tuple]) -> str:
    """Report blocks as a self-contained HTML page (images by relative file name)."""
    import re

    def inline(text):
        text = html.escape(text)
        text = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", text)
        text = re.sub(r"\*(.+?)\*", r"<i>\1</i>", text)
        return re.sub(r"`(.+?)`", r"<code>\1</code>", text)

    out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'><title>springcad fit</title>",
           "<style>body{font-family:sans-serif;max-width:60em;margin:auto}"
           "table{border-collapse:collapse}td,th{border:1px solid #aaa;padding:2px 6px}"
           "img{max-width:100%}</style></head><body>"]
    for blk in blocks:
        kind = blk[0]
        if kind in ("h1", "h2", "h3"):
            out.append(f"<{kind}>{inline(blk[1])}</{kind}>")
        elif kind == "p":
            out.append(f"<p>{inline(blk[1])}</p>")
        elif kind == "ul":
            out.append("<ul>" + "".join(f"<li>{inline(i)}</li>" for i in blk[1]) + "</ul>")
        elif kind == "table":
            head = "".join(f"<th>{inline(h)}</th>" for h in blk[1])
            body = "".join("<tr>" + "".join(f"<td>{inline(c)}</td>" for c in r) + "</tr>"
                           for r in blk[2])
            out.append(f"<table><tr>{head}</tr>{body}</table>")
        elif kind == "img":
            out.append(f"<p><img src='{html.escape(blk[1])}' alt='{html.escape(blk[2])}'></p>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


# --- plots ---------------------------------------------------------------------

def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _every(n: int) -> slice:
    return slice(None, None, max(1, math.ceil(n / _MAX_POINTS)))


def _plot_all(result: FitResult, out_dir: Path) -> dict[str, Path]:
    plt = _pyplot()
    images = {}
    try:
        images["torque_deflection"] = _plot_models(plt, result, out_dir / "torque_deflection.png",
                                                   zoom=False)
        images["crossover"] = _plot_models(plt, result, out_dir / "crossover.png", zoom=True)
        images["energy"] = _plot_energy(plt, result, out_dir / "energy_by_cycle.png")
        steps = result.loop.steps
        if steps:
            for i, s in enumerate(steps):
                images[f"step{i}"] = _plot_residuals(
                    plt, result, s.before, s.after,
                    out_dir / f"residual_step_{i + 1}_{s.effect}.png",
                    f"step {i + 1}: {s.action} {s.effect}")
        else:
            images["step_none"] = _plot_residuals(plt, result, result.loop.baseline, None,
                                                  out_dir / "residual_linear.png",
                                                  "linear model (no effect added)")
    finally:
        plt.close("all")
    return images


def _plot_models(plt, result: FitResult, path: Path, zoom: bool) -> Path:
    sig, rec = result.signals, result.record
    th, tq = rec.deflection_rad, rec.torque_Nm
    final = result.loop.final
    pred_final = final.model.predict(final.x, sig, np.arange(sig.n))
    fig, ax = plt.subplots(figsize=(7, 5))
    sel = _every(th.size)
    ax.plot(th[sel], tq[sel], ".", ms=1.5, color="0.6", label="measured", rasterized=True)
    grid = np.linspace(th.min(), th.max(), 2001)
    styles = {"linear": "C0", "deadband": "C1", "logit": "C2"}
    for name, m in result.paper_models.items():
        ax.plot(grid, m.predict(grid), color=styles[name], lw=1.2,
                label=f"{name} (NRMSE {m.nrmse_pct:.2f} %)")
    ax.plot(th[sel], pred_final[sel], ".", ms=1.0, color="C3",
            label=f"final: {final.label} (NRMSE {result.nrmse_pct(final):.2f} %)")
    if zoom:
        b = max(result.paper_models["deadband"].backlash_rad, 0.02 * sig.scales.theta_ref)
        half = 3.0 * b
        k = result.paper_models["deadband"].stiffness_Nm_per_rad
        ax.set_xlim(-half, half)
        ax.set_ylim(-k * half, k * half)
        ax.set_title("Crossover region (zoom)")
    else:
        ax.set_title("Torque against deflection")
    ax.set_xlabel("deflection (rad)")
    ax.set_ylabel("torque (N·m)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", markerscale=4)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_energy(plt, result: FitResult, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    amps = [c.sign * c.amplitude_rad for c in result.cycles]
    ax.plot(amps, [c.loss_pct for c in result.cycles], "o")
    ax.set_xlabel("cycle amplitude (rad)")
    ax.set_ylabel("energy loss (%)")
    ax.set_title("Energy loss per loading–unloading cycle")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_residuals(plt, result: FitResult, before: State, after: State | None, path: Path,
                    title: str) -> Path:
    sig = result.signals
    idx = np.arange(sig.n)
    states = [("before", before)] + ([("after", after)] if after is not None else [])
    fig, axes = plt.subplots(len(states), 2, figsize=(10, 3.2 * len(states)), squeeze=False)
    sel = _every(sig.n)
    for row, (label, st) in enumerate(states):
        r = st.model.residual(st.x, sig, idx)
        keep = np.ones(sig.n, bool) if st.mask is None else ~st.mask
        for col, (x, xlabel) in enumerate(((sig.theta, "deflection (rad)"), (sig.t, "time (s)"))):
            ax = axes[row, col]
            ax.plot(x[sel][keep[sel]], r[sel][keep[sel]], ".", ms=1.0, rasterized=True)
            if st.mask is not None and st.mask.any():
                ax.plot(x[st.mask], r[st.mask], "x", ms=3, color="C3", label="glitches")
                ax.legend(fontsize=7)
            ax.axhline(0.0, color="k", lw=0.5)
            ax.set_xlabel(xlabel)
            ax.set_ylabel("residual (N·m)")
            ax.set_title(f"{label}: {st.label} (NRMSE {result.nrmse_pct(st):.2f} %)", fontsize=8)
            ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _sentence(text: str) -> str:
    return (text[:1].upper() + text[1:] + ".") if text else ""
