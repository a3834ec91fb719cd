// `kiln plot`: the case quantities of a run over time into DIR/plots.png (scripts/plot_case.py).
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "src/app/command.h"
#include "src/base/atomic_write.h"
#include "src/base/error.h"
#include "src/base/figure_script.h"
#include "src/base/text_format.h"
#include "src/output/run_outputs.h"
#include "src/scene/observer_catalogue.h"

namespace kiln {

namespace {

// What the script is told of the case quantities: the observer catalogue's keys, so that a new
// observer's figures are drawn and labelled without a change to it.
const char* kind_name(ObserverKey::Kind kind) {
  switch (kind) {
    case ObserverKey::Kind::number: return "number";
    case ObserverKey::Kind::list: return "list";
    case ObserverKey::Kind::text: return "text";
  }
  return "";
}

std::string catalogue_keys() {
  nlohmann::json keys = nlohmann::json::array();
  for (const ObserverEntry& entry : observer_catalogue())
    for (const ObserverKey& k : entry.keys)
      keys.push_back({{"path", k.path},
                      {"kind", kind_name(k.kind)},
                      {"unit", k.unit},
                      {"meaning", k.meaning},
                      {"against", k.against}});
  return keys.dump();
}

class PlotCommand final : public Command {
 public:
  explicit PlotCommand(CLI::App& app)
      : Command(app.add_subcommand(
            "plot", "plot a run's case quantities over time (DIR/summary.json, DIR/result.h5) into DIR/plots.png")) {
    cli_->add_option("dir", dir_, "the output directory of a run")->required()->check(CLI::ExistingDirectory);
    cli_->add_flag("--quiet", quiet_, "no closing line");
  }

  int run() override {
    RunOutputs::require_published(dir_, "summary.json", "plot it");
    // A read-only run printed a Python traceback; it is told before drawing, with the exit status
    // of a figure that cannot be written (4: no permission), not of bad input.
    try {
      require_writable_directory(dir_, "kiln plot");
    } catch (const InputError& e) {
      std::fprintf(stderr, "error: %s\n", bounded(e.what()).c_str());
      return exit_output_failed;
    }
    const std::string figure = (std::filesystem::path(dir_) / "plots.png").string();
    // A figure not drawn says why in one line, with its exit code (4: no room, no permission or
    // no matplotlib; 6: a defect of the script's): before, a full disk printed the script's
    // traceback, then a hint to install matplotlib.
    try {
      draw_figure("plot_case.py", {dir_, "--keys", catalogue_keys()}, figure);
    } catch (const FigureError& e) {
      std::fprintf(stderr, "error: %s\n", bounded(e.what()).c_str());
      return e.status;
    }
    if (!quiet_) std::printf("plots: %s\n", figure.c_str());
    return exit_success;
  }

 private:
  std::string dir_;
  bool quiet_ = false;
};

}  // namespace

std::unique_ptr<Command> add_plot_command(CLI::App& app) { return std::make_unique<PlotCommand>(app); }

}  // namespace kiln
