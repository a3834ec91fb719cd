// `kiln cases` and `kiln integrators`: the shipped cases and the integrators, listed.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "integrators/integrator.h"
#include "integrators/stability_region.h"
#include "src/app/command.h"
#include "src/scene/scene_yaml.h"

namespace kiln {

namespace {

class CasesCommand final : public Command {
 public:
  explicit CasesCommand(CLI::App& app) : Command(app.add_subcommand("cases", "list the shipped cases")) {}

  int run() override {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(KILN_CASES_DIR))
      if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const Scene scene = load_scene(f.string());
      std::printf("%-30s %s\n", f.filename().c_str(), scene.description.c_str());
    }
    std::printf("(in %s)\n", KILN_CASES_DIR);
    return 0;
  }
};

class IntegratorsCommand final : public Command {
 public:
  explicit IntegratorsCommand(CLI::App& app)
      : Command(app.add_subcommand("integrators", "list the integrators with their orders")) {}

  int run() override {
    std::printf("%-30s %5s %9s %9s %6s %9s %9s  %s\n", "name", "order", "dashpot", "embedded", "adapts", "imag",
                "neg.real", "scheme");
    for (const auto& info : integrator_catalogue()) {
      const StabilityIntervals s = stability_intervals(info);
      std::printf("%-30s %5d %9d %9s %6s %9.4g %9.4g  %s\n", info.name.c_str(), info.order, info.order_with_dashpot,
                  info.embedding ? std::to_string(info.embedding).c_str() : "-", info.embedding ? "yes" : "no",
                  s.imaginary, s.negative_real, info.summary.c_str());
    }
    std::printf(
        "(order: nominal order on smooth forces; dashpot: order when forces depend on velocity;\n"
        " imag, neg.real: the stability interval in dt |lambda| on the imaginary axis (an undamped spring:\n"
        " stable while dt omega is below it) and on the negative real axis (a dashpot alone: while c dt / m is\n"
        " below it; for an explicit table also a conduction mode); an IMEX pair's are its explicit table's,\n"
        " which takes the mechanics, its conduction being implicit; the Verlet schemes step temperatures\n"
        " by Heun's method, reach 2)\n");
    return 0;
  }
};

}  // namespace

std::unique_ptr<Command> add_cases_command(CLI::App& app) { return std::make_unique<CasesCommand>(app); }
std::unique_ptr<Command> add_integrators_command(CLI::App& app) { return std::make_unique<IntegratorsCommand>(app); }

}  // namespace kiln
