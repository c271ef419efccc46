#!/usr/bin/python3
"""The DISPLAY program of the headless LinuxCNC test sessions (tests/linuxcnc/, docs/linuxcnc.md).

LinuxCNC's launcher starts it once the machine is up; it drives the machine through the
`linuxcnc` Python module (estop reset, machine on, home, MDI, programs), reads and sets HAL pins,
checks one scenario and writes its verdict as JSON to $TRUEAXIS_LCNC_RESULT:
  {"scenario": ..., "failures": ["..."], "figures": {...}}
When it exits, LinuxCNC shuts down. Scenarios: hal, enable, lost_terminal, compfile, closed_loop, campaign.
"""
import json
import os
import subprocess
import sys
import time
import traceback

import hal
import linuxcnc

SCENARIO = os.environ["TRUEAXIS_LCNC_SCENARIO"]
RESULT = os.environ["TRUEAXIS_LCNC_RESULT"]
CLI = os.environ.get("TRUEAXIS_CLI", "")
MODEL = os.environ.get("TRUEAXIS_MODEL", "")

stat = linuxcnc.stat()
cmd = linuxcnc.command()
failures = []
figures = {}
_component = hal.component("tadriver")  # hal.get_value/set_p need a component of our own
_component.ready()


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def getp(name):
    v = hal.get_value(name)
    return float(v) if not isinstance(v, bool) else (1.0 if v else 0.0)


def setp(name, value):
    hal.set_p(name, str(value))


def wait_for(predicate, timeout_s, what):
    t0 = time.time()
    while time.time() - t0 < timeout_s:
        stat.poll()
        if predicate():
            return True
        time.sleep(0.005)
    failures.append(f"timed out after {timeout_s} s waiting for {what}")
    return False


def machine_on_and_home():
    cmd.state(linuxcnc.STATE_ESTOP_RESET)
    cmd.state(linuxcnc.STATE_ON)
    cmd.wait_complete()
    cmd.home(-1)
    if not wait_for(lambda: all(stat.homed[: stat.joints]), 10, "homing"):
        raise RuntimeError("the machine did not home")
    cmd.mode(linuxcnc.MODE_MDI)
    cmd.wait_complete()


def mdi(line, timeout_s=30):
    cmd.mdi(line)
    cmd.wait_complete(timeout_s)
    wait_for(lambda: stat.interp_state == linuxcnc.INTERP_IDLE and stat.inpos, timeout_s, f"MDI '{line}'")


def move_to(x_mm, direction):
    """Approach x from below (+1) or above (-1), as the laser test does."""
    mdi(f"G0 X{x_mm - 5 * direction:.4f}")
    mdi(f"G0 X{x_mm:.4f}")


def settle(pin, quiet_s=0.3, timeout_s=5):
    """Wait until `pin` has not changed for quiet_s; returns its value."""
    t0 = time.time()
    last, since = getp(pin), time.time()
    while time.time() - t0 < timeout_s:
        time.sleep(0.01)
        v = getp(pin)
        if v != last:
            last, since = v, time.time()
        elif time.time() - since >= quiet_s:
            return v
    failures.append(f"{pin} did not settle within {timeout_s} s")
    return last


def predict(x_mm, direction, temps, ambient_c):
    out = subprocess.check_output([CLI, "predict", "--model", MODEL, "--axis", "X", "--position-mm", str(x_mm),
                                   "--direction", "+" if direction > 0 else "-", "--temp",
                                   ",".join(f"{k}={v}" for k, v in temps.items()), "--ambient-c", str(ambient_c),
                                   "--json"])
    return json.loads(out)["correction_um"]


def offset_at_joint_um(x_mm):
    """What reached the joint: the motor command minus the programmed position."""
    return (getp("joint.0.motor-pos-cmd") - x_mm) * 1000.0


def sample_ramp(duration_s, until=None):
    """(t, correction-um, axis.x.eoffset µm, t after the reads) every ~2 ms: the pins were read
    somewhere between the two times (a loaded machine can stall this process between them)."""
    samples, t0 = [], time.time()
    while time.time() - t0 < duration_s:
        t = time.time() - t0
        corr, eoffset_um = getp("trueaxis.x.correction-um"), getp("axis.x.eoffset") * 1000.0
        samples.append((t, corr, eoffset_um, time.time() - t0))
        if until and until(samples[-1]):
            break
        time.sleep(0.002)
    return samples


