#!/usr/bin/env python3
"""Is the default thermal model ever worse than a constant on data it was not tuned on?

For every recording and split the default model (`trueaxis thermal fit` defaults: ridge, inputs and
lags chosen by time-ordered cross-validation) is evaluated with `trueaxis thermal evaluate --models
ridge` next to no compensation, the constant (the training mean) and ridge on all inputs. Prints one
Markdown table: validation RMSE per recording, split and channel, then the worst case.

Recordings:
  fl_thermal            the real 46 h spindle recording (../shared/data/fl_thermal), 16 sensors
  steady-A/B/C          drawn here: long steady spindle runs (16 sensors, one row a minute) that start
                        with a warm-up; sensor t1 follows the warm-up and afterwards only the coolant
                        (the case where a cross-validation dominated by the warm-up picks t1)
  <machine>-day<N>      a drawn working day of a zoo machine (`trueaxis sim recording`)
  <machine>-5days       five such days as five experiments
  with --extra, recordings drawn with other lengths, sample intervals and sensor counts:
  <machine>-<H>h-<S>s   `trueaxis sim recording --hours H --interval-s S` of other zoo machines
                        (the lathe logs 8 sensors, the others 11)
  steady-D              a 96 h steady run like steady-A/B/C with 6 sensors only
Splits: chronological 90/10 and 70/30 (`--validate-last 0.1 / 0.3`); leave one experiment out
where there are several.

Usage (from the repository root, after a build; minutes on two cores):
  /usr/bin/python3 bench/thermal_cv_table.py [--out out/thermal_cv] [--trueaxis build/apps/trueaxis/trueaxis] [--extra]
"""
import argparse, math, os, random, subprocess, sys

ap = argparse.ArgumentParser()
ap.add_argument("--out", default="out/thermal_cv")
ap.add_argument("--trueaxis", default="build/apps/trueaxis/trueaxis")
ap.add_argument("--fl-thermal", default="../shared/data/fl_thermal/fl_thermal.csv")
ap.add_argument("--only", default="", help="comma list of recording names to run (default: all)")
ap.add_argument("--extra", action="store_true", help="run only the recordings of other lengths, intervals and sensor counts")
a = ap.parse_args()
os.makedirs(a.out, exist_ok=True)


def lag(values, tau_min):
    out, v = [], values[0]
    k = 1 - math.exp(-1.0 / tau_min)
    for x in values:
        v += (x - v) * k
        out.append(v)
    return out


def walk(rng, n, step, revert=0.002):
    out, x, d = [], 0.0, 0.0
    for _ in range(n):
        d = 0.95 * d + rng.gauss(0, step)
        x += d - revert * x
        out.append(x)
    return out


def draw_steady(path, seed, hours, steady_um, sensors=16):
    """A long run at one spindle speed, one row a minute. The spindle starts at t = 0: a 45 min
    warm-up raises the error by about 13 µm; after it the error follows the structure's slow
    response to the workshop air (3 h lag, `steady_um` per °C) plus 0.05 µm noise. t1 (spindle
    housing) follows the warm-up and afterwards a wander of its own (the bearing preload, the motor
    load) that moves no error the laser sees; t2 is the air; t3..t6 the structure at 0.5/1/2/6 h;
    t7..t10 the coolant circuit; t11..t16 other machine parts that warm up with their own time
    constants and then wander."""
    rng = random.Random(seed)
    n = int(hours * 60)
    air = [20 + 1.0 * math.sin(2 * math.pi * (m / 1440.0) + rng.uniform(0, 6.3)) + w
           for m, w in zip(range(n), walk(rng, n, 0.002))]
    coolant = walk(rng, n, 0.003)
    housing = walk(rng, n, 0.003)
    warm = [5.0 * (1 - math.exp(-m / 45.0)) for m in range(n)]
    structure = lag(air, 180)
    err = [2.7 * warm[m] + steady_um * (structure[m] - structure[0]) + rng.gauss(0, 0.05) for m in range(n)]
    cols = {}
    cols["t1_C"] = [25 + warm[m] + housing[m] + rng.gauss(0, 0.02) for m in range(n)]
    cols["t2_C"] = [air[m] + rng.gauss(0, 0.03) for m in range(n)]
    for i, tau in zip(range(3, 7), (30, 60, 120, 360)):
        lagged = lag(air, tau)
        cols[f"t{i}_C"] = [lagged[m] + 0.3 * i + rng.gauss(0, 0.02) for m in range(n)]
    for i in range(7, 11):
        cols[f"t{i}_C"] = [21 + 0.5 * i + coolant[m] * (0.5 + 0.1 * i) + rng.gauss(0, 0.02) for m in range(n)]
    for i in range(11, 17):
        other = walk(rng, n, 0.002)
        rise = rng.uniform(10, 90)
        cols[f"t{i}_C"] = [22 + i * 0.2 + 2.0 * (1 - math.exp(-m / rise)) + other[m] + rng.gauss(0, 0.02)
                           for m in range(n)]
    cols = dict(list(cols.items())[:sensors])
    with open(path, "w") as f:
        f.write("time_s,spindle_rpm,e_um," + ",".join(cols) + "\n")
        for m in range(n):
            f.write(f"{m * 60},{6000},{err[m]:.4f}," + ",".join(f"{cols[c][m]:.4f}" for c in cols) + "\n")


