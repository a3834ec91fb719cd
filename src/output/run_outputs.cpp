#include "src/output/run_outputs.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "src/base/error.h"
#include "src/output/outputs.h"

namespace kiln {

namespace fs = std::filesystem;

const std::vector<std::string>& RunOutputs::names() {
  static const std::vector<std::string> n = {"result.h5",    "result.h5.tmp",   "result.xdmf",    "result.xdmf.tmp",
                                             "summary.json", "summary.json.tmp", "picture.png",    "picture.png.tmp",
                                             "checkpoint.h5", "checkpoint.h5.tmp", "result.h5.unfinished",
                                             "wall_loads.csv", "wall_loads.csv.tmp", "units.csv", "units.csv.tmp",
                                             // drawn from a run's results (movie.h, scripts/plot_case.py)
                                             "movie",         "movie.tmp",         "movie.mp4",        "movie.mp4.tmp",
                                             "plots.png",     "plots.png.tmp"};
  return n;
}

std::string RunOutputs::path(const std::string& name) const { return (fs::path(dir_) / name).string(); }

namespace {

void make_directory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw OutputError("cannot create the output directory " + dir + ": " + error.message());
}

// Moves what an earlier run wrote in `dir` into dir/previous/.
void move_aside(const std::string& dir) {
  const fs::path previous = fs::path(dir) / "previous";
  bool any = false;
  for (const std::string& name : RunOutputs::names()) any = any || fs::exists(fs::path(dir) / name);
  if (!any) return;
  std::error_code error;
  fs::create_directories(previous, error);
  for (const std::string& name : RunOutputs::names()) {
    fs::remove_all(previous / name, error);
    if (fs::exists(fs::path(dir) / name)) fs::rename(fs::path(dir) / name, previous / name, error);
    if (error) throw OutputError("cannot move " + (fs::path(dir) / name).string() + " into " + previous.string() + ": " +
                                 error.message());
  }
}

}  // namespace

bool walls_move(const DemSystem& sys) {
  for (const Wall& w : sys.scene().walls)
    if (w.motion.moves()) return true;
  return false;
}

ResultLayout result_layout(const DemSystem& sys) {
  ResultLayout l;
  l.particles = sys.particles();
  l.thermal = sys.thermal();
  l.walls = static_cast<int>(sys.scene().walls.size());
  for (int pieces : pieces_of_segments(sys)) l.segments += pieces;
  l.walls_move = walls_move(sys);
  return l;
}

