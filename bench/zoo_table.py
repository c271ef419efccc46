#!/usr/bin/env python3
"""The machine-zoo table (issue 10): runs `trueaxis demo` (calibration campaign, fit, held-out
working day with the compensator in its loop) on every machine description in examples/machines/
and writes one Markdown table: machine, axis, state, A off, A on, R on and the score
A_on / max(10 % of A_off, 1.3 x R_on); 'must' marks A_on <= max(20 % of A_off, 2 x R_on), and
fails any row where compensation made A worse or more than doubled the repeatability (R_on > 2 R_off
+ 2 µm: the correction moved during the test), which the R_on term would otherwise excuse.

Usage (from the repository root, after a build):
  /usr/bin/python3 bench/zoo_table.py [--seed 3] [--out out/zoo] [--trueaxis build/apps/trueaxis/trueaxis] [machines...]
  /usr/bin/python3 bench/zoo_table.py --kill x_nut@7.5 --out out/zoo_x_nut   # that sensor opens 7.5 h into every day
"""
import argparse, glob, json, os, subprocess, sys, time

ap = argparse.ArgumentParser()
ap.add_argument("--seed", type=int, default=3)
ap.add_argument("--out", default="out/zoo")
ap.add_argument("--trueaxis", default="build/apps/trueaxis/trueaxis")
# Options passed on to `trueaxis demo`: (zoo_table option, demo option, flag?, help).
DEMO_OPTIONS = [
    ("--baseline", "--no-envelope", True,
     "fit without the fitted envelope (demo --no-envelope; the coolant memory is off by default): the model "
     "before issue 10's coolant work"),
    ("--coolant-memory", "--coolant-memory", True,
     "let the fit try the coolant memory (demo --coolant-memory): stop 27's default"),
    ("--coolant-soak", "--coolant-soak", True,
     "a coolant's own gains keep the off gains' soaked response (demo --coolant-soak)"),
    ("--coolant-visit", "--coolant-visit", False,
     "when the campaign measures its coolant sessions: after-seasons, first or both (demo --coolant-visit)"),
    ("--no-coolant-rest", "--no-coolant-rest", True,
     "calibrate without the campaign's stop under coolant (demo --no-coolant-rest), for comparison"),
    ("--ambient-hours", "--ambient-hours", False,
     "hours of the day the campaign's ambient days measure at, e.g. 10,19 or 14 (demo --ambient-hours; default: the demo's)"),
    ("--secondary-key-ridge", "--secondary-key-ridge", False,
     "ridge on the bearing key's gain (demo --secondary-key-ridge; 0: the seed's plain least squares)"),
    ("--key-offsets", "--key-offsets", False,
     "each key's own pivot: auto, on, off (demo --key-offsets; off: one pivot Px, the seed's form)"),
    ("--no-fallback-models", "--no-fallback-models", True,
     "fit no fallback models (demo --no-fallback-models): a sensor that dies in the day ([[day_fault]]) leaves its "
     "axis the geometric part only"),
    ("--keys", "--keys", False,
     "key sensors: seed (nut and bearing) or auto (chosen by the fit's CV from every sensor) (demo --keys)"),
    ("--fallback-handover-s", "--fallback-handover-s", False,
     "time constant of a fallback model's hand-over, s (demo --fallback-handover-s; 0: none)"),
    ("--motion-heat", "--motion-heat", False,
     "the motion-heat input (the axis's lagged feed as one more key): auto, on, off (demo --motion-heat; off: the "
     "model before it)"),
    ("--motion-lag-grid-s", "--motion-lag-grid-s", False,
     "lag tau values (s) tried for the motion-heat input, e.g. 3600 (demo --motion-lag-grid-s)"),
    ("--warmup-per-test", "--warmup-per-test", False,
     "study: the dry warm-up's next test waits for r x the last test's duration of machining (demo --warmup-per-test)"),
    ("--coolant-prewarm-h", "--coolant-prewarm-h", False,
     "hours of dry machining before each of the campaign's coolant sessions, e.g. 0,2 (demo --coolant-prewarm-h)"),
    ("--ambient-days", "--ambient-days", False,
     "days after the first on which the campaign measures other room temperatures, e.g. 1,2 for a campaign in one "
     "season (demo --ambient-days; default 60,150)"),
    ("--other-day", "--other-day", False,
     "the other day's offset from the campaign's first, days (demo --other-day; default 250)"),
    ("--rho-fit", "--rho-fit", True,
     "fit rho from the campaign's room temperatures instead of the screw's CTE (demo --rho-fit): the rule before"),
    ("--no-lag-fall", "--no-lag-fall", True,
     "fit one lag tau both ways (demo --no-lag-fall): the lag before the longer fall"),
]
for opt, _, flag, help_text in DEMO_OPTIONS:
    if flag:
        ap.add_argument(opt, action="store_true", help=help_text)
    else:
        ap.add_argument(opt, default="", help=help_text)
