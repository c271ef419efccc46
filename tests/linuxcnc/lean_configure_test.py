#!/usr/bin/env python3
"""The lean build of the HAL programs (cmake -DTRUEAXIS_ONLY_HAL=ON, docs/linuxcnc.md) configures on
a LinuxCNC machine that has only the libraries trueaxis-hal links.

Configures the source tree into a temporary folder as a LinuxCNC machine would see it: the packages
the HAL programs do not link (OpenCV, libpqxx, Paho MQTT, cpp-httplib, GoogleTest, Google Benchmark)
hidden — find_package of them disabled, their pkg-config files removed from pkg-config's path — and
with CMake's trace on. Fails when the configure fails, when it asks (find_package, pkg_check_modules,
find_library, find_path, find_program) for anything outside the libraries trueaxis-hal links, when
the default build target is more than src/linuxcnc (the HAL programs and what they link), when
trueaxis-hal is not a target, or when a run-in-place LinuxCNC tree named by $EMC2_HOME (as its
scripts/rip-environment sets it) is not where hal.h and liblinuxcnchal are taken from. With --build it also builds trueaxis-hal there (slow: the modules it
links, from scratch)."""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

# What trueaxis-hal links (src/linuxcnc/CMakeLists.txt and the modules under it) and the tools the
# configure itself uses. The names are the first argument of the find call (the package, or the
# result variable of find_path/find_library/find_program).
ALLOWED = {
    "find_package": {"PkgConfig", "Threads", "Eigen3", "nlohmann_json", "fmt", "CLI11", "tomlplusplus", "SQLite3",
                     "pugixml"},
    "pkg_check_modules": {"MODBUS", "SODIUM", "XLSXWRITER", "MINIZIP", "LINUXCNC_PC"},
    "find_path": {"LINUXCNC_HAL_INCLUDE_DIR"},
    "find_library": {"LINUXCNC_HAL_LIBRARY"},
    "find_program": set(),
}
# Hidden from the configure: a LinuxCNC machine does not have them.
HIDDEN_PACKAGES = ["OpenCV", "PahoMqttCpp", "PahoMqttC", "GTest", "benchmark", "Chromium"]
HIDDEN_PC = ["libpqxx", "cpp-httplib", "opencv4", "paho-mqtt3a", "paho-mqtt3c", "gtest", "benchmark"]


def filtered_pkg_config_dir(work: pathlib.Path) -> pathlib.Path:
    """A pkg-config search folder with every .pc file of the system's path except HIDDEN_PC."""
    out = work / "pkgconfig"
    out.mkdir()
    pc_path = subprocess.run(["pkg-config", "--variable", "pc_path", "pkg-config"], capture_output=True, text=True,
                             check=True).stdout.strip()
    for d in pc_path.split(":"):
        if not os.path.isdir(d):
            continue
        for pc in pathlib.Path(d).glob("*.pc"):
            if pc.stem not in HIDDEN_PC and not (out / pc.name).exists():
                (out / pc.name).symlink_to(pc)
    return out


