#!/usr/bin/python3
"""Plot material point driver curves (CSV files written by `pbxmpm material`).

Left panel: stress against strain for constant-rate paths (LABEL=FILE arguments).
Right panel (optional, --relax LABEL=FILE): relaxation modulus stress/strain against log time
for step_shear runs.

Example (the F2314 temperature figure of docs/theory/materials.md):
  /usr/bin/python3 tools/report/plot_material_curves.py --out docs/figures/f2314_temperature.png \
      "293 K=f2314_293.csv" "333 K=f2314_333.csv" --relax "293 K=relax_293.csv" ...
"""
import argparse
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0:
        sys.exit(f"plot_material_curves: {path} has no rows")
    return data


def split(arg):
    if "=" not in arg:
        sys.exit(f"plot_material_curves: expected LABEL=FILE, got '{arg}'")
    label, path = arg.split("=", 1)
    return label, path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("curves", nargs="+", help="LABEL=FILE of constant-rate runs")
    ap.add_argument("--relax", nargs="*", default=[], help="LABEL=FILE of step_shear runs")
    ap.add_argument("--y", default="stress_xy_Pa", help="stress column to plot (default stress_xy_Pa)")
    ap.add_argument("--xlabel", default="shear strain (%)")
    ap.add_argument("--ylabel", default="shear stress (MPa)")
    ap.add_argument("--title", default="")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()

    ncol = 2 if a.relax else 1
    fig, axes = plt.subplots(1, ncol, figsize=(5.2 * ncol, 4.0), squeeze=False)
    ax = axes[0][0]
    for arg in a.curves:
        label, path = split(arg)
        d = read(path)
        if a.y not in d.dtype.names:
            sys.exit(f"plot_material_curves: {path} has no column '{a.y}' (has {', '.join(d.dtype.names)})")
        x = 100.0 * np.abs(d["strain"])
        y = np.abs(d[a.y]) / 1e6
        ax.plot(x, y, label=label)
        secant = y[-1] / (x[-1] / 100.0) if x[-1] > 0 else float("nan")
        print(f"{label}: final strain {x[-1]:.3f} %, stress {y[-1]:.4g} MPa, secant {secant:.4g} MPa")
    ax.set_xlabel(a.xlabel)
    ax.set_ylabel(a.ylabel)
    ax.grid(alpha=0.3)
    ax.legend()
    if a.title:
        ax.set_title(a.title, fontsize=10)
    if a.relax:
        ax = axes[0][1]
        for arg in a.relax:
            label, path = split(arg)
            d = read(path)
            t = d["time_s"]
            keep = (t > 0) & (d["strain"] != 0)
            ax.semilogx(t[keep], d[a.y][keep] / d["strain"][keep] / 1e6, label=label)
        ax.set_xlabel("time after the strain step (s)")
        ax.set_ylabel("relaxation modulus G(t) (MPa)")
        ax.set_title("step shear relaxation", fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend()
    fig.tight_layout()
    fig.savefig(a.out, dpi=130)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
