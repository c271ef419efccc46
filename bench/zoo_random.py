#!/usr/bin/env python3
"""Random machine descriptions for the zoo (issue 10): machines nobody tuned the method on.

The nine descriptions in examples/machines/ are hand-made, and every choice of the method was
judged on them. This script draws new ones from the ranges issue 10 names — travel 200–2000 mm,
leads 5–25 mm, the thrust bearing at either end, one to three axes, shops from 15 to 30 °C with
0.5–3 °C of daily swing, heat from half to three times vmc850's, every sensor kind with its
offsets and noise, now and then a sensor that dies during the day — and writes one TOML file per
machine (docs/machine-file.md). `bench/zoo_table.py` then runs them like the zoo:

  /usr/bin/python3 bench/zoo_random.py --seed 1 --count 12 --out out/zoo_random/machines
  /usr/bin/python3 bench/zoo_table.py --seed 3 --out out/zoo_random/s3 out/zoo_random/machines/*.toml

The same --seed gives the same machines (Python's random.Random, no other input), so a row that
fails can be re-run and looked at. Nothing here reads the simulator's code: the ranges are the
issue's and docs/machine-file.md's.
"""
import argparse, math, os, random, sys

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
ap.add_argument("--seed", type=int, default=1, help="draws the machines (default 1)")
ap.add_argument("--count", type=int, default=12, help="how many machines (default 12)")
ap.add_argument("--out", default="out/zoo_random/machines", help="directory for the .toml files")
a = ap.parse_args()
if a.count < 1:
    sys.exit("zoo_random.py: --count must be at least 1")

rng = random.Random(a.seed)
LEADS = [5, 6, 8, 10, 12, 16, 20, 25]
SENSOR_KINDS = ["pt100_adc", "ds18b20", "rtd_module"]
# vmc850's heat per axis (W): nut, fixed bearing, floating bearing, motor, motor at standstill.
VMC850_HEAT = (24.0, 9.0, 4.0, 30.0, 4.0)


