#include "trueaxis/web/model_figures.hpp"

#include <filesystem>
#include <map>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/measure/measurement_file.hpp"

namespace trueaxis::web {

namespace fs = std::filesystem;

std::vector<ModelFigure> IsoFiguresFromLaserPairs(const std::string& dir, std::vector<std::string>* warnings) {
  std::vector<ModelFigure> out;
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return out;
  std::map<std::string, fs::path> offs;  // sorted: stable order on the page
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 8 && name.ends_with("_off.csv")) offs[name.substr(0, name.size() - 8)] = e.path();
  }
  for (const auto& [stem, off_path] : offs) {
    const fs::path on_path = fs::path(dir) / (stem + "_on.csv");
    if (!fs::is_regular_file(on_path, ec)) continue;
    try {
      const measure::Measurement off = measure::ReadMeasurementFile(off_path.string());
      const measure::Measurement on = measure::ReadMeasurementFile(on_path.string());
      const analysis::Evaluation before = analysis::Evaluate(off), after = analysis::Evaluate(on);
      const std::string axis = off.Meta("axis").value_or(stem.substr(0, stem.find('_')));
      const std::string state = stem.find('_') == std::string::npos ? stem : stem.substr(stem.find('_') + 1);
      const std::string source = off_path.filename().string() + " / " + on_path.filename().string();
      out.push_back({axis, "A (ISO 230-2 accuracy), " + state, before.axis.A_um, after.axis.A_um, source});
      out.push_back({axis, "E (ISO 230-2 systematic), " + state, before.axis.E_um, after.axis.E_um, source});
    } catch (const std::exception& e) {
      if (warnings) warnings->push_back(e.what());
    }
  }
  return out;
}

std::vector<ModelFigure> FiguresFromFitSummary(const model::CompositeModel& model) {
  std::vector<ModelFigure> out;
  const auto& axes = model.fit_summary.value("axes", nlohmann::json::array());
  for (const auto& a : axes) {
    if (!a.is_object()) continue;
    const std::string axis = a.value("axis", "");
    for (const auto& s : a.value("states", nlohmann::json::array())) {
      const auto num = [&](const char* k) {
        return s.contains(k) && s[k].is_number() ? s[k].get<double>() : std::numeric_limits<double>::quiet_NaN();
      };
      out.push_back({axis, "max |error| on the fit data, state " + s.value("label", std::string("?")),
                     num("uncorrected_max_um"), num("residual_max_um"), "model fit summary (not an ISO test)"});
    }
  }
  return out;
}

}  // namespace trueaxis::web