ap.add_argument("--kill", default="",
                help="SENSOR@HOURS[:KIND]: a [[day_fault]] added to every machine (a copy of its file in the output "
                     "directory), e.g. x_nut@7.5 or ambient@7.5:drift; KIND open (default), short, stuck, drift, spikes")
ap.add_argument("machines", nargs="*")
a = ap.parse_args()
machines = a.machines or sorted(glob.glob("examples/machines/*.toml"))
kill = None
if a.kill:
    sensor, _, rest = a.kill.partition("@")
    hours, _, kind = rest.partition(":")
    try:
        kill = (sensor, float(hours), kind or "open")
    except ValueError:
        ap.error(f"--kill {a.kill}: expected SENSOR@HOURS[:KIND], e.g. x_nut@7.5")
rows, worst = [], []
for m in machines:
    name = os.path.splitext(os.path.basename(m))[0]
    out = os.path.join(a.out, name)
    t0 = time.time()
    machine_file = m
    if kill:
        # The machine's own file plus the fault (run without it when the machine has no such sensor).
        os.makedirs(out, exist_ok=True)
        machine_file = os.path.join(out, "machine_with_fault.toml")
        with open(m) as src, open(machine_file, "w") as dst:
            dst.write(src.read())
            dst.write(f'\n[[day_fault]]\nsensor = "{kill[0]}"\nat_h = {kill[1]}\nkind = "{kill[2]}"\n')
    demo_args = []
    for opt, demo_opt, flag, _ in DEMO_OPTIONS:
        value = getattr(a, opt[2:].replace("-", "_"))
        if value:
            demo_args += [demo_opt] if flag else [demo_opt, value]
    demo = lambda f: subprocess.run([a.trueaxis, "demo", "--machine", f, "--seed", str(a.seed), "--out", out, "--quiet"] +
                                    demo_args, capture_output=True, text=True)
    r = demo(machine_file)
    if kill and r.returncode != 0 and f"has no sensor '{kill[0]}'" in r.stderr:
        print(f"{name}: no sensor {kill[0]}, run without the fault", file=sys.stderr)
        r = demo(m)
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
failed = len(rows) - len(ok)
worst_row = max(ok, key=lambda r: r[6]) if ok else None
worse = [r for r in ok if r[4] >= r[3]]  # compensation on no better than off: said, never averaged away
print(f"\n{len(ok)} rows: {sum(1 for r in ok if r[7])} under the must line, {sum(1 for r in ok if r[6] <= 1)} at the goal (score <= 1)" +
      (f"; worst score {worst_row[6]:.2f} ({worst_row[0]} {worst_row[1]} {worst_row[2]})" if worst_row else "") +
      f"; {len(worse)} made worse than uncompensated" +
      "".join(f" ({r[0]} {r[1]} {r[2]}: {r[3]:.1f} -> {r[4]:.1f} um)" for r in worse) +
      (f"; {failed} demo(s) failed" if failed else ""))
sys.exit(1 if failed else 0)  # a failed demo is not a table row: the run fails
