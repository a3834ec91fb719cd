// `kiln plot`: the case quantities of a run over time into DIR/plots.png (scripts/plot_case.py).
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "src/app/command.h"
#include "src/base/atomic_write.h"
#include "src/base/error.h"
#include "src/base/subprocess.h"
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
    const std::string summary = (std::filesystem::path(dir_) / "summary.json").string();
    if (!std::filesystem::exists(summary))
      throw InputError("kiln plot: " + summary + " not found: give the output directory of a run (kiln run "
                       "SCENE --out DIR)");
    require_writable_directory(dir_, "kiln plot");  // a read-only run printed a Python traceback
    const ProgramResult r = run_program(
        {"/usr/bin/python3", std::string(KILN_SCRIPTS_DIR) + "/plot_case.py", dir_, "--keys", catalogue_keys()});
    std::fprintf(stderr, "%s", r.errors.c_str());  // the script's warnings and errors
    // 4: the script could not write plots.png (a full disk) and said so in one line; before, its
    // traceback was printed, then a hint to install matplotlib.
    if (r.status == exit_output_failed) return exit_output_failed;
    if (r.status != 0) {
      std::fprintf(stderr, "error: %s/plots.png not written (it needs Debian's /usr/bin/python3 with matplotlib and "
                           "h5py: apt-get install python3-matplotlib python3-h5py)\n", dir_.c_str());
      return exit_output_failed;
    }
    if (!quiet_) std::printf("plots: %s/plots.png\n", dir_.c_str());
    return exit_success;
  }

 private:
  std::string dir_;
  bool quiet_ = false;
};

}  // namespace

std::unique_ptr<Command> add_plot_command(CLI::App& app) { return std::make_unique<PlotCommand>(app); }

}  // namespace kiln
