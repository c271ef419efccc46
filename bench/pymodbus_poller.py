#!/usr/bin/python3
"""The comparison poller of bench/server_bench.cpp: the same work as the
workshop server's cycle done the plain way with pymodbus 3.0 (Debian's
python3-pymodbus), one synchronous client per terminal, one thread:
per machine and period, FC 04 the PMC window, FC 03 the AI values of each
ADAM-6015 (once per second, as the server's temperature_period_s), FC 16 the
compensation vector (written back as read: no model).

usage: pymodbus_poller.py BASE_PORT MACHINES AXES CHANNELS PERIOD_S DURATION_S
prints one JSON object: complete cycles per second (all, and of the slowest machine), latency percentiles.
"""
import json
import os
import sys
import time

# The test peer's import (it stubs the serial modules Debian's pymodbus 3.0 imports even for TCP).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "drivers", "peers"))
from pymodbus_peer import ModbusTcpClient  # noqa: E402


def main():
    base, n, axes, channels = (int(x) for x in sys.argv[1:5])
    period, duration = float(sys.argv[5]), float(sys.argv[6])
    clients = []
    for i in range(n):
        c = ModbusTcpClient("127.0.0.1", port=base + i, timeout=1)
        c.connect()
        clients.append(c)
    modules = (channels + 6) // 7
    window = 16 + 8 * axes
    lat = []
    done = 0
    per_machine = [0] * n
    start = time.monotonic()
    next_t = start
    cycle = 0
    every = max(1, round(1.0 / period))  # temperatures once per second
    while time.monotonic() - start < duration:
        for i, c in enumerate(clients):
            t0 = time.monotonic()
            r = c.read_input_registers(0, window, slave=1)
            if r.isError():
                continue
            for k in range(modules if cycle % every == 0 else 0):
                c.read_holding_registers(0, min(7, channels - 7 * k), slave=2 + k)
            words = []
            for a in range(axes):
                words += r.registers[20 + 8 * a: 22 + 8 * a]  # applied compensation, written back
            w = c.write_registers(16, words, slave=1)
            if not w.isError():
                done += 1
                per_machine[i] += 1
                lat.append((time.monotonic() - t0) * 1000)
        cycle += 1
        next_t += period
        delay = next_t - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    elapsed = time.monotonic() - start
    lat.sort()
    pick = lambda q: lat[min(len(lat) - 1, int(q * len(lat)))] if lat else 0
    print(json.dumps({"machines": n, "cycles_per_s": done / elapsed, "per_machine_hz": done / elapsed / n,
                      "min_machine_hz": min(per_machine) / elapsed,
                      "p50_ms": pick(0.5), "p99_ms": pick(0.99), "max_ms": lat[-1] if lat else 0,
                      "cpu_s": time.process_time(), "elapsed_s": elapsed}))


if __name__ == "__main__":
    main()