def pin_signal(pin):
    """The signal `pin` is netted to ('' when none), from `halcmd -s show pin`."""
    out = subprocess.check_output(["halcmd", "-s", "show", "pin", pin], text=True)
    for line in out.splitlines():
        words = line.split()
        if pin in words:
            i = words.index(pin)
            return words[i + 2] if len(words) > i + 2 and words[i + 1] in ("<==", "==>", "<=>") else ""
    failures.append(f"halcmd show pin {pin}: no such pin")
    return ""


# The machine's own signals in sim.hal and the pins trueaxis.hal (examples/run/linuxcnc.hal) nets onto them.
CONFIG_SIGNALS = {"machine-is-enabled": ("motion.motion-enabled", "trueaxis.machine-on"),
                  "coolant-flood": ("iocontrol.0.coolant-flood", "trueaxis.coolant-flood"),
                  "coolant-mist": ("iocontrol.0.coolant-mist", "trueaxis.coolant-mist")}


def check_config_signals():
    """The snippet reused the configuration's signals: each trueaxis input sits on the signal the
    configuration already drives from the controller's pin (not on a signal of its own)."""
    for signal, (writer, reader) in CONFIG_SIGNALS.items():
        for pin in (writer, reader):
            got = pin_signal(pin)
            check(got == signal, f"{pin} is on signal '{got}', not the configuration's '{signal}'")


# ---- scenarios -------------------------------------------------------------------------------

