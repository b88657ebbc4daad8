"""Write the outputs of ``springcad fit``: ``fit.json``, a readable report and PNG plots.

The plots are drawn by :mod:`springcad.report.fit_plots`.

The report is Markdown (``report.md``) or HTML (``report.html``), built from the
same blocks. Units: N·m, rad, s.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from springcad.fit.analysis import FitResult
from springcad.report.fit_plots import plot_all
from springcad.report.html_page import markdown_html, page
from springcad.report.jsonio import write_json
from springcad.units import fmt_interval


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

    out_dir = Path(out_dir)
    written = [out_dir / "fit.json"]
    write_json(written[0], result.to_dict())
    data = json.loads(written[0].read_text(encoding="utf-8"))  # exactly what the file says
    images = plot_all(result, out_dir) if plots else {}
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
                   "(leave-one-run-out jackknife over the runs between reversals, floored at "
                   "the noise, Student t)."))
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
        only_laws = bool(where and where["findings"]) and all(
            f["kind"] == "law_outside_library" for f in where["findings"])
        out.append(("p", ("**Physics outside the library**: " if only_laws else
                          "**Unexplained structure remains** in the residual: ")
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
        b.append(("ul", [f"{f['text']}" + ("" if f["kind"] == "law_outside_library" else
                                            f" ({_f(100 * f['share'], 2)} % of the structure)")
                         + f". Such a signature comes from {f['causes']}." for f in where["findings"]]
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
                ["target", _f(st["target_stiffness_Nm_per_rad"]), _f(st["error_vs_target_pct"], 3)],
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
    title = next((blk[1] for blk in blocks if blk[0] == "h1"), "springcad fit")
    return page(title, markdown_html(render_markdown(blocks), image_dir))


def _sentence(text: str) -> str:
    return (text[:1].upper() + text[1:] + ".") if text else ""