// One run at a time per directory: two runs writing into one would publish a mix of both. The
// lock is the kernel's (flock), so it goes with the process however that ends.
void RunOutputs::lock_directory() {
  make_directory(dir_);
  lock_ = ::open(path(".kiln.lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock_ < 0) throw OutputError("cannot create " + path(".kiln.lock") + ": " + std::strerror(errno));
  if (::flock(lock_, LOCK_EX | LOCK_NB) != 0)
    throw InputError(dir_ + " is in use by another kiln run (it holds " + path(".kiln.lock") +
                     "): wait for it to end, or give another --out");
}

bool RunOutputs::running_in(const std::string& dir) {
  const int fd = ::open((fs::path(dir) / ".kiln.lock").c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

void RunOutputs::require_published(const std::string& dir, const std::string& name, const std::string& then) {
  const std::string file = (fs::path(dir) / name).string();
  if (fs::exists(file)) return;
  if (running_in(dir))
    throw InputError(file + " is missing: the run in " + dir + " is still running (it holds .kiln.lock); " + then +
                     " when it has ended");
  // A run killed outright leaves its finished frames in result.h5.tmp and its last checkpoint;
  // one whose output failed (a full disk), in result.h5.unfinished.
  const std::string result = (fs::path(dir) / "result.h5").string();
  for (const char* left : {".tmp", ".unfinished"})
    if (fs::exists(result + left))
      throw InputError(file + " is missing: the run in " + dir + " did not finish (" +
                       (std::string(left) == ".tmp" ? "it was killed" : "its output failed") +
                       "; its finished frames are in result.h5" + left + "); finish it with kiln run --restart " +
                       (fs::path(dir) / "checkpoint.h5").string() + ", then " + then);
  throw InputError(file + " is missing: give the directory of a run (kiln run SCENE --out DIR)");
}

RunOutputs::RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id)
    : dir_(dir), sys_(sys), layout_(result_layout(sys)), pieces_(pieces_of_segments(sys)), run_id_(run_id) {
  lock_directory();
  move_aside(dir_);
  try {
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), layout_);
    const Scene& scene = sys.scene();
    h5_->attribute("scene", scene.name);
    h5_->attribute("integrator", scene.integrator);
    h5_->attribute("dt", scene.dt);
    h5_->attribute("kiln_version", KILN_VERSION);
    h5_->attribute("run_id", run_id);
    std::vector<double> r(sys.particles());
    for (int i = 0; i < sys.particles(); ++i) r[i] = sys.radius(i);
    h5_->write_constant(r);
    if (layout_.walls > 0) {
      std::vector<int> wall_of_segment;
      for (size_t k = 0; k < scene.segments.size(); ++k) wall_of_segment.insert(wall_of_segment.end(), pieces_[k], scene.segments[k].wall);
      std::vector<std::string> names;
      for (const Wall& w : scene.walls) names.push_back(w.name);
      if (!layout_.walls_move) {
        const std::vector<double> y0 = sys.initial_state();
        sys.wall_geometry(0, y0.data(), wall_a_, wall_b_);
        segments_rows();
      }
      h5_->write_walls(wall_of_segment, names, layout_.walls_move ? nullptr : segments_.data());
    }
  } catch (...) {
    if (h5_) h5_->abandon();
    h5_.reset();
    std::remove(path("result.h5.tmp").c_str());
    throw;
  }
}

RunOutputs::RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id, int frames,
                       const Snapshot& checkpoint)
    : dir_(dir),
      sys_(sys),
      layout_(result_layout(sys)),
      pieces_(pieces_of_segments(sys)),
      run_id_(run_id),
      resumed_from_(&checkpoint) {
  lock_directory();
  // The result holding this run's frames up to the checkpoint: the result.h5.tmp of a killed run
  // (a killed resumed run's holds more than result.h5), the frames of a killed or failed run kept
  // by an earlier restart or by the run itself (result.h5.unfinished), or the published result.h5.
  std::string original;
  for (const char* name : {"result.h5.tmp", "result.h5.unfinished", "result.h5"})
    if (fs::exists(path(name)) && H5Frames::frames_of_run(path(name), run_id) >= frames) {
      original = name;
      break;
    }
  if (original.empty())
    throw InputError(dir_ + ": none of result.h5, result.h5.tmp (a killed run's) and result.h5.unfinished holds the " +
                     std::to_string(frames) + " frames of run '" + run_id +
                     "' that the checkpoint continues: a result of another run, or frames lost");
  std::error_code error;
  if (original == "result.h5.tmp") {  // kept under a name of its own while a copy is extended
    fs::rename(path("result.h5.tmp"), path("result.h5.unfinished"), error);
    if (error) throw OutputError("cannot rename " + path("result.h5.tmp") + ": " + error.message());
    original = "result.h5.unfinished";
  }
  fs::copy_file(path(original), path("result.h5.tmp"), fs::copy_options::overwrite_existing, error);
  try {
    if (error)
      throw OutputError("cannot copy " + path(original) + " to " + path("result.h5.tmp") + ": " + error.message());
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), layout_, frames, checkpoint.real("time"));
    times_ = h5_->times();
  } catch (...) {
    if (h5_) h5_->abandon();
    h5_.reset();
    std::remove(path("result.h5.tmp").c_str());
    throw;
  }
}

RunOutputs::~RunOutputs() {
  if (!done_ && h5_) clean_up();
  if (lock_ >= 0) ::close(lock_);  // the lock goes last, after every file is in place
}

namespace {
// What a run writes on its way to publishing, besides its frames.
const char* const publication_temporaries[] = {"result.xdmf.tmp",    "summary.json.tmp", "picture.png.tmp",
                                               "checkpoint.h5.tmp",  "wall_loads.csv.tmp", "units.csv.tmp"};
}  // namespace

void RunOutputs::clean_up() {
  h5_->abandon();
  std::remove(path("result.h5.tmp").c_str());
  for (const char* name : publication_temporaries) std::remove(path(name).c_str());
  if (!checkpointed_) return;
  if (!resumed_from_) {
    std::remove(path("checkpoint.h5").c_str());  // only of use beside the frames it continues
    return;
  }
  try {
    resumed_from_->write(path("checkpoint.h5"));  // the one that matches the original's frames
  } catch (const std::exception&) {
    // A later checkpoint is left: a restart from it reports the frames it misses.
  }
}

