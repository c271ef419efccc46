// trueaxis pitch into-model --pitch-file X.pitch.csv [--pitch-file Y.pitch.csv] --model M.json --out M2.json
// Puts pitch tables into the model file `run` loads: each table's axis gets
// the table as its geometric part and the range the table vouches for
// (docs/pitch-error-file.md, "Into the model").
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "pitch_command.hpp"
#include "utc_now.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/pitch/error_file.hpp"
#include "trueaxis/pitch/model_table.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::vector<std::string> pitch_files;
  std::string model, out;
};

void Run(const Options& o) {
  std::vector<std::string> inputs = o.pitch_files;
  inputs.push_back(o.model);
  RefuseOutputOverInput(o.out, inputs, "--out");
  model::CompositeModel m = model::ReadModelFile(o.model);
  const std::string parent_sha = model::Sha256OfFile(o.model);
  std::vector<std::string> axes_done;
  for (const auto& path : o.pitch_files) {
    const pitch::PitchErrorTable table = pitch::ReadPitchErrorFile(path);
    for (const auto& done : axes_done)
      if (done == table.axis)
        throw InputError(path, 0, "axis", fmt::format("a second pitch table for axis {}", table.axis));
    axes_done.push_back(table.axis);
    if (auto w = pitch::MeasuredRangeWarning(table, path)) fmt::print(stderr, "warning: {}\n", *w);
    pitch::PutTableIntoModel(table, m, o.model);
    model::SourceRecord src;
    src.path = path;
    src.sha256 = model::Sha256OfFile(path);
    src.state = "pitch table";
    src.axis = table.axis;
    m.sources.push_back(src);
    fmt::print("axis {}: geometric part = the pitch table ({} samples every {:.4g} mm), measured range {}…{} mm\n",
               table.axis, table.size(), table.SpacingMm(), table.VouchedFromMm(), table.VouchedToMm());
  }
  m.lineage.push_back({m.revision, parent_sha, m.created_utc});
  m.revision += 1;
  m.parent_sha256 = parent_sha;
  m.created_utc = cli::UtcNow();
  m.generator = "trueaxis pitch into-model";
  model::WriteModelFile(m, o.out);
  fmt::print("wrote {} (revision {}, sha256 {})\n", o.out, m.revision, model::Sha256OfFile(o.out));
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::PitchCommand(app)->add_subcommand(
      "into-model", "Put pitch tables into a model file for run: the axis's geometric part and the range it was measured over");
  cmd->add_option("--pitch-file", o->pitch_files, "pitch error file (repeat for more axes)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--model", o->model, "model file (JSON) to start from")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out, "model file to write")->required();
  cmd->callback([o] { Run(*o); });
}

cli::CommandRegistrar reg("pitch_into_model", Setup);

}  // namespace
