#!/usr/bin/env python3
"""Tool thermal proof over days and tools not used for tuning (bench/results/tool_thermal.md).

Runs `trueaxis tool day` for random tool tables and day pairs (train on seed s, test on s + 1)
with the camera and the pyrometers at several sample intervals, and prints per configuration
the RMS reduction of each model over all tools and the worst tool.
Usage: python3 bench/tool_thermal_days.py [--cli build/apps/trueaxis/trueaxis] [--seeds 101,102,...]
"""
import argparse
import re
import subprocess

MODELS = ["none", "one", "intervals", "lag", "two_body", "zones", "best"]


def run(cli, args):
    out = subprocess.run([cli, "tool", "day", *args], check=True, capture_output=True, text=True).stdout
    rows = []
    for line in out.splitlines():
        if not line.startswith("| T"):
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        tool, samples, spread = cells[0], int(cells[1]), float(cells[2])
        rms = [float(c.split("/")[0]) for c in cells[3:10]]
        mx = [float(re.split(r"[/(]", c)[1]) for c in cells[3:10]]
        found = re.search(r"\((\w+)\)", cells[9])
        if not found:  # no model (alone on its day, never used; a stand-in shows "fallback"): nothing to score
            continue
        best = found.group(1)
        rows.append(dict(tool=tool, samples=samples, spread=spread, rms=rms, max=mx, best=best))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default="build/apps/trueaxis/trueaxis")
    ap.add_argument("--seeds", default="101,201,301,401,501")
    ap.add_argument("--tools", type=int, default=4, help="random tools per day")
    ap.add_argument("--tool-file", default="", help="use this tool file instead of random tools (e.g. examples/tool/tools.toml)")
    ap.add_argument("--hours", default="10")
    args = ap.parse_args()
    configs = [("camera", "2", "mixed"), ("camera", "30", "mixed"), ("pyrometer", "10", "mixed"), ("camera", "5", "blocks"),
               ("pyrometer", "10", "blocks")]
    tools = ["--tools", args.tool_file] if args.tool_file else ["--random-tools", str(args.tools)]
    print("| program, sensor, sample | tools | RMS reduction, all tools pooled: one / sub-models / lag / two-body / zones / best | "
          "worst tool's reduction: one / sub-models / zones / best | worst tool by best | where hysteresis > 1 µm: one vs sub-models RMS µm | "
          "sub-models vs one curve per tool: > 10 % worse / > 10 % better, worst RMS ratio |")
    print("|---|---|---|---|---|---|---|")
    for sensor, sample, program in configs:
        allrows = []
        for s in args.seeds.split(","):
            for r in run(args.cli, [*tools, "--seed", s, "--hours", args.hours,
                                    "--sample-s", sample, "--sensor", sensor, "--program", program]):
                r["seed"] = s
                allrows.append(r)
        allrows = [r for r in allrows if r["samples"] >= 50]
        pooled = []
        for k in range(len(MODELS)):
            num = sum(r["samples"] * r["rms"][k] ** 2 for r in allrows)
            pooled.append((num / sum(r["samples"] for r in allrows)) ** 0.5)
        red = [100 * (1 - p / pooled[0]) for p in pooled]
        worst = max(allrows, key=lambda r: r["rms"][6] / r["rms"][0])
        worst_red = [min(100 * (1 - r["rms"][k] / r["rms"][0]) for r in allrows) for k in (1, 2, 5, 6)]
        hyst = [r for r in allrows if r["spread"] > 1.0]
        ratio = [r["rms"][2] / r["rms"][1] for r in allrows]
        vs_one = f"{sum(x > 1.1 for x in ratio)} / {sum(x < 0.9 for x in ratio)}, {max(ratio):.2f}"
        hyst_txt = "; ".join(f"seed {r['seed']} {r['tool'].split()[0]} {r['rms'][1]:.2f} vs {r['rms'][2]:.2f}" for r in hyst) or "none"
        print(f"| {program}, {sensor}, {sample} s | {len(allrows)} | " + " / ".join(f"{x:.0f} %" for x in red[1:]) +
              " | " + " / ".join(f"{x:.0f} %" for x in worst_red) +
              f" | seed {worst['seed']} {worst['tool']}: {worst['rms'][0]:.2f} → {worst['rms'][6]:.2f} µm RMS "
              f"({100 * (1 - worst['rms'][6] / worst['rms'][0]):.0f} %, {worst['best']}), max {worst['max'][0]:.1f} → {worst['max'][6]:.1f} µm"
              f" | {hyst_txt} | {vs_one} |")


if __name__ == "__main__":
    main()
