"""Write the paper validation report: validation.json, validation.md and a plot."""

from __future__ import annotations

from pathlib import Path

from springcad.report.jsonio import write_json


def plot_predicted_vs_measured(v, path: Path) -> None:
    """Predicted (before/after) vs measured stiffness, one point per configuration."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 5.5))
    meas = [c.measured_stiffness for c in v.configurations]
    ax.plot(meas, [c.target_stiffness for c in v.configurations], "o", mfc="none",
            label="before: design target")
    ax.plot(meas, [c.predicted_stiffness_after for c in v.configurations], "s",
            label="after: enriched model (leave-one-out)")
    for c in v.configurations:
        ax.annotate(c.configuration, (c.measured_stiffness, c.predicted_stiffness_after),
                    textcoords="offset points", xytext=(4, -10), fontsize=7)
    lim = [0.9 * min(meas), 1.1 * max(meas)]
    ax.plot(lim, lim, "k-", lw=0.8, label="predicted = measured")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("measured stiffness (N·m/rad)")
    ax.set_ylabel("predicted stiffness (N·m/rad)")
    ax.set_title("Paper Table I: predicted vs measured")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def markdown(v) -> str:
    d = v.to_dict()
    s = d["summary"]
    lines = [
        "# springcad validation against the paper",
        "",
        "Every predicted number comes from springcad's design, tolerance"
        + (" and FEA" if any(m.source != "beam" for m in v.springs.values()) else "")
        + " models run on the paper templates; only the *measured* columns come from the "
          "paper's Tables I and II.",
        "",
        "## Assumptions the paper leaves open",
        "",
        "| quantity | value | source |",
        "|---|---|---|",
        "| N, tip radius, contact radius | 28, 0.300 mm, 5.5 mm (S1 and S2) | paper Section II-C and shared/data README |",
        "| outer radius | 33.5 mm | shared/notes/design-method.md check value (not in the paper) |",
        "| thickness | 4.5 mm | design-method.md check value (not in the paper) |",
        "| design stress | 912 MPa | design-method.md check value (not in the paper) |",
        "| root radius | rim rule, R_o - R_r = (2 pi R_r/N - w0)/1.5 | reference tool's rule (design-method.md eq. 8) |",
        "| material | 420 hardened, E 200 GPa, nu 0.28, yield 1344 MPa, 7740 kg/m³ | AK Steel 420 data sheet |",
        "| tip-to-cam gap | 0.025 mm per side | paper Section II-B |",
        "| tolerances (Table I) | Mfr. 2: t_shaft 0.02 mm, t_spring 0.05 mm | paper Table II |",
        "",
        "## Stiffness (N·m/rad)",
        "",
        f"| configuration | measured | target (before) | beam | "
        f"{'FEA of the design' if any(m.source != 'beam' for m in v.springs.values()) else 'beam (no FEA run)'}"
        " | after (LOO) "
        "| error before | error after |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in v.configurations:
        lines.append(f"| {c.configuration} | {c.measured_stiffness:.2f} | {c.target_stiffness:.2f} "
                     f"| {c.beam_stiffness:.2f} | {c.geometry_stiffness:.2f} "
                     f"| {c.predicted_stiffness_after:.2f} | {c.error_before_pct:+.2f} % "
                     f"| {c.error_after_pct:+.2f} % |")
    lines += [
        "",
        f"Mean absolute error: **{s['mean_abs_error_before_pct']:.2f} % before**, "
        f"**{s['mean_abs_error_after_pct']:.2f} % after** (worst {s['worst_abs_error_before_pct']:.2f} % "
        f"-> {s['worst_abs_error_after_pct']:.2f} %). The after-error is out of sample: each "
        "configuration is predicted with the width offset fitted on the other six. Error = "
        "(predicted - measured) / measured.",
        "",
        "![predicted vs measured](predicted_vs_measured.png)",
        "",
        "## What each effect contributes (per spring)",
        "",
        "| effect | spring | change of K | added | how |",
        "|---|---|---|---|---|",
    ]
    for e in d["effects"]:
        if e["effect"] == "width_offset":
            change = (f"{e['sensitivity_pct_per_0.01mm']:+.2f} % per +0.01 mm; "
                      f"[{e['range_pct_at_t_spring'][0]:+.1f}, {e['range_pct_at_t_spring'][1]:+.1f}] % "
                      f"at ±t_spring = {e['t_spring_mm']} mm; {e['change_pct']:+.2f} % at the "
                      f"fitted {e['fitted_offset_mm_in_sample']:.4f} mm")
        elif e["effect"] == "youngs_modulus":
            change = f"[{e['range_pct'][0]:+.1f}, {e['range_pct'][1]:+.1f}] %"
        else:
            change = f"{e['change_pct']:+.2f} %"
        lines.append(f"| {e['effect']} | {e['spring']} | {change} | {'yes' if e['added'] else 'no'} "
                     f"| {e['how']} |")
    resid = [c.error_after_pct for c in v.configurations]
    lines += [
        "",
        "### What remains unexplained",
        "",
        f"After the added effects the residual ranges {min(resid):+.2f} % to {max(resid):+.2f} %. "
        "A single width offset cannot make S2 (measured +14.8 % over target) and S1 (+7.4 %) stiffer "
        "by the measured ratio with one value; spring-to-spring scatter of the physical parts "
        "(each configuration reuses a different subset of four S1 and two S2) is not in any model "
        "here and is the likely remainder.",
        "",
        "## Deflection limits (eq. 10)",
        "",
        "| configuration | eq. 10 (rad) | Table I (rad) | agrees |",
        "|---|---|---|---|",
    ]
    for c in v.configurations:
        ok = abs(c.deflection_limit_rad - c.table_deflection_limit_rad) < 1e-3
        lines.append(f"| {c.configuration} | {c.deflection_limit_rad:.3f} "
                     f"| {c.table_deflection_limit_rad:.3f} | {'yes' if ok else '**no**'} |")
    lines += ["", *[f"- {n}" for n in d["notes"]], "",
              "## Backlash (rad): measured vs the tolerance range (per-interface range x interfaces)",
              "", "| configuration | nominal | worst min | worst max | measured | where |",
              "|---|---|---|---|---|---|"]
    for c in v.configurations:
        lo, hi = c.predicted_backlash_range_rad
        lines.append(f"| {c.configuration} | {c.nominal_backlash_rad:.4f} | {lo:.4f} | {hi:.4f} "
                     f"| {c.measured_backlash_rad:.4f} | {c.backlash_position} |")
    lines += ["", "Manufacturer comparison (4xS1, Table II):", "",
              "| manufacturer | t_shaft | t_spring | backlash worst max | measured | where "
              "| K range at ±t_spring | measured K | where |",
              "|---|---|---|---|---|---|---|---|---|"]
    for m in d["manufacturers"]:
        lo, hi = m["predicted_stiffness_range_at_t_spring"]
        lines.append(f"| {m['manufacturer']} | {m['t_shaft_mm']} | {m['t_spring_mm']} "
                     f"| {m['predicted_backlash_range_rad'][1]:.4f} | {m['measured_backlash_rad']:.4f} "
                     f"| {m['backlash_position']} | [{lo:.2f}, {hi:.2f}] | {m['measured_stiffness']:.2f} "
                     f"| {m['stiffness_position']} |")
    lines += _geometry_change_lines(v.geometry_changes)
    lines += ["", "## Energy", "", "| configuration | J/cm³ | J/kg |", "|---|---|---|"]
    for c in v.configurations:
        lines.append(f"| {c.configuration} | {c.energy_density_J_per_cm3:.3f} "
                     f"| {c.specific_energy_J_per_kg:.1f} |")
    lines += ["", "The paper reports 0.24-0.39 J/cm³ and 31-52 J/kg for its series stacks "
              "(measured hardware, thick bolted rims)."]
    return "\n".join(lines) + "\n"


def _geometry_change_lines(changes: list[dict]) -> list[str]:
    """Markdown: springcad's geometry against the reference tool's, per paper spring."""
    if not changes:
        return []
    fea = "peak_fea_2d_MPa" in changes[0]["reference"]
    lines = ["", "## What springcad changed against the reference geometry", "",
             "The reference tool draws a plain circular root fillet and sizes the flexures to the "
             "design stress as a beam. springcad adds a root flare (the flexure widens smoothly "
             "over the last part before the rim, chosen by the FEA-calibrated stress model) and "
             "rescales the widths so the beam stiffness is unchanged; it would lower the beam "
             "stress if the predicted peak still missed the required yield margin.", "",
             "| spring | geometry | root flare | beam K N·m/rad | nominal beam MPa | predicted peak MPa "
             "| yield margin | mass g |" + (" FEA 2D K N·m/rad | FEA 2D peak MPa | FEA margin |" if fea else ""),
             "|---|---|---|---|---|---|---|---|" + ("---|---|---|" if fea else "")]
    for c in changes:
        for tag in ("reference", "springcad"):
            g = c[tag]
            flare = "0" if tag == "reference" else f"{c['root_flare']:g} over {c['root_flare_length_mm']:.2f} mm"
            row = (f"| {c['spring']} | {tag} | {flare} | {g['beam_stiffness_Nm_per_rad']:.2f} "
                   f"| {g['nominal_beam_stress_MPa']:.0f} | {g['predicted_peak_MPa']:.0f} "
                   f"({g['predicted_region']}) | {g['yield_margin_predicted']:.3f} | {g['mass_g']:.2f} |")
            if fea:
                row += (f" {g['stiffness_fea_2d_Nm_per_rad']:.2f} | {g['peak_fea_2d_MPa']:.0f} "
                        f"({g['peak_fea_2d_region']}) | {g['yield_margin_fea_2d']:.3f} |")
            lines.append(row)
    return lines


def write_paper_report(v, out_dir: Path) -> list[Path]:
    out_dir = Path(out_dir)
    write_json(out_dir / "validation.json", v.to_dict())
    plot_predicted_vs_measured(v, out_dir / "predicted_vs_measured.png")
    (out_dir / "validation.md").write_text(markdown(v))
    return [out_dir / n for n in ("validation.json", "predicted_vs_measured.png", "validation.md")]
