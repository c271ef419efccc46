#!/usr/bin/env python3
"""Re-fit a machine-zoo run with other fit options and score its working day again, without running
the day (issue 10's model studies). A `bench/zoo_table.py` run keeps, per machine, the calibration
campaign (campaign/), the model the day ran with (model.json) and the day's tests with the
compensator off and on (day/<axis>_<state>_off.csv, _on.csv) on the day's machine log. This script
fits each axis again from the campaign with `trueaxis fit` and the options given, then:

- the off test: A of measured − predicted (`trueaxis predict --measurement`), as compensation
  would have left it;
- the on test: the day's own residual with the run's correction swapped for the re-fit one,
  on − predicted(run's model) + predicted(re-fit). The run's correction is taken as `predict`'s:
  the compensator's ramps, rate limits and holds are not replayed. Checked against days run again
  in full: gantry2000 X warm + coolant 28.5 / 27.7 µm here against 30.2 / 30.2 µm closed loop
  (bench/results/zoo.md).

With no fit options the re-fit is the run's own model (the demo's fit: nut and bearing keys where
the axis has them, no fallback models) and every row comes out as the run's. The table has the
run's A on next to the re-fit's; 'must' is zoo_table.py's criterion on the re-fit. A day whose
sensor died (a [[day_fault]]) is predicted without fallback models: such rows say "no prediction".

Usage (from the repository root, after a zoo run):
  /usr/bin/python3 bench/zoo_table.py --out out/zoo
  /usr/bin/python3 bench/zoo_refit.py --run out/zoo --fit-options "--motion-heat off"
"""
import argparse, glob, json, os, re, shlex, subprocess, sys, tempfile

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
ap.add_argument("--run", required=True, help="output directory of a bench/zoo_table.py run (its --out)")
ap.add_argument("--trueaxis", default="build/apps/trueaxis/trueaxis")
ap.add_argument("--fit-options", default="", help='options for `trueaxis fit`, e.g. "--motion-heat off"')
ap.add_argument("--keys", default="seed", choices=["seed", "auto"],
                help="seed: the nut and bearing keys where the axis has them, as the demo fits; auto: the fit's choice")
ap.add_argument("machines", nargs="*", help="machine names under --run (default: every one)")
# "--fit-options --coolant-soak": the value starts with "--", which argparse would take for an option.
argv = sys.argv[1:]
for i in range(len(argv) - 1):
    if argv[i] == "--fit-options":
        argv[i:i + 2] = ["--fit-options=" + argv[i + 1]]
        break
a = ap.parse_args(argv)


def run(args):
    return subprocess.run([a.trueaxis] + args, capture_output=True, text=True)


def table(path):
    """(header lines up to the column names, column names, rows as lists) of a measurement CSV."""
    lines = open(path).read().splitlines()
    head = next(i for i, l in enumerate(lines) if l.startswith("run,"))
    return lines[:head + 1], lines[head].split(","), [l.split(",") for l in lines[head + 1:] if l]


def predicted_residual(model, measurement, log, out):
    """measured − predicted per point (the file's order), or None when predict gives none."""
    r = run(["predict", "--model", model, "--measurement", measurement, "--temperature-log", log, "--residual-out", out])
    if r.returncode != 0 or not os.path.exists(out):
        return None
    _, cols, rows = table(out)
    i = cols.index("deviation_um")
    return [float(row[i]) for row in rows]


def iso(path):
    j = json.loads(run(["analyze", path, "--json"]).stdout)
    return j["A_um"], j["R_um"]


names = a.machines or sorted(os.path.basename(os.path.dirname(p)) for p in glob.glob(os.path.join(a.run, "*", "model.json")))
if not names:
    sys.exit(f"{a.run}: no machine directories with a model.json (run bench/zoo_table.py --out {a.run} first)")
if not os.access(a.trueaxis, os.X_OK):
    sys.exit(f"{a.trueaxis}: no trueaxis binary there (build first, or give --trueaxis)")
for name in names:
    if not os.path.exists(os.path.join(a.run, name, "campaign", "manifest.json")):
        sys.exit(f"{os.path.join(a.run, name)}: no campaign/manifest.json (not a machine of a bench/zoo_table.py run)")
