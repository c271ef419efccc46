#pragma once
// Importer for the ecmc (PSI EPICS motion control) ISO 230-2 input file,
// "*.dat" (docs/formats.md), e.g.
//
//   TEST_DATA=# Input data file for ISO230-2 calcs derived from: /path/data.log
//   # comment lines
//   UNIT=mm
//   CYCLES=5
//   POSITIONS=5
//   TGT_DATA[1]=-10
//   REF_DATA_FWD[1,1]=-10.0000990190
//   REF_DATA_BWD[1,1]=-10.0000810190
//
// TGT_DATA[i] is the target of position i, REF_DATA_FWD[i,j] / REF_DATA_BWD[i,j]
// the reference (laser/encoder) reading at position i in cycle j, approached
// forward ('+') / backward ('-'). Deviation = (REF − TGT) converted to µm.
//
// Quirks of real files handled here: the first line glues a comment to a key
// ("TEST_DATA=# ..."); numbers without a leading zero (".2399"); trailing
// blank or whitespace-only lines; CRLF line ends; keys in any order.
// Bad input throws InputError(file, line, field, why), field being the key as
// written, e.g. "REF_DATA_FWD[3,2]". CYCLES/POSITIONS, when given, must agree
// with the data (a truncated export must not pass silently).
#include <string>
#include <string_view>

#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::measure {

Measurement ParseEcmcDat(std::string_view text, const std::string& source);
Measurement ReadEcmcDat(const std::string& path);

}  // namespace trueaxis::measure
