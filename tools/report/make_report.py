#!/usr/bin/python3
"""Builds STUDY/report/ from a finished, analysed study: figures in the spirit of the paper's
Fig. 1b-9 (PNG + SVG), tables beside the paper's numbers (Markdown, HTML, CSV) and the macroscale
model card. Called by `pbxmpm report STUDY` after it has written every run's analysis.json and
report/fits.json; it reads only those files, study.json and the runs' last snapshot (Fig. 1b).

Usage: /usr/bin/python3 make_report.py STUDY --out STUDY/report --paper-values paper_values.toml
"""
import argparse
import csv
import glob
import html
import json
import math
import os
import sys
import tomllib

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

NAN = float("nan")


def fail(msg):
    print(f"make_report: {msg}", file=sys.stderr)
    sys.exit(2)


def get(d, *path, default=NAN):
    for k in path:
        if not isinstance(d, dict) or k not in d or d[k] is None:
            return default
        d = d[k]
    return d


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{digits}g}"


def finite_or_none(o):
    """JSON has no NaN: not-available values are written as null."""
    if isinstance(o, float):
        return o if math.isfinite(o) else None
    if isinstance(o, dict):
        return {k: finite_or_none(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [finite_or_none(v) for v in o]
    return o


def ratio(ours, paper):
    if ours is None or paper is None or not math.isfinite(ours) or not paper:
        return NAN
    return ours / paper


# every table the report may write (as NAME.csv), removed before a report is written again
REPORT_TABLES = ("conditions", "ratios_within_groups", "run_checks", "table2_moduli_vs_temperature",
                 "table3_strength_vs_temperature", "moduli_vs_density", "trends", "fitted_constants",
                 "hashin_shtrikman_bounds")


class Report:
    """Collects sections, then writes report.md and report.html from the same content."""

    def __init__(self, out):
        self.out = out
        self.blocks = []  # (kind, payload)

    def h(self, text, level=2):
        self.blocks.append(("h", (level, text)))

    def p(self, text):
        self.blocks.append(("p", text))

    def table(self, name, header, rows, caption):
        assert name in REPORT_TABLES, f"{name}: add it to REPORT_TABLES (so that a stale copy is removed)"
        with open(os.path.join(self.out, name + ".csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            for r in rows:
                w.writerow(["" if (isinstance(v, float) and not math.isfinite(v)) else v for v in r])
        self.blocks.append(("table", (header, rows, caption, name + ".csv")))

    def figure(self, fig, name, caption, dpi=110):
        for ext in ("png", "svg"):
            fig.savefig(os.path.join(self.out, f"{name}.{ext}"), dpi=dpi, bbox_inches="tight")
        plt.close(fig)
        self.blocks.append(("fig", (name, caption)))

    @staticmethod
    def cell(v):
        return fmt(v, 4) if isinstance(v, float) else str(v)

    def write(self, title):
        md = [f"# {title}", ""]
        body = []
        for kind, x in self.blocks:
            if kind == "h":
                md += ["#" * x[0] + " " + x[1], ""]
                body.append(f"<h{x[0]}>{html.escape(x[1])}</h{x[0]}>")
            elif kind == "p":
                md += [x, ""]
                body.append(f"<p>{html.escape(x)}</p>")
            elif kind == "table":
                header, rows, caption, csvname = x
                md += [f"**{caption}** ([{csvname}]({csvname}))", ""]
                md.append("| " + " | ".join(header) + " |")
                md.append("|" + "---|" * len(header))
                for r in rows:
                    md.append("| " + " | ".join(self.cell(v) for v in r) + " |")
                md.append("")
                t = [f"<div style='overflow-x:auto'><table><caption>{html.escape(caption)} (<a href='{csvname}'>CSV</a>)</caption><tr>"]
                t += [f"<th>{html.escape(h)}</th>" for h in header]
                t.append("</tr>")
                for r in rows:
                    t.append("<tr>" + "".join(f"<td>{html.escape(self.cell(v))}</td>" for v in r) + "</tr>")
                t.append("</table></div>")
                body.append("".join(t))
            elif kind == "fig":
                name, caption = x
                md += [f"![{caption}]({name}.png)", "", f"*{caption}* ([SVG]({name}.svg))", ""]
                body.append(f"<figure><img src='{name}.png' alt='{html.escape(caption)}'>"
                            f"<figcaption>{html.escape(caption)} (<a href='{name}.svg'>SVG</a>)</figcaption></figure>")
        with open(os.path.join(self.out, "report.md"), "w") as f:
            f.write("\n".join(md) + "\n")
        style = ("body{font-family:sans-serif;max-width:1100px;margin:auto}table{border-collapse:collapse;margin:1em 0}"
                 "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}caption{text-align:left;font-weight:bold}"
                 "img{max-width:100%}")
        with open(os.path.join(self.out, "report.html"), "w") as f:
            f.write(f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
                    f"<style>{style}</style></head><body><h1>{html.escape(title)}</h1>\n" + "\n".join(body) +
                    "\n</body></html>\n")


def load(study_dir, out):
    sj = os.path.join(study_dir, "study.json")
    if not os.path.exists(sj):
        fail(f"{sj}: missing")
    with open(sj) as f:
        study = json.load(f)
    fits_path = os.path.join(out, "fits.json")
    fits = {}
    if os.path.exists(fits_path):
        with open(fits_path) as f:
            fits = json.load(f)
    # a partial report (pbxmpm report --partial) leaves out the runs fits.json names
    left_out = {m.get("id") for m in fits.get("missing_runs", [])}
    runs = []
    missing = []
    for e in study.get("runs", []):
        rid = e.get("id") or os.path.basename(e.get("dir", ""))
        if rid in left_out:
            continue
        d = os.path.join(study_dir, e.get("dir", f"runs/{rid}"))
        a = os.path.join(d, "analysis.json")
        if not os.path.exists(a):
            missing.append(a)
            continue
        with open(a) as f:
            runs.append({"id": rid, "dir": d, "entry": e, "a": json.load(f)})
    if not os.path.exists(fits_path):
        missing.append(fits_path)
    if missing:
        fail("missing (run `pbxmpm report`, which writes them first): " + ", ".join(missing))
    return study, runs, fits


def run_T(r):
    T = r["entry"].get("temperature_K")
    return T if T is not None else get(r["a"], "temperature_K")


def run_group(r):
    return r["entry"].get("group") or get(r["a"], "study", "group", default="")


def sweep_by(group):
    """The paper's sweep by a group's name alone ('temperature', 'density'; 'none' for others; 'both'
    without a group): for a fits.json written before 2026-12-06. Since then fits.json says each run's
    and condition's sweep by the key its group varies (sweep_of in src/analysis/study_fits.cpp)."""
    return group if group in ("temperature", "density") else ("both" if not group else "none")


def run_sweep(r, fits):
    return fits.get("run_sweeps", {}).get(r["id"]) or sweep_by(run_group(r))


def cond_sweep(c):
    return c["sweep"] if "sweep" in c else sweep_by(c.get("group", ""))


def stat(cond, key, scale=1.0):
    m = get(cond, "stats", key, "mean")
    s = get(cond, "stats", key, "std")
    return (m * scale if m is not None else NAN), (s * scale if s is not None else NAN)



# two-sided 95 % Student t quantiles by degrees of freedom (beyond 30: the normal's 1.96)
T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228,
       12: 2.179, 15: 2.131, 20: 2.086, 25: 2.060, 30: 2.042}


def t95(df):
    if df > 30:
        return 1.96
    return T95[max(k for k in T95 if k <= df)]  # the next smaller df's quantile: a slightly wider interval


def ratio_interval(ref, other):
    """Ratio of a quantity between two conditions with a 95 % interval. ref, other: {seed: value}.
    Seeds present in both are paired (the same microstructure at both conditions: the ratio per seed,
    its mean and t interval); otherwise the ratio of the means with the interval of its logarithm
    (delta method). Returns (ratio, low, high, how)."""
    ref = {k: v for k, v in ref.items() if math.isfinite(v) and v != 0}
    other = {k: v for k, v in other.items() if math.isfinite(v)}
    common = sorted(set(ref) & set(other))
    if len(common) >= 2:
        r = [other[k] / ref[k] for k in common]
        m = sum(r) / len(r)
        sd = math.sqrt(sum((x - m) ** 2 for x in r) / (len(r) - 1))
        half = t95(len(r) - 1) * sd / math.sqrt(len(r))
        return m, m - half, m + half, f"paired, {len(r)} seeds"
    if len(ref) >= 2 and len(other) >= 2:
        def ms(d):
            v = list(d.values())
            m = sum(v) / len(v)
            return m, math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)), len(v)
        ma, sa, na = ms(ref)
        mb, sb, nb = ms(other)
        r = mb / ma
        se = math.sqrt((sa / ma) ** 2 / na + (sb / mb) ** 2 / nb)
        k = t95(min(na, nb) - 1)
        return r, r * math.exp(-k * se), r * math.exp(k * se), f"unpaired, {na} and {nb} seeds"
    if ref and other:
        return (sum(other.values()) / len(other)) / (sum(ref.values()) / len(ref)), NAN, NAN, "one seed: no interval"
    return NAN, NAN, NAN, "no values"


def refit_verdict(nl, ll, pf):
    """Which of the two refits of the paper's Table 3 reproduce its sigma0 and alpha, judged by the
    printed digits (the paper gives 4 significant figures) and by the fits' confidence intervals."""
    def reproduces(fit, name, value, rel):
        v = par(fit, name)
        lo, hi = ci(fit, name)
        return abs(v - value) <= rel * abs(value), lo <= value <= hi
    s0 = pf["sigma0_MPa"] * 1e6
    parts = []
    for lab, fit in (("the nonlinear fit", nl), ("the log-linear fit", ll)):
        s_ok, _ = reproduces(fit, "sigma0", s0, 5e-3)
        a_ok, a_in = reproduces(fit, "alpha", pf["alpha"], 5e-3)
        parts.append((lab, s_ok, a_ok, a_in))
    s_by = [lab for lab, s_ok, _, _ in parts if s_ok]
    a_by = [lab for lab, _, a_ok, _ in parts if a_ok]
    a_inside = [lab for lab, _, _, inside in parts if inside]
    txt = (f"The paper reports σ0 = {pf['sigma0_MPa']:.2f} MPa and α = {pf['alpha']}: its σ0 is reproduced (to 0.5 %) by "
           f"{' and '.join(s_by) if s_by else 'neither method'}; its α = {pf['alpha']} is reproduced by "
           f"{' and '.join(a_by) if a_by else 'neither method'}")
    txt += (f" (it lies inside the confidence interval of {' and '.join(a_inside)})." if a_inside and not a_by
            else " (nor inside either fit's confidence interval)." if not a_by else ".")
    return txt


def rising(cond, runs):
    """How many of the condition's runs end their strength window with the stress still rising (no
    plateau: their strength, the mean over the plateau window, and their peak are lower bounds)."""
    ids = set(cond.get("runs", []))
    return sum(1 for r in runs if r["id"] in ids and get(r["a"], "strength", "still_rising", default=False))


def curve(r):
    c = r["a"].get("curve", {})
    e = np.array([NAN if v is None else v for v in c.get("strain", [])], float)
    p = np.array([NAN if v is None else v for v in c.get("punch_stress_Pa", [])], float)
    v = np.array([NAN if v is None else v for v in c.get("minus_syy_Pa", [])], float)
    return e, p, v


def eq13(T, s0, a, T0):
    return s0 * np.exp(a * (1 - np.asarray(T, float) / T0))


def eq14(e_pct, A, B, n):
    e_pct = np.asarray(e_pct, float)
    return A * e_pct + B * e_pct ** n


def max_paper_eq14(pn):
    """Peak of the paper's Eq. 14, A e + B e^n (e in percent): at e* = (-A/(B n))^(1/(n-1)), 1.0597."""
    A, B, n = pn["A"], pn["B"], pn["n"]
    e = (-A / (B * n)) ** (1.0 / (n - 1.0))
    return float(eq14(e, A, B, n))


def par(fit, name):
    return get(fit, "parameters", name, "value")


def ci(fit, name):
    return get(fit, "parameters", name, "ci_low"), get(fit, "parameters", name, "ci_high")


def snapshot_material_names(run):
    """Material names in the order of the snapshot's material index (run.json 'materials')."""
    try:
        with open(os.path.join(run["dir"], "run.json")) as f:
            return [m["name"] for m in json.load(f).get("materials", [])]
    except (OSError, ValueError, KeyError):
        return []


def last_snapshot(run_dir):
    files = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snap_*.h5")))
    return files[-1] if files else None


def pct(a, b):
    """Relative change from a to b in percent (NaN when a is not finite or zero)."""
    return 100 * (b - a) / a if (math.isfinite(a) and math.isfinite(b) and a != 0) else NAN


def trend_section(rep, tconds, dconds, p2, p3, phs):
    """The trends the paper reports (Sections 3.1-3.2), each measured on ours and on the paper's
    own numbers over the same conditions, with whether ours goes the paper's way."""
    rows = []

    def yes(ok):
        return "yes" if ok else "no"

    Ts = [c["temperature_K"] for c in tconds]
    if len(tconds) >= 2:
        lo, hi = tconds[0], tconds[-1]
        Tlo, Thi = int(round(Ts[0])), int(round(Ts[-1]))
        span = f"{Tlo} -> {Thi} K"
        d = {}
        for key, lab in (("E_Pa", "E"), ("G_Pa", "G"), ("K_Pa", "K")):
            ours = pct(stat(lo, key)[0], stat(hi, key)[0])
            paper = pct(p2.get((Tlo, "this"), {}).get(lab + "_GPa", NAN), p2.get((Thi, "this"), {}).get(lab + "_GPa", NAN))
            d[lab] = (ours, paper)
            if lab != "K":
                rows.append([f"{lab} falls with temperature ({span}), %", ours, paper, yes(ours < 0)])
        def k_share(v):  # |change of K| / the smaller |change| of E and G
            m = min(abs(v["E"]), abs(v["G"]))
            return abs(v["K"]) / m if m > 0 else NAN
        kr_ours = k_share({k: x[0] for k, x in d.items()})
        kr_paper = k_share({k: x[1] for k, x in d.items()})
        rows.append([f"K changes less than E and G ({span}): size of the change of K / the smaller one of E and G",
                     kr_ours, kr_paper, yes(kr_ours < 1)])
        s_ours = pct(stat(lo, "strength_Pa")[0], stat(hi, "strength_Pa")[0])
        s_paper = pct(p3.get(Tlo, NAN), p3.get(Thi, NAN))
        rows.append([f"strength falls with temperature ({span}), %", s_ours, s_paper, yes(s_ours < 0)])
        # "sharply above 353 K": the fall per kelvin above 353 K against the fall per kelvin below it
        mid = next((c for c in tconds if abs(c["temperature_K"] - 353) < 0.5), None)
        if mid is not None and Tlo < 353 < Thi:
            def rate_ratio(a, m, b):
                below = (a - m) / (353 - Tlo)
                above = (m - b) / (Thi - 353)
                return above / below if below > 0 else NAN
            r_ours = rate_ratio(stat(lo, "strength_Pa")[0], stat(mid, "strength_Pa")[0], stat(hi, "strength_Pa")[0])
            r_paper = rate_ratio(p3.get(Tlo, NAN), p3.get(353, NAN), p3.get(Thi, NAN))
            rows.append([f"strength falls sharply above 353 K: fall per K above / below 353 K (sharp: > 1.5)",
                         r_ours, r_paper, yes(r_ours > 1.5)])
    if len(dconds) >= 2:
        rlo, rhi = stat(dconds[0], "density_kg_m3")[0], stat(dconds[-1], "density_kg_m3")[0]
        span = f"{rlo / 1e3:.3f} -> {rhi / 1e3:.3f} g/cm3"

        def paper_law(lab, rho):
            return phs[lab + "U_GPa"] * phs[lab + "_k"] * (rho / 1e3 / phs["rho0_g_cm3"]) ** phs[lab + "_n"]
        Kp = [paper_law("K", rlo), paper_law("K", rhi)]
        Gp = [paper_law("G", rlo), paper_law("G", rhi)]
        Ep = [9 * k * g / (3 * k + g) for k, g in zip(Kp, Gp)]
        paper = {"K": pct(*Kp), "G": pct(*Gp), "E": pct(*Ep), "strength": NAN}
        for key, lab in (("K_Pa", "K"), ("G_Pa", "G"), ("E_Pa", "E"), ("strength_Pa", "strength")):
            v = [stat(c, key)[0] for c in dconds]
            mono = all(b > a for a, b in zip(v, v[1:]))
            rows.append([f"{lab} rises with density ({span}; every step up), %", pct(v[0], v[-1]), paper[lab], yes(mono)])
    if rows:
        rep.h("The paper's trends, measured")
        rep.table("trends", ["trend", "ours", "paper", "ours goes the paper's way"], rows,
                  "Each trend the paper reports, measured on our conditions and on the paper's numbers at the same "
                  "conditions (Table 2-3; for density its Eq. 21-22, E from them; strength vs density: no table)")


def hs_section(rep, conds, phs, paper_conditions):
    """Hashin-Shtrikman bounds of every condition from its own materials (its first run: conditions
    may differ in material, temperature and porosity), beside the paper's G^U, K^U where the study has
    the paper's conditions (they are bounds of the paper's materials)."""
    rows = []
    fallback = []
    for c in conds:
        b = c.get("hashin_shtrikman")
        if not b:
            continue
        phases = "; ".join(f"{p.get('name', '?')} {fmt(get(p, 'K_Pa') / 1e9, 3)}/{fmt(get(p, 'G_Pa') / 1e9, 3)}, "
                           f"{fmt(get(p, 'volume_fraction'), 3)}" for p in b.get("phases", []))
        if str(b.get("phases_source", "")).startswith("the paper's Table 1"):
            fallback.append(f"{b.get('run', '?')}: {b['phases_source']}")
        rows.append([c.get("group", ""), str(c.get("value", "")).strip("'"), b.get("run", ""), phases,
                     get(b, "pore_free", "K_upper_Pa") / 1e9, get(b, "pore_free", "G_upper_Pa") / 1e9,
                     get(b, "pore_free", "K_lower_Pa") / 1e9, get(b, "pore_free", "G_lower_Pa") / 1e9,
                     get(b, "with_pores", "K_upper_Pa") / 1e9, get(b, "with_pores", "G_upper_Pa") / 1e9])
    if not rows:
        rep.p("Hashin-Shtrikman bounds not computed: fits.json has no per-condition bounds (an older pbxmpm; "
              "run `pbxmpm report` again).")
        return
    if paper_conditions:
        rows.append(["paper (its ref. 41)", "", "", "the paper's materials", phs["KU_GPa"], phs["GU_GPa"], NAN, NAN,
                     NAN, NAN])
    rep.h("Hashin-Shtrikman bounds")
    rep.table("hashin_shtrikman_bounds",
              ["group", "value", "run", "phases (K/G GPa, volume fraction)", "K_upper_GPa", "G_upper_GPa",
               "K_lower_GPa", "G_lower_GPa", "K_upper_with_pores_GPa", "G_upper_with_pores_GPa"], rows,
              "Hashin-Shtrikman bounds of each condition from its own materials (its first run's phases: each material "
              "probed at the run temperature after the loading time to the middle of the linear window, volume "
              "fractions from the particle counts and the porosity; docs/theory/analysis.md §8): K and G bounds of "
              "the pore-free composite, and the upper bounds with the run's pores (the lower ones are 0)" +
              ("; last row, the paper's G^U, K^U (its materials, its ref. 41)" if paper_conditions else ""))
    if fallback:
        rep.p("The paper's Table 1 phases stand in for: " + "; ".join(fallback))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study")
    ap.add_argument("--out")
    ap.add_argument("--paper-values", default=os.path.join(os.path.dirname(__file__), "paper_values.toml"))
    args = ap.parse_args()
    out = args.out or os.path.join(args.study, "report")
    os.makedirs(out, exist_ok=True)
    study, runs, fits = load(args.study, out)
    with open(args.paper_values, "rb") as f:
        paper = tomllib.load(f)

    # the files an earlier report wrote and this one may not (a paper section this study lacks) go first
    for old in (glob.glob(os.path.join(out, "fig[0-9]*_*.png")) + glob.glob(os.path.join(out, "fig[0-9]*_*.svg")) +
                [os.path.join(out, n + ".csv") for n in REPORT_TABLES] +
                [os.path.join(out, n) for n in ("model_card.json", "model_card_curves.csv")]):
        if os.path.isfile(old):
            os.remove(old)
    rep = Report(out)
    conds = fits.get("conditions", [])
    tconds = sorted([c for c in conds if cond_sweep(c) in ("temperature", "both")], key=lambda c: c["temperature_K"])
    dconds = sorted([c for c in conds if cond_sweep(c) in ("density", "both")],
                    key=lambda c: get(c, "stats", "density_kg_m3", "mean"))
    truns = [r for r in runs if run_sweep(r, fits) in ("temperature", "both")]
    druns = [r for r in runs if run_sweep(r, fits) in ("density", "both")]
    T0 = get(fits, "eq13", "T0_K", default=293.0)
    groups_of_study = list(dict.fromkeys(c.get("group", "") or "(none)" for c in conds))
    nseeds = max([len(c.get("runs", [])) for c in conds] or [1])

    left_out = fits.get("missing_runs", [])
    if left_out:
        rep.p(f"PARTIAL REPORT: {len(runs)} of {len(runs) + len(left_out)} runs; left out (not finished): " +
              "; ".join(f"{m.get('id')} ({m.get('why')})" for m in left_out) +
              ". Fits, trends and tables below use only the runs present.")
    versions = sorted({str(get(r["a"], "code_version", default="?")) for r in runs})
    titles = sorted({str(get(r["a"], "title", default="")) for r in runs} - {""})
    if titles:  # a calibrated study says so in its runs' title
        rep.p("Run title: " + "; ".join(titles) + ".")
    def count(n, one, many):
        return f"{n} {one if n == 1 else many}"
    rep.p(f"Study '{study.get('name', '?')}': {count(len(runs), 'run', 'runs')}, "
          f"{count(len(conds), 'condition', 'conditions')}, up to {count(nseeds, 'seed', 'seeds')} "
          f"per condition; {'code version' if len(versions) == 1 else 'code versions'}: {', '.join(versions)}. Values are mean ± standard deviation over seeds "
          "(std = 0 with one seed). " +
          (f"Fitted constants carry {100 * fits.get('confidence', 0.95):.0f} % confidence "
           "intervals (Student t on the linearised covariance). Paper values are from its Tables 2-3 and Eq. 13-22 "
           "(tools/report/paper_values.toml); ratio = ours / paper. " if truns or druns else "") +
          "Definitions: docs/theory/analysis.md.")

    # ---- a few lines on top: how the runs went, and ours against the paper where comparable ----
    flagged = [r["id"] for r in runs if get(r["a"], "quasi_static", "flagged", default=False)]
    overlap = [r["id"] for r in runs if get(r["a"], "interpenetration", "flagged", default=False)]
    energy = [r["id"] for r in runs if get(r["a"], "energy_balance", "flagged", default=False)]
    lines = [f"{count(len(runs), 'run', 'runs')} finished; {len(flagged)} flagged as not quasi-static"
             + (f" ({', '.join(flagged)})" if flagged else "")
             + f", {len(overlap)} for grains passing into each other, {len(energy)} for energy not conserved "
             "(run checks below)."]
    p2this = {t["T_K"]: t for t in paper.get("table2", []) if t.get("source") == "this"}
    comp = [(c["temperature_K"], get(c, "stats", "E_Pa", "mean") / 1e9, p2this[c["temperature_K"]]["E_GPa"])
            for c in tconds if c.get("temperature_K") in p2this and cond_sweep(c) == "temperature"]
    if comp:
        lines.append("E against the paper's Table 2 (ours / paper, GPa): " +
                     ", ".join(f"{T:.0f} K {o:.2f} / {pp:.2f} ({o / pp:.2f}x)" for T, o, pp in comp) + ".")
        if len(comp) >= 2:
            ours_drop, paper_drop = comp[-1][1] / comp[0][1] - 1, comp[-1][2] / comp[0][2] - 1
            lines.append(f"E from {comp[0][0]:.0f} to {comp[-1][0]:.0f} K: ours {100 * ours_drop:+.0f} %, "
                         f"the paper's {100 * paper_drop:+.0f} %.")
        # K, G and the strength as ratios at each temperature, so that what disagrees most shows here too
        p3 = dict(zip(paper.get("table3", {}).get("T_K", []), paper.get("table3", {}).get("strength_MPa", [])))
        ratios = []
        for c in tconds:
            T = c.get("temperature_K")
            if cond_sweep(c) != "temperature" or T not in p2this:
                continue
            parts = [f"{name} {get(c, 'stats', key, 'mean') / 1e9 / p2this[T][pk]:.2f}"
                     for name, key, pk in (("K", "K_Pa", "K_GPa"), ("G", "G_Pa", "G_GPa"))]
            if T in p3:
                parts.append(f"strength {get(c, 'stats', 'strength_Pa', 'mean') / 1e6 / p3[T]:.2f}")
            ratios.append(f"{T:.0f} K " + ", ".join(parts))
        if ratios:
            lines.append("Ours / paper (Tables 2 and 3): " + "; ".join(ratios) + ".")
    else:
        lines.append("This study has none of the paper's temperature conditions: the per-condition table below is "
                     "its result; the paper's comparisons follow only where its conditions occur.")
    rep.h("Summary")
    rep.p(" ".join(lines))

    # ---- every condition, whatever the study varies ----
    rep.h("Results per condition")
    rows = []
    for c in conds:
        def pm(key, scale, digits=3):
            m, sd = stat(c, key, scale)
            return f"{fmt(m, digits)} ± {fmt(sd, 2)}" if math.isfinite(m) else ""
        rows.append([c.get("group", ""), str(c.get("value", "")).strip("'"), len(c.get("runs", [])),
                     fmt(get(c, "temperature_K"), 4), pm("density_kg_m3", 1e-3, 4), pm("K_Pa", 1e-9), pm("G_Pa", 1e-9),
                     pm("E_Pa", 1e-9), pm("nu", 1.0), pm("yield_stress_Pa", 1e-6), pm("strength_Pa", 1e-6)])
    rep.table("conditions", ["group", "value", "seeds", "T_K", "density_g_cm3", "K_GPa", "G_GPa", "E_GPa", "nu",
                             "yield_MPa", "strength_MPa"], rows,
              "K, G, E, Poisson's ratio, yield and compression strength of every condition of the study (mean ± "
              "standard deviation over its seeds; docs/theory/analysis.md), whatever the groups vary: the sections "
              "below compare them with the paper where the study has the paper's conditions")

    # ---- each condition against the first: the ratio a user's question is about, with its interval ----
    if len(conds) > 1:
        by_id = {r["id"]: r for r in runs}

        def per_seed(c, *path):
            return {get(by_id[i]["a"], "study", "seed", default=i): get(by_id[i]["a"], *path)
                    for i in c.get("runs", []) if i in by_id}
        # the reference: the first condition of the same group, or for a group of one condition (a
        # study of groups like "reference" and "binder_x2") the study's first condition
        first_of, count = {}, {}
        for c in conds:
            first_of.setdefault(c.get("group", ""), c)
            count[c.get("group", "")] = count.get(c.get("group", ""), 0) + 1
        rows = []
        quantities = (("E", ("moduli", "E_Pa")), ("G", ("moduli", "G_Pa")), ("K", ("moduli", "K_Pa")),
                      ("strength", ("strength", "strength_Pa")))
        for c in conds:
            ref = first_of[c.get("group", "")] if count[c.get("group", "")] > 1 else conds[0]
            if c is ref:
                continue
            row = [c.get("group", ""), f"{ref.get('group', '')} {str(ref.get('value', '')).strip(chr(39))}".strip(),
                   str(c.get("value", "")).strip("'")]
            how = ""
            for _, path in quantities:
                r, lo, hi, how = ratio_interval(per_seed(ref, *path), per_seed(c, *path))
                row.append(f"{fmt(r, 3)} [{fmt(lo, 3)}, {fmt(hi, 3)}]" if math.isfinite(lo) else fmt(r, 3))
            row.append(how)
            rows.append(row)
        if rows:
            rep.table("ratios_within_groups", ["group", "reference", "value"] + [f"{q}_ratio" for q, _ in quantities] +
                      ["interval"], rows,
                  "Each condition against the first of its group (a group of one condition: against the study's first "
                  "condition): "
                  "ratio of E, G, K and strength with its 95 % interval [low, high] (docs/theory/analysis.md): seeds run at "
                  "both conditions are paired (one microstructure, two conditions), otherwise the ratio of the means; an "
                  "interval that excludes 1 is a change the seeds resolve")

    # ---- quality checks ----
    rep.h("Run checks")
    rows = []
    for r in runs:
        a = r["a"]
        rows.append([r["id"], fmt(run_T(r), 4), fmt(get(a, "density_kg_m3"), 5),
                     f"{fmt(get(a, 'linear_window', 'lo'))}-{fmt(get(a, 'linear_window', 'hi'))}",
                     100 * get(a, "agreement", "punch_vs_minus_syy", "rms_relative"),
                     100 * get(a, "agreement", "M_relative_difference"),
                     get(a, "quasi_static", "ke_ie_max_from_window_start",
                         default=get(a, "quasi_static", "ke_ie_max_after_ramp")),
                     "YES" if get(a, "quasi_static", "flagged", default=False) else "no",
                     100 * get(a, "interpenetration", "share_of_compaction_at_window_end"),
                     100 * get(a, "interpenetration", "share_of_compaction"),
                     "YES" if get(a, "interpenetration", "flagged", default=False) else "no",
                     get(a, "energy_balance", "ratio_at_window_end"),
                     get(a, "energy_balance", "max_ratio"),
                     "YES" if get(a, "energy_balance", "flagged", default=False) else "no",
                     100 * get(a, "moduli_window_spread", "relative", default=float("nan"))])
    rep.table("run_checks", ["run", "T_K", "density_kg_m3", "linear_window_strain", "punch_vs_volume_rms_percent",
                             "M_volume_vs_punch_percent", "ke_ie_max_from_window_start", "ke_ie_flagged",
                             "interpenetration_window_end_percent", "interpenetration_end_percent",
                             "interpenetration_flagged", "energy_ratio_window_end", "energy_ratio_max",
                             "energy_flagged", "moduli_window_spread_percent"], rows,
              "Per-run checks: linear window, agreement of the punch and volume-averaged stress, KE/IE beyond the affine motion behind the punch, (KE - f m v^2/6)/IE, from the start of "
              "the linear window (where the moduli and the strength are read; docs/theory/analysis.md §5), "
              "share of the compaction taken by grains passing into each other at the end of the linear window and of "
              "the run (empty: run without the measure), and kinetic energy plus stress work over the punch work "
              "at the end of the linear window and at most from its start (above 1.05: energy made by the "
              "discretisation, docs/theory/analysis.md §5), and how much K, G or E move when refitted over the "
              "window's first or last three quarters (half the range, in % of the value; above 10 %: moduli that "
              "follow single rows, docs/theory/analysis.md §3)")
    # one line per distinct warning, with the runs it concerns (the same warning on seven runs was
    # seven copies in one paragraph)
    # seven copies in one paragraph): warnings of one kind (the text before its first ':') are one
    # line, with the first run's text and every run named; each run's own numbers are in run checks
    grouped = {}
    for r in runs:
        for w in r["a"].get("warnings", []):
            grouped.setdefault(w.split(":")[0], []).append((r["id"], w))
    for kind, items in grouped.items():
        ids = [i for i, _ in items]
        alike = "" if len({w for _, w in items}) == 1 else " (the others alike, with their own numbers: see the run checks)"
        rep.p(f"Warning, {len(ids)} run{'s' if len(ids) > 1 else ''} ({', '.join(ids)}): {items[0][1]}{alike}")

    # ---- Fig. 1b ----
    snap_run = next((r for r in truns if abs(run_T(r) - T0) < 0.5 and last_snapshot(r["dir"])), None) or \
        next((r for r in runs if last_snapshot(r["dir"])), None)
    if snap_run:
        try:
            import h5py
            with h5py.File(last_snapshot(snap_run["dir"]), "r") as h:
                x = np.array(h["position"])
                mat = np.array(h["material"]).ravel()
                vm = np.array(h["von_mises"]).ravel()
                vol = np.array(h["volume"]).ravel() if "volume" in h else None
            names = snapshot_material_names(snap_run)
            fig, ax = plt.subplots(1, 2, figsize=(11, 5.2))
            # Each particle drawn as a square of its own area (volume per unit depth), so the
            # picture is continuous like the paper's Fig. 1b and voids show as white.
            xmin, xmax = x[:, 0].min(), x[:, 0].max()
            ymin, ymax = x[:, 1].min(), x[:, 1].max()
            side = np.sqrt(np.median(vol)) if vol is not None and len(vol) else (xmax - xmin) / 200
            for a_ in ax:
                a_.set_xlim((xmin - side) * 1e3, (xmax + side) * 1e3)
                a_.set_ylim((ymin - side) * 1e3, (ymax + side) * 1e3)
                a_.set_aspect("equal")
            fig.canvas.draw()
            bbox = ax[0].get_window_extent()
            pts_per_mm = bbox.width / fig.dpi * 72 / ((xmax - xmin + 2 * side) * 1e3)
            s = (side * 1e3 * pts_per_mm) ** 2
            colours = ["#d9a441", "#2a7ab0", "#7f7f7f", "#59a14f", "#e15759"]
            for k in np.unique(mat):
                sel = mat == k
                label = names[int(k)] if int(k) < len(names) else f"material {int(k)}"
                ax[0].scatter(x[sel, 0] * 1e3, x[sel, 1] * 1e3, s=s, marker="s", linewidths=0,
                              color=colours[int(k) % len(colours)], label=label, rasterized=True)
            ax[0].legend(loc="upper right", fontsize=8, markerscale=max(1.0, 6 / max(np.sqrt(s), 1e-3)))
            # rasterized: one vector square per particle made a 40 MB SVG at 5 um cells
            sc = ax[1].scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=vm / 1e6, s=s, cmap="viridis", marker="s", linewidths=0,
                               rasterized=True)
            fig.colorbar(sc, ax=ax[1], label="von Mises stress (MPa)")
            for a_ in ax:
                a_.set_xlabel("x (mm)")
                a_.set_ylabel("y (mm)")
            ax[0].set_title("material")
            ax[1].set_title("von Mises stress")
            rep.h("Final state (cf. paper Fig. 1b)")
            rep.figure(fig, "fig1b_final_state", f"Final state of run {snap_run['id']} coloured by material and by stress", dpi=200)
        except Exception as exc:  # a snapshot from another code version must not stop the report
            rep.p(f"Fig. 1b skipped: could not read the last snapshot of {snap_run['id']} ({exc}).")
    else:
        rep.p("Fig. 1b skipped: no run has snapshots/snap_*.h5.")

    # ---- the paper's sections only where the study has the paper's sweeps, else one line why ----
    absent = []
    if not truns:
        absent.append("the temperature sections (Tables 2-3, Fig. 2-6, Eq. 13-15, the refit of the paper's Table 3 "
                      "and the model card) need a study group varying run.temperature, the paper's sweep over "
                      "temperature at porosity 0.08")
    if not druns:
        absent.append("the density sections (Fig. 7-9, Eq. 19-22) need a group varying packing.porosity, the "
                      "paper's sweep over porosity at 293 K")
    if absent:
        rep.p("Not in this report, as the study does not have the paper's conditions: " + "; ".join(absent) +
              f". This study's groups: {', '.join(groups_of_study)} (the paper's sweeps: examples/paper/quick.toml).")

    # ---- temperature group ----
    p2 = {(t["T_K"], t["source"]): t for t in paper.get("table2", [])}
    p3 = dict(zip(paper["table3"]["T_K"], paper["table3"]["strength_MPa"]))
    if truns:
        rep.h("Temperature (porosity 0.08): paper Section 3.1")
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for r in sorted(truns, key=run_T):
            e, p, v = curve(r)
            line, = ax.plot(100 * e, p / 1e6, label=f"{run_T(r):.0f} K ({r['id']})")
            ax.plot(100 * e, v / 1e6, "--", color=line.get_color(), lw=0.8,
                    label="volume average -σyy" if r is sorted(truns, key=run_T)[0] else None)
            # the paper's own curve at this temperature: its Eq. 15 (Eq. 13 x Eq. 14, its constants) on
            # the plateau it was fitted to
            pf, pn = paper["fits"]["temperature"], paper["fits"]["normalized_curve"]
            eg = np.linspace(0.5, 100 * max(e[-1], 0.005), 100)
            ax.plot(eg, eq13(run_T(r), pf["sigma0_MPa"], pf["alpha"], pf["T0_K"]) * eq14(eg, pn["A"], pn["B"], pn["n"]),
                    ":", color=line.get_color(), lw=1.2, label=f"paper Eq. 15, {run_T(r):.0f} K")
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("stress (MPa)")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        rep.figure(fig, "fig2_curves_vs_temperature",
                   "Stress-strain curves vs temperature (cf. Fig. 2): punch stress solid, volume average -σyy dashed, "
                   "the paper's curve (its Eq. 15 with its constants, from 0.5 % strain) dotted")

        rows = []
        for c in tconds:
            T = c["temperature_K"]
            pt = p2.get((int(round(T)), "this"), {})
            K, Ks = stat(c, "K_Pa", 1e-9)
            G, Gs = stat(c, "G_Pa", 1e-9)
            E, Es = stat(c, "E_Pa", 1e-9)
            M, Ms = stat(c, "M_Pa", 1e-9)
            nu, _ = stat(c, "nu")
            Ki, _ = stat(c, "K_isotropic_Pa", 1e-9)
            rows.append([T, K, Ks, pt.get("K_GPa", NAN), ratio(K, pt.get("K_GPa")), Ki, ratio(Ki, pt.get("K_GPa")),
                         G, Gs, pt.get("G_GPa", NAN),
                         ratio(G, pt.get("G_GPa")), E, Es, pt.get("E_GPa", NAN), ratio(E, pt.get("E_GPa")), M, nu,
                         stat(c, "K_volume_average_Pa", 1e-9)[0], stat(c, "G_volume_average_Pa", 1e-9)[0],
                         stat(c, "E_volume_average_Pa", 1e-9)[0]])
        rep.table("table2_moduli_vs_temperature",
                  ["T_K", "K_GPa", "K_std_GPa", "K_paper_GPa", "K_ratio", "K_iso_GPa", "K_iso_ratio", "G_GPa", "G_std_GPa", "G_paper_GPa", "G_ratio",
                   "E_GPa", "E_std_GPa", "E_paper_GPa", "E_ratio", "M_GPa", "nu", "K_volavg_GPa", "G_volavg_GPa",
                   "E_volavg_GPa"], rows,
                  "Moduli vs temperature beside the paper's Table 2 (E = 9KG/(3K+G); K, G, E from the punch and wall "
                  "reactions, K = (M + lambda + lambda_z)/3 with the measured out-of-plane stress; K_iso = (M + 2 lambda)/3 "
                  "assumes sigma_zz = sigma_xx, the paper does not say which it used; *_volavg from the volume-averaged "
                  "stresses)")

        fig, ax = plt.subplots(figsize=(6, 4.5))
        Ts = [c["temperature_K"] for c in tconds]
        for key, lab, mk in (("K_Pa", "K", "o"), ("G_Pa", "G", "s"), ("E_Pa", "E", "^")):
            m = [stat(c, key, 1e-9)[0] for c in tconds]
            s = [stat(c, key, 1e-9)[1] for c in tconds]
            eb = ax.errorbar(Ts, m, yerr=s, marker=mk, capsize=3, label=f"{lab} (ours)")
            pts = [(t["T_K"], t.get(lab + "_GPa")) for t in paper.get("table2", []) if t["source"] == "this" and t.get(lab + "_GPa")]
            if pts:
                ax.plot(*zip(*pts), mk, mfc="none", color=eb[0].get_color(), ms=9, label=f"{lab} (paper)")
        exp = [(t["T_K"], t["E_GPa"]) for t in paper.get("table2", []) if t["source"] == "exp"]
        if exp:
            ax.plot(*zip(*exp), "kx", label="E experiment (paper ref. 32)")
        ax.set_xlabel("temperature (K)")
        ax.set_ylabel("modulus (GPa)")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        rep.figure(fig, "fig3_moduli_vs_temperature", "Moduli vs temperature (cf. Fig. 3); open symbols: paper Table 2")

        rows = []
        for c in tconds:
            T = c["temperature_K"]
            s, ss = stat(c, "strength_Pa", 1e-6)
            y, ys = stat(c, "yield_stress_Pa", 1e-6)
            ye, _ = stat(c, "yield_strain")
            pv = p3.get(int(round(T)), NAN)
            pk, _ = stat(c, "peak_strength_Pa", 1e-6)
            rows.append([T, s, ss, pv, ratio(s, pv), pk, f"{rising(c, runs)}/{len(c.get('runs', []))}", y, ys,
                         100 * ye if math.isfinite(ye) else NAN])
        rep.table("table3_strength_vs_temperature",
                  ["T_K", "strength_MPa", "strength_std_MPa", "strength_paper_MPa", "strength_ratio", "peak_MPa",
                   "runs_still_rising", "yield_MPa", "yield_std_MPa", "yield_strain_percent"], rows,
                  "Compression strength and yield vs temperature beside the paper's Table 3. Strength = the plateau "
                  "level as the paper reads it: the mean punch stress from 0.5 to 3 % strain (the paper's Eq. 14 "
                  "averages 1.011 σc there); peak = the largest stress up to 3 % (Eq. 14: 1.060 σc at 2.88 %) "
                  "(docs/theory/analysis.md §4). "
                  f"(paper: yield 13-25 MPa, read by eye where the linear stage ends, near "
                  f"{100 * paper['curves']['linear_stage_ends_at_strain']:.1f} %; ours: where the elastic line meets the "
                  "plateau line, docs/theory/analysis.md §4, which on a flat plateau lies close to the strength: compare "
                  "the two yields as trends, not as numbers). runs_still_rising: runs whose stress still rises at the "
                  "end of the strength window: they have no plateau, and their strength and peak are lower bounds")

        fig, ax = plt.subplots(figsize=(6, 4.5))
        ax.errorbar(Ts, [stat(c, "strength_Pa", 1e-6)[0] for c in tconds],
                    yerr=[stat(c, "strength_Pa", 1e-6)[1] for c in tconds], fmt="o", capsize=3, label="ours")
        ax.plot(paper["table3"]["T_K"], paper["table3"]["strength_MPa"], "s", mfc="none", ms=9, label="paper Table 3")
        Tg = np.linspace(min(Ts + [293]) - 5, max(Ts + [373]) + 5, 100)
        for key, style in (("nonlinear", "-"), ("loglinear", ":")):
            f = get(fits, "eq13", key, default=None)
            if f:
                ax.plot(Tg, eq13(Tg, par(f, "sigma0"), par(f, "alpha"), T0) / 1e6, style, label=f"Eq. 13 ours, {key}")
        pf = paper["fits"]["temperature"]
        ax.plot(Tg, eq13(Tg, pf["sigma0_MPa"], pf["alpha"], pf["T0_K"]), "k--", lw=0.8, label="Eq. 13 paper")
        ax.set_xlabel("temperature (K)")
        ax.set_ylabel("compression strength (MPa)")
        # a log axis when ours and the paper's differ by more than 3x, so that neither is squashed flat
        ours_s = [stat(c, "strength_Pa", 1e-6)[0] for c in tconds]
        spread = [v for v in ours_s + list(paper["table3"]["strength_MPa"]) if math.isfinite(v) and v > 0]
        log_axis = bool(spread) and max(spread) / min(spread) > 3
        if log_axis:
            ax.set_yscale("log")
            for axis in (ax.yaxis,):  # plain numbers (20, 30, 60 MPa), not 2x10^1
                axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
                axis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        rep.figure(fig, "fig4_strength_vs_temperature", "Compression strength vs temperature (cf. Fig. 4)"
                   + ("; logarithmic axis: ours and the paper's differ by more than 3x" if log_axis else ""))

        fig, ax = plt.subplots(figsize=(6, 4.5))
        w = get(fits, "eq14", "window_percent", default=[0.5, 3])
        top = NAN  # the highest sigma/sigma_c of ours up to the window's end
        for r in sorted(truns, key=run_T):
            e, p, _ = curve(r)
            sc = get(r["a"], "strength", "strength_Pa")
            ax.plot(100 * e, p / sc, label=f"{run_T(r):.0f} K")
            inside = (100 * e <= w[1]) & np.isfinite(p)
            if inside.any() and sc and math.isfinite(sc):
                top = max(top, float(np.max(p[inside] / sc))) if math.isfinite(top) else float(np.max(p[inside] / sc))
        f14 = get(fits, "eq14", "fit", default=None)
        eg = np.linspace(0.05, max(5.0, 100 * max((get(r["a"], "strength", "strength_window_end_strain") for r in truns), default=0.05)), 200)
        pn = paper["fits"]["normalized_curve"]
        ax.plot(eg, eq14(eg, pn["A"], pn["B"], pn["n"]), "k--", lw=0.8, label="Eq. 14 paper")
        if f14:
            ax.plot(eg, eq14(eg, par(f14, "A"), par(f14, "B"), par(f14, "n")), "k-", lw=1.2, label="Eq. 14 ours")
        ax.axvspan(w[0], w[1], color="0.9", zorder=0, label="Eq. 14 fitting window")
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("σ / σc")
        ax.set_ylim(0, max(1.3, 1.05 * top) if math.isfinite(top) else 1.3)  # curves still rising go past 1.3
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        e_peak = (-pn["A"] / (pn["B"] * pn["n"])) ** (1.0 / (pn["n"] - 1.0))
        rep.figure(fig, "fig5_normalized_curves",
                   "Normalised stress-strain curves (cf. Fig. 5): σ/σc against strain in %, one coloured line per "
                   "temperature, each run's punch stress σ divided by its own compression strength σc (the mean punch "
                   f"stress from {w[0]:g} to {w[1]:g} % strain, so a curve rises above 1 where the stress climbs past its "
                   f"plateau mean: ours reach at most {fmt(top, 3)} up to {w[1]:g} %); black dashed, the paper's Eq. 14, "
                   f"σ/σc = A ε + B ε^n with ε in %, at its A = {pn['A']}, B = {pn['B']}, n = {pn['n']} (peak "
                   f"{max_paper_eq14(pn):.3f} at {e_peak:.2f} %); " +
                   (f"black solid, Eq. 14 fitted to our curves at T0 = {T0:.0f} K (constants under 'Fitted constants'); "
                    if f14 else "Eq. 14 not fitted to ours (see 'Fitted constants'); ") +
                   f"grey band, the fitting window {w[0]:g}-{w[1]:g} %")

        f13 = get(fits, "eq13", "nonlinear", default=None)
        if f13 and f14:
            fig, ax = plt.subplots(figsize=(6, 4.5))
            eg = np.linspace(w[0], w[1], 100)
            for r in sorted(truns, key=run_T):
                e, p, _ = curve(r)
                keep = (100 * e >= w[0] * 0.5)
                pts, = ax.plot(100 * e[keep][::4], p[keep][::4] / 1e6, ".", ms=3)
                law = eq13(run_T(r), par(f13, "sigma0"), par(f13, "alpha"), T0) * eq14(eg, par(f14, "A"), par(f14, "B"), par(f14, "n"))
                ax.plot(eg, law / 1e6, "-", color=pts.get_color(), label=f"Eq. 15, {run_T(r):.0f} K")
            ax.set_xlabel("strain (%)")
            ax.set_ylabel("stress (MPa)")
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
            rep.figure(fig, "fig6_eq15_vs_simulation",
                       "Eq. 15 (ours, on its plateau window) against the simulation points (cf. Fig. 6)")

    # ---- density group ----
    hs = fits.get("density_law", {})
    phs = paper["fits"]["hashin_shtrikman"]
    rho0 = get(hs, "rho0_kg_m3", default=phs["rho0_g_cm3"] * 1e3)
    if druns:
        rep.h("Density (293 K): paper Section 3.2")
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for r in sorted(druns, key=lambda r: get(r["a"], "density_kg_m3")):
            e, p, _ = curve(r)
            line, = ax.plot(100 * e, p / 1e6, label=f"{get(r['a'], 'density_kg_m3') / 1e3:.3f} g/cm³ ({r['id']})")
            s99 = r["a"].get("stress_at_99_tmd") or {}
            if s99.get("punch_stress_Pa") is not None:  # where this specimen reaches 99 % TMD
                ax.plot(100 * s99["strain"], s99["punch_stress_Pa"] / 1e6, "o", ms=7, color=line.get_color(), mec="k", zorder=5)
        ax.axhline(paper["curves"]["stress_at_99pct_TMD_MPa"], color="k", lw=0.6, ls=":", label="paper: 42.3 MPa at 99 % TMD")
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("stress (MPa)")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        rep.figure(fig, "fig7_curves_vs_density",
                   "Stress-strain curves vs density (cf. Fig. 7): punch stress; circles (black rim) where each specimen "
                   "reaches 99 % of the theoretical density (runs that get there); dotted, the paper's 42.3 MPa "
                   "at 99 % TMD (the paper gives no curve law per density to draw)")

        rows = []
        for c in dconds:
            rho, rs = stat(c, "density_kg_m3")
            K, Ks = stat(c, "K_Pa", 1e-9)
            G, Gs = stat(c, "G_Pa", 1e-9)
            E, Es = stat(c, "E_Pa", 1e-9)
            s, ss = stat(c, "strength_Pa", 1e-6)
            # the paper's law at the same relative density 1 - porosity (ours: rho over our own TMD)
            x = rho / rho0
            Gp = phs["GU_GPa"] * phs["G_k"] * x ** phs["G_n"]
            Kp = phs["KU_GPa"] * phs["K_k"] * x ** phs["K_n"]
            s99, s99s = stat(c, "stress_at_99_tmd_Pa", 1e-6)
            p99 = paper["curves"]["stress_at_99pct_TMD_MPa"]
            rows.append([rho / 1e3, rs / 1e3, K, Ks, Kp, ratio(K, Kp), G, Gs, Gp, ratio(G, Gp), E, Es, s, ss,
                         f"{rising(c, runs)}/{len(c.get('runs', []))}", s99, s99s, p99, ratio(s99, p99)])
        rep.table("moduli_vs_density",
                  ["density_g_cm3", "density_std_g_cm3", "K_GPa", "K_std_GPa", "K_paper_eq22_GPa", "K_ratio", "G_GPa",
                   "G_std_GPa", "G_paper_eq21_GPa", "G_ratio", "E_GPa", "E_std_GPa", "strength_MPa", "strength_std_MPa",
                   "runs_still_rising", "stress_at_99_tmd_MPa", "stress_at_99_tmd_std_MPa", "stress_at_99_tmd_paper_MPa",
                   "stress_at_99_tmd_ratio"],
                  rows, "Moduli and strength vs density beside the paper's Eq. 21-22 (its fit of its Fig. 8 data); "
                  "runs_still_rising: runs without a plateau (strength a lower bound); stress_at_99_tmd: the punch "
                  "stress where the box reaches 99 % of the theoretical density (the paper's Fig. 7: 42.3 MPa for "
                  "every density; empty where the runs end before it)")

        fig, ax = plt.subplots(figsize=(6, 4.5))
        rhos = [stat(c, "density_kg_m3")[0] / 1e3 for c in dconds]
        rline = np.linspace(min(rhos), max(rhos), 50)
        xl = rline * 1e3 / rho0
        Kl = phs["KU_GPa"] * phs["K_k"] * xl ** phs["K_n"]
        Gl = phs["GU_GPa"] * phs["G_k"] * xl ** phs["G_n"]
        paper_lines = {"K": Kl, "G": Gl, "E": 9 * Kl * Gl / (3 * Kl + Gl)}
        for key, lab, mk in (("K_Pa", "K", "o"), ("G_Pa", "G", "s"), ("E_Pa", "E", "^")):
            eb = ax.errorbar(rhos, [stat(c, key, 1e-9)[0] for c in dconds], yerr=[stat(c, key, 1e-9)[1] for c in dconds],
                             marker=mk, capsize=3, label=f"{lab} (ours, mean ± std over seeds)")
            ax.plot(rline, paper_lines[lab], "--", color=eb[0].get_color(), lw=1, label=f"{lab} (paper Eq. 21-22)")
        ax.set_xlabel("density (g/cm³)")
        ax.set_ylabel("modulus (GPa)")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: never over the data
        rep.figure(fig, "fig8_moduli_vs_density", "Moduli vs density (cf. Fig. 8): ours with error bars (std over "
                   "seeds), the paper's Eq. 21-22 dashed (E from them, 9KG/(3K+G))")

        fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
        rg = np.linspace(min(rhos + [1.70]), max(rhos + [1.942]), 100)
        for i, (lab, key, U) in enumerate((("G", "G_Pa", phs["GU_GPa"]), ("K", "K_Pa", phs["KU_GPa"]))):
            ax[i].errorbar(rhos, [stat(c, key, 1e-9)[0] for c in dconds], yerr=[stat(c, key, 1e-9)[1] for c in dconds],
                           fmt="o", capsize=3, label="ours")
            f = hs.get(lab)
            if f:
                ax[i].plot(rg, U * par(f, "k") * (rg * 1e3 / rho0) ** par(f, "n"), "-", label=f"Eq. {21 if lab == 'G' else 22} ours")
            ax[i].plot(rg, U * phs[lab + "_k"] * (rg * 1e3 / rho0) ** phs[lab + "_n"], "k--", lw=0.8,
                       label=f"Eq. {21 if lab == 'G' else 22} paper (at our relative density)")
            ax[i].set_xlabel("density (g/cm³)")
            ax[i].set_ylabel(f"{lab} (GPa)")
            ax[i].legend(fontsize=7)
        fitted = [lab for lab in ("G", "K") if hs.get(lab)]
        rep.figure(fig, "fig9_density_law",
                   "Shear modulus G (left) and bulk modulus K (right) in GPa against density in g/cm³ (cf. Fig. 9a, b): "
                   "circles with error bars, ours (mean ± standard deviation over the seeds of each density condition); " +
                   (f"coloured solid line, the density law fitted to ours ({' and '.join(fitted)}: Eq. 21 for G, Eq. 22 "
                    f"for K), X = X^U k (ρ/ρ0)^n with G^U = {phs['GU_GPa']}, K^U = {phs['KU_GPa']} GPa and ρ0 = our "
                    f"theoretical density {rho0 / 1e3:.4f} g/cm³; " if fitted else
                    "the density law is not fitted to ours (see 'Fitted constants'); ") +
                   f"black dashed, the paper's Eq. 21-22 with its constants (G: k = {phs['G_k']}, n = {phs['G_n']}; "
                   f"K: k = {phs['K_k']}, n = {phs['K_n']}) at our relative density ρ/ρ0 (the paper's ρ0 is "
                   f"{phs['rho0_g_cm3']} g/cm³)")

    # ---- the paper's trends, one by one ----
    trend_section(rep, tconds, dconds, p2, p3, phs)

    # ---- fitted constants (the paper's Eq. 13-14 on its temperature sweep, Eq. 19-22 on its density
    # sweep): a study without those sweeps has none, and the line above says why ----
    rows = []

    unconverged = []

    def add(name, fit, pname, paper_value, scale=1.0, unit=""):
        if not fit:
            return
        v = par(fit, pname)
        lo, hi = ci(fit, pname)
        method = fit.get("method", "")
        if fit.get("converged") is False:  # a stalled iteration is said, never shown as a result
            method += " (NOT CONVERGED)"
            unconverged.append(f"{name}: {fit.get('note', 'the iteration did not converge')}")
        rows.append([name, v * scale, lo * scale, hi * scale, paper_value, ratio(v * scale, paper_value), unit, method])

    pf = paper["fits"]["temperature"]
    pn = paper["fits"]["normalized_curve"]
    add("Eq. 13 sigma0", get(fits, "eq13", "nonlinear", default=None), "sigma0", pf["sigma0_MPa"], 1e-6, "MPa")
    add("Eq. 13 alpha", get(fits, "eq13", "nonlinear", default=None), "alpha", pf["alpha"])
    add("Eq. 13 sigma0 (log-linear)", get(fits, "eq13", "loglinear", default=None), "sigma0", pf["sigma0_MPa"], 1e-6, "MPa")
    add("Eq. 13 alpha (log-linear)", get(fits, "eq13", "loglinear", default=None), "alpha", pf["alpha"])
    for k in ("A", "B", "n"):
        add(f"Eq. 14 {k}", get(fits, "eq14", "fit", default=None), k, pn[k], unit="strain in %" if k == "A" else "")
    for lab in ("G", "K"):
        add(f"Eq. {21 if lab == 'G' else 22} k ({lab})", hs.get(lab), "k", phs[lab + "_k"])
        add(f"Eq. {21 if lab == 'G' else 22} n ({lab})", hs.get(lab), "n", phs[lab + "_n"])
    if truns or druns:
        rep.h("Fitted constants")
    if rows:
        rep.table("fitted_constants", ["constant", "ours", "ci_low", "ci_high", "paper", "ratio", "unit", "method"],
                  rows, f"Fitted constants with {100 * fits.get('confidence', 0.95):.0f} % confidence intervals beside "
                  "the paper's")
    if unconverged:
        rep.p("WARNING: these fits did not converge, and their constants are not results: " + "; ".join(unconverged))
    # why a fit of a sweep the study has is missing (too few temperatures, ...); the sweeps it does not
    # have are named once, above
    for key, present in (("eq13", truns), ("eq14", truns), ("density_law", druns)):
        if present and get(fits, key, "note", default=None):
            rep.p(f"{key}: {fits[key]['note']}")
    if get(fits, "eq14", "fit", default=None):
        rep.p(f"Eq. 14 is fitted at T0 = {T0:.0f} K on the plateau window {w[0]}-{w[1]} % strain with strain in percent "
              "(the form has an infinite initial slope; it is not meant for the elastic stage). Our curves are "
              "normalised by their strength σc, the plateau level (the mean stress from 0.5 to 3 % strain), as the "
              "paper's are: its constants average 1.011 and peak at σ/σc = "
              f"{max_paper_eq14(pn):.4f} there, so a perfect reproduction of the paper's curve would give back its "
              "A, B and n within about 1 %.")

    refit = fits.get("paper_table3_refit", {})
    if truns and refit.get("nonlinear"):
        nl, ll = refit["nonlinear"], refit["loglinear"]
        rep.h("Refit of the paper's own Table 3 (Eq. 13)", 3)
        rep.p(f"Nonlinear least squares on σc gives σ0 = {par(nl, 'sigma0') / 1e6:.2f} MPa, α = {par(nl, 'alpha'):.3f}; "
              f"the log-linear fit gives σ0 = {par(ll, 'sigma0') / 1e6:.2f} MPa, α = {par(ll, 'alpha'):.3f}. "
              + refit_verdict(nl, ll, pf))

    hs_section(rep, conds, phs, paper_conditions=bool(truns or druns))

    # ---- model card ----
    f13 = get(fits, "eq13", "nonlinear", default=None)
    f14 = get(fits, "eq14", "fit", default=None)
    if f13 and f14:
        w = get(fits, "eq14", "window_percent", default=[0.5, 3])
        Ts_card = sorted({round(run_T(r)) for r in truns}) or [T0]
        card = {
            "format": "pbxmpm-model-card-1",
            "material": "TATB/F2314 PBX (mesoscale MPM, study '%s')" % study.get("name", "?"),
            "law": "sigma = sigma0 * exp(alpha * (1 - T/T0)) * (A * e + B * e**n), e = compressive strain in PERCENT, "
                   "sigma compressive stress in Pa (paper Eq. 15)",
            "constants": {
                "sigma0_Pa": {"value": par(f13, "sigma0"), "ci95": list(ci(f13, "sigma0"))},
                "alpha": {"value": par(f13, "alpha"), "ci95": list(ci(f13, "alpha"))},
                "T0_K": T0,
                "A": {"value": par(f14, "A"), "ci95": list(ci(f14, "A"))},
                "B": {"value": par(f14, "B"), "ci95": list(ci(f14, "B"))},
                "n": {"value": par(f14, "n"), "ci95": list(ci(f14, "n"))},
            },
            "valid_strain_percent": w,
            "valid_temperature_K": [min(Ts_card), max(Ts_card)],
            "elastic": {c_["temperature_K"]: {"K_Pa": stat(c_, "K_Pa")[0], "G_Pa": stat(c_, "G_Pa")[0],
                                              "E_Pa": stat(c_, "E_Pa")[0]} for c_ in tconds},
            "density_law": {lab: {"law": f"{lab} = {lab}U * k * (rho/rho0)**n", f"{lab}U_Pa": get(hs, f"{lab}U_Pa"),
                                  "rho0_kg_m3": rho0,
                                  "k": {"value": par(hs[lab], "k"), "ci95": list(ci(hs[lab], "k"))},
                                  "n": {"value": par(hs[lab], "n"), "ci95": list(ci(hs[lab], "n"))}}
                            for lab in ("G", "K") if hs.get(lab)},
            "curves_file": "model_card_curves.csv",
            "note": "Below the window's lower end the law over-predicts (infinite initial slope): use the elastic "
                    "moduli there.",
        }
        card["elastic"] = {str(k): v for k, v in card["elastic"].items()}
        with open(os.path.join(out, "model_card.json"), "w") as f:
            json.dump(finite_or_none(card), f, indent=2, allow_nan=False, default=lambda o: None)
        eg = np.linspace(w[0], w[1], 51)
        with open(os.path.join(out, "model_card_curves.csv"), "w", newline="") as f:
            wtr = csv.writer(f)
            wtr.writerow(["strain"] + [f"stress_T{T:.0f}K_Pa" for T in Ts_card])
            for e in eg:
                wtr.writerow([f"{e / 100:.6g}"] + [f"{eq13(T, par(f13, 'sigma0'), par(f13, 'alpha'), T0) * eq14(e, par(f14, 'A'), par(f14, 'B'), par(f14, 'n')):.6g}" for T in Ts_card])
        rep.h("Macroscale model card")
        rep.p("model_card.json holds the fitted Eq. 15 (and the density law) with intervals and validity ranges; "
              "model_card_curves.csv tabulates stress (Pa) against strain (fraction) for each simulated temperature.")
    elif truns:
        rep.p("Model card not written: Eq. 13 or Eq. 14 could not be fitted from this study.")

    rep.write(f"pbxmpm report: {study.get('name', os.path.basename(os.path.abspath(args.study)))}" +
              (" (partial)" if left_out else ""))
    print(f"make_report: wrote {out}/report.md, report.html and {len(glob.glob(os.path.join(out, '*.png')))} figures")


if __name__ == "__main__":
    main()
