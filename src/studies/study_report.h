// What a study publishes, written one way for `kiln order`, `kiln sweep` and `kiln wp`: its table
// on standard output, and in the output directory <kind>.json, <kind>.csv and <kind>.png (drawn
// from the JSON by scripts/plot_study.py). A study fills the three as it goes, then publishes.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/base/text_format.h"
#include "src/scene/scene.h"

namespace kiln {

class StudyReport {
 public:
  // kind: order, sweep or wp (the files' names and the plot's kind); json: the fields it opens with.
  StudyReport(std::string kind, nlohmann::json json) : kind_(std::move(kind)), json_(std::move(json)) {}
  nlohmann::json& json() { return json_; }
  // A row of the CSV, its cells as written (numbers by csv_number); the first row is the header.
  void csv_row(const std::vector<std::string>& cells);
  // Text of the printed table, printf-style.
  void table(const char* format, ...) __attribute__((format(printf, 2, 3)));
  // Prints heading, the table and footer unless quiet; then writes the files into out_dir unless
  // it is empty (a rank other than 0 under mpirun, a test). A plot not drawn is a FigureError
  // (src/base/figure_script.h), thrown once the JSON and the CSV are written.
  void publish(const std::string& heading, const std::string& footer, const std::string& out_dir, bool quiet) const;

 private:
  std::string kind_;
  nlohmann::json json_;
  std::string csv_, table_;
};

// A number in a CSV cell: six significant digits, as an ostream writes it (the studies' steps,
// errors and times).
std::string csv_number(double v);
// A value in a CSV cell, every digit (the shortest text that reads back as v): a sweep's values,
// whose change with the step is what it shows.
std::string csv_exact(double v);

// The fields the JSON of a study of integrators against a reference opens with (order, wp).
nlohmann::json study_header(const Scene& scene, const std::string& quantity, const std::string& reference, double t_end);

}  // namespace kiln
