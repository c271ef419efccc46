%
(trueaxis five-axis example: a tilted pocket wall with sharp corners)
(tool tip in the workpiece frame, TCP mode; docs/fiveaxis.md)
G21 G90
G0 X-40 Y-30 Z5 A0 C0
G1 X40 Y-30 Z5 A15 C0 F4000
G1 X40 Y30 Z5 A15 C90
G1 X-40 Y30 Z5 A15 C180
G1 X-40 Y-30 Z5 A15 C270
G91
G1 Z-2 F1000          (incremental step down)
G90 G1 X0 Y0 Z3 A0 C270 F3000
M30
%