std::string RunOutputs::keep_finished_work() {
  if (done_ || !h5_) return "";
  h5_->leave_as_flushed();  // every frame up to the last flushed one, as a killed run leaves them
  for (const char* name : publication_temporaries) std::remove(path(name).c_str());
  // The frames are of use only with the checkpoint that continues them: a checkpoint follows the
  // flush of every frame it counts.
  std::error_code error;
  if (checkpointed_) fs::rename(path("result.h5.tmp"), path("result.h5.unfinished"), error);
  const bool kept_frames = checkpointed_ && !error;
  if (!kept_frames) clean_up();
  done_ = true;
  if (!kept_frames) return resumed_from_ ? "; the result and the checkpoint it resumed from are as they were" : "";
  std::ostringstream kept;
  kept << "; kept: " << checkpoint_frames_ << " frames in " << path("result.h5.unfinished") << " and "
       << path("checkpoint.h5") << " (t = " << checkpoint_time_ << " s): once there is room, `kiln run --restart "
       << path("checkpoint.h5") << "` finishes the run";
  return kept.str();
}

bool RunOutputs::published(const std::string& dir, const std::string& run_id, double t) {
  std::ifstream in(fs::path(dir) / "summary.json");
  if (!in) return false;
  try {
    const nlohmann::json s = nlohmann::json::parse(in);
    return s.value("run_id", std::string()) == run_id && s.value("t_end", -HUGE_VAL) >= t;  // HUGE_VAL: a double
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

// How many pieces a segment of length `length` is written as in the cell: one, and one more per
// edge of a periodic axis it can cross (a rigid wall's length is its own at every time).
int pieces_in_cell(const PeriodicCell& cell, double length) {
  int pieces = 1;
  if (cell.x) pieces += static_cast<int>(std::ceil(length / cell.length_x()));
  if (cell.y) pieces += static_cast<int>(std::ceil(length / cell.length_y()));
  return pieces;
}

// A segment as it is seen in a periodic cell: cut where it crosses the cell's edges, each piece
// moved by whole periods into the cell (a wall driven along a periodic axis has travelled many
// periods, and a lid as long as the period crosses an edge at almost every frame). `pieces` slots
// are filled: those it does not need are of zero length at its last end.
void cut_into_cell(const PeriodicCell& cell, Vec2 a, Vec2 b, int pieces, std::vector<Vec2>& ends) {
  if (!cell.any()) {
    ends.push_back(a);
    ends.push_back(b);
    return;
  }
  const Vec2 start = cell.wrap(a), d = b - a;
  std::vector<double> cuts = {0.0, 1.0};  // where the segment crosses x0 + k Lx or y0 + m Ly
  auto crossings = [&](bool periodic, double from, double delta, double origin, double period) {
    if (!periodic || delta == 0) return;
    const double lo = std::min(from, from + delta), hi = std::max(from, from + delta);
    for (double e = origin + period * std::ceil((lo - origin) / period); e < hi; e += period)
      if (e > lo) cuts.push_back((e - from) / delta);
  };
  crossings(cell.x, start.x, d.x, cell.x0, cell.length_x());
  crossings(cell.y, start.y, d.y, cell.y0, cell.length_y());
  std::sort(cuts.begin(), cuts.end());
  for (size_t k = 0; k + 1 < cuts.size() && static_cast<int>(k) < pieces; ++k) {
    const Vec2 p = start + cuts[k] * d, q = start + cuts[k + 1] * d;
    const Vec2 shift = cell.wrap(0.5 * (p + q)) - 0.5 * (p + q);
    ends.push_back(p + shift);
    ends.push_back(q + shift);
  }
  for (int k = static_cast<int>(cuts.size()) - 1; k < pieces; ++k) {
    const Vec2 last = ends.back();
    ends.push_back(last);
    ends.push_back(last);
  }
}

}  // namespace

std::vector<int> pieces_of_segments(const DemSystem& sys) {
  std::vector<int> pieces;
  for (const Segment& seg : sys.scene().segments) pieces.push_back(pieces_in_cell(sys.cell(), norm(seg.b - seg.a)));
  return pieces;
}

void RunOutputs::cut_walls(const std::vector<Vec2>& a, const std::vector<Vec2>& b, std::vector<Vec2>& ends) const {
  ends.clear();
  for (size_t s = 0; s < a.size(); ++s) cut_into_cell(sys_.cell(), a[s], b[s], pieces_[s], ends);
}

void RunOutputs::segments_rows() {
  cut_walls(wall_a_, wall_b_, ends_);
  segments_.resize(2 * ends_.size());
  for (size_t e = 0; e < ends_.size(); ++e) {
    segments_[2 * e] = ends_[e].x;
    segments_[2 * e + 1] = ends_[e].y;
  }
}

void RunOutputs::frame(double t, const double* y) {
  H5Frame f;
  f.t = t;
  f[FrameField::position] = y + sys_.x_at();  // the y block follows the x block (DemSystem's layout)
  if (sys_.cell().any()) {  // the places in the periodic cell, not the continuous positions
    const int n = sys_.particles();
    wrapped_.resize(2 * n);
    for (int i = 0; i < n; ++i) {
      const Vec2 p = sys_.cell().wrap({y[sys_.x_at() + i], y[sys_.y_at() + i]});
      wrapped_[i] = p.x;
      wrapped_[n + i] = p.y;
    }
    f[FrameField::position] = wrapped_.data();
  }
  f[FrameField::velocity] = y + sys_.vx_at();
  f[FrameField::angle] = sys_.rotates() ? y + sys_.angle_at() : nullptr;
  f[FrameField::angular_velocity] = sys_.rotates() ? y + sys_.omega_at() : nullptr;
  f[FrameField::temperature] = sys_.thermal() ? y + sys_.temperature_at() : nullptr;
  if (layout_.walls > 0) {
    if (layout_.walls_move) {
      sys_.wall_geometry(t, y, wall_a_, wall_b_);
      segments_rows();
      f[FrameField::wall_segments] = segments_.data();
    }
    // The loads of the system's latest force evaluation (DemSystem::wall_loads).
    const std::vector<DemSystem::WallLoad>& loads = sys_.wall_loads();
    if (loads.size() != static_cast<size_t>(layout_.walls))
      throw std::logic_error("the system gives the loads of " + std::to_string(loads.size()) + " walls, the scene has " +
                             std::to_string(layout_.walls));
    wall_force_.resize(2 * loads.size());
    wall_torque_.resize(loads.size());
    wall_power_.resize(loads.size());
    for (size_t w = 0; w < loads.size(); ++w) {
      wall_force_[2 * w] = loads[w].force.x;
      wall_force_[2 * w + 1] = loads[w].force.y;
      wall_torque_[w] = loads[w].torque;
      wall_power_[w] = loads[w].power;
    }
    f[FrameField::wall_force] = wall_force_.data();
    f[FrameField::wall_torque] = wall_torque_.data();
    f[FrameField::wall_power] = wall_power_.data();
  }
  h5_->append(f);
  times_.push_back(t);
}

std::string how_it_ended(const nlohmann::json& summary) {
  std::ostringstream s;
  const nlohmann::json& stopped = summary.value("stopped_early", nlohmann::json(false));
  if (stopped == "at_rest") {
    s << "stopped at rest (kinetic energy below the scene's stop)";
  } else if (stopped == "signal") {
    s << "stopped by a signal (resume from checkpoint.h5)";
  } else if (summary.contains("frozen_at") && summary["frozen_at"].is_number()) {
    s << "mechanics frozen at " << summary["frozen_at"].get<double>() << " s, heat to t_end";
  } else {
    s << "reached t_end";
  }
  const long steps = summary.value("steps", 0L);
  const nlohmann::json heat = summary.contains("integrator_stats")
                                  ? summary["integrator_stats"].value("heat_stage", nlohmann::json())
                                  : nlohmann::json();
  if (heat.is_object() && heat.contains("steps")) {  // settled, then heat alone with its own integrator
    const long heat_steps = heat["steps"].get<long>();
    s << "; " << steps - heat_steps << " steps of " << summary.value("integrator", std::string("?")) << ", then "
      << heat_steps << " of " << heat.value("integrator", std::string("?")) << " (heat alone)";
  } else {
    s << "; " << steps << " steps of " << summary.value("integrator", std::string("?"));
  }
  return s.str();
}


namespace {

// A wall's name as a CSV column's: ParaView's CSV reader (5.11) does not read a doubled quote
// back, and a line break ends a row, so quotes become ' and control characters spaces; a name
// that then repeats another's gets its wall's index (ParaView keeps one column of a name).
std::vector<std::string> csv_wall_names(const std::vector<Wall>& walls) {
  std::vector<std::string> names;
  for (size_t w = 0; w < walls.size(); ++w) {
    std::string name = walls[w].name;
    for (char& c : name)
      if (c == '"') c = '\'';
      else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    if (std::find(names.begin(), names.end(), name) != names.end()) name += " #" + std::to_string(w);
    names.push_back(name);
  }
  return names;
}

}  // namespace

std::string RunOutputs::wall_loads_csv() const {
  const std::vector<double> t = h5_->times(), force = h5_->read(FrameField::wall_force),
                            torque = h5_->read(FrameField::wall_torque), power = h5_->read(FrameField::wall_power);
  std::ostringstream csv;
  csv << "\"time (s)\"";
  for (const std::string& name : csv_wall_names(sys_.scene().walls))
    for (const char* load : {" force_x (N)", " force_y (N)", " torque (N m)", " power (W)"})
      csv << ",\"" << name << load << '"';
  csv << '\n';
  const size_t walls = sys_.scene().walls.size();
  char number[32];
  auto put = [&](double v) {
    std::snprintf(number, sizeof number, ",%.17g", v);
    csv << number;
  };
  for (size_t k = 0; k < t.size(); ++k) {
    std::snprintf(number, sizeof number, "%.17g", t[k]);
    csv << number;
    for (size_t w = 0; w < walls; ++w) {
      put(force[3 * (k * walls + w)]);
      put(force[3 * (k * walls + w) + 1]);
      put(torque[k * walls + w]);
      put(power[k * walls + w]);
    }
    csv << '\n';
  }
  return csv.str();
}

PictureInput RunOutputs::picture(double t, const double* y, const std::string& title) const {
  PictureInput pic;
  for (int i = 0; i < sys_.particles(); ++i) {
    pic.centre.push_back(sys_.cell().wrap({y[sys_.x_at() + i], y[sys_.y_at() + i]}));
    pic.radius.push_back(sys_.radius(i));
    pic.value.push_back(sys_.thermal() ? y[sys_.temperature_at() + i]
                                       : std::hypot(y[sys_.vx_at() + i], y[sys_.vy_at() + i]));
    pic.of_wall.push_back(sys_.attached(i));
  }
  pic.value_label = sys_.thermal() ? "temperature (C)" : "speed (m/s)";
  std::vector<Vec2> a, b, ends;
  sys_.wall_geometry(t, y, a, b);  // where the walls are at t, moving ones too
  cut_walls(a, b, ends);
  for (size_t e = 0; e < ends.size(); e += 2) {
    pic.wall_a.push_back(ends[e]);
    pic.wall_b.push_back(ends[e + 1]);
  }
  pic.title = title;
  return pic;
}

void RunOutputs::checkpoint(const Snapshot& s) {
  s.write(path("checkpoint.h5"));
  checkpointed_ = true;
  checkpoint_frames_ = s.integer_as<int>("frames", 0);
  checkpoint_time_ = s.real("time");
}

void RunOutputs::finish(double t, const double* y, const nlohmann::json& summary, const std::string& title,
                        const std::vector<ResultTable>& tables) {
  h5_->reserve_for_closing(tables);
  for (const ResultTable& table : tables) h5_->write_table(table);
  h5_->write_frame_views();
  const std::string loads = layout_.walls > 0 ? wall_loads_csv() : "";
  h5_->close();
  PictureInput pic = picture(t, y, title);
  pic.subtitle = how_it_ended(summary);
  // Everything is written before anything is published: a failure leaves no final name behind.
  write_picture(path("picture.png.tmp"), pic);
  write_file(path("result.xdmf.tmp"), xdmf_document("result.h5", layout_, times_));
  if (layout_.walls > 0) write_file(path("wall_loads.csv.tmp"), loads);
  write_file(path("units.csv.tmp"), units_table(layout_));
  // A byte that is not UTF-8 (which the scene reader refuses) must not lose the run here.
  write_file(path("summary.json.tmp"), summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  // summary.json last: it says the run was published (a run killed before it resumes to publish).
  for (const char* name : {"result.h5", "result.xdmf", "units.csv", "picture.png", "wall_loads.csv", "summary.json"})
    if (layout_.walls > 0 || std::string(name) != "wall_loads.csv") publish(path(std::string(name) + ".tmp"), path(name));
  std::remove(path("result.h5.unfinished").c_str());  // a resumed run's earlier frames, now in result.h5
  done_ = true;
}

}  // namespace kiln