def log_uniform(lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


def r(x, digits=2):
    return round(x, digits)


def kind_of_machine():
    """Axis names and a travel scale for one of the kinds issue 10 lists."""
    k = rng.choice(["vertical", "horizontal", "lathe", "gantry", "single"])
    if k == "lathe":
        return k, ["X", "Z"]
    if k == "single":
        return k, [rng.choice(["X", "Y", "Z"])]
    return k, ["X", "Y", "Z"]


def axis_block(name, kind, heat_scale, lines):
    if kind == "gantry" and name in ("X", "Y"):
        travel = log_uniform(1000, 2000)
    elif kind == "lathe" and name == "X":
        travel = log_uniform(200, 400)  # a diameter axis: short, on the cross slide
    elif name == "Z" and kind != "lathe":
        travel = log_uniform(200, 700)
    else:
        travel = log_uniform(250, 1600)
    travel = round(travel / 10) * 10
    # Longer axes tend to coarser leads and thicker screws; keep some spread.
    lead = rng.choice([l for l in LEADS if (l >= 10 or travel < 1200) and (l <= 16 or travel > 500)])
    dia = min(63, max(16, round(16 + travel / 40 + rng.uniform(-6, 6))))
    heat = [h * heat_scale * rng.uniform(0.8, 1.2) for h in VMC850_HEAT]
    lines += [
        "",
        "[[axis]]",
        f'name = "{name}"',
        f"travel_mm = {travel}",
        f"lead_mm = {lead}",
        f'fixed_end = "{rng.choice(["min", "max"])}"',
        f"screw_diameter_mm = {dia}",
        f"screw_overhang_mm = {rng.choice([100, 120, 150])}",
        f"backlash_um = {r(rng.uniform(1.5, 6), 1)}",
        f"homing_repeatability_um = {r(rng.uniform(0.3, 1.0), 2)}",
        "  [axis.pitch]",
        f"  progressive_um = {r(rng.uniform(-30, 30) * travel / 1000, 1)}",
        f"  curvature_um = {r(rng.uniform(0, 8), 1)}",
        f"  lead_harmonics_um = [{r(rng.uniform(0.4, 2.0), 1)}, {r(rng.uniform(0.1, 0.8), 1)}]",
        f"  random_um = {r(rng.uniform(1.0, 3.5), 1)}",
        f"  random_wavelength_mm = {rng.choice([30, 40, 60, 80, 100])}",
        f"  flank_difference_um = {r(rng.uniform(0.4, 1.2), 1)}",
        "  [axis.thermal]",
        f"  heat_speed_exponent = {r(rng.uniform(0.8, 1.3), 2)}",
        f"  nut_heat_w = {r(heat[0], 1)}",
        f"  fixed_bearing_heat_w = {r(heat[1], 1)}",
        f"  floating_bearing_heat_w = {r(heat[2], 1)}",
        f"  motor_heat_w = {r(heat[3], 1)}",
        f"  motor_idle_heat_w = {r(heat[4], 1)}",
    ]
    return travel


def sensor_block(name, kind, lines):
    lines += ["", "[[sensor]]", f'name = "{name}"', f'kind = "{kind}"']


def machine(i):
    kind, axes = kind_of_machine()
    heat_scale = log_uniform(0.5, 3.0)
    name = f"rnd{a.seed}_{i:02d}_{kind}"
    lines = [
        f"# Drawn by bench/zoo_random.py --seed {a.seed} (machine {i}): a {kind} machine, "
        f"heat {heat_scale:.2f}x vmc850's. Plausible, not a real machine.",
        "",
        "[machine]",
        f'name = "{name.upper().replace("_", "-")}"',
        f"axes = [{', '.join(repr(x).replace(chr(39), chr(34)) for x in axes)}]",
        f"serial_seed = {rng.randrange(1, 10**6)}",
        "",
        "[ambient]",
        f"mean_c = {r(rng.uniform(15, 30), 1)}",
        f"seasonal_amplitude_c = {r(rng.uniform(1, 5), 1)}",
        f"seasonal_peak_day = {rng.randrange(180, 221)}",
        f"daily_amplitude_c = {r(rng.uniform(0.5, 3), 2)}",
        f"daily_peak_hour = {rng.randrange(13, 18)}",
        f"weather_amplitude_c = {r(rng.uniform(0.2, 0.8), 2)}",
        "",
        "[coolant.flood]",
        f"nut_w_per_k = {r(rng.uniform(2, 6), 1)}",
        f"screw_w_per_m2_k = {rng.randrange(30, 91, 5)}",
        f"temperature_offset_c = {r(rng.uniform(0.5, 2.5), 1)}",
    ]
    longest = 0
    for ax in axes:
        longest = max(longest, axis_block(ax, kind, heat_scale, lines))
    lines[lines.index("[coolant.flood]"):lines.index("[coolant.flood]")] = [
        "[bed]",
        f"capacity_j_per_k = {r(1.0e6 + 2.5e3 * longest * rng.uniform(0.7, 1.3), -4)}",
        f"to_ambient_w_per_k = {rng.randrange(70, 131, 10)}",
        "cte_um_per_m_c = 10.5",
        "",
    ]
    # Sensors: one package per machine, as a retrofit would buy them; the room and bed on an RTD
    # module or the same package.
    package = rng.choice(SENSOR_KINDS)
    names = []
    for ax in axes:
        for where in ("nut", "bearing", "motor"):
            names.append((f"{ax.lower()}_{where}", package if where != "motor" else rng.choice([package, "ds18b20"])))
    names.append(("ambient", rng.choice(["rtd_module", package])))
    names.append(("bed", rng.choice(["rtd_module", package])))
    for n, k in names:
        sensor_block(n, k, lines)
    if rng.random() < 0.25:  # a sensor that dies during the working day
        victim = f"{rng.choice(axes).lower()}_{rng.choice(['nut', 'bearing'])}"
        lines += ["", "[[day_fault]]", f'sensor = "{victim}"', f"at_h = {r(rng.uniform(2, 9), 1)}",
                  f'kind = "{rng.choice(["open", "open", "stuck", "short"])}"']
    return name, "\n".join(lines) + "\n"


os.makedirs(a.out, exist_ok=True)
for i in range(1, a.count + 1):
    name, text = machine(i)
    path = os.path.join(a.out, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    print(path)