def run(args):
    r = subprocess.run([a.trueaxis, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"trueaxis {' '.join(args)} failed (exit {r.returncode}): {r.stderr.strip()}")
    return r


def evaluate(series, split_args, md):
    run(["thermal", "evaluate", "--series", *series, "--models", "ridge", *split_args, "--markdown", md])
    rows = {}
    for line in open(md):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[0] not in ("model", "---"):
            rows.setdefault(cells[1], {})[cells[0]] = float(cells[4])
    return rows


recordings = []  # (name, [files], [(split label, args)])
chrono = [("90/10", ["--validate-last", "0.1"]), ("70/30", ["--validate-last", "0.3"])]
if not a.extra:
    if os.path.exists(a.fl_thermal):
        recordings.append(("fl_thermal", [a.fl_thermal], chrono))
    for name, seed, hours, steady in (("steady-A", 1, 72, 0.0), ("steady-B", 2, 72, 0.5), ("steady-C", 3, 120, 0.2)):
        path = os.path.join(a.out, name + ".csv")
        draw_steady(path, seed, hours, steady)
        recordings.append((name, [path], chrono))
    for machine in ("vmc850", "hmc1250"):
        days = []
        for seed in range(3, 8):
            path = os.path.join(a.out, f"{machine}_day{seed}.csv")
            run(["sim", "recording", "--machine", f"examples/machines/{machine}.toml", "--seed", str(seed), "--out", path])
            days.append(path)
        recordings.append((f"{machine}-day3", days[:1], chrono))
        recordings.append((f"{machine}-5days", days, [("leave one day out", [])]))
else:
    path = os.path.join(a.out, "steady-D.csv")
    draw_steady(path, 27, 96, 0.3, sensors=6)
    recordings.append(("steady-D", [path], chrono))
    for machine, seed, hours, interval in (("lathe_tc620", 21, 12, 30), ("gantry2000", 22, 48, 120),
                                           ("vmc400_small", 23, 6, 10), ("vmc850_cheap_sensors", 24, 36, 60),
                                           ("vmc1000_tropical", 25, 24, 300), ("drill_tap200", 26, 72, 180)):
        name = f"{machine}-{hours}h-{interval}s"
        path = os.path.join(a.out, name + ".csv")
        run(["sim", "recording", "--machine", f"examples/machines/{machine}.toml", "--seed", str(seed),
             "--hours", str(hours), "--interval-s", str(interval), "--out", path])
        recordings.append((name, [path], chrono))
only = set(filter(None, a.only.split(",")))

print("| recording | split | channel | none (µm) | constant (µm) | all inputs (µm) | default (µm) "
      "| default / none | default / constant |")
print("|---|---|---|---:|---:|---:|---:|---:|---:|")
worst_const, worst_none = (0, ""), (0, "")
for name, files, splits in recordings:
    if only and name not in only:
        continue
    for label, args in splits:
        md = os.path.join(a.out, f"{name}_{label.replace('/', '-').replace(' ', '_')}.md")
        for channel, m in evaluate(files, args, md).items():
            none, const = m["no compensation"], m["constant (train mean)"]
            allin, default = m["ridge (all sensors)"], m["ridge"]
            rc, rn = default / const if const else 0, default / none if none else 0
            where = f"{name} {label} {channel}"
            worst_const = max(worst_const, (rc, where))
            worst_none = max(worst_none, (rn, where))
            print(f"| {name} | {label} | {channel} | {none:.3f} | {const:.3f} | {allin:.3f} | {default:.3f} "
                  f"| {100 * rn:.0f} % | {rc:.2f} |", flush=True)
print(f"\nworst default / constant: {worst_const[0]:.2f} ({worst_const[1]}); "
      f"worst default / none: {100 * worst_none[0]:.0f} % ({worst_none[1]})")
