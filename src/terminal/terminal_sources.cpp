#include "trueaxis/terminal/terminal_sources.hpp"

#include "trueaxis/drivers/modbus_temperature_source.hpp"

namespace trueaxis::terminal {

TerminalSources BuildTerminalSources(const TerminalConfig& config) {
  TerminalSources s;
  std::vector<std::unique_ptr<hw::TemperatureSource>> parts;
  auto add = [&](std::unique_ptr<hw::TemperatureSource> source, const PollSettings& poll) {
    auto p = std::make_unique<PolledTemperatureSource>(std::move(source), poll.period_s, poll.stale_after_s);
    s.parts.push_back(p.get());
    parts.push_back(std::move(p));
  };
  if (config.one_wire.present) {
    auto w1 = std::make_unique<OneWireTemperatureSource>(config.one_wire.options);
    s.one_wire = w1.get();
    add(std::move(w1), config.one_wire.poll);
  }
  for (const auto& g : config.rtd) add(std::make_unique<drivers::ModbusTemperatureSource>(g.options), g.poll);
  s.combined = std::make_unique<CombinedTemperatureSource>(std::move(parts));
  return s;
}

}  // namespace trueaxis::terminal
