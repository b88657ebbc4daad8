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

import json
import math
from pathlib import Path

import numpy as np

from springcad.fit.analysis import FitResult, final_label
from springcad.fit.loop import State
from springcad.units import fmt_interval

#: at most this many points are drawn per scatter (evenly decimated)
_MAX_POINTS = 6000


def write_fit_outputs(result: FitResult, out_dir: Path | str, fmt: str = "md",
                      plots: bool = True) -> list[Path]:
    """Write ``fit.json``, the report and the plots into ``out_dir``.

    Args:
        result: the fit result.
        out_dir: an existing, empty folder (use ``atomic_output_dir``).
        fmt: ``"md"`` (``report.md`` and ``report.html``) or ``"html"`` (only
            ``report.html``, self-contained).
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
    if fmt == "md":
        written.append(out_dir / "report.md")
        written[-1].write_text(render_markdown(blocks), encoding="utf-8")
    # report.html always: one self-contained page (plots inlined) to open or send
    written.append(out_dir / "report.html")
    written[-1].write_text(render_html(blocks, out_dir), encoding="utf-8")
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
    b.append(("h2", "Verdict"))
    b += _verdict_blocks(data)
    inp, seg = data["input"], data["segmentation"]
    b.append(("h2", "Data"))
    b.append(("table", ["quantity", "value"], [
        ["samples", _f(inp["n_samples"])], ["duration (s)", _f(inp["duration_s"])],
        ["sample rate (Hz)", _f(inp["sample_rate_hz"])],
        ["loading–unloading cycles", _f(seg["n_cycles"])],
        ["distinct amplitudes (rad)", ", ".join(_f(a, 3) for a in seg["distinct_amplitudes_rad"])],
        ["typical ramp speed (rad/s)", _f(seg["typical_speed_rad_per_s"], 3)],
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
    en = data["energy_loss"]
    text = ("**Energy loss** (from the hysteresis model: friction loop area over the energy "
            "stored on loading, largest cycles): ")
    text += (f"{_f(en['pct'], 3)} % (95 % CI {_f(en['ci_low_pct'], 3)}–"
             f"{_f(en['ci_high_pct'], 3)} %); {en['note']}." if en["pct"] is not None
             else f"{en['note']}.")
    b.append(("p", text))
    b.append(("p", "The measured loop area of each cycle below is *apparent*: a late torque "
                   "channel or a drifting zero changes it (it can even be negative), so it is "
                   "shown for reference only."))
    b.append(("table", ["cycle", "amplitude (rad)", "stored (J)", "returned (J)",
                        "apparent loss (%)"],
              [[str(i + 1), _f(c["sign"] * c["amplitude_rad"], 3), _f(c["stored_J"]),
                _f(c["returned_J"]), _f(c["apparent_loss_pct"], 3)]
               for i, c in enumerate(data["energy_by_cycle"])]))
    for key, alt in (("torque_deflection", "torque against deflection with each model"),
                     ("crossover", "crossover region"), ("energy", "energy loss per cycle")):
        if key in images:
            b.append(("img", images[key], alt))
    if not final["no_spring"]:
        b += _loop_blocks(data, images)
        b += _evidence_blocks(data)
        b += _confounded_blocks(data)
    b.append(("h2", "Final model"))
    b.append(("p", f"`{final['model']}`, NRMSE {_f(final['nrmse_pct'])} %, RMSE "
                   f"{_f(final['rmse_Nm'])} N·m. Intervals are 95 % confidence intervals "
                   "(sandwich covariance clustered on the runs between reversals, Student t)."))
    rows = []
    for k, ci in final["intervals"].items():
        if ci.get("confounded_with"):
            rows.append([k, "not separately identified",
                         f"confounded with {', '.join(ci['confounded_with'])}", ""])
            continue
        rows.append([k, _f(ci["value"], 5), " … ".join(fmt_interval(ci["ci_low"], ci["ci_high"])),
                     "yes" if ci.get("at_bound") else ""])
    for k, v in final["params"].items():
        if k not in final["intervals"]:
            rows.append([k, _f(v, 5), "", ""])
    for g in final["confounded"]:
        rows.append([f"combined {' | '.join(g['effects'])} torque (N·m, typical)",
                     _f(g["combined_Nm"], 4), "", ""])
    b.append(("table", ["parameter", "value", "95 % CI", "at a bound"], rows))
    b += _unexplained_blocks(data, images)
    b += _design_blocks(data)
    return b


def _verdict_blocks(data: dict) -> list[tuple]:
    final = data["final"]
    if final["no_spring"]:
        sc = data["spring_check"]
        return [("p", f"**No stiffness above noise.** The torque does not follow the deflection: "
                      f"K = {_f(sc['stiffness_Nm_per_rad'], 3)} N·m/rad, 95 % CI "
                      f"{_f(sc['ci_low'], 3)} … {_f(sc['ci_high'], 3)} N·m/rad "
                      f"({_f(sc['z'], 3)} standard errors from zero, {_f(sc['threshold_z'])} "
                      "needed). Is the spring engaged, and are the right columns read?")]
    named = ", ".join(f"`{e}`" for e in final["effects"]) or "none beyond the linear spring"
    out = [("p", f"Baseline `{data['baseline']['model']}` NRMSE "
                 f"{_f(data['baseline']['nrmse_pct'])} % → final `{final['model']}` NRMSE "
                 f"{_f(final['nrmse_pct'])} % (noise floor {_f(final['noise_floor_nrmse_pct'])} %). "
                 f"Effects identified: {named}.")]
    for g in final["confounded"]:
        out.append(("p", "**Confounded**: " + g["statement"] + "."))
    if final["unexplained"]:
        where = final["unexplained_where"]
        out.append(("p", "**Unexplained structure remains** in the residual: "
                         + (where["summary"] if where else "see below") + "."))
    else:
        out.append(("p", "The final residual is consistent with noise."))
    return out


def _loop_blocks(data: dict, images: dict[str, str]) -> list[tuple]:
    b = [("h2", "Residual loop")]
    b.append(("p", "From `τ = K·θ`, each round tests every effect of the library: its detector "
                   "looks for the effect's signature in the residual (score test, z), then the "
                   "model with the effect is fitted on half of the cycles and scored on the "
                   "others (and vice versa). An effect is added when the held-out criterion "
                   f"N·ln(SSE/N) + k·ln(N) drops by more than "
                   f"{_f(data['loop_settings']['gain_threshold'])}; it stays only if the "
                   "evidence audit below supports it."))
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
            params = ", ".join(f"{k} = {_f(v)}" for k, v in s["params"].items())
            b.append(("p", f"**Step {i + 1}: {s['action']} `{s['effect']}`.** "
                           f"{_sentence(s['evidence'].get('meaning', ''))} "
                           + (f"{_sentence(s['evidence']['beside_structure'])} "
                              if s["evidence"].get("beside_structure") else "")
                           + (f"Parameters right after this step (later steps refit them): "
                              f"{params}." if params else "")))
            if f"step{i}" in images:
                b.append(("img", images[f"step{i}"], f"residual before and after step {i + 1}"))
    else:
        b.append(("p", "No effect was added: the linear model leaves nothing any effect explains "
                       "better on held-out cycles with consistent evidence."))
        if "step_none" in images:
            b.append(("img", images["step_none"], "residual of the linear model"))
    if data["last_round_candidates"]:
        b.append(("p", "Candidates in the last round (none cleared the threshold):"))
        b.append(("table", ["effect", "detector", "fitted", "held-out gain", "note"],
                  [[c["effect"], _f(c["detector"], 3), _f(c["fitted"]), _f(c["heldout_gain"]),
                    c.get("note") or ""] for c in data["last_round_candidates"]]))
    return b


def _evidence_blocks(data: dict) -> list[tuple]:
    b = [("h2", "Evidence audit")]
    s = data["loop_settings"]
    b.append(("p", "Each effect's size is fitted again on two parts of the record for each "
                   "split (early/late, small/large amplitude, loading/unloading), with the rest "
                   f"of the model free on each part. It must agree between the parts (p ≥ "
                   f"{_f(s['agreement_p'])}) and the parts together must support it (|z| ≥ "
                   f"{_f(s['support_z'])}). An effect that only patches structure outside the "
                   "library fails one of the two."))
    rows = []
    for name, ev in data["evidence"].items():
        for c in ev["splits"]:
            rows.append([name, c["split"], c["parameter"],
                         f"{_f(c['values'][0])} ± {_f(c['se'][0], 2)}",
                         f"{_f(c['values'][1])} ± {_f(c['se'][1], 2)}",
                         _f(c["agreement_p"], 3), _f(c["support_z"], 3),
                         "ok" if c["agrees"] and c["supported"] else "fails"])
    if rows:
        b.append(("table", ["effect", "split", "parameter", "part 1", "part 2", "agreement p",
                            "support z", "verdict"], rows))
    if data["rejected"]:
        b.append(("p", "Rejected although they lowered the held-out error (they only help "
                       "because something else is missing):"))
        b.append(("ul", [f"`{r['effect']}`: {r['reason']}" for r in data["rejected"]]))
    return b


def _confounded_blocks(data: dict) -> list[tuple]:
    final = data["final"]
    b = [("h2", "Identifiability")]
    b.append(("p", "For every pair of effects (in the model, or one in and one from the "
                   "library that can do its job), the correlation ρ of their signatures after "
                   "removing what the rest of the model can absorb gives the variance inflation "
                   f"1/(1-ρ²), on all samples and away from the reversals (a split that rests "
                   f"on the turns alone rests on how each model draws a turn); at "
                   f"{_f(data['loop_settings']['vif_confounded'])} or more the "
                   "record cannot separate them and one combined term is carried."))
    if not final["confounded"]:
        b.append(("p", "No confounded pair on this record."))
    for g in final["confounded"]:
        b.append(("p", _sentence(g["statement"])))
        adv = g.get("advice")
        if adv:
            ci = ", ".join(f"{k} ± {_f(v, 2)}" for k, v in adv["predicted_ci_halfwidth"].items())
            b.append(("p", f"**Recommended protocol**: {adv['change']} "
                           f"({_f(adv['protocol']['duration_s'], 3)} s). Predicted variance "
                           f"inflation {_f(adv['vif_protocol'], 3)} (now "
                           f"{_f(adv['vif_record'], 3)}); predicted 95 % half-widths with this "
                           f"record's noise: {ci}. Write it with `{adv['command']}`."))
            b.append(("table", ["protocol tried", "variance inflation", "duration (s)"],
                      [[a["change"], _f(a["vif"], 3), _f(a["duration_s"], 3)]
                       for a in adv["alternatives"]]))
    return b


def _unexplained_blocks(data: dict, images: dict[str, str]) -> list[tuple]:
    final = data["final"]
    b = [("h2", "Unexplained structure")]
    ev = final["unexplained_evidence"]
    rows = [[name, _f(t["p_value"], 3), _f(t["structure_rms_over_noise"], 3),
             _f(t["significant"])] for name, t in ev["tests"].items()]
    b.append(("p", ("**Unexplained**: " if final["unexplained"] else "None found: ")
              + f"residual RMS is {_f(ev['residual_rms_over_noise'], 3)} × the noise level "
                f"({_f(ev['noise_Nm'])} N·m); tests of the residual:"))
    b.append(("table", ["test", "p-value", "structure RMS / noise", "significant"], rows))
    where = final.get("unexplained_where")
    if where:
        b.append(("p", "Where it lives (each pattern with its share of the structure, and the "
                       "kinds of cause that leave such a signature; none is claimed):"))
        b.append(("ul", [f"{f['text']} ({_f(100 * f['share'], 2)} % of the structure). "
                         f"Such a signature comes from {f['causes']}." for f in where["findings"]]
                  or [where["summary"]]))
        if "unexplained" in images:
            b.append(("img", images["unexplained"], "where the unexplained structure lives"))
    return b


def _design_blocks(data: dict) -> list[tuple]:
    b = []
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


def render_html(blocks: list[tuple], image_dir: Path | str | None = None) -> str:
    """Report blocks as a self-contained HTML page (the Markdown text, plots inlined).

    Args:
        blocks: see :func:`report_blocks`.
        image_dir: folder of the plots (an image not found there shows its alt text).
    """
    from springcad.report.html_page import markdown_html, page

    title = next((blk[1] for blk in blocks if blk[0] == "h1"), "springcad fit")
    return page(title, markdown_html(render_markdown(blocks), image_dir))


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
        if result.loop.localisation is not None:
            images["unexplained"] = _plot_unexplained(plt, result, out_dir / "unexplained.png")
    finally:
        plt.close("all")
    return images


#: drawing order: model lines and points below, the measured data on top (a reader judges
#: the models against the data, so the data must never be hidden)
ZORDER_MODELS, ZORDER_FINAL, ZORDER_DATA = 2, 3, 4


def _plot_models(plt, result: FitResult, path: Path, zoom: bool) -> Path:
    fig = models_figure(plt, result, zoom)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def models_figure(plt, result: FitResult, zoom: bool):
    """Torque against deflection: the measured data above the paper models and the final model.

    Args:
        plt: ``matplotlib.pyplot`` (Agg).
        result: the fit.
        zoom: show the crossover region around zero torque only.

    Returns:
        The figure (the caller saves and closes it).
    """
    sig, rec = result.signals, result.record
    th, tq = rec.deflection_rad, rec.torque_Nm
    final = result.loop.final
    pred_final = final.model.predict(final.x, sig, np.arange(sig.n))
    fig, ax = plt.subplots(figsize=(7, 5))
    sel = _every(th.size)
    ax.plot(th[sel], tq[sel], ".", ms=1.6, color="0.15", alpha=0.35, label="measured",
            rasterized=True, zorder=ZORDER_DATA)
    grid = np.linspace(th.min(), th.max(), 2001)
    styles = {"linear": "C0", "deadband": "C1", "logit": "C2"}
    for name, m in result.paper_models.items():
        ax.plot(grid, m.predict(grid), color=styles[name], lw=1.4, zorder=ZORDER_MODELS,
                label=f"{name} (NRMSE {m.nrmse_pct:.2f} %)")
    if not result.loop.no_spring:
        ax.plot(th[sel], pred_final[sel], ".", ms=1.0, color="C3", alpha=0.5, zorder=ZORDER_FINAL,
                label=f"final: {final_label(result.loop)} (NRMSE {result.nrmse_pct(final):.2f} %)")
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
    return fig


def _plot_energy(plt, result: FitResult, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    amps = [c.sign * c.amplitude_rad for c in result.cycles]
    ax.plot(amps, [c.loss_pct for c in result.cycles], "o", color="0.5",
            label="apparent (measured loop area)")
    en = result.energy
    if en.pct is not None:
        a = max(abs(x) for x in amps)
        for side in (-1, 1):
            ax.errorbar([side * a], [en.pct], yerr=[[en.pct - en.ci_low], [en.ci_high - en.pct]],
                        fmt="s", color="C3", capsize=3,
                        label="hysteresis model, largest cycles (95 % CI)" if side > 0 else None)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.legend(fontsize=7)
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


def _plot_unexplained(plt, result: FitResult, path: Path) -> Path:
    """Residual of the final model in time, in deflection (per direction) and as spectra,
    with the localised patterns marked."""
    loc = result.loop.localisation
    data, findings = loc["data"], loc["findings"]
    sig, final = result.signals, result.loop.final
    idx = final.inliers(np.arange(sig.n))
    r = final.model.residual(final.x, sig, idx)
    ang = data.get("angle_spectrum")
    fig, axes = plt.subplots(2, 2, figsize=(11, 7))
    sel = _every(idx.size)
    ax = axes[0, 0]
    ax.plot(sig.t[idx][sel], r[sel], ".", ms=1.0, color="0.6", rasterized=True, label="residual")
    tc = data["time_component"]
    if any(tc["torque_Nm"]):
        ax.plot(tc["t_s"], tc["torque_Nm"], "-", color="C3", lw=1.0, label="time pattern found")
    for f in findings:
        if "at_s" in f:
            ax.axvline(f["at_s"], color="C3", ls="--", lw=1.0)
            ax.annotate(f"change at {f['at_s']:.3g} s", (f["at_s"], ax.get_ylim()[1]),
                        fontsize=7, color="C3", va="top")
    ax.set_xlabel("time (s)")
    ax.set_title("in time", fontsize=9)
    ax.legend(fontsize=7, markerscale=4)
    ax = axes[0, 1]
    d = data["deflection"]
    centre = np.asarray(d["centre_rad"])
    for key, label, colour in (("up", "deflection increasing", "C0"),
                               ("down", "deflection decreasing", "C1")):
        ax.plot(centre, np.asarray(d[f"mean_{key}_Nm"], float), "-o", ms=2, lw=1, color=colour,
                label=label)
    for f in findings:
        if "beyond_rad" in f:
            for side in (-1, 1):
                ax.axvspan(side * f["beyond_rad"], side * abs(centre).max(), color="C3",
                           alpha=0.12)
        if "within_rad" in f:
            ax.axvspan(-f["within_rad"], f["within_rad"], color="C3", alpha=0.12)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("deflection (rad)")
    ax.set_title("in deflection: mean residual per bin and direction", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    ts = data["time_spectrum"]
    f_hz = np.asarray(ts["frequency_hz"])
    ax.semilogy(f_hz[1:], np.asarray(ts["amplitude_Nm"])[1:], lw=0.6, label="residual")
    ax.semilogy(f_hz[1:], np.asarray(ts["level_Nm"])[1:], lw=1.0, color="k",
                label="local noise level")
    for f in findings:
        if f["kind"] == "periodic_time":
            ax.axvline(f["frequency_hz"], color="C3", ls="--", lw=1.0)
    ax.set_xlabel("frequency (Hz)")
    ax.set_title("periodic in time? (amplitude spectrum)", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    if ang:
        ax.plot(ang["cycles_per_rad"][1:], ang["amplitude_Nm"][1:], lw=0.8)
        for f in findings:
            if f["kind"] == "periodic_angle":
                ax.axvline(1.0 / f["period_rad"], color="C3", ls="--", lw=1.0)
        ax.set_xlabel("cycles per rad")
        ax.set_title("periodic in deflection? (spectrum of the deflection pattern)", fontsize=9)
    else:
        runs = data["runs"]
        ax.plot(runs["t_s"], runs["mean_Nm"], "o", ms=3, label="mean per run (N·m)")
        ax2 = ax.twinx()
        ax2.plot(runs["t_s"], runs["slope_Nm_per_rad"], "s", ms=3, color="C1",
                 label="slope per run (N·m/rad)")
        ax2.set_ylabel("slope (N·m/rad)", fontsize=8)
        ax.set_xlabel("time (s)")
        ax.set_title("per run between reversals", fontsize=9)
        ax.legend(fontsize=7, loc="lower left", framealpha=0.6)
        ax2.legend(fontsize=7, loc="lower right", framealpha=0.6)
    for a in axes.flat:
        a.grid(alpha=0.3)
        a.set_ylabel(a.get_ylabel() or "residual (N·m)", fontsize=8)
    fig.suptitle("Unexplained structure: " + _wrap(loc["summary"], 110), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _wrap(text: str, width: int) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))


def _sentence(text: str) -> str:
    return (text[:1].upper() + text[1:] + ".") if text else ""
