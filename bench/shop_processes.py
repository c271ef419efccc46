#!/usr/bin/python3
"""The workshop server's scale with separate processes, as a shop runs them: `trueaxis sim shop`
(N virtual terminals, one process) and `trueaxis server` polling them (another process) on
127.0.0.1, for each N a fixed time; then bench/pymodbus_poller.py against the same kind of
virtual shop for the comparison. Prints one Markdown table row per run (bench/results/server.md).

  /usr/bin/python3 bench/shop_processes.py                      # 200, 600, 1000 machines; pymodbus 150, 250
  /usr/bin/python3 bench/shop_processes.py --machines 1000 --pymodbus ''

Per server run: the complete cycles of every machine over the measured window (from the server's
HTTP API, /api/machines), so the rate per machine (mean and the slowest machine); the read→write
latency p99 of the window (the difference of two /api/stats latency histograms); overruns and
faults in the window; the CPU of the server process and of the virtual shop process (all their
threads, /proc/PID/stat) as % of one core and per machine-cycle (CPU time over the complete cycles
of every machine in the window: robust to other work on the box, where Hz and p99 are not); the server's resident memory (VmRSS) at the end.
The load average (/proc/loadavg) is printed beside every row: the box may be shared.
Every process is started here and ended here (SIGTERM, then SIGKILL), also on Ctrl-C or a failure.
"""
import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TICKS = os.sysconf("SC_CLK_TCK")
STARTED = []  # every child process, ended in finally


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def cpu_s(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime + stime of every thread


def status_kb(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


def free_port_block(count, first=20000):
    """A base port with `count` consecutive free ports on 127.0.0.1 (checked by binding each)."""
    for base in range(first, 65000 - count, 997):
        socks = []
        try:
            for p in range(base, base + count):
                s = socket.socket()
                s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
                s.bind(("127.0.0.1", p))
                socks.append(s)
            return base
        except OSError:
            pass
        finally:
            for s in socks:
                s.close()
    raise RuntimeError(f"no {count} consecutive free ports on 127.0.0.1")


def write_model(path):
    """A model over the VMC-850's nut sensors (tens of µm of correction), as the server tests use."""
    side = {"geometric": {"center_mm": 300.0, "coefficients_um": [30.0, 5.0], "half_span_mm": 300.0, "kind": "polynomial"},
            "thermal": []}
    axes = [{"axis": a, "baseline_temp_c": [20.0], "forward": side, "reverse": side, "key_sensors": [a.lower() + "_nut"],
             "key_temperature_rise": "from_baseline", "reference_position_mm": 0.0, "rho_um_per_mm_per_c": 0.0}
            for a in "XYZ"]
    model = {"format": "trueaxis-model", "format_version": 1, "machine": "VMC-850", "revision": 1,
             "created_utc": "2026-01-01T00:00:00Z", "generator": "bench/shop_processes.py", "fit_summary": {},
             "lineage": [], "parent_sha256": "", "sources": [], "axes": axes,
             "sign_convention": "values are errors (actual - commanded); correction = -error"}
    with open(path, "w") as f:
        json.dump(model, f)


def start(cmd, log, nice=0):
    if nice:
        cmd = ["nice", "-n", str(nice)] + cmd
    p = subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
    STARTED.append(p)
    return p


def stop(p):
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
        try:
            p.wait(timeout=15)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


def wait_for(what, done, limit_s, proc=None, log=None):
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        if proc is not None and proc.poll() is not None:
            raise RuntimeError(f"{what}: the process ended ({proc.returncode}): {open(log).read()[-2000:] if log else ''}")
        try:
            if done():
                return
        except (OSError, ValueError):
            pass
        time.sleep(0.2)
    raise RuntimeError(f"{what}: not within {limit_s} s")


def get_json(url):
    with urllib.request.urlopen(url, timeout=30) as r:
        return json.loads(r.read())


def start_virtual_shop(args, tmp, n, tag, model=None, http_port=0):
    base = free_port_block(n)
    log = os.path.join(tmp, f"shop_{tag}.log")
    cmd = [args.trueaxis, "sim", "shop", "--machines", str(n), "--base-port", str(base), "--status-interval-s", "0",
           "--duration-s", str(args.warmup_s + args.measure_s + 120)]
    if model:
        cmd += ["--write-shop", os.path.join(tmp, f"shop_{tag}.toml"), "--model", model,
                "--history", os.path.join(tmp, f"history_{tag}.db"), "--period-s", str(args.period_s),
                "--http-port", str(http_port)]
    p = start(cmd, log, args.nice)
    wait_for("the virtual shop", lambda: "machines on" in open(log).read(), 120, p, log)
    return p, base


def latency_p99(before, after):
    """p99 (upper bucket edge, ms) of the samples that arrived between two /api/stats."""
    b = {e: c for e, c in before.get("latency_histogram", [])}
    counts = sorted((e, c - b.get(e, 0)) for e, c in after.get("latency_histogram", []))
    total = sum(c for _, c in counts)
    if total == 0:
        return float("nan")
    seen = 0
    for edge, c in counts:
        seen += c
        if seen >= 0.99 * total:
            return edge
    return counts[-1][0]


def run_server(args, tmp, n):
    http_port = free_port_block(1, first=60000)  # away from the terminals' ports
    model = os.path.join(tmp, "model.json")
    shop, _ = start_virtual_shop(args, tmp, n, str(n), model, http_port)
    log = os.path.join(tmp, f"server_{n}.log")
    server = start([args.trueaxis, "server", "--config", os.path.join(tmp, f"shop_{n}.toml"), "--quiet",
                    "--duration-s", str(args.warmup_s + args.measure_s + 120)]
                   + (["--poll-threads", str(args.poll_threads)] if args.poll_threads else []), log, args.nice)
    api = f"http://127.0.0.1:{http_port}/api"
    try:
        wait_for("the server's API", lambda: get_json(api + "/stats") is not None, 120, server, log)
        try:  # a box too loaded for N machines may never have all connected at once: measure anyway
            wait_for("every machine connected", lambda: all(m["connected"] for m in get_json(api + "/machines")), 30,
                     server, log)
        except RuntimeError as e:
            if server.poll() is not None:
                raise
            print(f"note: {n} machines: {e}; measured anyway", file=sys.stderr)
        time.sleep(args.warmup_s)
        load0 = loadavg()
        t0 = time.monotonic()  # the server takes its snapshot as the request arrives
        m0 = {m["name"]: m["complete_cycles"] for m in get_json(api + "/machines")}
        s0 = get_json(api + "/stats")
        c0 = (cpu_s(server.pid), cpu_s(shop.pid), time.monotonic())
        time.sleep(args.measure_s)
        t1 = time.monotonic()
        m1 = {m["name"]: m["complete_cycles"] for m in get_json(api + "/machines")}
        s1 = get_json(api + "/stats")
        c1 = (cpu_s(server.pid), cpu_s(shop.pid), time.monotonic())
        load1 = loadavg()
        rss_kb, hwm_kb = status_kb(server.pid, "VmRSS"), status_kb(server.pid, "VmHWM")
    finally:
        stop(server)
        stop(shop)
    wall = c1[2] - c0[2]
    hz = [(m1[k] - m0[k]) / (t1 - t0) for k in m0]
    machine_cycles = max(1, sum(m1[k] - m0[k] for k in m0))  # complete cycles of every machine in the window
    p99 = latency_p99(s0, s1)
    if p99 != p99:  # a server without the histogram: its p99 since the start
        p99 = s1["latency_p99_ms"]
    return {"machines": n, "hz_mean": sum(hz) / len(hz), "hz_min": min(hz), "p99_ms": p99,
            "overruns": s1["overruns"] - s0["overruns"], "faults": s1["faults"] - s0["faults"],
            "server_cpu_pct": 100 * (c1[0] - c0[0]) / wall, "shop_cpu_pct": 100 * (c1[1] - c0[1]) / wall,
            "server_us_per_cycle": 1e6 * (c1[0] - c0[0]) / machine_cycles,
            "shop_us_per_cycle": 1e6 * (c1[1] - c0[1]) / machine_cycles,
            "server_rss_mb": rss_kb / 1024, "server_hwm_mb": hwm_kb / 1024, "load": f"{load0} → {load1}"}


def run_pymodbus(args, tmp, n):
    shop, base = start_virtual_shop(args, tmp, n, f"py{n}")
    try:
        time.sleep(1)
        load0 = loadavg()
        c0 = cpu_s(shop.pid)
        out = subprocess.run((["nice", "-n", str(args.nice)] if args.nice else []) + ["/usr/bin/python3", os.path.join(HERE, "pymodbus_poller.py"), str(base), str(n), "3", "9",
                              str(args.period_s), str(args.measure_s)], capture_output=True, text=True,
                             timeout=args.measure_s + 120)
        c1 = cpu_s(shop.pid)
        load1 = loadavg()
    finally:
        stop(shop)
    j = json.loads(out.stdout[out.stdout.find("{"):])
    return {"machines": n, "hz_mean": j["per_machine_hz"], "hz_min": j["min_machine_hz"], "p99_ms": j["p99_ms"],
            "poller_cpu_pct": 100 * j["cpu_s"] / j["elapsed_s"], "shop_cpu_pct": 100 * (c1 - c0) / j["elapsed_s"],
            "poller_us_per_cycle": 1e6 * j["cpu_s"] / max(1e-9, j["per_machine_hz"] * n * j["elapsed_s"]),
            "load": f"{load0} → {load1}"}


def held(r, hz):
    return r["hz_min"] >= hz and r.get("overruns", 0) == 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--trueaxis", default=os.path.join(ROOT, "build", "apps", "trueaxis", "trueaxis"))
    ap.add_argument("--machines", default="200,600,1000", help="server runs: machine counts (comma-separated)")
    ap.add_argument("--pymodbus", default="150,250", help="pymodbus poller runs: machine counts ('' none)")
    ap.add_argument("--warmup-s", type=float, default=3)
    ap.add_argument("--measure-s", type=float, default=10)
    ap.add_argument("--period-s", type=float, default=0.1)
    ap.add_argument("--hold-hz", type=float, default=9.9, help="a run holds 10 Hz when its slowest machine reaches this")
    ap.add_argument("--nice", type=int, default=0,
                    help="run the server, the virtual shop and the poller with this niceness (e.g. -5: ahead of other work)")
    ap.add_argument("--poll-threads", type=int, default=0,
                    help="the server's polling threads (--poll-threads of `trueaxis server`; 0: the shop file's, 1)")
    ap.add_argument("--json", help="also write every run's figures to this file")
    args = ap.parse_args()
    if not os.access(args.trueaxis, os.X_OK):
        sys.exit(f"{args.trueaxis}: not found (build the trueaxis target, or give --trueaxis)")
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    results = {"server": [], "pymodbus": []}
    with tempfile.TemporaryDirectory(prefix="trueaxis_shop_processes_") as tmp:
        write_model(os.path.join(tmp, "model.json"))
        try:
            print(f"separate processes, period {args.period_s} s, warm-up {args.warmup_s} s, measured {args.measure_s} s, "
                  f"{os.cpu_count()} cores" + (f", niceness {args.nice}" if args.nice else "")
                  + (f", {args.poll_threads} server polling threads" if args.poll_threads else ""))
            print("| N machines | Hz per machine mean (min) | p99 read→write | overruns | faults | server CPU | server RSS "
                  "| virtual shop CPU | server / shop CPU per machine-cycle | load average (start → end) |")
            print("|---|---|---|---|---|---|---|---|---|---|")
            for n in [int(x) for x in args.machines.split(",") if x]:
                r = run_server(args, tmp, n)
                results["server"].append(r)
                print(f"| {n} | {r['hz_mean']:.2f} ({r['hz_min']:.2f}) | {r['p99_ms']:.2f} ms | {r['overruns']} | "
                      f"{r['faults']} | {r['server_cpu_pct']:.1f} % | {r['server_rss_mb']:.1f} MB "
                      f"| {r['shop_cpu_pct']:.1f} % | {r['server_us_per_cycle']:.1f} / {r['shop_us_per_cycle']:.1f} µs | {r['load']} |",
                      flush=True)
            py = [int(x) for x in args.pymodbus.split(",") if x]
            if py:
                print("\npymodbus poller (bench/pymodbus_poller.py, one process) against the virtual shop:")
                print("| N machines | Hz per machine mean (min) | p99 cycle | poller CPU | virtual shop CPU "
                      "| poller CPU per machine-cycle | load average |")
                print("|---|---|---|---|---|---|---|")
            for n in py:
                r = run_pymodbus(args, tmp, n)
                results["pymodbus"].append(r)
                print(f"| {n} | {r['hz_mean']:.2f} ({r['hz_min']:.2f}) | {r['p99_ms']:.2f} ms | {r['poller_cpu_pct']:.1f} % | "
                      f"{r['shop_cpu_pct']:.1f} % | {r['poller_us_per_cycle']:.0f} µs | {r['load']} |", flush=True)
        finally:
            for p in STARTED:
                stop(p)
    srv = sorted(results["server"], key=lambda r: r["machines"])
    if len(srv) >= 2 and srv[-1]["machines"] > srv[0]["machines"]:
        a, b = srv[0], srv[-1]
        print(f"\nserver memory per machine (RSS difference {a['machines']} → {b['machines']} machines): "
              f"{1024 * (b['server_rss_mb'] - a['server_rss_mb']) / (b['machines'] - a['machines']):.0f} kB")
    for hz in sorted({args.hold_hz, 9.5}, reverse=True):
        best_server = max([r["machines"] for r in results["server"] if held(r, hz)], default=0)
        best_py = max([r["machines"] for r in results["pymodbus"] if held(r, hz)], default=0)
        print(f"held ≥ {hz} Hz on every machine without overruns: server {best_server or 'none'} machines, "
              f"pymodbus poller {best_py or 'none'}" +
              (f": {best_server / best_py:.1f}× by machine count (of the counts run)" if best_server and best_py else ""))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
