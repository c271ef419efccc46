#!/usr/bin/python3
"""An independent MODBUS TCP peer (pymodbus 3.0, Debian's python3-pymodbus) for
the trueaxis terminal: reads the documented registers (docs/protocols.md) and
writes a compensation vector. Prints one JSON object on stdout.

usage: pymodbus_peer.py PORT AXES WRITE_UM [WRITE_UM ...]
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


def main():
    port = int(sys.argv[1])
    axes = int(sys.argv[2])
    write_um = [float(x) for x in sys.argv[3:]]
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=2)
    if not client.connect():
        print(json.dumps({"error": "connect failed"}))
        return 1
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
    words = []
    for um in write_um:
        counts = int(round(um * 10)) & 0xFFFFFFFF
        words += [counts >> 16, counts & 0xFFFF]
    wr = client.write_registers(16, words, slave=1)
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
