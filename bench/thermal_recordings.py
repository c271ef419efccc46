#!/usr/bin/env python3
"""Data-driven thermal models on recordings of zoo machines (issue 14): for each machine, two
working days of the virtual machine (`trueaxis sim recording`, seeds A and B: other programmes,
other noise) are taken as two experiments and evaluated leave-one-experiment-out with
`trueaxis thermal evaluate` (each day validated by models fitted on the other day). Writes one
Markdown table per machine: validation RMSE and max |error| per model and channel, with % of no
compensation and of the constant baseline.

Usage (from the repository root, after a build):
  /usr/bin/python3 bench/thermal_recordings.py [--out out/thermal_zoo] [--seeds 3,4] [machines...]
"""
import argparse, glob, os, subprocess, sys, time

ap = argparse.ArgumentParser()
ap.add_argument("--out", default="out/thermal_zoo")
ap.add_argument("--seeds", default="3,4")
ap.add_argument("--trueaxis", default="build/apps/trueaxis/trueaxis")
ap.add_argument("--models", default="mlr,ridge,pso-bp,hysteresis")
ap.add_argument("machines", nargs="*")
a = ap.parse_args()
machines = a.machines or ["examples/machines/vmc850.toml", "examples/machines/hmc1250.toml",
                          "examples/machines/lathe_tc620.toml", "examples/machines/gantry2000.toml",
                          "examples/machines/vmc1000_tropical.toml"]
os.makedirs(a.out, exist_ok=True)
seeds = a.seeds.split(",")
for m in machines:
    name = os.path.splitext(os.path.basename(m))[0]
    files = []
    for s in seeds:
        f = os.path.join(a.out, f"{name}_day{s}.csv")
        subprocess.run([a.trueaxis, "sim", "recording", "--machine", m, "--seed", s, "--out", f],
                       check=True, capture_output=True)
        files.append(f)
    md = os.path.join(a.out, f"{name}.md")
    t0 = time.time()
    r = subprocess.run([a.trueaxis, "thermal", "evaluate", "--series", *files, "--models", a.models,
                        "--temperature-inputs", "2", "--markdown", md], capture_output=True, text=True)
    if r.returncode != 0:
        print(f"{name}: evaluate failed (exit {r.returncode}): {r.stderr.strip()}", file=sys.stderr)
        continue
    print(f"### {name} (days {', '.join(seeds)}, leave one day out; {time.time() - t0:.0f} s)\n")
    print(open(md).read())
