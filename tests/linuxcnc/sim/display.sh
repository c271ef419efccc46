#!/bin/sh
# LinuxCNC's DISPLAY: the test's driver (no GUI). The launcher passes -ini FILE.
exec /usr/bin/python3 "${TRUEAXIS_LCNC_DRIVER:?TRUEAXIS_LCNC_DRIVER names the driver script}" "$@"
