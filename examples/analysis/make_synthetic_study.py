#!/usr/bin/python3
"""Writes a small synthetic study directory (the format of `pbxmpm study`) to try `pbxmpm report`
without running the engine:

    /usr/bin/python3 examples/analysis/make_synthetic_study.py /tmp/synthetic_study
    pbxmpm report /tmp/synthetic_study

Each run is confined compression of an elastic solid with the paper's Table 2 moduli (temperature
group) or Eq. 21-22 moduli (density group) that softens onto the paper's Eq. 14 plateau scaled by
its Table 3 strength: sigma = min(M e, sigma_c (A e% + B e%^n)); lateral stress = (lambda/M) sigma.
The numbers are made up from the paper's own fits: a report on them checks the plumbing, not physics.
"""
import json
import os
import sys

A, B, N = -0.1206, 1.084, 0.2467
COLUMNS = ("step,t_s,dt_s,strain,punch_velocity_m_s,punch_force_N_per_m,punch_stress_Pa,wall_left_force_N_per_m,"
           "wall_right_force_N_per_m,wall_bottom_force_N_per_m,wall_stress_Pa,sxx_Pa,syy_Pa,szz_Pa,sxy_Pa,"
           "kinetic_J_per_m,internal_J_per_m,dissipated_J_per_m,punch_work_J_per_m,ke_ie")


def write_run(d, K, G, sc, T, rho, group, seed, ramp=0.0005, rows=241, emax=0.04):
    os.makedirs(d, exist_ok=True)
    M, lam = K + 4 * G / 3, K - 2 * G / 3
    with open(os.path.join(d, "history.csv"), "w") as f:
        f.write(COLUMNS + "\n")
        for i in range(rows):
            e = emax * i / (rows - 1)
            s = min(M * e, sc * (A * 100 * e + B * (100 * e) ** N)) if e > 0 else 0.0
            w = lam / M * s
            f.write(f"{i},{e / 250:.9g},1e-9,{e:.9g},0.3,{s * 1e-3:.9g},{s:.9g},{w * 1.2e-3:.9g},{w * 1.2e-3:.9g},"
                    f"{s * 1e-3:.9g},{w:.9g},{-w:.9g},{-s:.9g},{-w:.9g},0,1,1,0,1,{0.3 if e < ramp else 0.01}\n")
    run = {"status": "finished", "code_version": "synthetic", "temperature_K": T, "ramp_strain": ramp,
           "mass_scaling": 100, "specimen": {"density_kg_m3": rho, "porosity": 1 - rho / 1942, "tmd_kg_m3": 1942,
                                             "width_m": 1e-3, "height_m": 1.2e-3},
           "study": {"group": group, "temperature_K": T, "density_g_cm3": rho / 1e3, "seed": seed}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f, indent=2)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    runs = []
    table2 = {293: (2.79e9, 1.30e9), 333: (2.76e9, 1.09e9), 353: (2.77e9, 0.98e9), 373: (2.63e9, 0.77e9)}
    table3 = {293: 32.8e6, 333: 28.2e6, 353: 24.1e6, 373: 15.6e6}
    for T, (K, G) in table2.items():
        rid = f"T{T}_s1"
        write_run(os.path.join(out, "runs", rid), K, G, table3[T], T, 1787, "temperature", 1)
        runs.append({"id": rid, "dir": f"runs/{rid}", "group": "temperature", "temperature_K": T,
                     "density_g_cm3": 1.787, "seed": 1})
    for rho in (1761, 1787, 1839):
        x = rho / 1942
        rid = f"rho{rho}_s1"
        write_run(os.path.join(out, "runs", rid), 10.52e9 * 0.696 * x ** 12.01, 10.84e9 * 0.318 * x ** 12.11,
                  32.8e6 * (x / 0.9202) ** 6, 293, rho, "density", 1)
        runs.append({"id": rid, "dir": f"runs/{rid}", "group": "density", "temperature_K": 293,
                     "density_g_cm3": rho / 1e3, "seed": 1})
    with open(os.path.join(out, "study.json"), "w") as f:
        json.dump({"name": "synthetic", "runs": runs}, f, indent=2)
    print(f"wrote {out}/study.json and {len(runs)} runs; now: pbxmpm report {out}")


if __name__ == "__main__":
    main()
