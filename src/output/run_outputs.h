// The files of one run in its output directory: result.h5 (frames), result.xdmf, summary.json,
// picture.png and checkpoint.h5.
//
// While the run goes, frames go to result.h5.tmp, flushed at every frame; checkpoints are written
// whole and renamed. When the run ends (at t_end, at rest, or stopped by a signal) everything is
// published under its final name. A run that fails a check removes what it wrote and publishes
// nothing. A run whose output fails (a full disk) keeps what it finished for `kiln run --restart`
// once there is room: its frames as result.h5.unfinished (when HDF5 still reads every frame of its
// last checkpoint) and that checkpoint, and says so. A run killed outright (SIGKILL, power) leaves
// result.h5.tmp with its finished frames readable and its last checkpoint, from which
// `kiln run --restart` goes on. A checkpoint at t_end whose run did not publish (killed or failed
// while publishing) resumes to publish.
//
// A resumed run appends to a copy (result.h5.tmp) of its result: result.h5, or result.h5.unfinished,
// the frames a killed or failed run left (its result.h5.tmp, renamed). The original is replaced only when
// the resumed run ends; one that fails leaves it, and the checkpoint it resumed from, as they were
// (a write that fails on a full disk can leave an HDF5 file unreadable, so the file holding finished
// frames is never written in place).
//
// One run writes into a directory at a time: each holds an exclusive lock on DIR/.kiln.lock; a
// second is refused.
//
// A new run first moves the results of an earlier run in the same directory into previous/
// (replacing what an even earlier run left there), so that nothing of two runs lies side by side.
#pragma once
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/dem/dem_system.h"
#include "src/output/output_h5.h"
#include "src/output/outputs.h"
#include "src/base/snapshot.h"

namespace kiln {

// What result.h5 holds for this system's scene (output_h5.h).
ResultLayout result_layout(const DemSystem& sys);
// Whether result.h5 records the wall segments of every frame: some wall can move. (A wall whose
// position a later kind of motion takes from the state moves too: only this predicate changes.)
bool walls_move(const DemSystem& sys);
// Per segment of the scene, the rows of wall_segments it is written as: 1 in a cell that is not
// periodic; in a periodic one, 1 + one per edge it can cross (cut where it crosses them, each
// piece shown in the cell; unused rows are of zero length).
std::vector<int> pieces_of_segments(const DemSystem& sys);
// The picture's second line from a run's summary: how the run ended (t_end, at rest, frozen, a
// signal), and its steps with the integrator of each stage.
std::string how_it_ended(const nlohmann::json& summary);

class RunOutputs {
 public:
  // A new run with id `run_id` (recorded in result.h5 and summary.json).
  RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id);
  // A resumed run from `checkpoint`: a copy of its result, cut to the checkpoint's frames. Throws
  // InputError when the result is missing or belongs to another run.
  RunOutputs(const std::string& dir, const DemSystem& sys, const std::string& run_id, int frames,
             const Snapshot& checkpoint);
  // Unless finish() ran, the temporary files are removed; a new run also removes its checkpoint,
  // a resumed run puts back the checkpoint it resumed from.
  ~RunOutputs();
  RunOutputs(const RunOutputs&) = delete;
  RunOutputs& operator=(const RunOutputs&) = delete;

  void frame(double t, const double* y);
  int frames() const { return h5_->frames(); }
  void checkpoint(const Snapshot& s);
  std::string checkpoint_path() const { return path("checkpoint.h5"); }
  // The time of the last frame written (-inf before the first).
  double last_frame_time() const { return times_.empty() ? -INFINITY : times_.back(); }
  // After an output failed: keeps what the run finished (see above) and ends the run's writing;
  // returns what was kept, for the message ("" when nothing could be).
  std::string keep_finished_work();
  // Whether summary.json in `dir` says that run `run_id` was published at time t or later: a
  // checkpoint at t_end of a run that was not is resumed to publish it.
  static bool published(const std::string& dir, const std::string& run_id, double t);
  void finish(double t, const double* y, const nlohmann::json& summary, const std::string& title,
              const std::vector<ResultTable>& tables = {});

  // The names a run writes, final and temporary (a new run moves these aside).
  static const std::vector<std::string>& names();
  // Whether a run holds DIR's lock now (it is writing there): a missing result.h5 then means
  // "still running", not "killed".
  static bool running_in(const std::string& dir);
  // For the commands that read a finished run (movie, plot): throws InputError when DIR lacks
  // `name` (result.h5, summary.json), saying why: the run is still running, it was killed or its
  // output failed (with how to finish it), or DIR holds no run.
  static void require_published(const std::string& dir, const std::string& name, const std::string& then);

 private:
  std::string path(const std::string& name) const;
  // The final state's picture: particles and walls where they are at t.
  PictureInput picture(double t, const double* y, const std::string& title) const;
  // wall_loads.csv: per frame (a row) the time and each wall's force_x, force_y, torque and
  // power, the columns named by wall (quotes made ', control characters spaces, a repeated name
  // given its index) and unit; ParaView's CSV reader plots it over time.
  std::string wall_loads_csv() const;
  // The scene's segments a -> b as the rows written (pieces_of_segments): the ends of each piece.
  void cut_walls(const std::vector<Vec2>& a, const std::vector<Vec2>& b, std::vector<Vec2>& ends) const;
  void segments_rows();  // wall_a_, wall_b_ into segments_ (x_a, y_a, x_b, y_b per written piece)
  void lock_directory();
  void clean_up();  // a run that did not finish
  std::string dir_;
  const DemSystem& sys_;
  const ResultLayout layout_;
  const std::vector<int> pieces_;  // per scene segment: the rows it is written as (pieces_of_segments)
  std::unique_ptr<H5Frames> h5_;
  std::vector<double> times_;
  // Scratch of frame(): the wall segments and loads of one frame.
  std::vector<Vec2> wall_a_, wall_b_, ends_;
  std::vector<double> segments_, wall_force_, wall_torque_, wall_power_;
  std::vector<double> wrapped_;  // periodic cells: positions wrapped into the cell
  bool checkpointed_ = false;  // this run wrote checkpoint.h5
  int checkpoint_frames_ = 0;   // the frames its latest checkpoint continues
  double checkpoint_time_ = 0;
  std::string run_id_;
  bool done_ = false;
  const Snapshot* resumed_from_ = nullptr;  // a resumed run's checkpoint
  int lock_ = -1;                            // the directory's .kiln.lock, held while the run writes
};

}  // namespace kiln