def scenario_hal():
    """Corrections of trueaxis-hal reach the joint: at several positions, directions and
    temperatures, motor-pos-cmd − programmed = the model's correction (trueaxis predict)."""
    temps = {"nut": 20.0, "bearing": 20.0}
    for k, v in temps.items():
        setp(f"trueaxis.temp.{k}", v)
    setp("trueaxis.temp.ambient", 20.0)
    setp("trueaxis.enable", 1)
    check_config_signals()
    machine_on_and_home()
    check(getp("trueaxis.machine-on") == 1, "trueaxis.machine-on did not follow the machine on (machine-is-enabled)")
    quantum_um = 0.1
    worst = 0.0
    for x, d, nut, bearing in [(300, 1, 20, 20), (300, 1, 30, 22), (120, -1, 30, 22), (50, 1, 25, 21), (380, -1, 27, 24)]:
        setp("trueaxis.temp.nut", nut)
        setp("trueaxis.temp.bearing", bearing)
        move_to(x, d)
        corr = settle("trueaxis.x.correction-um")
        time.sleep(0.3)  # the eoffset planner follows at its own rate
        at_joint = offset_at_joint_um(x)
        expected = predict(x, d, {"nut": nut, "bearing": bearing}, 20.0)
        err = at_joint - expected
        worst = max(worst, abs(err))
        check(abs(at_joint - corr) < 1e-3, f"X{x}: joint offset {at_joint:.4f} µm != component output {corr:.4f} µm")
        check(abs(err) <= quantum_um, f"X{x} dir {d} nut {nut}: joint offset {at_joint:.4f} µm vs model correction "
                                      f"{expected:.4f} µm (diff {err:.4f} > quantum {quantum_um})")
        check(getp("trueaxis.alarms") == 0, f"X{x}: alarms {getp('trueaxis.alarms')}")
        check(getp("trueaxis.x.thermal") == 1 and getp("trueaxis.x.fallback-model") == -1,
              f"X{x}: the model with its own sensors expected (thermal {getp('trueaxis.x.thermal')}, "
              f"fallback-model {getp('trueaxis.x.fallback-model')})")
    figures["worst_joint_vs_model_um"] = worst

    # Latency: a temperature step → first change of the correction pin → first change at the joint,
    # over 8 steps (the temperature worker reads every 20 ms, the loop and the CNC worker every 5 ms).
    to_comp, to_joint = [], []
    for k, nut in enumerate([35, 30, 34, 29, 36, 31, 33, 28]):
        before, joint_before = getp("trueaxis.x.correction-um"), getp("joint.0.motor-pos-cmd")
        t0 = time.time()
        setp("trueaxis.temp.nut", nut)
        t_comp = t_joint = None
        while time.time() - t0 < 3 and (t_comp is None or t_joint is None):
            if t_comp is None and getp("trueaxis.x.correction-um") != before:
                t_comp = time.time() - t0
            if t_joint is None and getp("joint.0.motor-pos-cmd") != joint_before:
                t_joint = time.time() - t0
            time.sleep(0.0005)
        if check(t_comp is not None and t_joint is not None, f"temperature step {k} did not reach the joint in 3 s"):
            to_comp.append(t_comp)
            to_joint.append(t_joint)
        settle("trueaxis.x.correction-um", quiet_s=0.2)
    if to_joint:
        figures["latency_temperature_to_component_s"] = {"median": sorted(to_comp)[len(to_comp) // 2], "max": max(to_comp)}
        figures["latency_temperature_to_joint_s"] = {"median": sorted(to_joint)[len(to_joint) // 2], "max": max(to_joint)}


def ramp_checks(samples, start_um, end_um, max_step_um, period_s, what):
    values = [s[1] for s in samples]
    check(abs(values[-1] - end_um) < 0.11, f"{what}: ends at {values[-1]:.3f} µm, not {end_um:.3f}")
    distinct = len(set(values))
    check(distinct >= 5, f"{what}: {distinct} distinct values — a jump, not a ramp")
    # Between two samples Δt apart the limiter allows max_step per cycle; Δt is the longest the two
    # reads can be apart (from before the first to after the second). The loop keeps deadlines: cycle
    # k starts somewhere in its own period slot, so a late wake-up followed by an on-time cycle puts
    # two cycles close together, and a window of Δt can hold Δt/period + 2 cycles (+1 count).
    worst_rate = 0.0
    for (t1, v1, _, _), (_, v2, _, t2) in zip(samples, samples[1:]):
        allowed = max_step_um * ((t2 - t1) / period_s + 2) + 0.1
        worst_rate = max(worst_rate, abs(v2 - v1) / allowed)
    check(worst_rate <= 1.0, f"{what}: a step of {worst_rate:.2f}× what the limiter allows")
    joint = [s[2] for s in samples]
    jumps = max(abs(b - a) for a, b in zip(joint, joint[1:]))
    check(jumps < abs(start_um - end_um) * 0.5 + 0.2, f"{what}: the joint's offset jumped {jumps:.2f} µm")
    duration = next((s[0] for s in samples if abs(s[1] - end_um) < 0.11), samples[-1][0])
    return duration


def scenario_enable():
    """trueaxis.enable off → the correction ramps to 0 through the limiter and the joint follows;
    on → it ramps back. Enable-off is what a panel switch or motion.motion-enabled does."""
    setp("trueaxis.temp.nut", 32)
    setp("trueaxis.temp.bearing", 22)
    setp("trueaxis.temp.ambient", 20)
    setp("trueaxis.enable", 1)
    machine_on_and_home()
    move_to(350, 1)
    c0 = settle("trueaxis.x.correction-um")
    time.sleep(0.5)
    check(abs(c0) > 20, f"the correction at X350 should be tens of µm, is {c0:.2f}")
    setp("trueaxis.enable", 0)
    off = sample_ramp(5, until=lambda s: s[1] == 0 and abs(s[2]) < 1e-3)
    d_off = ramp_checks(off, c0, 0.0, 0.5, 0.005, "disable")
    setp("trueaxis.enable", 1)
    on = sample_ramp(5, until=lambda s: abs(s[1] - c0) < 0.11 and abs(s[2] - c0) < 0.05)
    d_on = ramp_checks(on, 0.0, c0, 0.5, 0.005, "enable")
    figures.update(correction_um=c0, disable_ramp_s=d_off, enable_ramp_s=d_on,
                   limiter_um_per_s=0.5 / 0.005)
    time.sleep(0.3)
    check(abs(offset_at_joint_um(350) - c0) < 0.01, "after enabling again the joint holds the correction")


def scenario_lost_terminal():
    """Temperatures from the terminal's RTD modules over MODBUS TCP (`trueaxis sim serve`): the
    terminal goes away → channels held (hold_last_good_s), then lost → fallback "zero": the
    correction ramps to 0 and the alarm pins say why."""
    port = os.environ["TRUEAXIS_MODBUS_PORT"]
    # The terminal is started by the harness before LinuxCNC (its pid in the environment).
    setp("trueaxis.enable", 1)
    machine_on_and_home()
    move_to(350, 1)
    wait_for(lambda: getp("trueaxis.temperatures-ok") == 1, 5, "temperatures from the terminal")
    c0 = settle("trueaxis.x.correction-um", quiet_s=0.5)
    check(c0 != 0, "a correction with the terminal up")
    check(getp("trueaxis.alarms") == 0, f"alarms with the terminal up: {getp('trueaxis.alarms')}")
    os.kill(int(os.environ["TRUEAXIS_TERMINAL_PID"]), 15)
    t0 = time.time()
    samples = sample_ramp(8, until=lambda s: s[1] == 0 and abs(s[2]) < 1e-3)
    t_zero = time.time() - t0
    check(getp("trueaxis.alarm") == 1, "the alarm pin is raised while the terminal is lost")
    alarms = int(getp("trueaxis.alarms"))
    check(alarms & (1 << 2), f"alarm temperature_source (bit 2) expected, alarms = {alarms}")
    check(alarms & (1 << 1), f"alarm sensor_fallback (bit 1) expected, alarms = {alarms}")
    check(getp("trueaxis.x.thermal") == 0, "no thermal part with every sensor lost")
    d = ramp_checks([s for s in samples if s[1] != c0] or samples, c0, 0.0, 0.5, 0.005, "lost terminal")
    figures.update(correction_um=c0, lost_to_zero_s=t_zero, ramp_s=d, alarms=alarms, port=port)


def scenario_compfile():
    """A COMP_FILE written by `trueaxis export --format linuxcnc` and loaded by joint 0: at
    positions approached from both sides, motor-pos-cmd − pos-cmd is the table's correction
    (interpolated as LinuxCNC does) and the model's correction at the frozen temperatures."""
    table = json.loads(os.environ["TRUEAXIS_COMP_TABLE"])  # [[pos, fwd_um, rev_um], ...] from `export --read`
    machine_on_and_home()
    worst_table = worst_model = 0.0
    for x, d in [(37.3, 1), (37.3, -1), (200, 1), (255.5, -1), (391.1, 1)]:
        move_to(x, d)
        time.sleep(0.2)
        applied = (getp("joint.0.motor-pos-cmd") - getp("joint.0.pos-cmd")) * 1000.0
        col = 1 if d > 0 else 2
        i = max(k for k in range(len(table) - 1) if table[k][0] <= x)
        f = (x - table[i][0]) / (table[i + 1][0] - table[i][0])
        from_table = table[i][col] + f * (table[i + 1][col] - table[i][col])
        model = predict(x, d, {"nut": 20, "bearing": 20}, 20.0)
        worst_table = max(worst_table, abs(applied - from_table))
        worst_model = max(worst_model, abs(applied - model))
        check(abs(applied - from_table) < 0.01, f"X{x} dir {d}: LinuxCNC applies {applied:.4f} µm, the table "
                                                f"says {from_table:.4f} µm")
        check(abs(applied - model) < 0.05, f"X{x} dir {d}: LinuxCNC applies {applied:.4f} µm, the model "
                                           f"{model:.4f} µm")
    figures.update(worst_vs_table_um=worst_table, worst_vs_model_um=worst_model)


def laser_cycle_gcode(targets, overrun, runs, datum, feed, dwell):
    """The ISO 230-2 bidirectional cycle as G-code: per run, approach the first target from below by
    the overrun and read every target going up, overrun the last and read every target coming down
    (sim::RunBidirectionalCycle's order). M68 E0/E1/E2 hand the laser the target, run and direction, M64/M65 P0
    pulse its trigger after the dwell (task issues them once the motion queue is empty, so the axis
    stands at the target); P1 zeroes it at the datum, P2 saves the measurement."""
    g = ["(trueaxis: ISO 230-2 laser cycle, generated by tests/linuxcnc/lcnc_driver.py)",
         "G21 G90 G61 G17", f"F{feed:.1f}",
         f"G1 X{max(0.0, datum - max(overrun, 1.0)):.4f}", f"G1 X{datum:.4f}", f"G4 P{dwell:.3f}",
         "M64 P1", "G4 P0.05", "M65 P1", "G4 P0.05"]

    def read(run, target, direction):
        g.extend([f"G1 X{target:.4f}", f"M68 E0 Q{target:.4f}", f"M68 E1 Q{run}", f"M68 E2 Q{direction}",
                  f"G4 P{dwell:.3f}",
                  "M64 P0", "G4 P0.05", "M65 P0", "G4 P0.02"])

    for run in range(1, runs + 1):
        g.append(f"G1 X{targets[0] - overrun:.4f}")
        for t in targets:
            read(run, t, 1)
        g.append(f"G1 X{targets[-1] + overrun:.4f}")
        for t in reversed(targets):
            read(run, t, -1)
    g += ["M64 P2", "G4 P0.05", "M65 P2", "G4 P0.05", "M2"]
    return "\n".join(g) + "\n"


def run_program(path, timeout_s):
    cmd.mode(linuxcnc.MODE_AUTO)
    cmd.wait_complete()
    cmd.program_open(path)
    cmd.auto(linuxcnc.AUTO_RUN, 0)
    time.sleep(0.5)
    wait_for(lambda: stat.interp_state == linuxcnc.INTERP_IDLE, timeout_s, f"the program {path}")
    check(stat.task_state == linuxcnc.STATE_ON, "the machine stayed on through the program")


def scenario_closed_loop():
    """LinuxCNC drives the virtual machine (trueaxis-hal-plant: motor command in, table with pitch,
    backlash and thermal errors out, measured by the virtual laser) with trueaxis-hal compensating
    from the plant's temperatures; the laser cycle runs as a G-code program with compensation on,
    then off. The harness compares A with the in-process reference."""
    out = os.environ["TRUEAXIS_PLANT_OUT"]
    lines = open(os.path.join(out, "targets.txt")).read().splitlines()
    targets = [float(l) for l in lines if l and not l.startswith("#")]
    overrun, runs, datum, feed, dwell = (float(v) for v in lines[-1].lstrip("# ").split())
    program = os.path.join(out, "laser_cycle.ngc")
    open(program, "w").write(laser_cycle_gcode(targets, overrun, int(runs), datum, feed, dwell))
    setp("trueaxis.enable", 1)
    machine_on_and_home()
    wait_for(lambda: getp("trueaxis.active") == 1, 5, "trueaxis-hal active")
    budget = 600
    for k, on in ((1, True), (2, False)):
        setp("trueaxis.enable", 1 if on else 0)
        time.sleep(1.5)  # the ramp to the new state (≤ 120 µm at 100 µm/s)
        t0 = time.time()
        run_program(program, budget)
        wait_for(lambda: getp("taplant.laser-saved") >= k, 5, f"measurement {k} saved")
        figures[f"cycle_{'on' if on else 'off'}_wall_s"] = round(time.time() - t0, 1)
        figures[f"readings_{'on' if on else 'off'}"] = int(getp("taplant.laser-readings"))
    check(figures.get("readings_on") == 2 * len(targets) * int(runs), "one reading per target, run and direction")


def scenario_campaign():
    """trueaxis-hal --campaign logs while LinuxCNC moves X: the driver sets the temperature pins, moves
    X through known targets (standing at each, so the log's 10 Hz reads catch every turn), runs the
    coolant for a while, and reports what it did; the harness checks temperature_log.csv against it."""
    temps = {"x_nut": 20.0, "x_bearing": 20.5, "ambient": 19.5}  # as sensors.hal starts them
    log = os.path.join(os.environ["TRUEAXIS_CAMPAIGN_DIR"], "temperature_log.csv")
    machine_on_and_home()
    # The first row is in (the log starts once its pins are netted): from here every move is logged.
    wait_for(lambda: os.path.exists(log) and len(open(log).read().splitlines()) >= 2, 20, "the campaign log's first row")
    check(getp("trueaxis.machine-on") == 1, "trueaxis.machine-on did not follow the machine on")
    stat.poll()
    x, path, nut_set = stat.joint_actual_position[0], 0.0, [temps["x_nut"]]
    figures["start_x_mm"] = x
    for k, target in enumerate([100.0, 300.0, 50.0, 250.0, 120.0]):
        temps["x_nut"] = 20.0 + 0.5 * (k + 1)
        subprocess.check_call(["halcmd", "sets", "t-x_nut", str(temps["x_nut"])])
        nut_set.append(temps["x_nut"])
        mdi(f"G0 X{target}")
        path += abs(target - x)
        x = target
        time.sleep(0.4)
        if k == 2:
            mdi("M8")
            time.sleep(2.5)  # at least two rows with the flood coolant on
            mdi("M9")
    time.sleep(2.5)  # the last position and temperatures in at least two rows
    figures.update(path_mm=path, last_x_mm=x, temperatures_c=temps, x_nut_set_c=nut_set, targets_mm=[100.0, 300.0, 50.0, 250.0, 120.0])


def main():
    try:
        globals()["scenario_" + SCENARIO]()
    except Exception:
        failures.append("driver error: " + traceback.format_exc())
    with open(RESULT, "w") as f:
        json.dump({"scenario": SCENARIO, "failures": failures, "figures": figures}, f, indent=1)
    try:
        cmd.state(linuxcnc.STATE_OFF)
    except Exception:
        pass


if __name__ == "__main__":
    main()
