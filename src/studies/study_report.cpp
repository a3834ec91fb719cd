#include "src/studies/study_report.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "src/base/atomic_write.h"
#include "src/base/figure_script.h"
#include "src/studies/study_ranks.h"

namespace kiln {

std::string csv_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string csv_exact(double v) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, v).ptr);
}

void StudyReport::csv_row(const std::vector<std::string>& cells) {
  for (size_t k = 0; k < cells.size(); ++k) csv_ += (k > 0 ? "," : "") + cells[k];
  csv_ += "\n";
}

void StudyReport::table(const char* format, ...) {
  va_list args;
  va_start(args, format);
  table_ += vformat(format, args);
  va_end(args);
}

void StudyReport::publish(const std::string& heading, const std::string& footer, const std::string& out_dir,
                          bool quiet) const {
  if (!quiet) std::printf("%s%s%s", heading.c_str(), table_.c_str(), footer.c_str());
  if (out_dir.empty()) return;
  std::filesystem::create_directories(out_dir);
  const std::string base = out_dir + "/" + kind_;
  write_file_atomically(base + ".json", json_.dump(2) + "\n");
  write_file_atomically(base + ".csv", csv_);
  // A plot not drawn is an output not written (exit 4; 6 for a defect of the script's), said in
  // one line that names what was written: before, a full disk or a null fitted order printed a
  // Python traceback and "needs matplotlib", and the study exited 0.
  try {
    draw_figure("plot_study.py", {kind_, base + ".json", base + ".png"}, base + ".png");
  } catch (const FigureError& e) {
    throw FigureError(e.status, std::string(e.what()) + " (" + kind_ + ".json and " + kind_ + ".csv are written)");
  }
}

nlohmann::json study_header(const Scene& scene, const std::string& quantity, const std::string& reference, double t_end) {
  return {{"scene", scene.name},
          {"quantity", quantity},
          {"norm", "max abs over components"},
          {"reference", reference},
          {"t_end", t_end},
          {"ranks", rank_count()},  // how it ran: the MPI processes (src/studies/study_ranks.h)
          {"integrators", nlohmann::json::array()}};
}

}  // namespace kiln