def project_calls(trace: pathlib.Path, source: pathlib.Path):
    """(command, first argument, file:line) of every find call made by the project's own files."""
    calls = []
    for line in trace.read_text().splitlines():
        d = json.loads(line)
        cmd = d.get("cmd", "").lower()
        if cmd not in ALLOWED or not d.get("file", "").startswith(str(source)):
            continue
        calls.append((cmd, d["args"][0] if d.get("args") else "", f"{d['file']}:{d['line']}"))
    return calls


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--cmake", default="cmake")
    ap.add_argument("--ninja", default="ninja")
    ap.add_argument("--hal-include-dir", default="/usr/include/linuxcnc", help="the folder of hal.h this build uses")
    ap.add_argument("--hal-library", default="/usr/lib/liblinuxcnchal.so", help="the liblinuxcnchal this build uses")
    ap.add_argument("--build", action="store_true", help="also build trueaxis-hal (slow)")
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    source = pathlib.Path(a.source).resolve()
    work = pathlib.Path(tempfile.mkdtemp(prefix="trueaxis-lean-"))
    failures = []
    try:
        env = dict(os.environ, PKG_CONFIG_LIBDIR=str(filtered_pkg_config_dir(work)), PKG_CONFIG_PATH="")
        env.pop("EMC2_HOME", None)
        build = work / "build"
        trace = work / "trace.json"
        cmd = [a.cmake, "-S", str(source), "-B", str(build), "-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={a.ninja}",
               "-DTRUEAXIS_ONLY_HAL=ON", "--trace-format=json-v1", f"--trace-redirect={trace}"]
        cmd += [f"-DCMAKE_DISABLE_FIND_PACKAGE_{p}=ON" for p in HIDDEN_PACKAGES]
        r = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stdout[-4000:], r.stderr[-4000:])
            print(f"FAIL: the lean configure failed without {', '.join(HIDDEN_PACKAGES + HIDDEN_PC)}")
            return 1
        calls = project_calls(trace, source)
        for cmd_name, what, where in calls:
            if what not in ALLOWED[cmd_name]:
                failures.append(f"the lean configure asks for {cmd_name}({what}) at {where}: trueaxis-hal does not link it")
        asked = sorted({f"{c}({w})" for c, w, _ in calls})
        print(f"the lean configure asks for: {', '.join(asked)}")
        if not any(c == "find_path" and w == "LINUXCNC_HAL_INCLUDE_DIR" for c, w, _ in calls):
            failures.append("the lean configure never looked for hal.h (the trace is not what this test expects)")

        q = subprocess.run([a.ninja, "-C", str(build), "-t", "query", "all"], capture_output=True, text=True, check=True)
        lines = q.stdout.splitlines()
        inputs = lines[lines.index("  input: phony") + 1:lines.index("  outputs:")] if "  outputs:" in lines else []
        inputs = [x.strip() for x in inputs]
        print(f"default build target: {', '.join(inputs)}")
        if inputs != ["src/linuxcnc/all"]:
            failures.append(f"the default target builds {inputs}, not only src/linuxcnc (the HAL programs)")
        t = subprocess.run([a.ninja, "-C", str(build), "-t", "targets", "all"], capture_output=True, text=True, check=True)
        targets = {x.split(":")[0] for x in t.stdout.splitlines()}
        for want in ("trueaxis-hal", "trueaxis-hal-plant"):
            if want not in targets:
                failures.append(f"no target {want} in the lean build")
        for unwanted in ("trueaxis", "src/server/libtrueaxis_server.a", "src/web/libtrueaxis_web.a"):
            if unwanted in targets:
                failures.append(f"the lean build defines {unwanted}")
        # A run-in-place LinuxCNC: hal.h in TREE/include, liblinuxcnchal in TREE/lib, found through
        # $EMC2_HOME as scripts/rip-environment sets it (here a tree of links to the packages' files).
        tree = work / "linuxcnc-rip"
        hal_dir, lib = pathlib.Path(a.hal_include_dir), pathlib.Path(a.hal_library)
        if (hal_dir / "hal.h").exists() and lib.exists():
            (tree / "lib").mkdir(parents=True)
            (tree / "include").symlink_to(hal_dir)
            (tree / "lib" / lib.name).symlink_to(lib)
            r = subprocess.run([a.cmake, "-S", str(source), "-B", str(work / "build-rip"), "-G", "Ninja",
                                f"-DCMAKE_MAKE_PROGRAM={a.ninja}", "-DTRUEAXIS_ONLY_HAL=ON"],
                               env=dict(env, EMC2_HOME=str(tree)), capture_output=True, text=True)
            want = f"LinuxCNC HAL: {tree}/include/hal.h, {tree}/lib/{lib.name}"
            print(f"run-in-place tree via EMC2_HOME: {'found' if want in r.stdout else 'NOT found'}")
            if r.returncode != 0 or want not in r.stdout:
                failures.append(f"with EMC2_HOME={tree} the configure did not take the tree's hal.h and library "
                                f"(expected '{want}'):\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
        else:
            failures.append(f"no {hal_dir}/hal.h or {lib} to build the run-in-place tree from")
        if a.build and not failures:
            b = subprocess.run([a.ninja, "-C", str(build), "trueaxis-hal"], capture_output=True, text=True)
            if b.returncode != 0:
                print(b.stdout[-4000:], b.stderr[-2000:])
                failures.append("building trueaxis-hal in the lean build failed")
            else:
                print(f"built {build / 'src/linuxcnc/trueaxis-hal'}")
    finally:
        if a.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print(f"FAIL: {f}")
    if failures:
        return 1
    print("PASS [lean configure: only what trueaxis-hal links]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
