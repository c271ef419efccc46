#!/usr/bin/python3
"""An independent MODBUS TCP peer (pymodbus 3.0, Debian's python3-pymodbus) for
the trueaxis terminal: reads the documented registers (docs/protocols.md) and
writes a compensation vector. Prints one JSON object on stdout.

usage: pymodbus_peer.py PORT AXES WRITE_UM [WRITE_UM ...]
       pymodbus_peer.py --read-write PORT AXES WRITE_UM [WRITE_UM ...]
The second form writes the compensation and reads the PMC window in one FC 23 (read/write
multiple registers: the window's copy at holding registers 100...), then reads the window itself
with FC 04, and prints both.
"""
import json
import sys
import types

# Debian's pymodbus 3.0 client package imports the serial modules even for TCP;
# without python3-serial-asyncio installed, stand-ins let the TCP client load.
for name in ("serial", "serial_asyncio"):
    try:
        __import__(name)
    except ImportError:
        stub = types.ModuleType(name)
        stub.create_serial_connection = None
        sys.modules[name] = stub

from pymodbus.client import ModbusTcpClient  # noqa: E402


def int32(hi, lo):
    v = (hi << 16) | lo
    return v - (1 << 32) if v & 0x80000000 else v


def words_of(write_um):
    words = []
    for um in write_um:
        counts = int(round(um * 10)) & 0xFFFFFFFF
        words += [counts >> 16, counts & 0xFFFF]
    return words


def read_write(client, axes, write_um):
    rw = client.readwrite_registers(read_address=100, read_count=16 + 8 * axes, write_address=16,
                                    write_registers=words_of(write_um), unit=1)  # this request takes unit=, not slave=
    if rw.isError():
        print(json.dumps({"error": "FC 23: %s" % rw, "exception": getattr(rw, "exception_code", None)}))
        return 1
    window = client.read_input_registers(0, 16 + 8 * axes, slave=1)
    if window.isError():
        print(json.dumps({"error": "read PMC window: %s" % window}))
        return 1
    print(json.dumps({"copy": rw.registers, "window": window.registers}))
    return 0


def main():
    args = sys.argv[1:]
    mode_read_write = args[0] == "--read-write"
    if mode_read_write:
        args = args[1:]
    port = int(args[0])
    axes = int(args[1])
    write_um = [float(x) for x in args[2:]]
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=2)
    if not client.connect():
        print(json.dumps({"error": "connect failed"}))
        return 1
    if mode_read_write:
        status = read_write(client, axes, write_um)
        client.close()
        return status
    out = {}
    rr = client.read_input_registers(0, 16 + 8 * axes, slave=1)
    if rr.isError():
        print(json.dumps({"error": "read PMC window: %s" % rr}))
        return 1
    r = rr.registers
    out["layout"] = r[0]
    out["axis_count"] = r[1]
    out["heartbeat"] = (r[2] << 16) | r[3]
    out["coolant"] = r[4]
    out["status"] = r[5]
    out["position_mm"] = [int32(r[16 + 8 * a], r[17 + 8 * a]) * 1e-4 for a in range(axes)]
    out["direction"] = [r[18 + 8 * a] - 65536 if r[18 + 8 * a] > 32767 else r[18 + 8 * a] for a in range(axes)]
    wr = client.write_registers(16, words_of(write_um), slave=1)
    out["write_ok"] = not wr.isError()
    # ADAM-6015 at unit 2: AI values 40001.., burn-out flags 00121.., type codes 40201.., name 40211
    ai = client.read_holding_registers(0, 7, slave=2)
    bo = client.read_coils(120, 7, slave=2)
    tc = client.read_holding_registers(200, 7, slave=2)
    nm = client.read_holding_registers(210, 1, slave=2)
    if ai.isError() or bo.isError() or tc.isError() or nm.isError():
        print(json.dumps({"error": "read ADAM-6015"}))
        return 1
    out["adam_raw"] = ai.registers
    out["adam_burnout"] = [1 if b else 0 for b in bo.bits[:7]]
    out["adam_type_codes"] = tc.registers
    out["adam_name"] = nm.registers[0]
    client.close()
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
