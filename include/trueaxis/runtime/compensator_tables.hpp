#pragma once
// The compensator's own tables of a TOML configuration ([limits], [sensor_fault], [link],
// [channels], [[axis]]: docs/runtime.md), read through a checked TomlTableReader — all the pure
// runtime reads of a configuration file. Where the machine is, its history and its web page are
// the station's (station::SiteConfig, the `run` file; server::ShopConfig, the shop file).
#include <vector>

#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/compensator_options.hpp"

namespace trueaxis::runtime {

// Shared by `run` and the shop file's machines (docs/server.md). `period_s` is the cycle period
// (the CNC snapshot goes stale after 3 of them). `axis_lines` (optional) gets the line of each
// [[axis]] name, in the order of `axes`.
void ReadCompensatorTables(TomlTableReader& r, double period_s, CompensatorOptions& o, std::vector<AxisInterface>& axes,
                           std::vector<int>* axis_lines = nullptr);

}  // namespace trueaxis::runtime