tmp = tempfile.mkdtemp(prefix="zoo_refit_")
rows = []
for name in names:
    d = os.path.join(a.run, name)
    camp = os.path.abspath(os.path.join(d, "campaign"))
    manifest = json.load(open(os.path.join(camp, "manifest.json")))
    log = os.path.join(d, "day", "machine_log.csv")
    axes = sorted({os.path.basename(p).split("_", 1)[0] for p in glob.glob(os.path.join(d, "day", "*_on.csv"))})
    for axis in axes:
        # The axis's own campaign files, with absolute paths: the manifest may live anywhere.
        m = dict(manifest, temperature_log=os.path.join(camp, manifest["temperature_log"]))
        m["measurements"] = [dict(x, file=os.path.join(camp, x["file"])) for x in manifest["measurements"]
                             if x["axis"] == axis]
        axis_manifest, model = os.path.join(tmp, f"{name}_{axis}.json"), os.path.join(tmp, f"{name}_{axis}_model.json")
        json.dump(m, open(axis_manifest, "w"))
        keys = []
        nut, bearing = axis.lower() + "_nut", axis.lower() + "_bearing"
        if a.keys == "seed" and nut in manifest["sensors"] and bearing in manifest["sensors"]:
            keys = ["--keys", f"{nut},{bearing}"]
        f = run(["fit", "--manifest", axis_manifest, "--out", model, "--no-fallback-models"] + keys + shlex.split(a.fit_options))
        if f.returncode != 0:
            sys.exit(f"{name} {axis}: trueaxis fit failed: {f.stderr.strip()}")
        for on in sorted(glob.glob(os.path.join(d, "day", f"{axis}_*_on.csv"))):
            state = os.path.basename(on)[len(axis) + 1:-len("_on.csv")]
            off = on[:-len("_on.csv")] + "_off.csv"
            a_off, r_off = iso(off)
            a_run, _ = iso(on)
            off_res = os.path.join(tmp, "off.csv")
            res_off = predicted_residual(model, off, log, off_res)
            res_run = predicted_residual(os.path.join(d, "model.json"), on, log, os.path.join(tmp, "run.csv"))
            res_new = predicted_residual(model, on, log, os.path.join(tmp, "new.csv"))
            if res_off is None or res_run is None or res_new is None:
                rows.append((name, axis, state, a_off, a_run, None))
                continue
            head, cols, pts = table(on)
            i = cols.index("deviation_um")
            for p, r_run, r_new in zip(pts, res_run, res_new):
                p[i] = f"{float(p[i]) - r_run + r_new:.4f}"
            rebuilt = os.path.join(tmp, "on_refit.csv")
            with open(rebuilt, "w") as out:
                out.write("\n".join(head + [",".join(p) for p in pts]) + "\n")
            a_on, r_on = iso(rebuilt)
            a_off_res, _ = iso(off_res)
            must = a_on <= max(0.2 * a_off, 2 * r_on) and a_on < a_off and r_on <= 2 * r_off + 2
            rows.append((name, axis, state, a_off, a_run, (a_on, r_on, a_on / max(0.1 * a_off, 1.3 * r_on), must, a_off_res)))
    print(f"{name}: re-fitted {', '.join(axes)}", file=sys.stderr)

print(f"Re-fit with `trueaxis fit {a.fit_options}`".rstrip() + f" on {a.run}\n")
print("| machine | axis | state | A off (µm) | A on, run (µm) | A on, re-fit (µm) | R on, re-fit (µm) | score | must | off test, predicted residual A (µm) |")
print("|---|---|---|---:|---:|---:|---:|---:|---|---:|")
for name, axis, state, a_off, a_run, new in rows:
    st = state.replace("_", " ")
    if new is None:
        print(f"| {name} | {axis} | {st} | {a_off:.1f} | {a_run:.1f} | no prediction | | | | |")
        continue
    a_on, r_on, score, must, a_res = new
    print(f"| {name} | {axis} | {st} | {a_off:.1f} | {a_run:.1f} | {a_on:.1f} | {r_on:.1f} | {score:.2f} | "
          f"{'yes' if must else '**no**'} | {a_res:.1f} |")
ok = [r for r in rows if r[5] is not None]
changed = [r for r in ok if abs(r[5][0] - r[4]) > 0.05]
print(f"\n{len(ok)} rows re-fitted: {sum(r[5][3] for r in ok)} under the must line, {sum(r[5][2] <= 1 for r in ok)} at the goal; "
      f"sum of A on {sum(r[5][0] for r in ok):.1f} µm against the run's {sum(r[4] for r in ok):.1f} µm; "
      f"{len(changed)} rows changed by more than 0.05 µm" + (f"; {len(rows) - len(ok)} without a prediction" if len(ok) < len(rows) else ""))
