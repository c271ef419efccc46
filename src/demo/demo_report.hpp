#pragma once
// The demo's single HTML report (report::HtmlPage): setup, model, the
// before/after table of ISO 230-2 values per state, error curves, and the
// day's temperatures and corrections.
#include "trueaxis/demo/demo.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::demo {

void WriteDemoReport(const DemoResult& result, const DemoOptions& options, const model::FitResult& fit,
                     const sim::MachineDescription& machine);

}  // namespace trueaxis::demo
