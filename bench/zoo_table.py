#!/usr/bin/env python3
"""The machine-zoo table (issue 10): runs `trueaxis demo` (calibration campaign, fit, held-out
working day with the compensator in its loop) on every machine description in examples/machines/
and writes one Markdown table: machine, axis, state, A off, A on, R on and the score
A_on / max(10 % of A_off, 1.3 x R_on); 'must' marks A_on <= max(20 % of A_off, 2 x R_on), and
fails any row where compensation made A worse or more than doubled the repeatability (R_on > 2 R_off
+ 2 µm: the correction moved during the test), which the R_on term would otherwise excuse.

Usage (from the repository root, after a build):
  /usr/bin/python3 bench/zoo_table.py [--seed 3] [--out out/zoo] [--trueaxis build/apps/trueaxis/trueaxis] [machines...]
"""
import argparse, glob, json, os, subprocess, sys, time

ap = argparse.ArgumentParser()
ap.add_argument("--seed", type=int, default=3)
ap.add_argument("--out", default="out/zoo")
ap.add_argument("--trueaxis", default="build/apps/trueaxis/trueaxis")
ap.add_argument("--baseline", action="store_true",
                help="fit without the coolant memory and fitted envelope (demo --no-coolant-memory): the model before them")
ap.add_argument("--no-coolant-rest", action="store_true",
                help="calibrate without the campaign's stop under coolant (demo --no-coolant-rest), for comparison")
ap.add_argument("--ambient-hours", default="",
                help="hours of the day the campaign's ambient days measure at, e.g. 10,19 or 14 (demo --ambient-hours; default: the demo's)")
ap.add_argument("--secondary-key-ridge", default="",
                help="ridge on the bearing key's gain (demo --secondary-key-ridge; 0: the seed's plain least squares)")
ap.add_argument("--key-offsets", default="",
                help="each key's own pivot: auto, on, off (demo --key-offsets; off: one pivot Px, the seed's form)")
ap.add_argument("--no-lag-fall", action="store_true",
                help="fit one lag tau both ways (demo --no-lag-fall): the lag before the longer fall")
ap.add_argument("machines", nargs="*")
a = ap.parse_args()
machines = a.machines or sorted(glob.glob("examples/machines/*.toml"))
rows, worst = [], []
for m in machines:
    name = os.path.splitext(os.path.basename(m))[0]
    out = os.path.join(a.out, name)
    t0 = time.time()
    r = subprocess.run([a.trueaxis, "demo", "--machine", m, "--seed", str(a.seed), "--out", out, "--quiet"] + (["--no-coolant-memory"] if a.baseline else []) + (["--no-coolant-rest"] if a.no_coolant_rest else []) + (["--ambient-hours", a.ambient_hours] if a.ambient_hours else []) + (["--secondary-key-ridge", a.secondary_key_ridge] if a.secondary_key_ridge else []) + (["--key-offsets", a.key_offsets] if a.key_offsets else []) + (["--no-lag-fall"] if a.no_lag_fall else []),
                       capture_output=True, text=True)
    if r.returncode != 0:
        print(f"{name}: demo failed (exit {r.returncode}): {r.stderr.strip()}", file=sys.stderr)
        rows.append((name, "-", "demo failed", "", "", "", "", ""))
        continue
    bounds = [l for l in r.stdout.splitlines() if l.startswith("bounds:")]
    for on in sorted(glob.glob(os.path.join(out, "day", "*_on.csv"))):
        off = on[:-len("_on.csv")] + "_off.csv"
        axis, state = os.path.basename(on)[:-len("_on.csv")].split("_", 1)
        ev = {}
        for k, f in (("on", on), ("off", off)):
            j = subprocess.run([a.trueaxis, "analyze", f, "--json"], capture_output=True, text=True)
            ev[k] = json.loads(j.stdout)
        a_off, a_on, r_on = ev["off"]["A_um"], ev["on"]["A_um"], ev["on"]["R_um"]
        score = a_on / max(0.1 * a_off, 1.3 * r_on)
        # A compensation that makes the axis worse, or scatters it (R_on far above R_off), must not
        # pass through the R_on term of the criterion: it fails whatever its score.
        r_off = ev["off"]["R_um"]
        must = a_on <= max(0.2 * a_off, 2 * r_on) and a_on < a_off and r_on <= 2 * r_off + 2
        rows.append((name, axis, state.replace("_", " "), a_off, a_on, r_on, score, must))
    print(f"{name}: {time.time() - t0:.1f} s; {bounds[0] if bounds else ''}", file=sys.stderr)

print("| machine | axis | state | A off (µm) | A on (µm) | R on (µm) | score | must |")
print("|---|---|---|---:|---:|---:|---:|---|")
for row in rows:
    if row[1] == "-":
        print(f"| {row[0]} | - | {row[2]} | | | | | |")
        continue
    n, ax, st, aoff, aon, ron, sc, must = row
    print(f"| {n} | {ax} | {st} | {aoff:.1f} | {aon:.1f} | {ron:.1f} | {sc:.2f} | {'yes' if must else '**no**'} |")
ok = [r for r in rows if r[1] != "-"]
print(f"\n{len(ok)} rows: {sum(1 for r in ok if r[7])} under the must line, {sum(1 for r in ok if r[6] <= 1)} at the goal (score <= 1); "
      f"worst score {max(r[6] for r in ok):.2f} ({max(ok, key=lambda r: r[6])[0]} {max(ok, key=lambda r: r[6])[1]} {max(ok, key=lambda r: r[6])[2]})")
